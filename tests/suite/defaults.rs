//! What a scene gets without asking: the default rotator, `plot`'s default
//! column, the time-step advice with prescribed torques, and which bodies
//! `orientation.csv` holds.

use crate::common::{fibresim, ok};
use std::path::Path;

/// The rotator a scene that names none runs (docs/studies.md, "The default
/// rotator": the most accurate per unit of run time on contact scenes).
const DEFAULT: &str = "omelyan";

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap()
}

/// Ten fibres dropped in a 6 cm box for 0.03 s at δt = 4e-6 s (the
/// recommended δt is 6.06e-6 s): the first impacts on the floor.
fn drop_scene(dir: &Path) -> String {
    let toml = dir.join("drop.toml");
    ok(fibresim(&[
        "generate",
        "--n",
        "10",
        "--diameter",
        "0.01",
        "--length",
        "0.03",
        "--box",
        "0.06,0.06,0.06",
        "--t-end",
        "0.03",
        "--dt",
        "4e-6",
        "-o",
        toml.to_str().unwrap(),
        "-q",
    ]));
    toml.to_str().unwrap().to_string()
}

/// A scene without `rotator` runs the default, and `check`, `keys` and
/// `rotators` say which. On a contact scene the default's full-budget energy
/// error is at least 100x below `pcdm`'s (the previous default, whose
/// start-of-step contact torque is first order) at the same step: 3.8e-5 %
/// against 1.2e-2 % when this was written.
#[test]
fn a_scene_without_a_rotator_runs_the_default() {
    let dir = tempfile::tempdir().unwrap();
    let scene = drop_scene(dir.path());
    let check = ok(fibresim(&["check", &scene]));
    assert!(
        check
            .lines()
            .next()
            .unwrap()
            .ends_with(&format!("rotator {DEFAULT}")),
        "{check}"
    );
    let keys = ok(fibresim(&["keys"]));
    let line = keys
        .lines()
        .find(|l| l.trim_start().starts_with("rotator"))
        .expect("keys lists simulation.rotator");
    assert!(line.contains(&format!("default: `{DEFAULT}`")), "{line}");
    let rotators = ok(fibresim(&["rotators"]));
    assert!(
        rotators.contains(&format!("\ndefault: {DEFAULT} ")),
        "{rotators}"
    );

    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let mut a = vec!["run", &scene, "-q", "--out", out.to_str().unwrap()];
        a.extend(extra);
        ok(fibresim(&a));
        json(&out.join("summary.json"))
    };
    let default = run("default", &[]);
    let pcdm = run("pcdm", &["--rotator", "pcdm"]);
    assert_eq!(default["rotator"], DEFAULT);
    let err = |s: &serde_json::Value| s["energy_error_full_max_pct"].as_f64().unwrap();
    assert!(
        err(&default) * 100.0 < err(&pcdm),
        "default {} % against pcdm {} %",
        err(&default),
        err(&pcdm)
    );
}

/// The paper's scenes name their rotator, so a change of the default
/// leaves their results alone.
#[test]
fn the_papers_scenes_name_their_rotator() {
    for f in [
        "single_fibre.toml",
        "single_fibre_ar3.toml",
        "nine_fibres.toml",
        "torque_sphere.toml",
        "torque_fibre.toml",
    ] {
        let p = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenarios")
            .join(f);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(
            text.lines().any(|l| l.trim() == "rotator = \"pcdm\""),
            "{f} names no rotator"
        );
    }
}

/// `fibresim plot energy.csv` draws the full-budget error (the conserved
/// quantity), not Eq. 65 without the elastic energy; the figure is named
/// by the column it draws.
#[test]
fn plot_of_an_energy_file_draws_the_full_budget_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    ok(fibresim(&[
        "run",
        "scenarios/nine_fibres.toml",
        "--t-end",
        "1e-3",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]));
    let energy = out.join("energy.csv");
    let printed = ok(fibresim(&["plot", energy.to_str().unwrap()]));
    assert_eq!(
        printed.trim(),
        out.join("energy_energy_error_full_pct.png")
            .to_str()
            .unwrap()
    );
    assert!(out.join("energy_energy_error_full_pct.png").is_file());
}

