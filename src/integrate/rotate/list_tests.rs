//! A rotator added to the list by one line (`midpoint_demo::MidpointDemo`,
//! compiled only in these unit tests) is run, listed, documented and
//! order-checked, with nothing else written for it.

use super::{rotator_markdown, rotator_table, RotatorKind};

const DEMO: &str = "midpoint-demo";

fn demo() -> RotatorKind {
    RotatorKind::from_name(DEMO).expect("the list line makes the name known")
}

#[test]
fn listed() {
    let k = demo();
    assert!(RotatorKind::ALL.contains(&k), "a scheme, so in ALL");
    assert!(RotatorKind::SELECTABLE.contains(&k));
    assert!(rotator_table().contains(DEMO));
    assert_eq!(k.to_string(), DEMO);
    let parsed: RotatorKind = serde_json::from_str(&format!("\"{DEMO}\"")).unwrap();
    assert_eq!(parsed, k);
}

#[test]
fn documented() {
    let info = demo().info();
    let row = rotator_markdown()
        .lines()
        .find(|l| l.contains(&format!("`{DEMO}`")))
        .map(str::to_string)
        .expect("a row of the rotator table");
    assert!(row.contains(info.torque_contract), "{row}");
    // `fibresim run --help` lists it with its title, from the same data.
    use clap::CommandFactory;
    let mut cmd = crate::cli::Cli::command();
    let help = cmd
        .find_subcommand_mut("run")
        .expect("run")
        .render_long_help()
        .to_string();
    assert!(help.contains(DEMO) && help.contains(info.title), "{help}");
    // A scenario may name it.
    let text = format!(
        "[simulation]\ndt = 1e-4\nt_end = 1e-3\nrotator = \"{DEMO}\"\n[[body]]\nshape = \"sphere\"\ndiameter = 1.0\ndensity = 1.0\nposition = [0.0, 0.0, 0.0]\n"
    );
    let scene = crate::scenario::parse_str(&text, "<demo>")
        .expect("the scenario key accepts every listed rotator");
    assert_eq!(scene.sim.rotator(), demo());
}

/// The order harness's smooth general load, cut to 100 steps, with the demo.
fn demo_scene() -> crate::scenario::Scene {
    let mut scene = crate::study::order::smooth_torque().scene;
    scene.sim = crate::scenario::SimParams::with_steps(1e-4, 100, demo(), None).unwrap();
    scene
}

#[test]
fn run() {
    let scene = demo_scene();
    let dir = tempfile::tempdir().unwrap();
    let opts = crate::run::RunOptions {
        out_dir: dir.path().to_path_buf(),
        ..Default::default()
    };
    let summary = crate::run::run(&scene, &opts).expect("the demo rotator runs");
    assert_eq!(summary.rotator, DEMO);
    assert_eq!(summary.steps, 100);
    let rows = std::fs::read_to_string(dir.path().join("orientation.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 101, "header and a row per step");
}

#[test]
fn order_checked() {
    use crate::study::order::{measure, reference, smooth_torque};
    let case = smooth_torque();
    let m = measure(&case, demo(), reference(&case));
    assert_eq!(m.window.len(), 4, "{m}");
    assert!(
        (m.order - f64::from(demo().info().order)).abs() < 0.2,
        "{m}"
    );
}
