//! Runs never mix, and what is on disk is whole: a resumed checkpoint must
//! still match its folder's outputs; a run refuses (or, in the default
//! folder, replaces) another run's outputs; a kill or a full disk leaves
//! whole rows; an interrupted settle names the command that resumes it and
//! leaves no half-written bed; rates count this process's steps; a run
//! without a terminal shows progress lines and puts its rows on disk while
//! it goes on.

use crate::common;
use common::{fibresim, ok, read_bytes};

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The README's test-case-1 fragment (a fibre falling in a box), t_end 1 ms.
const TC1: &str = r#"
[simulation]
dt = 1e-6
t_end = 0.001
rotator = "pcdm"
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
position = [0.5, 0.5, 0.5]
axis = [0.8660254037844387, 0.0, 0.5]
velocity = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 0.0]
"#;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `TC1` without gravity, at rest, for `t_end` in `dir/rest.toml`: a run as
/// long as a test needs that no guard stops and no machine finishes while
/// a test watches it.
fn rest(dir: &Path, t_end: &str) -> PathBuf {
    let p = dir.join("rest.toml");
    let text = TC1
        .replace("t_end = 0.001", &format!("t_end = {t_end}"))
        .replace("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]");
    std::fs::write(&p, text).unwrap();
    p
}

/// `TC1` with `t_end` written into `dir/base.toml`.
fn base(dir: &Path, t_end: &str) -> PathBuf {
    let p = dir.join("base.toml");
    std::fs::write(
        &p,
        TC1.replace("t_end = 0.001", &format!("t_end = {t_end}")),
    )
    .unwrap();
    p
}

