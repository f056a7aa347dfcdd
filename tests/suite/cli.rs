//! The `fibresim` binary: output files, cadence, determinism, errors and exit codes.

use crate::common;
use common::fibresim;

use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn write_scene(dir: &Path, text: &str) -> String {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

const FIBRE: &str = r#"
[simulation]
dt = 1e-4
t_end = 0.01
[[body]]
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
position = [0.0, 0.0, 0.0]
angular_velocity = [10.0, 5.0, 0.0]
torque = ["1e-6", "0", "0"]
"#;

#[test]
fn run_writes_the_documented_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tc3");
    let o = fibresim(&[
        "run",
        "scenarios/torque_sphere.toml",
        "--t-end",
        "0.01",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let energy = read(&out.join("energy.csv"));
    assert!(energy.starts_with(
        "step,t,e_grav,e_trans,e_rot,e_elastic,e_total,energy_error_pct,energy_error_full_pct,energy_error_window_max_pct,energy_error_full_window_max_pct\n"
    ));
    assert_eq!(
        energy.lines().count(),
        1 + 101,
        "header + rows for steps 0..=100 (every = 1)"
    );
    let orient = read(&out.join("orientation.csv"));
    assert!(orient
        .starts_with("step,t,body,qw,qx,qy,qz,ax,ay,az,ref_qw,ref_qx,ref_qy,ref_qz,err_rad\n"));
    let last = orient.lines().last().unwrap();
    assert!(last.starts_with("100,0.01,0,"), "{last}");
    let s: serde_json::Value = serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    for key in [
        "rotator",
        "dt",
        "steps",
        "t_end",
        "wall_s",
        "ns_per_body_step",
        "energy_error_max_pct",
        "energy_error_final_pct",
        "final",
    ] {
        assert!(s.get(key).is_some(), "summary lacks {key}");
    }
    assert_eq!(s["rotator"], "pcdm");
    assert_eq!(s["steps"], 100);
    let f = &s["final"][0];
    assert_eq!(f["q"].as_array().unwrap().len(), 4);
    assert!(f["omega_body"].is_array() && f["x"].is_array() && f["v"].is_array());
    assert!(s["stopped"].is_null());
}

#[test]
fn cadence_and_window_maximum() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), FIBRE);
    let out = dir.path().join("o");
    let o = fibresim(&[
        "run",
        &scene,
        "--every",
        "7",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let energy = read(&out.join("energy.csv"));
    let steps: Vec<u64> = energy
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    // Rows at 0, 7, 14, ..., 98 and the final step 100.
    let mut want: Vec<u64> = (0..=100).step_by(7).collect();
    want.push(100);
    assert_eq!(steps, want);
    // The torque does work from a spinning start: errors are defined and every
    // row's window maximum is at least its own error.
    for l in energy.lines().skip(2) {
        let c: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(c[9] >= c[7], "{l}");
    }
    // Default cadence: 1e5 steps -> at most 2e4 rows.
    let out2 = dir.path().join("o2");
    let o = fibresim(&[
        "run",
        &scene,
        "--dt",
        "1e-7",
        "--out",
        out2.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read(&out2.join("energy.csv")).lines().count() - 1;
    assert!(rows <= 20_001 && rows > 10_000, "{rows}");
}

#[test]
fn same_inputs_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), FIBRE);
    let mut outs = vec![];
    for name in ["a", "b"] {
        let out = dir.path().join(name);
        let o = fibresim(&[
            "run",
            &scene,
            "--rotator",
            "leapfrog",
            "--out",
            out.to_str().unwrap(),
            "-q",
        ]);
        assert!(o.status.success());
        outs.push((
            read(&out.join("energy.csv")),
            read(&out.join("orientation.csv")),
        ));
    }
    assert_eq!(outs[0], outs[1]);
}

#[test]
fn unstable_run_exits_3_and_keeps_rows() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        &FIBRE
            .replace("[10.0, 5.0, 0.0]", "[0.0, 0.0, 0.0]")
            .replace("\"1e-6\"", "\"1e-3\""),
    );
    let out = dir.path().join("o");
    // Constant torque spins the fibre up until |w| dt / 2 reaches pi/2.
    let o = fibresim(&[
        "run",
        &scene,
        "--rotator",
        "scalar",
        "--dt",
        "1e-3",
        "--t-end",
        "10",
        "--every",
        "1",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("scalar-factor singularity"),
        "{}",
        stderr(&o)
    );
    let s: serde_json::Value = serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
    let stop = &s["stopped"];
    assert_eq!(stop["quantity"], "|omega| dt / 2");
    let step = stop["step"].as_u64().unwrap();
    let rows = read(&out.join("energy.csv")).lines().count() - 1;
    assert_eq!(
        rows as u64,
        step + 1,
        "one row per completed step, 0..=step"
    );
}

