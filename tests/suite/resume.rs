//! Interrupt and resume: a run of 2T gives the same bytes as a run of
//! T followed by a resumed run to 2T, with contacts, with a prescribed torque,
//! and after a real SIGINT.

use crate::common;
use common::{fibresim, ok, read_bytes, resume_to, states_file};

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fibre dropped at 30° close to the floor: it hits the floor within T.
const DROP: &str = r#"
[simulation]
dt = 1e-6
t_end = 0.04
rotator = "leapfrog"
[world]
gravity = [0.0, 0.0, -9.81]
[box]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
young = 5e7
poisson = 0.23
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
young = 5e7
poisson = 0.35
position = [0.5, 0.5, 0.0125]
axis = [0.8660254037844387, 0.0, 0.5]
"#;

fn split_run_equals_whole(scene_text: &str, files: &[&str], extra: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, scene_text).unwrap();
    let scene = scene.to_str().unwrap();
    let whole = dir.path().join("whole");
    let split = dir.path().join("split");
    let mut a = vec![
        "run",
        scene,
        "--every",
        "7",
        "-q",
        "--out",
        whole.to_str().unwrap(),
    ];
    a.extend(extra);
    ok(fibresim(&a));
    let mut b = vec![
        "run",
        scene,
        "--every",
        "7",
        "-q",
        "--t-end",
        "0.02",
        "--checkpoint-every",
        "20000",
        "--out",
        split.to_str().unwrap(),
    ];
    b.extend(extra);
    ok(fibresim(&b));
    let ckpt = split.join("checkpoint.json");
    resume_to(&ckpt, "0.04", &[]);
    for f in files {
        assert_eq!(
            read_bytes(&whole.join(f)),
            read_bytes(&split.join(f)),
            "{f} differs"
        );
    }
    let s: serde_json::Value =
        serde_json::from_slice(&read_bytes(&split.join("summary.json"))).unwrap();
    assert_eq!(s["steps"], 40000);
}

#[test]
fn resume_with_contacts_gives_the_same_bytes() {
    split_run_equals_whole(DROP, &["energy.csv"], &[]);
}

/// A fibre spinning up under the paper's test case 4 torque.
const TORQUED: &str = r#"
[simulation]
dt = 1e-6
t_end = 0.04
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
angular_velocity = [3.0, 20.0, 0.0]
torque = ["5e-4*sin(200*pi*t)", "1e-5*exp(3+24*t)", "1e-5*5^(52*t)"]
"#;

#[test]
fn resume_with_prescribed_torque_gives_the_same_bytes() {
    split_run_equals_whole(
        TORQUED,
        &["energy.csv", "orientation.csv"],
        &["--rotator", "pcdm"],
    );
}

/// The staggered rotators carry their half-step state in the checkpoint
/// (`Rotator::Aux`): resuming them gives the same bytes, with contacts and
/// with a prescribed torque.
#[test]
fn resume_of_staggered_rotators_gives_the_same_bytes() {
    for rotator in ["pcdm-staggered", "cayley-cd"] {
        split_run_equals_whole(DROP, &["energy.csv"], &["--rotator", rotator]);
        split_run_equals_whole(
            TORQUED,
            &["energy.csv", "orientation.csv"],
            &["--rotator", rotator],
        );
    }
}

/// `--resume CKPT --out NEW`: the checkpoint folder's outputs, cut to the
/// checkpoint, are continued in NEW; the checkpoint's own folder is untouched.
#[test]
fn resume_into_another_folder_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, DROP).unwrap();
    let scene = scene.to_str().unwrap();
    let (whole, split, moved) = (
        dir.path().join("w"),
        dir.path().join("s"),
        dir.path().join("m"),
    );
    let run = |out: &Path, extra: &[&str]| {
        let mut a = vec![
            "run",
            scene,
            "--every",
            "7",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ];
        a.extend(extra);
        ok(fibresim(&a));
    };
    run(&whole, &[]);
    // Checkpoint at 0.015 s, then the run goes on to 0.02 s in its own folder.
    run(&split, &["--t-end", "0.02", "--checkpoint-every", "15000"]);
    let before = read_bytes(&split.join("energy.csv"));
    let ckpt = split.join("checkpoint.json");
    resume_to(&ckpt, "0.04", &["--out", moved.to_str().unwrap()]);
    assert_eq!(
        read_bytes(&whole.join("energy.csv")),
        read_bytes(&moved.join("energy.csv"))
    );
    assert_eq!(
        read_bytes(&split.join("energy.csv")),
        before,
        "source folder changed"
    );
    let s: serde_json::Value =
        serde_json::from_slice(&read_bytes(&moved.join("summary.json"))).unwrap();
    assert_eq!(s["steps"], 40000);
}

