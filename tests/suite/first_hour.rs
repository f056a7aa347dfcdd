//! A new user's first hour: every problem of a scene in one
//! message, no silent rounding of t_end, warnings for implausible values,
//! tiny tilts kept, negative numbers as flag values, and the overlap ratio
//! the user guide (docs/guide.md) defines.

use crate::common;
use common::{fibresim, scene_str};

use std::f64::consts::PI;
use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn write(dir: &Path, text: &str) -> String {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// `run FILE ARGS -q` in a temporary folder.
fn run(text: &str, args: &[&str]) -> Output {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), text);
    let out = dir.path().join("o").display().to_string();
    let mut a = vec!["run", &scene];
    a.extend_from_slice(args);
    a.extend(["--out", &out, "-q"]);
    fibresim(&a)
}

const SIM: &str = "[simulation]\ndt = 1e-6\nt_end = 1e-3\n";
const BOX: &str =
    "[box]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nyoung = 5e7\npoisson = 0.23\n";
const FIBRE: &str = "[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.5, 0.5, 0.5]\n";

/// A box without `young` and `poisson`, and a body without its elastic
/// constants: one message names all four, each with its line, unit and an
/// example; nothing runs.
#[test]
fn every_missing_key_is_named_in_one_message() {
    let text = format!(
        "{SIM}{}{}",
        BOX.replace("young = 5e7\npoisson = 0.23\n", ""),
        FIBRE.replace("young = 5e7\npoisson = 0.35\n", "")
    );
    let o = run(&text, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("4 problems"), "{err}");
    for needle in [
        "scene.toml:4:2: box.young: missing: Young's modulus of the walls (Pa, > 0); add e.g. `young = 5e7`",
        "scene.toml:4:2: box.poisson: missing: Poisson's ratio of the walls (in (−1, 0.5))",
        "scene.toml:7:1: body[0].young: missing: Young's modulus (Pa, > 0)",
        "scene.toml:7:1: body[0].poisson: missing",
    ] {
        assert!(err.contains(needle), "lacks `{needle}`:\n{err}");
    }
    assert_eq!(err.matches("error:").count(), 1, "{err}");
}

