//! Every run-time guard (docs/physics.md §8) through the CLI: exit code 3, the named
//! diagnosis on stderr and in `summary.json` (`stopped`), and every row before
//! the stop intact. The quaternion-norm guard is unreachable with correct
//! rotators, so it is checked on a `World` directly.

use crate::common;
use common::fibresim;

use fibresim::integrate::rotate::Frozen;
use fibresim::integrate::step::{World, QUAT_NORM_TOLERANCE};
use fibresim::stop::{Diagnosis, StopKind};
use std::path::Path;

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn scenario(name: &str) -> String {
    read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(name),
    )
}

/// Run `scene` into a fresh folder with `--every 1`; expect exit 3 with
/// `diagnosis` on stderr. Returns the folder, `stopped` and stderr.
fn run_to_stop(
    dir: &Path,
    scene: &str,
    args: &[&str],
    diagnosis: &str,
) -> (std::path::PathBuf, serde_json::Value, String) {
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out");
    let mut a = vec!["run", path.to_str().unwrap(), "--every", "1", "-q"];
    a.extend_from_slice(args);
    a.extend(["--out", out.to_str().unwrap()]);
    let o = fibresim(&a);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains(&format!("run stopped: {diagnosis}")), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let s: serde_json::Value = serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    let stopped = s["stopped"].clone();
    assert!(
        stopped["kind"].as_str().unwrap().starts_with(diagnosis),
        "{stopped}"
    );
    assert_eq!(s["steps"], stopped["step"], "summary steps = the stop's");
    (out, stopped, err)
}

/// Rows 0..n-1 of `energy.csv`, one per step, whole (every field a number,
/// the last line terminated), as written before a guard stopped step `n`.
fn rows_before_stop(out: &Path, n: u64) -> Vec<Vec<f64>> {
    let text = read(&out.join("energy.csv"));
    assert!(text.ends_with('\n'), "last row torn");
    let mut lines = text.lines();
    let width = lines.next().unwrap().split(',').count();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let r: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(r.len(), width, "{l}");
            r
        })
        .collect();
    let steps: Vec<u64> = rows.iter().map(|r| r[0] as u64).collect();
    assert_eq!(
        steps,
        (0..n).collect::<Vec<_>>(),
        "one row per completed step"
    );
    rows
}

/// steel_drop with euler at 4e-6 s (12 steps per collision): the stale contact
/// torque pumps energy in until the full-budget error passes 10 %.
#[test]
fn energy_blow_up_exits_3_and_keeps_rows() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenario("stress/steel_drop.toml");
    let flags = ["--rotator", "euler", "--dt", "4e-6", "--allow-large-dt"];
    let (out, stop, _) = run_to_stop(
        dir.path(),
        &scene,
        &flags,
        "energy blow-up (full-budget energy error above the limit)",
    );
    assert_eq!(stop["quantity"], "energy error %");
    assert_eq!(stop["limit"], 10.0);
    assert!(stop["value"].as_f64().unwrap() > 10.0, "{stop}");
    let n = stop["step"].as_u64().unwrap();
    let rows = rows_before_stop(&out, n);
    // Column 8 = energy_error_full_pct: below the limit on every kept row.
    assert!(rows.iter().all(|r| r[8] <= 10.0), "{:?}", rows.last());
    // The kept rows are byte for byte those of a run that ends just before.
    let until = dir.path().join("until");
    let t = format!("{:e}", (n - 1) as f64 * 4e-6);
    let path = dir.path().join("scene.toml");
    let mut a = vec!["run", path.to_str().unwrap(), "--every", "1", "-q"];
    a.extend(flags);
    a.extend(["--t-end", &t, "--out", until.to_str().unwrap()]);
    let o = fibresim(&a);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        read(&out.join("energy.csv")),
        read(&until.join("energy.csv"))
    );
}

/// A torque that overflows (e^1000 at t = 1 ms) makes the spin infinite.
#[test]
fn non_finite_state_exits_3_and_keeps_rows() {
    let dir = tempfile::tempdir().unwrap();
    let scene = r#"
[simulation]
dt = 1e-3
t_end = 0.01
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
torque = ["0", "exp(1e6*t)", "0"]
"#;
    let (out, stop, err) = run_to_stop(
        dir.path(),
        scene,
        &["--rotator", "euler"],
        "non-finite state",
    );
    // euler takes the torque at t_n: finite at step 1 (t = 0), infinite at
    // step 2 (t = 1 ms), so the state of step 2 is not finite.
    assert_eq!(stop["step"], 2);
    assert_eq!(stop["body"], 0);
    assert!(stop["value"].is_null(), "NaN is written as null: {stop}");
    assert!(
        err.contains("body 0: state is NaN (must be finite)"),
        "{err}"
    );
    assert!(!err.contains("exceeds the limit"), "{err}");
    let rows = rows_before_stop(&out, 2);
    assert!(
        rows.iter().all(|r| r[4].is_finite()),
        "e_rot finite: {rows:?}"
    );
    let orient = read(&out.join("orientation.csv"));
    assert_eq!(orient.lines().count(), 1 + 2, "{orient}");
}

