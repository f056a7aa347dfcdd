//! `summary.json` after `--resume`: `wall_s` is the resumed part,
//! `wall_total_s` every part (docs/guide.md, Outputs).

use crate::common;
use common::fibresim;

use serde_json::Value;
use std::path::Path;

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn wall_total_covers_every_part_of_a_resumed_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = fibresim(&[
        "run",
        "scenarios/torque_fibre.toml",
        "--dt",
        "1e-6",
        "--t-end",
        "0.02",
        "--checkpoint-every",
        "20000",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let first = summary(&out);
    let (w1, t1) = (
        first["wall_s"].as_f64().unwrap(),
        first["wall_total_s"].as_f64().unwrap(),
    );
    assert_eq!(w1, t1, "a run that was not resumed has one part");
    let ckpt = out.join("checkpoint.json");
    let c: Value = serde_json::from_str(&std::fs::read_to_string(&ckpt).unwrap()).unwrap();
    assert_eq!(c["step"], 20000);
    let o = fibresim(&[
        "run",
        "--resume",
        ckpt.to_str().unwrap(),
        "--t-end",
        "0.04",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let resumed = summary(&out);
    let (w2, t2) = (
        resumed["wall_s"].as_f64().unwrap(),
        resumed["wall_total_s"].as_f64().unwrap(),
    );
    assert_eq!(resumed["steps"], 40000);
    // The first part (up to its checkpoint at its last step) plus this one.
    let before = t2 - w2;
    assert!(
        before > 0.0 && before <= w1 * 1.05 + 1e-3,
        "first {w1} s, total {t2} s, resumed {w2} s"
    );
    // ns_per_body_step counts this part's steps only.
    let ns = resumed["ns_per_body_step"].as_f64().unwrap();
    assert!((ns / (w2 * 1e9 / 20000.0) - 1.0).abs() < 1e-9, "{ns}");
}
