//! Interrupt and resume (issue 5): a run of 2T gives the same bytes as a run of
//! T followed by a resumed run to 2T, with contacts, with a prescribed torque,
//! and after a real SIGINT.

mod common;
use common::{fibresim, ok, read_bytes, resume_to};

use std::path::Path;
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

#[test]
fn resume_with_prescribed_torque_gives_the_same_bytes() {
    let text = r#"
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
    split_run_equals_whole(
        text,
        &["energy.csv", "orientation.csv"],
        &["--rotator", "pcdm"],
    );
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
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, common::packed_scene(6, 8, 8, 6e-4)).unwrap();
    let scene = scene.to_str().unwrap();
    let (whole, split) = (dir.path().join("w"), dir.path().join("s"));
    let t = ["--threads", "2", "-q", "--every", "50"];
    let mut a = vec!["run", scene, "--out", whole.to_str().unwrap()];
    a.extend(t);
    ok(fibresim(&a));
    let mut b = vec![
        "run",
        scene,
        "--out",
        split.to_str().unwrap(),
        "--t-end",
        "3e-4",
        "--checkpoint-every",
        "300",
    ];
    b.extend(t);
    ok(fibresim(&b));
    let ckpt = split.join("checkpoint.json");
    let states = std::fs::metadata(split.join("checkpoint.states"))
        .unwrap()
        .len();
    assert!(
        states <= 200 * 384,
        "{states} bytes of states for 384 fibres"
    );
    resume_to(&ckpt, "6e-4", &["--threads", "2"]);
    assert_eq!(
        read_bytes(&whole.join("energy.csv")),
        read_bytes(&split.join("energy.csv"))
    );
    let strip = |p: &Path| -> String {
        String::from_utf8(read_bytes(p))
            .unwrap()
            .lines()
            .filter(|l| !l.contains("\"wall_") && !l.contains("ns_per_body_step"))
            .collect()
    };
    assert_eq!(
        strip(&whole.join("summary.json")),
        strip(&split.join("summary.json"))
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
    ok(fibresim(&[
        "run",
        scene.to_str().unwrap(),
        "--t-end",
        "0.001",
        "--checkpoint-every",
        "500",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let states = out.join("checkpoint.states");
    let mut bytes = read_bytes(&states);
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&states, bytes).unwrap();
    let ckpt = out.join("checkpoint.json");
    let o = fibresim(&["run", "--resume", ckpt.to_str().unwrap(), "-q"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("checkpoint.states") && err.contains("does not belong"),
        "{err}"
    );
}