/// Exit 2 with every needle in stderr.
fn refused(o: &Output, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` not in: {err}");
    }
}

/// Every line of the CSV file at `p` is a whole row: the file ends with a
/// newline and each row has the header's number of fields, each a number.
fn whole_rows(p: &Path) -> usize {
    let text = String::from_utf8(read_bytes(p)).unwrap();
    assert!(text.ends_with('\n'), "{} ends in half a row", p.display());
    let mut lines = text.lines();
    let fields = lines.next().unwrap().split(',').count();
    let mut rows = 0;
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        assert_eq!(cells.len(), fields, "{}: a cut row `{l}`", p.display());
        assert!(cells.iter().all(|c| c.parse::<f64>().is_ok()), "{l}");
        rows += 1;
    }
    rows
}

/// The reported corruption reproduced: a run with checkpoints, then another run into
/// the same folder with another δt, then a resume of the first run's
/// checkpoint. The second run is refused (exit 2, naming `--force` and
/// `--out`) and touches nothing, so the resume continues the first run:
/// its energy.csv is the straight run's to 2 ms. A checkpoint that another
/// run's outputs did come to lie beside (the second run forced, the
/// checkpoint put back) is refused naming energy.csv, which it leaves as it
/// was.
#[test]
fn a_checkpoint_never_continues_another_runs_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "0.001");
    let (o, straight) = (dir.path().join("o"), dir.path().join("straight"));
    let sc = s(&scene);
    ok(fibresim(&[
        "run",
        sc,
        "--out",
        s(&o),
        "--checkpoint-every",
        "300",
        "-q",
    ]));
    let first = read_bytes(&o.join("energy.csv"));
    let second = fibresim(&["run", sc, "--out", s(&o), "--dt", "5e-7", "-q"]);
    refused(&second, &["--force", "--out", "energy.csv", "--resume"]);
    assert_eq!(read_bytes(&o.join("energy.csv")), first);
    let ckpt = o.join("checkpoint.json");
    ok(fibresim(&[
        "run",
        "--resume",
        s(&ckpt),
        "--t-end",
        "0.002",
        "-q",
    ]));
    ok(fibresim(&[
        "run",
        sc,
        "--out",
        s(&straight),
        "--t-end",
        "0.002",
        "-q",
    ]));
    assert_eq!(
        read_bytes(&o.join("energy.csv")),
        read_bytes(&straight.join("energy.csv"))
    );

    // The stale checkpoint: kept aside, the second run forced, put back.
    let keep = dir.path().join("keep");
    std::fs::create_dir(&keep).unwrap();
    ok(fibresim(&[
        "run",
        sc,
        "--out",
        s(&o),
        "--checkpoint-every",
        "300",
        "-q",
        "--force",
    ]));
    let states = common::states_file(&o);
    let names = [
        "checkpoint.json",
        states.file_name().unwrap().to_str().unwrap(),
    ];
    for f in names {
        std::fs::copy(o.join(f), keep.join(f)).unwrap();
    }
    ok(fibresim(&[
        "run",
        sc,
        "--out",
        s(&o),
        "--dt",
        "5e-7",
        "-q",
        "--force",
    ]));
    assert!(
        !o.join("checkpoint.json").exists() && !states.exists(),
        "--force clears every output"
    );
    for f in names {
        std::fs::copy(keep.join(f), o.join(f)).unwrap();
    }
    let other = read_bytes(&o.join("energy.csv"));
    let o2 = fibresim(&["run", "--resume", s(&ckpt), "--t-end", "0.002"]);
    refused(
        &o2,
        &["energy.csv", "--resume", "two runs", "rerun from the start"],
    );
    assert_eq!(read_bytes(&o.join("energy.csv")), other);
}

/// The checkpoint is the run's identity: an edit of its embedded scenario
/// is refused by the scenario hash, and a resumed run keeps its guards (a
/// guard flag with `--resume` is refused, not ignored).
#[test]
fn a_resumed_run_is_the_checkpointed_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "0.001");
    let o = dir.path().join("o");
    ok(fibresim(&[
        "run",
        s(&scene),
        "--out",
        s(&o),
        "--checkpoint-every",
        "500",
        "-q",
    ]));
    let ckpt = o.join("checkpoint.json");
    let guard = fibresim(&[
        "run",
        "--resume",
        s(&ckpt),
        "--max-energy-error",
        "1e-20",
        "-q",
    ]);
    refused(&guard, &["--max-energy-error", "--resume"]);
    let mut c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
    let text = c["scenario_text"].as_str().unwrap().to_string();
    assert!(text.contains("max = [1.0, 1.0, 1.0]"));
    c["scenario_text"] = text
        .replace("max = [1.0, 1.0, 1.0]", "max = [2.0, 1.0, 1.0]")
        .into();
    std::fs::write(&ckpt, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    let before = read_bytes(&o.join("energy.csv"));
    refused(
        &fibresim(&["run", "--resume", s(&ckpt), "-q"]),
        &["checkpoint.json", "scenario_text", "edited"],
    );
    assert_eq!(read_bytes(&o.join("energy.csv")), before);
}

/// A given folder holding another run's outputs (VTK frames and a
/// checkpoint among them) is refused, and nothing in it changes; with
/// `--force` every earlier output goes (frames included) and a user's own
/// file stays. Resuming into another given folder that holds outputs is
/// refused the same way.
#[test]
fn a_given_folder_with_outputs_is_refused_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "0.001");
    let sc = s(&scene);
    let o = dir.path().join("o");
    let first = [
        "run",
        sc,
        "--out",
        s(&o),
        "--vtk-every",
        "100",
        "--trajectory-every",
        "100",
        "--checkpoint-every",
        "400",
        "-q",
    ];
    ok(fibresim(&first));
    std::fs::write(o.join("notes.txt"), "mine").unwrap();
    let listing = |d: &Path| -> Vec<String> {
        let mut v: Vec<String> = walk(d);
        v.sort();
        v
    };
    let before = listing(&o);
    assert!(
        before.iter().any(|f| f == "vtk/fibres_1000.vtp"),
        "{before:?}"
    );
    refused(
        &fibresim(&["run", sc, "--out", s(&o), "-q"]),
        &["--force", "--out DIR", "11 VTK frames", "checkpoint.json"],
    );
    assert_eq!(listing(&o), before);
    let moved = dir.path().join("m");
    ok(fibresim(&["run", sc, "--out", s(&moved), "-q"]));
    refused(
        &fibresim(&[
            "run",
            "--resume",
            s(&o.join("checkpoint.json")),
            "--out",
            s(&moved),
            "-q",
        ]),
        &["--force", "energy.csv"],
    );
    ok(fibresim(&["run", sc, "--out", s(&o), "-q", "--force"]));
    assert_eq!(
        listing(&o),
        ["energy.csv", "notes.txt", "summary.json"],
        "the earlier run's frames, checkpoint, trajectory and collection are gone"
    );
}

/// Files under `d`, relative, `/`-separated.
fn walk(d: &Path) -> Vec<String> {
    let mut out = vec![];
    for e in std::fs::read_dir(d).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        if e.file_type().unwrap().is_dir() {
            out.extend(walk(&e.path()).into_iter().map(|n| format!("{name}/{n}")));
        } else {
            out.push(name);
        }
    }
    out
}

/// The default folder (`out/<scenario>/<rotator>`, no `--out`) is replaced
/// with a one-line note: a second plain run works, and no frame of the
/// first one stays beside the second's outputs.
#[test]
fn the_default_folder_is_replaced_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    base(dir.path(), "0.001");
    let run = |extra: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_fibresim"));
        c.args(["run", "base.toml", "-q"])
            .args(extra)
            .current_dir(dir.path());
        c.output().unwrap()
    };
    let first = run(&["--vtk-every", "100"]);
    assert!(first.status.success(), "{}", stderr(&first));
    assert!(!stderr(&first).contains("note:"), "{}", stderr(&first));
    let folder = dir.path().join("out/base/pcdm");
    assert!(folder.join("vtk/fibres_0500.vtp").exists());
    let second = run(&[]);
    assert!(second.status.success(), "{}", stderr(&second));
    let note = stderr(&second);
    assert!(
        note.contains("note: replacing an earlier run's outputs in out/base/pcdm")
            && note.contains("--out DIR")
            && note.lines().count() == 1,
        "{note}"
    );
    assert_eq!(walk(&folder).len(), 2, "{:?}", walk(&folder));
}

/// kill -9 mid-run: energy.csv holds whole rows only; resumed from the
/// last checkpoint to a little past it, it is the straight run's, byte for
/// byte.
#[test]
fn a_killed_run_leaves_whole_rows_and_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "40");
    let (o, straight) = (dir.path().join("o"), dir.path().join("straight"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args([
            "run",
            s(&scene),
            "--out",
            s(&o),
            "--every",
            "100",
            "--checkpoint-every",
            "1000000",
            "-q",
        ])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    // Past a checkpoint (rows are then written after it).
    while !o.join("checkpoint.json").exists() {
        assert!(t0.elapsed() < Duration::from_secs(120), "no checkpoint");
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before the kill"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(300));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    whole_rows(&o.join("energy.csv"));
    let ckpt = o.join("checkpoint.json");
    let c: serde_json::Value = serde_json::from_slice(&read_bytes(&ckpt)).unwrap();
    let t = format!("{:e}", (c["step"].as_u64().unwrap() + 20_000) as f64 * 1e-6);
    ok(fibresim(&[
        "run",
        "--resume",
        s(&ckpt),
        "--t-end",
        &t,
        "-q",
    ]));
    ok(fibresim(&[
        "run",
        s(&scene),
        "--out",
        s(&straight),
        "--every",
        "100",
        "--t-end",
        &t,
        "-q",
    ]));
    assert_eq!(
        read_bytes(&o.join("energy.csv")),
        read_bytes(&straight.join("energy.csv"))
    );
}

/// A tmpfs of 256 KiB that a run writing a row every step fills: exit 1,
/// a message naming energy.csv and the full disk, and a file of whole rows
/// with no temporary file beside it. Needs root (mount); skipped with a
/// message elsewhere.
#[test]
fn a_full_disk_leaves_whole_rows() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "0.01");
    let mnt = dir.path().join("mnt");
    std::fs::create_dir(&mnt).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=256k", "tmpfs", s(&mnt)])
        .stderr(Stdio::piped())
        .output();
    match mounted {
        Ok(m) if m.status.success() => {}
        Ok(m) => {
            eprintln!(
                "skipped: cannot mount a tmpfs here (needs root): {}",
                stderr(&m).trim()
            );
            return;
        }
        Err(e) => {
            eprintln!("skipped: cannot run mount: {e}");
            return;
        }
    }
    struct Unmount<'a>(&'a Path);
    impl Drop for Unmount<'_> {
        fn drop(&mut self) {
            let _ = Command::new("umount").arg(self.0).status();
        }
    }
    let _guard = Unmount(&mnt);
    let o = mnt.join("o");
    let out = fibresim(&[
        "run",
        s(&scene),
        "--out",
        s(&o),
        "--every",
        "1",
        "--vtk-every",
        "2000",
        "-q",
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("No space left on device") && err.contains("whole rows"),
        "{err}"
    );
    let rows = whole_rows(&o.join("energy.csv"));
    assert!(rows > 100, "{rows} rows before the disk was full");
    let left: Vec<String> = walk(&o)
        .into_iter()
        .filter(|f| f.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// Three fibres crossed in a stack, dropped on the floor with e = 0.3
/// (the resume tests' stack): it settles after 39 000 steps of 2 µs.
const STACK: &str = r#"
[simulation]
dt = 2e-6
t_end = 1.0
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

/// Ctrl-C on `settle`: exit 130, no bed written (neither the scenario nor
/// its body file, nor a temporary one), and the message's command, run as
/// printed, resumes it to its end (`--t-end` and `--write-dt` of the
/// first command included), where it writes both files.
#[test]
fn ctrl_c_on_settle_names_the_command_that_resumes_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("stack.toml");
    std::fs::write(&scene, STACK).unwrap();
    let (o, bed) = (dir.path().join("o"), dir.path().join("bed.toml"));
    // Never settles (threshold 1e-30 J): it runs to --t-end. Ten times
    // longer on each retry, so that the signal lands mid-run.
    let (status, err) = ["0.4", "4", "40"]
        .iter()
        .find_map(|t_end| {
            // A retry starts clean: an earlier attempt that ended before
            // the signal wrote its bed.
            let _ = std::fs::remove_dir_all(&o);
            for f in ["bed.toml", "bed_bodies.csv"] {
                let _ = std::fs::remove_file(dir.path().join(f));
            }
            let child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
                .args([
                    "settle",
                    s(&scene),
                    "--ke-per-body",
                    "1e-30",
                    "--t-end",
                    t_end,
                ])
                .args([
                    "--write",
                    s(&bed),
                    "--write-dt",
                    "1e-6",
                    "--out",
                    s(&o),
                    "-q",
                ])
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            interrupt(child, &o.join("energy.csv"))
        })
        .expect("every settle ended before SIGINT arrived: nothing was tested");
    assert_eq!(status.code(), Some(130), "{err}");
    for f in [
        "bed.toml",
        "bed_bodies.csv",
        "bed.toml.tmp",
        "bed_bodies.csv.tmp",
    ] {
        assert!(
            !dir.path().join(f).exists(),
            "{f} written by an interrupted settle"
        );
    }
    let command = err
        .split('`')
        .find(|c| c.starts_with("fibresim settle --resume"))
        .unwrap_or_else(|| panic!("no resume command in: {err}"));
    assert!(command.contains(" --write-dt 1e-6"), "{command}");
    let words: Vec<&str> = command.split_whitespace().skip(1).collect();
    let resumed = fibresim(&words);
    let rerr = stderr(&resumed);
    // Not settled by its t_end (exit 2, the bed written anyway).
    assert_eq!(resumed.status.code(), Some(2), "{rerr}");
    assert!(rerr.contains("did not settle"), "{rerr}");
    let written = std::fs::read_to_string(&bed).unwrap();
    assert!(written.contains("dt = 1e-6") && dir.path().join("bed_bodies.csv").exists());
    let summary: serde_json::Value =
        serde_json::from_slice(&read_bytes(&o.join("summary.json"))).unwrap();
    assert_eq!(summary["steps"], summary["steps_planned"]);
}