/// Send SIGINT to a run once it is writing; `None` if it finished first.
fn interrupt(scene: &str, out: &Path) -> Option<std::process::ExitStatus> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args([
            "run",
            scene,
            "--every",
            "1000",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // energy.csv exists only after the SIGINT handler is installed.
    let t0 = std::time::Instant::now();
    while !out.join("energy.csv").exists() {
        assert!(t0.elapsed().as_secs() < 60, "the run never started");
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let status = child.wait().unwrap();
    (!status.success()).then_some(status)
}

#[test]
fn sigint_writes_a_checkpoint_and_resume_completes_identically() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    let cut = dir.path().join("cut");
    // Ten times longer on each retry (4e6 steps take ~0.6 s): the test fails
    // rather than pass without a signal having landed mid-run.
    let status = [4.0, 40.0, 400.0]
        .iter()
        .find_map(|t_end| {
            std::fs::write(
                &scene,
                DROP.replace("t_end = 0.04", &format!("t_end = {t_end:?}")),
            )
            .unwrap();
            let _ = std::fs::remove_dir_all(&cut);
            interrupt(scene.to_str().unwrap(), &cut)
        })
        .expect("every run finished before SIGINT arrived: nothing was tested");
    assert_eq!(status.code(), Some(130));
    let s: serde_json::Value =
        serde_json::from_slice(&read_bytes(&cut.join("summary.json"))).unwrap();
    assert!(s["stopped"]["kind"]
        .as_str()
        .unwrap()
        .contains("interrupted"));
    // Resume to a little past the interrupt (a multiple of --every, so the
    // last row is on cadence) and compare with an uninterrupted run to there.
    let ckpt = cut.join("checkpoint.json");
    let c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
    let steps = (c["step"].as_u64().unwrap() / 1000 + 50) * 1000;
    let t = format!("{:e}", steps as f64 * 1e-6);
    resume_to(&ckpt, &t, &[]);
    let whole = dir.path().join("whole");
    let scene = scene.to_str().unwrap();
    ok(fibresim(&[
        "run",
        scene,
        "--every",
        "1000",
        "--t-end",
        &t,
        "-q",
        "--out",
        whole.to_str().unwrap(),
    ]));
    assert_eq!(
        read_bytes(&whole.join("energy.csv")),
        read_bytes(&cut.join("energy.csv"))
    );
    let s: serde_json::Value =
        serde_json::from_slice(&read_bytes(&cut.join("summary.json"))).unwrap();
    assert_eq!(s["steps"].as_u64(), Some(steps));
}

/// A dense scene with live contacts on two threads (above the parallel
/// threshold): the split run's bytes equal the whole run's, and the
/// checkpoint's binary states take at most 200 bytes per fibre.
#[test]
fn resume_of_a_dense_scene_gives_the_same_bytes() {
    resume_of_a_dense_scene(&common::packed_scene(6, 8, 8, 6e-4));
}

/// The same with a dense mixed bed (256 fibres, 128 spheres).
#[test]
fn resume_of_a_dense_mixed_bed_gives_the_same_bytes() {
    resume_of_a_dense_scene(&common::packed_mixed_scene(6, 8, 8, 6e-4));
}

fn resume_of_a_dense_scene(text: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.to_str().unwrap();
    let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
    let t = ["--threads", "2", "-q", "--every", "50"];
    let mut a = vec!["run", scene, "--out", whole.to_str().unwrap()];
    a.extend(t);
    ok(fibresim(&a));
    let ckpt = run_checkpointed(scene, &split, "3e-4", "300", &t);
    let states = std::fs::metadata(states_file(&split)).unwrap().len();
    assert!(
        states <= 200 * 384,
        "{states} bytes of states for 384 bodies"
    );
    resume_to(&ckpt, "6e-4", &["--threads", "2"]);
    assert_eq!(
        read_bytes(&whole.join("energy.csv")),
        read_bytes(&split.join("energy.csv"))
    );
    assert_eq!(
        strip_timings(&whole.join("summary.json")),
        strip_timings(&split.join("summary.json"))
    );
}

/// A states file that is not the checkpoint's (a byte changed) is refused
/// with exit 2, naming it, before anything runs.
#[test]
fn a_tampered_states_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(&scene, DROP).unwrap();
    let out = dir.path().join("o");
    let ckpt = run_checkpointed(scene.to_str().unwrap(), &out, "0.001", "500", &["-q"]);
    let states = states_file(&out);
    let mut bytes = read_bytes(&states);
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&states, bytes).unwrap();
    let o = fibresim(&["run", "--resume", ckpt.to_str().unwrap(), "-q"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("checkpoint.1000.states") && err.contains("does not belong"),
        "{err}"
    );
}

