//! `fibresim settle`: the stop at the kinetic-energy threshold, the settled
//! bed it writes (an elastic scenario whose body file holds the final
//! states to the bit), and its refusals.

use crate::common;
use common::fibresim;

const SCENE: &str = "[simulation]\ndt = 1e-5\nt_end = 0.01\n[world]\ngravity = [0.0, 0.0, -9.81]\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.2, 0.2, 0.2]\nyoung = 5e7\npoisson = 0.35\n[material.pa]\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\n[contact]\nrestitution = 0.3\n";

fn fibre(x: f64, z: f64) -> String {
    format!("[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.03\nmaterial = \"pa\"\nposition = [{x}, 0.1, {z}]\naxis = [1.0, 0.2, 0.1]\nvelocity = [0.1, 0.0, 0.0]\n")
}

fn column(row: &str, k: usize) -> f64 {
    row.split(',').nth(k).unwrap().parse().unwrap()
}

/// `fibresim settle scene` under a generous threshold (1 J per fibre),
/// tested every 50 steps, writing `dir/settled.toml` with outputs in
/// `dir/out`, and `extra` flags.
fn settle_generously(
    dir: &std::path::Path,
    scene: &std::path::Path,
    extra: &[&str],
) -> std::process::Output {
    let (write, out) = (dir.join("settled.toml"), dir.join("out"));
    let mut args = vec!["settle", scene.to_str().unwrap(), "--ke-per-body", "1"];
    args.extend(["--check-every", "50", "--write", write.to_str().unwrap()]);
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(extra);
    fibresim(&args)
}

/// Under gravity, low kinetic energy is not settled: two fibres released
/// in the air under a threshold they are far below (1 J) are falling, not
/// resting, and the bed does not settle before it lands (0.01 s of a fall
/// of about 0.1 s).
#[test]
fn a_bed_released_in_the_air_is_not_settled() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    let text = format!("{SCENE}{}{}", fibre(0.05, 0.05), fibre(0.12, 0.04));
    std::fs::write(&scene, text).unwrap();
    let o = settle_generously(dir.path(), &scene, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("did not settle by t = 0.01 s"), "{err}");
}

/// Settled (a generous threshold, tested every 50 steps, no gravity so
/// that no body need rest on another): the run ends at the first test, and
/// the written bed is elastic, loads, and holds the run's final states bit
/// for bit (summary.json's `final`).
#[test]
fn settle_writes_the_final_states_as_an_elastic_bed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        format!(
            "{}{}{}",
            SCENE.replace("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]"),
            fibre(0.05, 0.05),
            fibre(0.12, 0.02)
        ),
    )
    .unwrap();
    let (write, out) = (dir.path().join("settled.toml"), dir.path().join("out"));
    let o = settle_generously(dir.path(), &scene, &["--write-dt", "1e-6"]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("settled after 50 steps"), "{stdout}");
    let text = std::fs::read_to_string(&write).unwrap();
    assert!(
        !text.contains("[contact]") && text.contains("start_overlap_ratio = 0.01"),
        "{text}"
    );
    assert!(text.contains("file = \"settled_bodies.csv\""), "{text}");
    let bed = fibresim::scenario::load(&write).expect("the settled bed loads");
    assert!(bed.damping.is_none() && bed.bodies.len() == 2 && bed.sim.dt() == 1e-6);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["settled"], true);
    assert_eq!(summary["steps"], 50);
    let rows = std::fs::read_to_string(dir.path().join("settled_bodies.csv")).unwrap();
    for (row, fin) in rows
        .lines()
        .skip(1)
        .zip(summary["final"].as_array().unwrap())
    {
        for k in 0..3 {
            assert_eq!(column(row, 1 + k), fin["x"][k].as_f64().unwrap());
            assert_eq!(column(row, 8 + k), fin["v"][k].as_f64().unwrap());
            assert_eq!(column(row, 11 + k), fin["omega_body"][k].as_f64().unwrap());
        }
    }
    // The dissipated energy is in the energy file, and the budget closes
    // within the run's full-budget error.
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    assert!(energy.lines().next().unwrap().ends_with(",e_dissipated"));
}

/// Nothing dissipates: refused. Not settled by t_end: exit 2, files written.
#[test]
fn settle_refuses_elastic_scenes_and_reports_an_unsettled_bed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.toml");
    let write = dir.path().join("w.toml");
    let args = |s: &str| {
        vec![
            "settle".to_string(),
            s.to_string(),
            "--write".into(),
            write.display().to_string(),
            "-q".into(),
            "--out".into(),
            dir.path().join("o").display().to_string(),
        ]
    };
    std::fs::write(
        &scene,
        format!(
            "{}{}",
            SCENE.replace("[contact]\nrestitution = 0.3\n", ""),
            fibre(0.05, 0.05)
        ),
    )
    .unwrap();
    let a = args(scene.to_str().unwrap());
    let o = fibresim(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("nothing dissipates"));
    std::fs::write(&scene, format!("{SCENE}{}", fibre(0.05, 0.05))).unwrap();
    let mut a = args(scene.to_str().unwrap());
    a.extend([
        "--ke-per-body".into(),
        "1e-30".into(),
        "--t-end".into(),
        "1e-3".into(),
    ]);
    let o = fibresim(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("did not settle by t = 1e-3 s"), "{err}");
    assert!(std::fs::read_to_string(&write)
        .unwrap()
        .contains("NOT settled"));
}

/// A settled bed keeps its resting wall contacts: a fibre 1e-5 m into the
/// floor (0.1 % of D) loads when `guards.start_overlap_ratio` allows it, and
/// is refused, naming the wall, when it does not.
#[test]
fn resting_wall_contacts_load_within_the_start_overlap() {
    let scene = |guards: &str| {
        format!(
            "[simulation]\ndt = 1e-6\nt_end = 1e-5\n[world]\ngravity = [0.0, 0.0, -9.81]\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [0.1, 0.1, 0.1]\nyoung = 5e7\npoisson = 0.35\n[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.03\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.05, 0.05, 0.00499]\n{guards}"
        )
    };
    let ok =
        fibresim::scenario::parse_str(&scene("[guards]\nstart_overlap_ratio = 0.01\n"), "bed.toml");
    assert!(ok.is_ok(), "{:?}", ok.err());
    let refused = fibresim::scenario::parse_str(&scene(""), "bed.toml")
        .map(|_| ())
        .expect_err("an overlap with the floor is refused by default")
        .to_string();
    assert!(
        refused.contains("box") || refused.contains("wall"),
        "{refused}"
    );
}
