//! The same scenario and flags give the same bytes whatever the thread
//! count: a dense scene with live contacts (384 fibres, above the parallel
//! threshold) run with `--threads 1`, `2`, `4` and with `RAYON_NUM_THREADS`
//! writes identical `energy.csv` and `summary.json` (less the wall times).

mod common;
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
        .filter(|l| !l.contains("wall_s") && !l.contains("ns_per_body_step"))
        .collect::<Vec<_>>()
        .join("\n");
    (energy, summary)
}

#[test]
fn output_bytes_do_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("packed.toml");
    std::fs::write(&scene, common::packed_scene(6, 8, 8, 6e-4)).unwrap();
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
}

#[test]
fn zero_threads_is_bad_input() {
    let o = common::fibresim(&["run", "scenarios/torque_fibre.toml", "--threads", "0", "-q"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads"));
}
