//! The kernel replay tool (`src/contact/replay.rs`, feature `replay`): a
//! run that replays recorded kernel answers is the recorded run, bit for
//! bit, whichever classes it replays. Run: `cargo test --release --features
//! replay --test suite replay::` (CI does).

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fibresim");

/// `bed_1k` for 30 steps on one thread, with `FIBRESIM_REPLAY=spec`.
fn run(spec: &str, out: &Path) -> std::process::Output {
    run_to("3e-5", spec, out)
}

/// `bed_1k` to `t_end` on one thread, with `FIBRESIM_REPLAY=spec`.
fn run_to(t_end: &str, spec: &str, out: &Path) -> std::process::Output {
    let args = [
        "run",
        "scenarios/bed_1k.toml",
        "--t-end",
        t_end,
        "--threads",
        "1",
        "-q",
    ];
    Command::new(BIN)
        .args(args)
        .arg("--out")
        .arg(out)
        .env("FIBRESIM_REPLAY", spec)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("fibresim runs")
}

/// A recorded run of [`run`] in `dir` (its output in `dir/record`): the
/// recording's path.
fn recorded(dir: &Path) -> std::path::PathBuf {
    let rec = dir.join("rec");
    let record = run(&format!("record:{}", rec.display()), &dir.join("record"));
    assert!(record.status.success(), "{record:?}");
    rec
}

/// Reference: the recorded run itself. Every set of replayed classes gives
/// its `energy.csv` byte for byte; the recording holds calls of all four
/// classes (a settled bed has pairs passed over, kept memories, scans and
/// other dispatched pairs), so each replay takes some work away.
#[test]
fn a_replayed_run_is_the_recorded_run() {
    let dir = tempfile::tempdir().unwrap();
    let rec = recorded(dir.path());
    let energy = std::fs::read(dir.path().join("record/energy.csv")).unwrap();
    let calls = std::fs::read(rec.with_extension("calls")).unwrap();
    let mut per_class = [0usize; 4];
    for call in calls.chunks_exact(8) {
        per_class[usize::from(call[0])] += 1;
    }
    assert!(per_class.iter().all(|&n| n > 100), "{per_class:?}");
    // One mark per computation: the start's and 30 steps', in order.
    let marks: Vec<u64> = std::fs::read(rec.with_extension("computations"))
        .unwrap()
        .chunks_exact(8)
        .map(|m| u64::from_le_bytes(m.try_into().unwrap()))
        .collect();
    assert_eq!(marks.len(), 31);
    assert!(
        marks[0] == 0 && marks.windows(2).all(|w| w[0] < w[1]),
        "{marks:?}"
    );
    assert!(*marks.last().unwrap() < (calls.len() / 8) as u64);
    for (k, classes) in [
        "",
        "passed",
        "kept",
        "scan",
        "dispatch",
        "passed,kept,scan,dispatch",
    ]
    .into_iter()
    .enumerate()
    {
        let out = dir.path().join(format!("replay{k}"));
        let replay = run(&format!("replay:{}:{classes}", rec.display()), &out);
        assert!(replay.status.success(), "{classes}: {replay:?}");
        let replayed = std::fs::read(out.join("energy.csv")).unwrap();
        assert!(
            replayed == energy,
            "replaying {classes:?} changed energy.csv"
        );
    }
}

/// A malformed request is refused with exit code 2, naming what is wrong;
/// so is a replay of another run than the one recorded (longer or shorter).
#[test]
fn a_bad_request_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let rec = recorded(dir.path());
    let replay = format!("replay:{}:kept", rec.display());
    for (t_end, says) in [
        ("4e-5", "more calls than were recorded"),
        ("2e-5", "recorded calls"),
    ] {
        let out = run_to(t_end, &replay, &dir.path().join(t_end));
        assert_eq!(out.status.code(), Some(2), "{t_end}: {out:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{t_end}: {err}");
    }
    for (spec, says) in [
        ("replay:/nonexistent/rec:kept", "cannot read"),
        ("replay:x:fast", "unknown class"),
        ("play:x", "expected record:PATH"),
    ] {
        let out = run(spec, &dir.path().join("o"));
        assert_eq!(out.status.code(), Some(2), "{spec}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{spec}: {err}");
    }
}