/// Test case 1's soft fibre at 50 m/s: exact Hertz theory gives δ ≈ 0.58 D,
/// stopped at 0.2 D (the library-level twin is in tests/suite/stress.rs).
#[test]
fn overlap_guard_exits_3_and_keeps_rows() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenario("stress/impact_50.toml")
        .replace("young = 2e11", "young = 5e7")
        .replace("density = 7800.0", "density = 1100.0")
        .replace("dt = 5e-7", "dt = 1e-7");
    let (out, stop, _) = run_to_stop(
        dir.path(),
        &scene,
        &["--rotator", "leapfrog"],
        "overlap beyond the Hertz range",
    );
    assert_eq!(stop["quantity"], "overlap / D");
    assert_eq!(stop["body"], 0);
    let v = stop["value"].as_f64().unwrap();
    assert!(v > 0.2 && v < 0.21, "{stop}");
    let rows = rows_before_stop(&out, stop["step"].as_u64().unwrap());
    // Last column = max_overlap_ratio: the kept rows are within the limit,
    // and the fibre was in contact before the stop.
    let last = rows.iter().map(|r| *r.last().unwrap());
    assert!(last.clone().all(|o| o <= 0.2));
    assert!(last.fold(0.0, f64::max) > 0.15);
}

/// The norm guard: a quaternion 1e-8 off unit norm (10x the tolerance) is
/// stopped after one `Frozen` step (which leaves `q` untouched); 1e-10 is not.
#[test]
fn quaternion_norm_drift_is_named() {
    let scene = common::scene_str(
        r#"
[simulation]
dt = 1e-4
t_end = 1e-3
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
axis = [0.6, 0.8, 0.0]
angular_velocity = [1.0, 2.0, 3.0]
"#,
    );
    for (off, stops) in [(1e-8, true), (1e-10, false)] {
        let mut w = World::new(&scene);
        w.states[0].rot.q *= 1.0 + off;
        match (w.step::<Frozen>(), stops) {
            (Err(d), true) => {
                assert_eq!(d.kind, StopKind::QuatNormDrift);
                assert_eq!(d.kind.to_string(), "quaternion norm drift");
                assert_eq!(d.quantity(), "| ||q|| - 1 |");
                assert_eq!((d.step, d.body, d.limit), (1, Some(0), QUAT_NORM_TOLERANCE));
                assert!((d.value - off).abs() < 1e-15, "{d}");
                assert!(d.to_string().contains("exceeds the limit 1e-9"));
            }
            (Ok(()), false) => {}
            (r, _) => panic!("norm off by {off}: {r:?}"),
        }
    }
}

fn diag(kind: StopKind, value: f64, limit: f64) -> Diagnosis {
    Diagnosis {
        kind,
        step: 7,
        t: 7e-3,
        body: Some(1),
        value,
        limit,
    }
}

/// Non-numeric stops say what is not finite instead of comparing with a limit.
#[test]
fn diagnosis_reads_well_for_non_finite_values() {
    assert_eq!(
        diag(StopKind::NonFiniteState, f64::NAN, f64::MAX).to_string(),
        "non-finite state (position, velocity, orientation or spin is NaN or infinite) at step 7 (t = 7e-3 s), body 1: state is NaN (must be finite)"
    );
    let mut energy = diag(StopKind::NonFiniteEnergy, f64::INFINITY, f64::MAX);
    energy.body = None;
    assert_eq!(
        energy.to_string(),
        "non-finite energy (the state has overflowed) at step 7 (t = 7e-3 s): energy is +inf (must be finite)"
    );
    assert_eq!(
        diag(StopKind::Overlap, 0.25, 0.2).to_string(),
        "overlap beyond the Hertz range (impact too fast or dt too large) at step 7 (t = 7e-3 s), body 1: overlap / D = 0.25 exceeds the limit 0.2"
    );
}