fn expect_bad_input(text: Option<&str>, args: &[&str], needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let scene = text.map(|t| write_scene(dir.path(), t));
    let out = dir.path().join("o").display().to_string();
    let mut a = vec!["run"];
    if let Some(s) = &scene {
        a.push(s);
    }
    a.extend_from_slice(args);
    if !args.contains(&"--out") {
        a.extend(["--out", &out]);
    }
    a.push("-q");
    let o = fibresim(&a);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "message lacks `{n}`: {err}");
    }
}

#[test]
fn bad_input_is_named_and_exits_2() {
    expect_bad_input(
        Some("[simulation\ndt = 1"),
        &[],
        &["scene.toml:1:12: TOML: invalid table header"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("density", "densty")),
        &[],
        &["scene.toml:9:1: body[0].densty: unknown key `densty`; did you mean `density`"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("diameter = 0.01", "diameter = \"big\"")),
        &[],
        &["scene.toml", "invalid type"],
    );
    // Value errors give file:line:column of the key, the key and the fix.
    expect_bad_input(
        Some(&FIBRE.replace("diameter = 0.01", "diameter = -0.01")),
        &[],
        &["scene.toml:7:1: body[0].diameter: must be a finite number > 0, got -0.01; give a positive value"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("diameter = 0.01", "diameter = nan")),
        &[],
        &["scene.toml:7:1: body[0].diameter: must be a finite number > 0, got NaN; give a positive value"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("length = 0.025", "length = 0.0")),
        &[],
        &["scene.toml:8:1: body[0].length: must be a finite number > 0, got 0; give a positive value"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("density = 1100.0", "density = -1100.0")),
        &[],
        &["scene.toml:9:1: body[0].density: must be a finite number > 0, got -1100"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("dt = 1e-4", "dt = 1.0")),
        &[],
        &[
            "scene.toml:3:1: simulation.dt",
            "larger than t_end",
            "choose dt <= t_end",
        ],
    );
    expect_bad_input(
        Some(&FIBRE.replace("\"1e-6\"", "\"1e-6*x\"")),
        &[],
        &["scene.toml:12:11: body[0].torque[0]", "unknown name `x`"],
    );
    // A value from a [material] table is located there.
    expect_bad_input(
        Some(
            &(FIBRE.replace("density = 1100.0", "material = \"m\"")
                + "[material.m]\ndensity = 0.0\n"),
        ),
        &[],
        &["scene.toml:14:1: material.m.density: must be a finite number > 0, got 0"],
    );
    expect_bad_input(
        Some("[simulation]\ndt = 1e-4\nt_end = 1.0\n"),
        &[],
        &["no bodies"],
    );
    expect_bad_input(
        Some(FIBRE),
        &["--rotator", "pcdm", "--dt=-1"],
        &["command line: --dt: must be a finite number > 0, got -1; give a positive value"],
    );
    expect_bad_input(
        Some(FIBRE),
        &["--t-end", "0"],
        &["command line: --t-end: must be a finite number > 0, got 0"],
    );
    expect_bad_input(
        Some(&FIBRE.replace("[simulation]", "[simulation]\nrotator = \"rk5\"")),
        &[],
        &["simulation.rotator", "unknown rotator `rk5`"],
    );
    expect_bad_input(
        None,
        &["--out", "/proc/nope/out"],
        &[
            "--out",
            "cannot create the output folder",
            "choose another folder",
        ],
    );
    // Bodies outside the box, and overlapping at the start.
    let boxed = |bodies: &str| {
        format!(
            "[simulation]\ndt = 1e-6\nt_end = 0.001\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.23\n{bodies}"
        )
    };
    let fibre = |x: f64, axis: &str| {
        format!("[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [{x}, 0.5, 0.5]\naxis = {axis}\n")
    };
    expect_bad_input(
        Some(&boxed(&fibre(0.005, "[1.0, 0.0, 0.0]"))),
        &[],
        &["body[0].position", "does not fit inside the box"],
    );
    expect_bad_input(
        Some(&boxed(
            &(fibre(0.5, "[1.0, 0.0, 0.0]") + &fibre(0.52, "[1.0, 0.0, 0.0]")),
        )),
        &[],
        &[
            "body[0].position",
            "overlaps body[1]",
            "move the bodies apart",
        ],
    );
    // A dt that does not resolve a collision at all is refused (see `fibresim check`).
    expect_bad_input(
        Some(
            &boxed(&fibre(0.5, "[1.0, 0.0, 0.0]"))
                .replace("dt = 1e-6", "dt = 1e-3")
                .replace("t_end = 0.001", "t_end = 0.01")
                .replace("[box]", "[world]\ngravity = [0.0, 0.0, -9.81]\n[box]"),
        ),
        &[],
        &["simulation.dt", "fewer than 5 steps", "--allow-large-dt"],
    );
    let o = fibresim(&["run", "does/not/exist.toml", "-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("does/not/exist.toml: <SCENARIO>: cannot read the scenario file")
            && stderr(&o).contains("give the path of a scenario TOML file"),
        "{}",
        stderr(&o)
    );
}

/// An output folder that exists but cannot take files is bad input naming
/// `--out` (exit 2), even for root: /proc/self takes no new files, and a
/// regular file is no folder.
#[test]
fn unwritable_output_folder_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a_file");
    std::fs::write(&file, "").unwrap();
    for (out, needle) in [
        (
            "/proc/self".to_string(),
            "/proc/self/energy.csv: --out: cannot write the output file",
        ),
        (
            file.display().to_string(),
            "--out: cannot create the output folder",
        ),
    ] {
        let o = fibresim(&[
            "run",
            "scenarios/torque_sphere.toml",
            "--t-end",
            "0.01",
            "-q",
            "--out",
            &out,
        ]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{}", stderr(&o));
        assert!(stderr(&o).contains("folder") && stderr(&o).contains("with --out DIR"));
    }
}

/// A write that fails mid-run (energy.csv on /dev/full: created fine, every
/// write fails with ENOSPC) stays an I/O error, exit 1.
#[test]
fn write_failure_mid_run_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.path().join("energy.csv")).unwrap();
    let o = fibresim(&[
        "run",
        "scenarios/torque_sphere.toml",
        "--every",
        "1",
        "-q",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot write") && stderr(&o).contains("energy.csv"));
    assert!(!stderr(&o).contains("--out"), "{}", stderr(&o));
}

/// The long help carries the exit-code table, 130 included; -h a summary.
#[test]
fn help_lists_the_exit_codes() {
    let long = fibresim(&["--help"]);
    let text = String::from_utf8_lossy(&long.stdout);
    for needle in [
        "Exit codes:",
        "  2    bad input",
        "  3    the run was stopped",
        "  130  interrupted by Ctrl-C",
    ] {
        assert!(text.contains(needle), "--help lacks `{needle}`:\n{text}");
    }
    let short = String::from_utf8_lossy(&fibresim(&["-h"]).stdout).into_owned();
    assert!(short.contains("130 interrupted"), "{short}");
}

/// docs/rotators.md's rotator table is `fibresim rotators --markdown`,
/// generated from each rotator's `RotatorInfo`.
#[test]
fn docs_rotator_table_is_generated() {
    let o = fibresim(&["rotators", "--markdown"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8(o.stdout).unwrap();
    let page = read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/rotators.md"));
    let inside = page
        .split("<!-- BEGIN rotators -->\n")
        .nth(1)
        .and_then(|s| s.split("<!-- END rotators -->").next())
        .expect("docs/rotators.md has the rotator table markers");
    assert_eq!(
        inside, table,
        "docs/rotators.md's rotator table is stale: paste `fibresim rotators --markdown`"
    );
    for k in fibresim::integrate::rotate::RotatorKind::SELECTABLE {
        assert!(table.contains(&format!("`{}`", k.name())));
    }
}

/// A reader that closes the pipe early (`fibresim rotators | head`) ends the
/// listing quietly: no panic, exit 0.
#[test]
fn closed_stdout_is_not_a_panic() {
    use std::process::{Command, Stdio};
    for args in [&["rotators"][..], &["check", "scenarios/nine_fibres.toml"]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_fibresim"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader is gone before a byte is written
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}