/// `scenarios/bed_1k.toml` (1000 fibres resting in their box, 3578 contacts)
/// with `[contact] restitution = 0.3` and the end time `t_end`, in `dir`
/// with its body file.
fn damped_bed(dir: &Path, t_end: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    std::fs::copy(
        root.join("bed_1k_bodies.csv"),
        dir.join("bed_1k_bodies.csv"),
    )
    .unwrap();
    let text = std::fs::read_to_string(root.join("bed_1k.toml")).unwrap();
    assert!(text.contains("t_end = 0.002") && !text.contains("[contact]"));
    // pcdm keeps no rotator state: the states file is the layout below.
    let text = text.replace(
        "t_end = 0.002",
        &format!("t_end = {t_end}\nrotator = \"pcdm\""),
    ) + "\n[contact]\nrestitution = 0.3\n";
    let path = dir.join("damped.toml");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// `fibresim run SCENE --out OUT --t-end T_END --checkpoint-every EVERY
/// EXTRA…`, which must succeed; returns its checkpoint's path.
fn run_checkpointed(scene: &str, out: &Path, t_end: &str, every: &str, extra: &[&str]) -> PathBuf {
    let mut a = vec![
        "run",
        scene,
        "--out",
        out.to_str().unwrap(),
        "--t-end",
        t_end,
        "--checkpoint-every",
        every,
    ];
    a.extend(extra);
    ok(fibresim(&a));
    out.join("checkpoint.json")
}

/// Without the summary's timings.
fn strip_timings(p: &Path) -> String {
    String::from_utf8(read_bytes(p))
        .unwrap()
        .lines()
        .filter(|l| !l.contains("\"wall_") && !l.contains("ns_per_body_step"))
        .collect()
}

/// A damped bed on two threads (the parallel force stage): checkpointed at
/// step 200 and resumed to 400, its energy.csv (with `e_dissipated`) and
/// summary are the bytes of the run straight to 400; resumed for no step,
/// its summary is the one the run wrote at step 200. The states file is
/// the format's size (header 24 B; 112 B per fibre, and the 48 B of the
/// contact force and torque a damped step carries; the pair memories).
#[test]
fn resume_of_a_damped_bed_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = damped_bed(dir.path(), "4e-4");
    let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
    let t = ["--threads", "2", "-q", "--every", "20"];
    let mut a = vec!["run", &scene, "--out", whole.to_str().unwrap()];
    a.extend(t);
    ok(fibresim(&a));
    let ckpt = run_checkpointed(&scene, &split, "2e-4", "200", &t);
    let zero = dir.path().join("z");
    resume_to(&ckpt, "2e-4", &["--out", zero.to_str().unwrap()]);
    assert_eq!(
        strip_timings(&split.join("summary.json")),
        strip_timings(&zero.join("summary.json"))
    );
    let states = read_bytes(&states_file(&split));
    // Then the count of pair memories (u64 at the end of the per-fibre
    // part), 14 B each: most resting end-involved contacts have one.
    let at = 24 + 160 * 1000;
    let remembered = u64::from_le_bytes(states[at..at + 8].try_into().unwrap()) as usize;
    assert_eq!(states.len(), at + 8 + 14 * remembered);
    assert!(remembered > 300, "{remembered} pair memories");
    resume_to(&ckpt, "4e-4", &["--threads", "2"]);
    let energy = read_bytes(&whole.join("energy.csv"));
    assert!(String::from_utf8_lossy(&energy)
        .lines()
        .next()
        .unwrap()
        .ends_with(",e_dissipated"));
    assert_eq!(energy, read_bytes(&split.join("energy.csv")));
    assert_eq!(
        strip_timings(&whole.join("summary.json")),
        strip_timings(&split.join("summary.json"))
    );
}

