//! The same scenario and flags give the same bytes whatever the thread
//! count: a dense scene with live contacts (384 fibres, above the parallel
//! threshold) run with `--threads 1`, `2`, `4` and with `RAYON_NUM_THREADS`
//! writes identical `energy.csv` and `summary.json` (less the wall times).

use crate::common;
use std::path::Path;
use std::process::Command;

fn run(dir: &Path, scene: &Path, threads: Option<&str>, env: Option<&str>) -> (String, String) {
    let out = dir.join(format!("t{}{}", threads.unwrap_or("-"), env.unwrap_or("-")));
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_fibresim"));
    cmd.args([
        "run",
        scene.to_str().unwrap(),
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    if let Some(t) = threads {
        cmd.args(["--threads", t]);
    }
    cmd.env_remove("RAYON_NUM_THREADS");
    if let Some(e) = env {
        cmd.env("RAYON_NUM_THREADS", e);
    }
    let o = cmd.output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    let summary: String = std::fs::read_to_string(out.join("summary.json"))
        .unwrap()
        .lines()
        .filter(|l| !l.contains("\"wall_") && !l.contains("ns_per_body_step"))
        .collect::<Vec<_>>()
        .join("\n");
    (energy, summary)
}

#[test]
fn output_bytes_do_not_depend_on_the_thread_count() {
    same_bytes_with_any_thread_count(&common::packed_scene(6, 8, 8, 6e-4));
}

/// With damping (`[contact] restitution`): the damping forces and their
/// per-body loads (the ledger's `e_dissipated`) go through the parallel
/// stage's slots in the serial order too.
#[test]
fn damped_output_bytes_do_not_depend_on_the_thread_count() {
    let scene = common::packed_scene(6, 8, 8, 6e-4) + "[contact]\nrestitution = 0.5\n";
    let energy = same_bytes_with_any_thread_count(&scene);
    let last = energy.lines().last().unwrap();
    let dissipated: f64 = last.rsplit(',').next().unwrap().parse().unwrap();
    assert!(
        energy.lines().next().unwrap().ends_with(",e_dissipated") && dissipated > 0.0,
        "the damping dissipates: {last}"
    );
}

/// The staggered rotators keep per-body half-step state (`Rotator::Aux`),
/// which the pool reads and writes in each body's own slot.
#[test]
fn staggered_rotators_give_the_same_bytes_with_any_thread_count() {
    for rotator in ["pcdm-staggered", "cayley-cd"] {
        let scene = common::packed_scene(6, 8, 8, 3e-4).replacen(
            "[simulation]\n",
            &format!("[simulation]\nrotator = \"{rotator}\"\n"),
            1,
        );
        assert!(scene.contains(rotator));
        same_bytes_with_any_thread_count(&scene);
    }
}

/// A settled random bed (`scenarios/bed_1k.toml`, 100 steps): its
/// end-involved contacts include blended ties, whose points carry the
/// weight's couple (kept apart by the candidate loop), which the lattice above
/// has none of.
#[test]
fn bed_output_bytes_do_not_depend_on_the_thread_count() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let text = std::fs::read_to_string(root.join("bed_1k.toml"))
        .unwrap()
        .replace("t_end = 0.002", "t_end = 1e-4")
        .replace(
            "file = \"bed_1k_bodies.csv\"",
            &format!("file = {:?}", root.join("bed_1k_bodies.csv")),
        );
    assert!(text.contains("t_end = 1e-4") && text.contains("scenarios"));
    same_bytes_with_any_thread_count(&text);
}

/// A dense mixed bed (`common::packed_mixed_scene`: 256 fibres and 128
/// spheres): every kind pair's contacts go through the blocks in list
/// order too.
#[test]
fn mixed_bed_output_bytes_do_not_depend_on_the_thread_count() {
    same_bytes_with_any_thread_count(&common::packed_mixed_scene(6, 8, 8, 6e-4));
}

/// Runs `text` with 1, 2, 4 and `RAYON_NUM_THREADS=3` threads, asserts the
/// same bytes, and returns the one-thread `energy.csv`.
pub(crate) fn same_bytes_with_any_thread_count(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, text).unwrap();
    let one = run(dir.path(), &scene, Some("1"), None);
    let contacts: u64 = one
        .0
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').nth(11)?.parse().ok())
        .max()
        .unwrap_or(0);
    assert!(
        contacts > 50,
        "the scene has live contacts ({contacts} at most)"
    );
    for (threads, env) in [(Some("2"), None), (Some("4"), None), (None, Some("3"))] {
        let other = run(dir.path(), &scene, threads, env);
        assert!(
            one.0 == other.0,
            "energy.csv differs with {threads:?} {env:?}"
        );
        assert_eq!(
            one.1, other.1,
            "summary.json differs with {threads:?} {env:?}"
        );
    }
    one.0
}

#[test]
fn zero_threads_is_bad_input() {
    let o = common::fibresim(&["run", "scenarios/torque_fibre.toml", "--threads", "0", "-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads"));
}