/// Send SIGINT to `child` once `file` exists and a moment has passed;
/// its status and stderr, or `None` if it ended first.
fn interrupt(
    mut child: std::process::Child,
    file: &Path,
) -> Option<(std::process::ExitStatus, String)> {
    let t0 = Instant::now();
    while !file.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "the run never started"
        );
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(100));
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let out = child.wait_with_output().unwrap();
    (out.status.code() == Some(130)).then(|| (out.status, stderr(&out)))
}

/// Ctrl-C on `run`: the printed command resumes the run to the end it was
/// given on the command line (not the scenario's).
#[test]
fn ctrl_c_on_run_names_the_command_that_resumes_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = base(dir.path(), "0.001");
    let o = dir.path().join("o");
    let (status, err) = ["1", "10", "100"]
        .iter()
        .find_map(|t_end| {
            let _ = std::fs::remove_dir_all(&o);
            let child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
                .args([
                    "run",
                    s(&scene),
                    "--t-end",
                    t_end,
                    "--every",
                    "1000",
                    "--out",
                    s(&o),
                    "-q",
                ])
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            interrupt(child, &o.join("energy.csv"))
        })
        .expect("every run ended before SIGINT arrived: nothing was tested");
    assert_eq!(status.code(), Some(130));
    let command = err
        .split('`')
        .find(|c| c.starts_with("fibresim run --resume"))
        .unwrap_or_else(|| panic!("no resume command in: {err}"));
    let c: serde_json::Value =
        serde_json::from_slice(&read_bytes(&o.join("checkpoint.json"))).unwrap();
    let planned = c["steps_planned"].as_u64().unwrap();
    assert!(planned >= 1_000_000, "{planned}");
    // Resumed to the planned end would take long: the printed command, with
    // the end moved to shortly after the checkpoint, must run; and the
    // planned end is what the checkpoint continues to without --t-end.
    let mut words: Vec<String> = command
        .split_whitespace()
        .skip(1)
        .map(String::from)
        .collect();
    let end = (c["step"].as_u64().unwrap() / 1000 + 5) * 1000;
    words.extend([
        "--t-end".into(),
        format!("{:e}", end as f64 * 1e-6),
        "-q".into(),
    ]);
    let args: Vec<&str> = words.iter().map(String::as_str).collect();
    ok(fibresim(&args));
    let scene = fibresim::run::scene_from_checkpoint(
        &fibresim::output::Checkpoint::read(&o.join("checkpoint.json")).unwrap(),
        None,
    )
    .unwrap();
    assert_eq!(scene.sim.steps(), planned, "resumed without --t-end");
}