/// Three fibres crossed in a stack, dropped at 0.5 m/s on the floor with
/// e = 0.3 (one thread: the serial force stage). Every contact is central,
/// so nothing is left sliding on the frictionless walls and the stack
/// settles (after 39 000 steps of 2 µs, tested every 1000).
const STACK: &str = r#"
[simulation]
dt = 2e-6
t_end = 1.0
rotator = "pcdm"
[world]
gravity = [0.0, 0.0, -9.81]
[box]
min = [0.0, 0.0, 0.0]
max = [0.1, 0.1, 0.1]
young = 5e7
poisson = 0.35
[material.pa]
density = 1100.0
young = 5e7
poisson = 0.35
[contact]
restitution = 0.3
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.03
material = "pa"
position = [0.05, 0.05, 0.02]
axis = [1.0, 0.0, 0.0]
velocity = [0.0, 0.0, -0.5]
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.03
material = "pa"
position = [0.05, 0.05, 0.045]
axis = [0.0, 1.0, 0.0]
velocity = [0.0, 0.0, -0.5]
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.03
material = "pa"
position = [0.05, 0.05, 0.07]
axis = [1.0, 0.0, 0.0]
velocity = [0.0, 0.0, -0.5]
"#;

/// `fibresim settle` stopped before it settles, with a checkpoint at step
/// 30 000 (two live contacts), then `settle --resume`: the same settled bed (body file), energy
/// rows and summary as the settle run straight through; its settle test
/// comes from the checkpoint. A settle checkpoint is not for `run --resume`.
#[test]
fn a_resumed_settle_writes_the_same_bed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("stack.toml");
    std::fs::write(&scene, STACK).unwrap();
    let scene = scene.to_str().unwrap();
    let p = |s: &str| dir.path().join(s).to_str().unwrap().to_string();
    let (w, s) = (p("w"), p("s"));
    let flags = ["--every", "1000", "-q"];
    let mut a = vec!["settle", scene, "--check-every", "1000", "--write"];
    let (wbed, sbed) = (p("whole.toml"), p("split.toml"));
    a.extend([wbed.as_str(), "--out", &w]);
    a.extend(flags);
    ok(fibresim(&a));
    let summary: serde_json::Value =
        serde_json::from_slice(&read_bytes(&Path::new(&w).join("summary.json"))).unwrap();
    // Settled at the first test with the three fibres resting (three
    // contacts); at step 39 000 the kinetic energy was already below the
    // threshold, but with one contact: the top fibres were in the air.
    assert_eq!(
        (summary["settled"].clone(), summary["steps"].clone()),
        (true.into(), 41000.into())
    );
    let energy = String::from_utf8(read_bytes(&Path::new(&w).join("energy.csv"))).unwrap();
    let row = |step: &str| -> Vec<String> {
        let line = energy
            .lines()
            .find(|l| l.starts_with(&format!("{step},")))
            .unwrap();
        line.split(',').map(String::from).collect()
    };
    let header: Vec<&str> = energy.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (contacts, ke) = (col("contacts"), |r: &[String]| -> f64 {
        r[col("e_trans")].parse::<f64>().unwrap() + r[col("e_rot")].parse::<f64>().unwrap()
    });
    let (early, end) = (row("39000"), row("41000"));
    // The default threshold, 1e-4 m g D per fibre (`settle --help`), for
    // the three fibres: m = ρ π D²/4 L.
    let m = 1100.0 * std::f64::consts::PI * 0.01f64.powi(2) / 4.0 * 0.03;
    let threshold = 3.0 * 1e-4 * m * 9.81 * 0.01;
    assert!(ke(&early) <= threshold, "{early:?}");
    assert!(ke(&end) <= threshold, "{end:?}");
    assert_eq!(early[contacts], "1", "{early:?}");
    assert_eq!(end[contacts], "3", "{end:?}");
    let mut b = vec!["settle", scene, "--check-every", "1000", "--write"];
    b.extend([sbed.as_str(), "--out", &s, "--t-end", "0.062"]);
    b.extend(["--checkpoint-every", "30000"]);
    b.extend(flags);
    let o = fibresim(&b);
    assert_eq!(o.status.code(), Some(2), "not settled by 0.062 s");
    let ckpt = p("s/checkpoint.json");
    let o = fibresim(&["run", "--resume", &ckpt, "-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("settle --resume"));
    ok(fibresim(&[
        "settle", "--resume", &ckpt, "--t-end", "1", "--write", &sbed, "-q",
    ]));
    let bodies = |s: &str| read_bytes(&dir.path().join(s));
    assert_eq!(bodies("whole_bodies.csv"), bodies("split_bodies.csv"));
    assert_eq!(bodies("w/energy.csv"), bodies("s/energy.csv"));
    assert_eq!(
        strip_timings(&dir.path().join("w/summary.json")),
        strip_timings(&dir.path().join("s/summary.json"))
    );
}

/// A damped checkpoint (the stack at step 1000) and its exit-2 refusals:
/// resumed with another restitution, a torn states file, and a checkpoint
/// without the damping state (as fibresim wrote them before: rewritten here
/// as such, its states file cut to the elastic layout with a matching hash).
#[test]
fn bad_damped_checkpoints_are_refused() {
    use fibresim::output::checkpoint::states;
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("stack.toml");
    std::fs::write(&scene, STACK).unwrap();
    let out = dir.path().join("o");
    let ckpt = run_checkpointed(scene.to_str().unwrap(), &out, "0.002", "1000", &["-q"]);
    let ck = ckpt.to_str().unwrap();
    let bed = dir.path().join("bed.toml");
    let refused = |args: &[&str], want: &[&str]| {
        let o = fibresim(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        for w in want {
            assert!(err.contains(w), "`{w}` not in: {err}");
        }
    };
    let bed = bed.to_str().unwrap();
    refused(
        &[
            "settle",
            "--resume",
            ck,
            "--restitution",
            "0.5",
            "--write",
            bed,
        ],
        &[
            "--restitution",
            "0.5 differs from the checkpoint's restitution 0.3",
        ],
    );
    let states_path = states_file(&out);
    let bytes = read_bytes(&states_path);
    assert_eq!(
        bytes.len(),
        24 + 160 * 3 + 8,
        "three fibres, no pair memory"
    );
    std::fs::write(&states_path, &bytes[..bytes.len() - 48]).unwrap();
    refused(
        &["run", "--resume", ck, "-q"],
        &["checkpoint.1000.states", "does not belong"],
    );
    // The elastic layout (no pair memory), and a JSON without `damping`,
    // consistent.
    let old = &[&bytes[..24 + 112 * 3], &0u64.to_le_bytes()[..]].concat();
    std::fs::write(&states_path, old).unwrap();
    let mut json: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
    let j = json.as_object_mut().unwrap();
    assert!(j.remove("damping").is_some());
    j.insert("states_bytes".into(), old.len().into());
    j.insert(
        "states_fnv".into(),
        format!("{:016x}", states::fnv(old)).into(),
    );
    std::fs::write(&ckpt, serde_json::to_string(&json).unwrap()).unwrap();
    refused(
        &["run", "--resume", ck, "-q"],
        &["no damping state", "rerun from the start"],
    );
}

/// The pairs' memories of their end-involved scans
/// (`contact/fibre_fibre/coherence.rs`) are part of the checkpoint: a
/// remembered contact is the scan's to the scan's rounding, not to its
/// bits, so a resumed run that scanned every pair again could drift from
/// the straight one. `bed_1k` at its settling step (its contacts slide,
/// and memories run out and are made again), 300 steps straight against
/// 150 + 150: the energy rows, and the states file both runs write at step
/// 300, which holds the memories then (a memory made again by a scan at
/// the resume has its whole room, a carried one has spent some: the file
/// differs when the resume drops them).
#[test]
fn resume_keeps_the_pair_memories() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!("{}/scenarios/bed_1k.toml", env!("CARGO_MANIFEST_DIR"));
    let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
    let t = ["--dt", "2e-5", "--threads", "1", "-q"];
    run_checkpointed(&scene, &whole, "6e-3", "150", &t);
    let ckpt = run_checkpointed(&scene, &split, "3e-3", "150", &t);
    resume_to(
        &ckpt,
        "6e-3",
        &["--threads", "1", "--checkpoint-every", "150"],
    );
    for f in ["energy.csv", "checkpoint.300.states"] {
        assert!(
            read_bytes(&whole.join(f)) == read_bytes(&split.join(f)),
            "{f} of the resumed run differs"
        );
    }
}

/// A dense frictional mixed bed (`common::packed_mixed_scene`: 256 fibres
/// and 128 spheres at up to 0.3 m/s) with the box's low walls moved to
/// 50 µm of the outer bodies, so fibres and spheres hit them within the
/// first 200 steps; with `contact` appended.
fn frictional_bed(contact: &str) -> String {
    let text = common::packed_mixed_scene(6, 8, 8, 6e-4);
    let (old, new) = ("min = [0.0, 0.0, 0.0]", "min = [0.005, 0.005, 0.005]");
    assert!(text.contains(old));
    text.replace(old, new) + "[contact]\n" + contact
}

/// Dense frictional mixed beds, without and with a restitution (μ = 0.4
/// body–body, 0.3 body–wall), on two threads: checkpointed at step 300,
/// when sticking and sliding springs are live on fibre–fibre, sphere–fibre,
/// sphere–sphere and body–wall contacts, and resumed to 600, the energy
/// rows, the trajectory, the summary (but its timings) and the final
/// states file (states, loads, pair memories and springs, written by both
/// runs at step 600) are the bytes of the run straight to 600. The springs
/// are what the checkpoint adds: 65 bytes per touching contact after the
/// pair memories (key, spring, place and weight).
#[test]
fn resume_of_a_frictional_mixed_bed_gives_the_same_bytes() {
    for contact in [
        "friction = 0.4\nwall_friction = 0.3\n",
        "restitution = 0.5\nfriction = 0.4\nwall_friction = 0.3\n",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("bed.toml");
        std::fs::write(&scene, frictional_bed(contact)).unwrap();
        let scene = scene.to_str().unwrap();
        let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
        let t = [
            "--threads",
            "2",
            "-q",
            "--every",
            "20",
            "--trajectory-every",
            "100",
        ];
        run_checkpointed(scene, &whole, "6e-4", "300", &t);
        let ckpt = run_checkpointed(scene, &split, "3e-4", "300", &t);
        let c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
        assert_eq!(c["format"], "fibresim-checkpoint-7");
        assert!(c["damping"]["friction"].is_array(), "{contact}");
        // The springs: after the 24 B header, 160 B per body (states and
        // loads) and the pair memories, the wall and pair records.
        let states = read_bytes(&states_file(&split));
        let word = |at: usize| u64::from_le_bytes(states[at..at + 8].try_into().unwrap()) as usize;
        assert_eq!(word(8), 384, "bodies");
        let walls_at = springs_at(&states);
        let (walls, pairs_at) = (word(walls_at), walls_at + 8 + ENTRY * word(walls_at));
        let pairs = word(pairs_at);
        assert_eq!(states.len(), pairs_at + 8 + ENTRY * pairs);
        assert!(
            walls > 20 && pairs > 80,
            "{walls} wall and {pairs} pair springs"
        );
        resume_to(
            &ckpt,
            "6e-4",
            &["--threads", "2", "--checkpoint-every", "300"],
        );
        for f in ["energy.csv", "trajectory.csv", "checkpoint.600.states"] {
            assert!(
                read_bytes(&whole.join(f)) == read_bytes(&split.join(f)),
                "{f} differs ({contact})"
            );
        }
        assert_eq!(
            strip_timings(&whole.join("summary.json")),
            strip_timings(&split.join("summary.json"))
        );
    }
}

/// A checkpoint written by an earlier build (`tests/data/checkpoint-7-frictional/`,
/// format 7, by commit 3bc40d3): the frictional mixed bed
/// of `common::packed_mixed_scene(3, 3, 4, 4e-4)` with its low walls moved
/// in, μ = 0.4 body–body and 0.3 body–wall, one thread, rows every 20
/// steps, checkpointed at step 1000 with pair memories, wall springs and
/// pair springs live. Resumed by this build to step 1500, its energy rows
/// are the bytes of this build's run straight through. (It fails when a
/// resume drops the springs.)
#[test]
fn a_checkpoint_of_an_earlier_build_resumes_to_the_same_bytes() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/checkpoint-7-frictional");
    let dir = tempfile::tempdir().unwrap();
    let split = dir.path().join("s");
    std::fs::create_dir(&split).unwrap();
    for f in ["checkpoint.json", "checkpoint.1000.states", "energy.csv"] {
        std::fs::copy(data.join(f), split.join(f)).unwrap();
    }
    let c: serde_json::Value =
        serde_json::from_slice(&read_bytes(&split.join("checkpoint.json"))).unwrap();
    assert_eq!(c["format"], "fibresim-checkpoint-7");
    // What the states file carries: pair memories, then the wall and pair
    // springs (a count, then the entries, each).
    let states = read_bytes(&split.join("checkpoint.1000.states"));
    let word = |at: usize| u64::from_le_bytes(states[at..at + 8].try_into().unwrap()) as usize;
    let memories_at = 24 + 36 * (112 + 8 * word(16) + 48);
    let walls_at = springs_at(&states);
    let pairs_at = walls_at + 8 + ENTRY * word(walls_at);
    assert_eq!(
        (word(memories_at), word(walls_at), word(pairs_at)),
        (5, 10, 29),
        "memories, wall springs, pair springs"
    );
    let scene = dir.path().join("bed.toml");
    std::fs::write(&scene, c["scenario_text"].as_str().unwrap()).unwrap();
    let whole = dir.path().join("w");
    ok(fibresim(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        whole.to_str().unwrap(),
        "--t-end",
        "1.5e-3",
        "--every",
        "20",
        "--threads",
        "1",
        "-q",
    ]));
    resume_to(
        &split.join("checkpoint.json"),
        "1.5e-3",
        &["--threads", "1"],
    );
    assert!(
        read_bytes(&whole.join("energy.csv")) == read_bytes(&split.join("energy.csv")),
        "energy.csv of the resumed run differs"
    );
}