/// Missing and invalid values of several tables, a misspelt key and a bad
/// torque expression are all reported together.
#[test]
fn invalid_values_and_misspelt_keys_are_collected() {
    let text = format!(
        "{SIM}{}{}torque = [\"sin(\", 0.0, 0.0]\n",
        BOX.replace("poisson = 0.23", "poisson = 0.7"),
        FIBRE
            .replace("density = 1100.0", "densty = 1100.0")
            .replace("diameter = 0.01", "diameter = -0.01")
    );
    let o = run(&text, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for needle in [
        "4 problems",
        "box.poisson: Poisson's ratio must lie in (-1, 0.5), got 0.7",
        "body[0].diameter: must be a finite number > 0, got -0.01",
        "scene.toml:13:1: body[0].densty: unknown key `densty`; did you mean `density`, density (kg/m³, > 0)? e.g. `density = 1100.0`",
        "body[0].torque[0]",
    ] {
        assert!(err.contains(needle), "lacks `{needle}`:\n{err}");
    }
}

/// No `[simulation]`: the table is named with the keys it needs, not
/// serde's `missing field` at line 1.
#[test]
fn a_missing_table_gets_its_required_keys() {
    let o = run(FIBRE, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("simulation: missing table [simulation]; add it:"),
        "{err}"
    );
    assert!(err.contains("dt = 1e-6   # time step δt (s, > 0)"), "{err}");
    assert!(err.contains("t_end = 0.1"), "{err}");
    assert!(!err.contains("missing field"), "{err}");
}

/// t_end must be a whole number of steps to rounding: 0.50000033 s at
/// δt = 1e-6 s (500000.33 steps) is refused with the two nearest whole
/// ones; decimals that are whole up to rounding (0.1 / 1e-7) are not.
#[test]
fn t_end_between_two_steps_is_refused() {
    let text = format!("{SIM}{FIBRE}").replace("t_end = 1e-3", "t_end = 0.50000033");
    let o = run(&text, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("simulation.t_end: t_end = 0.50000033 s is 500000.330 steps of dt = 1e-6 s, not a whole number; use t_end = 0.5 s (500000 steps) or 0.500001 s (500001 steps)"),
        "{err}"
    );
    let o = run(
        &format!("{SIM}{FIBRE}"),
        &["--dt", "1e-7", "--t-end", "0.00030000003"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("command line: --t-end:"),
        "{}",
        stderr(&o)
    );
    for (dt, t) in [("1e-7", "0.1"), ("3e-7", "0.0003"), ("1e-4", "0.07")] {
        let s = fibresim::scenario::SimParams::new(
            dt.parse().unwrap(),
            t.parse().unwrap(),
            fibresim::integrate::rotate::RotatorKind::Pcdm,
            None,
            "test",
            "--",
        )
        .unwrap_or_else(|e| panic!("{dt} {t}: {e}"));
        let want = (t.parse::<f64>().unwrap() / dt.parse::<f64>().unwrap()).round() as u64;
        assert_eq!(s.steps(), want);
    }
}

/// Values outside engineering practice warn (exit 0) and name the unit the
/// value was probably meant in; the shipped scenes warn about nothing.
#[test]
fn implausible_values_warn_with_the_likely_unit() {
    let text = format!("{SIM}{}{}", BOX.replace("young = 5e7", "young = 50"), FIBRE)
        .replace("density = 1100.0", "density = 1.1")
        .replace("diameter = 0.01", "diameter = 10")
        .replace("length = 0.025", "length = 25")
        .replace("max = [1.0, 1.0, 1.0]", "max = [100.0, 100.0, 100.0]")
        .replace(
            "position = [0.5, 0.5, 0.5]",
            "position = [50.0, 50.0, 50.0]",
        );
    let dir = tempfile::tempdir().unwrap();
    let o = fibresim(&["check", &write(dir.path(), &text)]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", stderr(&o));
    for needle in [
        "box.young: 50 Pa is below the range of engineering materials",
        "if you meant 50 MPa or 50 GPa, write 5e7 or 5e10",
        "body[0].density: 1.1 kg/m³ is below the range of solids",
        "if you meant 1.1 g/cm³, write 1.1e3",
        "body[0].diameter: 10 m is above the range of fibres",
        "if you meant 10 mm or 10 µm or 10 cm, write 1e-2 or 1e-5 or 1e-1",
        "body[0].length: 25 m is above the range of fibres",
    ] {
        assert!(out.contains(needle), "lacks `{needle}`:\n{out}");
    }
    // The same warnings go to stderr before a run.
    let o = run(&text, &["--t-end", "1e-5", "--allow-large-dt"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("warning: ") && stderr(&o).contains("box.young: 50 Pa"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut shipped: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .chain(std::fs::read_dir(root.join("stress")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    shipped.sort();
    assert!(shipped.len() >= 13);
    for p in shipped {
        let (_, w) = fibresim::scenario::load_with_warnings(&p).unwrap();
        assert!(w.is_empty(), "{}: {w:?}", p.display());
    }
}

/// `axis = [1, 1e-9, 0]` is a tilt of 1e-9 rad about z, not the identity.
#[test]
fn a_tiny_tilt_is_kept() {
    for (axis, tilt) in [("[1.0, 1e-9, 0.0]", 1e-9), ("[1.0, 0.0, 1e-12]", -1e-12)] {
        let s = scene_str(&format!(
            "[simulation]\ndt = 1e-3\nt_end = 1e-2\n[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.025\ndensity = 1100.0\nposition = [0.0, 0.0, 0.0]\naxis = {axis}\n"
        ));
        let q = s.initial[0].rot.q;
        // Closed form: a rotation by |tilt| about z (or −y), half angle tilt/2.
        let half = (tilt / 2.0f64).abs();
        let v = if tilt > 0.0 { q.z } else { -q.y };
        assert!((v - half).abs() < 1e-15 * half, "{axis}: {q}");
        assert!((q.w - 1.0).abs() < 1e-15, "{axis}: {q}");
    }
}

/// Negative numbers are taken as flag values, so the range check answers.
#[test]
fn negative_flag_values_reach_the_range_check() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), &format!("{SIM}{FIBRE}"));
    for (args, needle) in [
        (
            vec!["run", &scene, "--dt", "-1e-6"],
            "command line: --dt: must be a finite number > 0, got -1e-6",
        ),
        (
            vec!["run", &scene, "--t-end", "-1"],
            "command line: --t-end: must be a finite number > 0, got -1",
        ),
        (
            vec!["run", &scene, "--max-overlap", "-0.1"],
            "--max-overlap: must be a finite number > 0, got -0.1",
        ),
        (
            vec!["check", &scene, "--dt", "-1e-6"],
            "--dt: must be a finite number > 0",
        ),
        (
            vec!["compare", &scene, "--t-end", "-1"],
            "--t-end: must be a finite number > 0",
        ),
        (
            vec!["stress", "--factors", "-1,2", "-q"],
            "--factors: \"-1\" is not a number > 0",
        ),
    ] {
        let o = fibresim(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("tip:"), "{args:?}: {err}");
    }
}

/// `max_overlap_ratio` is the largest overlap over the smaller diameter of
/// the pair (docs/guide.md, Outputs). Two crossed fibres of diameters 10 and 4 mm
/// meeting head on through their centres (no torque): energy balance
/// `½ m* v² = (8/15) E* √R* δ^{5/2}` gives the deepest overlap.
#[test]
fn overlap_ratio_divides_by_the_smaller_diameter() {
    let (d1, d2, l, rho, e, nu, v) = (0.01, 0.004, 0.05, 1100.0, 5e7, 0.35, 0.1);
    let text = format!(
        "[simulation]\ndt = 1e-7\nt_end = 0.004\n\
         [[body]]\nshape = \"fibre\"\ndiameter = {d1}\nlength = {l}\ndensity = {rho}\nyoung = {e}\npoisson = {nu}\nposition = [0.0, 0.0, 0.0]\naxis = [1.0, 0.0, 0.0]\n\
         [[body]]\nshape = \"fibre\"\ndiameter = {d2}\nlength = {l}\ndensity = {rho}\nyoung = {e}\npoisson = {nu}\nposition = [0.0, 0.0, 0.0071]\naxis = [0.0, 1.0, 0.0]\nvelocity = [0.0, 0.0, -{v}]\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), &text);
    let out = dir.path().join("o");
    let o = fibresim(&["run", &scene, "-q", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mass = |d: f64| rho * PI * d * d * l / 4.0;
    let m_star = mass(d1) * mass(d2) / (mass(d1) + mass(d2));
    let e_star = 1.0 / (2.0 * (1.0 - nu * nu) / e);
    let r_star = 1.0 / (2.0 / d1 + 2.0 / d2);
    let depth = (15.0 * m_star * v * v / (16.0 * e_star * r_star.sqrt())).powf(0.4);
    let ratio = s["max_overlap_ratio"].as_f64().unwrap();
    assert!(
        (ratio / (depth / d2) - 1.0).abs() < 1e-3,
        "printed {ratio:e}, closed form δ/min(D) = {:e} (δ/max(D) = {:e})",
        depth / d2,
        depth / d1
    );
}