/// `settle --resume`: the printed rate counts the steps of this process
/// only: 11 000 of the 41 000 (a checkpoint at 30 000), against its wall
/// time in summary.json.
#[test]
fn a_resumed_settle_reports_the_rate_of_its_own_steps() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("stack.toml");
    std::fs::write(&scene, STACK).unwrap();
    let o = dir.path().join("o");
    let bed = dir.path().join("bed.toml");
    let first = fibresim(&[
        "settle",
        s(&scene),
        "--check-every",
        "1000",
        "--write",
        s(&bed),
        "--out",
        s(&o),
        "--t-end",
        "0.062",
        "--checkpoint-every",
        "30000",
        "--every",
        "1000",
        "-q",
    ]);
    assert_eq!(
        first.status.code(),
        Some(2),
        "not settled by 0.062 s: {}",
        stderr(&first)
    );
    let ckpt = o.join("checkpoint.json");
    let out = ok(fibresim(&[
        "settle",
        "--resume",
        s(&ckpt),
        "--t-end",
        "1",
        "--write",
        s(&bed),
    ]));
    let summary: serde_json::Value =
        serde_json::from_slice(&read_bytes(&o.join("summary.json"))).unwrap();
    assert_eq!(summary["steps"], 41000);
    let wall = summary["wall_s"].as_f64().unwrap();
    let rate: f64 = out
        .split(" fibre-steps/s")
        .next()
        .and_then(|h| h.rsplit('(').next())
        .and_then(|r| r.parse().ok())
        .unwrap_or_else(|| panic!("no rate in: {out}"));
    let own = 11000.0 * 3.0 / wall;
    assert!(
        (rate / own - 1.0).abs() < 0.01,
        "printed {rate}, this process {own}: {out}"
    );
    assert!(out.contains("(11000 of them in this run)"), "{out}");
    let ns = summary["ns_per_body_step"].as_f64().unwrap();
    assert!(
        (ns / (wall * 1e9 / (11000.0 * 3.0)) - 1.0).abs() < 1e-9,
        "{ns}"
    );
}