/// 50 fibres in the lower 10 cm of a 15 cm box and one more above them
/// with a prescribed torque `torque` (by its three components).
fn with_torque_body(dir: &Path, name: &str, torque: &str, output: &str) -> String {
    let toml = dir.join(format!("{name}.toml"));
    ok(fibresim(&[
        "generate",
        "--n",
        "50",
        "--diameter",
        "0.01",
        "--length",
        "0.03",
        "--box",
        "0.1,0.1,0.15",
        "--region",
        "0,0,0,0.1,0.1,0.1",
        "--t-end",
        "2e-3",
        "-o",
        toml.to_str().unwrap(),
        "-q",
    ]));
    // The body file's ids from 1: the [[body]] table is id 0.
    let bodies = dir.join(format!("{name}_bodies.csv"));
    let text = std::fs::read_to_string(&bodies).unwrap();
    let mut lines = text.lines();
    let mut shifted = format!("{}\n", lines.next().unwrap());
    for l in lines {
        let (id, rest) = l.split_once(',').unwrap();
        shifted += &format!("{},{rest}\n", id.parse::<u64>().unwrap() + 1);
    }
    std::fs::write(&bodies, shifted).unwrap();
    let mut scene = std::fs::read_to_string(&toml).unwrap();
    scene += &format!(
        "{output}\n[[body]]\nname = \"spinner\"\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.03\nmaterial = \"fibre\"\nposition = [0.05, 0.05, 0.13]\ntorque = [{torque}]\n"
    );
    std::fs::write(&toml, scene).unwrap();
    toml.to_str().unwrap().to_string()
}

/// One body with a prescribed torque leaves the contact advice and the
/// large-δt refusal on for the other 50 fibres; the torque body is covered
/// by a line of its own; a zero torque does no work, so its body's contacts
/// are bounded as any other's.
#[test]
fn one_torque_body_keeps_the_contact_advice_for_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let torqued = with_torque_body(dir.path(), "torqued", r#""1e-6", "0", "0""#, "");
    let check = ok(fibresim(&["check", &torqued]));
    assert!(check.contains("\nrecommended dt <= "), "{check}");
    assert!(!check.contains("no contacts to resolve"), "{check}");
    assert!(
        check.contains(
            "prescribed torques on 1 body: its rotation is limited by the rotator's accuracy only"
        ),
        "{check}"
    );
    assert!(
        check.contains("warning: 1 body with a prescribed torque"),
        "{check}"
    );
    // 2e-4 s is not even one step per collision (t_Hertz ~ 3e-4 s).
    let o = fibresim(&[
        "run",
        &torqued,
        "--dt",
        "2e-4",
        "-q",
        "--out",
        dir.path().join("big").to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("leaves fewer than 5 steps"), "{err}");

    // The zero torque's body is bounded: it falls from the highest point,
    // so the advice (a faster impact) recommends a shorter step than
    // without it.
    let zero = with_torque_body(dir.path(), "zero", r#""0", "0", "0""#, "");
    let check_zero = ok(fibresim(&["check", &zero]));
    let rec = |text: &str| -> f64 {
        let l = text
            .lines()
            .find(|l| l.starts_with("recommended dt <= "))
            .unwrap();
        l["recommended dt <= ".len()..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(
        rec(&check_zero) < rec(&check),
        "{} vs {}",
        rec(&check_zero),
        rec(&check)
    );
    assert!(
        !check_zero.contains("warning: 1 body with a prescribed torque"),
        "{check_zero}"
    );
}

/// Distinct bodies of an `orientation.csv`.
fn bodies_in(orientation: &Path) -> Vec<u64> {
    let text = std::fs::read_to_string(orientation).unwrap();
    let mut ids: Vec<u64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
        .collect();
    ids.sort_unstable();
    ids.dedup();
    ids
}

/// `orientation.csv` holds the bodies that need it (a prescribed torque),
/// every body only when `[output] orientation = "all"` asks, and is not
/// written for a scene with neither torques nor a closed form.
#[test]
fn orientation_rows_only_for_the_bodies_that_need_them() {
    let dir = tempfile::tempdir().unwrap();
    let run = |scene: &str, name: &str| {
        let out = dir.path().join(name);
        ok(fibresim(&[
            "run",
            scene,
            "--t-end",
            "2e-4",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ]));
        out
    };
    let needed = with_torque_body(dir.path(), "needed", r#""0", "0", "1e-6""#, "");
    let out = run(&needed, "needed");
    assert_eq!(bodies_in(&out.join("orientation.csv")), vec![0]);

    let all = with_torque_body(
        dir.path(),
        "all",
        r#""0", "0", "1e-6""#,
        "\n[output]\norientation = \"all\"\n",
    );
    let out = run(&all, "all");
    assert_eq!(
        bodies_in(&out.join("orientation.csv")),
        (0..=50).collect::<Vec<_>>()
    );

    let out = run("scenarios/nine_fibres.toml", "nine");
    assert!(out.join("energy.csv").is_file());
    assert!(!out.join("orientation.csv").exists(), "no body needs one");

    let bad = dir.path().join("bad.toml");
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/torque_fibre.toml"),
    )
    .unwrap();
    std::fs::write(&bad, format!("{text}\n[output]\norientation = \"every\"\n")).unwrap();
    let o = fibresim(&["check", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("output.orientation") && err.contains("choose one of needed, all"),
        "{err}"
    );
}