/// Bytes of a contact's record in a states file: `u32` a, `u32` b, `u8`
/// slot, the spring's three `f64`, the place's three and the weight.
const ENTRY: usize = 9 + 8 * 7;

/// A checkpoint of the format before places (`fibresim-checkpoint-6`: a
/// record is its key and its spring) still resumes a frictional run: its
/// records go to the points of their own ranks at the first computation,
/// as that format's runs matched them, and by place from then on. The
/// frictional mixed bed of the test above, checkpointed at step 300 and
/// rewritten into that format, resumes to 600; in that bed every touching
/// pair's points keep their ranks between two steps, so the bytes are the
/// run's straight through (energy rows, trajectory, final states file).
#[test]
fn a_checkpoint_without_places_resumes_a_frictional_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bed.toml");
    std::fs::write(
        &scene,
        frictional_bed(
            "friction = 0.4
wall_friction = 0.3
",
        ),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
    let t = ["-q", "--every", "20", "--trajectory-every", "100"];
    run_checkpointed(scene, &whole, "6e-4", "300", &t);
    let ckpt = run_checkpointed(scene, &split, "3e-4", "300", &t);
    let mut c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
    c["format"] = "fibresim-checkpoint-6".into();
    let states = states_file(&split);
    let bytes = read_bytes(&states);
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
    // Each record cut to its key and spring (33 bytes).
    let mut at = springs_at(&bytes);
    let mut old = bytes[..at].to_vec();
    for _ in 0..2 {
        let count = word(at);
        old.extend_from_slice(&bytes[at..at + 8]);
        at += 8;
        for _ in 0..count {
            old.extend_from_slice(&bytes[at..at + 33]);
            at += ENTRY;
        }
    }
    assert_eq!(at, bytes.len());
    assert!(old.len() < bytes.len());
    std::fs::write(&states, &old).unwrap();
    c["states_bytes"] = old.len().into();
    c["states_fnv"] = format!("{:016x}", fnv(&old)).into();
    std::fs::write(&ckpt, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    resume_to(&ckpt, "6e-4", &["--checkpoint-every", "300"]);
    for f in ["energy.csv", "trajectory.csv", "checkpoint.600.states"] {
        assert!(
            read_bytes(&whole.join(f)) == read_bytes(&split.join(f)),
            "{f} differs"
        );
    }
}

/// A checkpoint of the format before records (`fibresim-checkpoint-5`, no
/// springs) still resumes a
/// frictionless run, and is refused for a frictional one (exit 2, naming
/// friction and the fix) before anything runs.
#[test]
fn a_checkpoint_without_springs_resumes_only_frictionless_scenes() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("plain", DROP.to_string()),
        (
            "rough",
            DROP.replace("[[body]]", "[contact]\nfriction = 0.3\n[[body]]"),
        ),
    ] {
        let scene = dir.path().join(format!("{name}.toml"));
        std::fs::write(&scene, &text).unwrap();
        let out = dir.path().join(name);
        let ckpt = run_checkpointed(scene.to_str().unwrap(), &out, "0.001", "500", &["-q"]);
        // The previous format's files: its name, and no friction part (so
        // no springs).
        let mut c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
        c["format"] = "fibresim-checkpoint-5".into();
        if let Some(d) = c.get_mut("damping").and_then(|d| d.as_object_mut()) {
            d.remove("friction");
        }
        let states = states_file(&out);
        let mut bytes = read_bytes(&states);
        if name == "rough" {
            // Without the springs.
            bytes.truncate(springs_at(&bytes));
            std::fs::write(&states, &bytes).unwrap();
            c["states_bytes"] = bytes.len().into();
            c["states_fnv"] = format!("{:016x}", fnv(&bytes)).into();
        }
        std::fs::write(&ckpt, serde_json::to_string_pretty(&c).unwrap()).unwrap();
        let o = fibresim(&[
            "run",
            "--resume",
            ckpt.to_str().unwrap(),
            "--t-end",
            "0.002",
            "-q",
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        if name == "plain" {
            assert!(o.status.success(), "{err}");
        } else {
            assert_eq!(o.status.code(), Some(2), "{err}");
            assert!(
                err.contains("friction") && err.contains("rerun from the start"),
                "{err}"
            );
        }
    }
}

/// 64-bit FNV-1a (the checkpoint's hash of its states file).
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Where a damped or frictional states file's springs start: after the
/// header, per body its id, state, rotator doubles and loads, and the pair
/// memories.
fn springs_at(states: &[u8]) -> usize {
    let word = |at: usize| u64::from_le_bytes(states[at..at + 8].try_into().unwrap()) as usize;
    let (n, per) = (word(8), word(16));
    let at = 24 + n * (112 + 8 * per + 48);
    at + 8 + 14 * word(at)
}