/// Without a terminal (stderr a pipe), `--progress=SECONDS` prints a plain
/// line (step, t, rate, time left) that often; `-q` prints none. The run is
/// far longer than the test watches it, so a fast machine cannot finish it
/// first: the lines are counted over one watched second after the first.
#[test]
fn progress_lines_without_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let scene = rest(dir.path(), "4000");
    let o = dir.path().join("o");
    let log = dir.path().join("stderr.txt");
    let mut child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args(["run", s(&scene), "--out", s(&o), "--progress=0.1"])
        .args(["--every", "10000"])
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let lines = |text: &str| text.lines().filter(|l| l.starts_with("step ")).count();
    let t0 = Instant::now();
    while lines(&std::fs::read_to_string(&log).unwrap()) == 0 {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "no progress line in a minute"
        );
        assert!(child.try_wait().unwrap().is_none(), "the run ended first");
        std::thread::sleep(Duration::from_millis(10));
    }
    let first = lines(&std::fs::read_to_string(&log).unwrap());
    let t1 = Instant::now();
    std::thread::sleep(Duration::from_secs(1));
    let text = std::fs::read_to_string(&log).unwrap();
    let watched = t1.elapsed().as_secs_f64();
    let _ = child.kill();
    let _ = child.wait();
    let during = lines(&text) - first;
    // One line per 0.1 s, give or take the two ends of the window.
    assert!(
        during as f64 >= watched / 0.1 - 2.0,
        "{during} lines in {watched} s: {text}"
    );
    for l in text.lines().filter(|l| l.starts_with("step ")) {
        assert!(
            l.contains("/4000000000  t = ") && l.contains("steps/s") && l.contains(" eta "),
            "{l}"
        );
    }
    let short = base(dir.path(), "0.01");
    let quiet = fibresim(&[
        "run",
        s(&short),
        "--out",
        s(&o),
        "--force",
        "-q",
        "--every",
        "1000",
    ]);
    assert!(quiet.status.success(), "{}", stderr(&quiet));
    assert!(!stderr(&quiet).contains("step "), "{}", stderr(&quiet));
}

/// A long run's rows reach the disk within seconds, not when 8 KiB have
/// accumulated: with a row every 2e6 steps and a run of 4e10 steps (longer
/// than any machine takes to reach the check), energy.csv holds the header
/// and a row while the run still goes on.
#[test]
fn rows_reach_the_disk_while_the_run_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let scene = rest(dir.path(), "40000");
    let o = dir.path().join("o");
    let mut child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args(["run", s(&scene), "--out", s(&o), "--every", "2000000", "-q"])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let energy = o.join("energy.csv");
    let on_disk = loop {
        let rows = std::fs::read_to_string(&energy).map_or(0, |t| t.lines().count());
        if rows >= 2 || t0.elapsed() > Duration::from_secs(20) {
            break rows;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    let _ = child.wait();
    assert!(running, "the run ended first: nothing was tested");
    assert!(on_disk >= 2, "no row on disk after {:?}", t0.elapsed());
}
