//! The user guide's Outputs table (docs/guide.md) names (with a unit) every
//! column of `energy.csv` and `orientation.csv` and every key of
//! `summary.json`.

use crate::common;
use common::fibresim;

use std::collections::BTreeSet;
use std::path::Path;

/// Every backticked name in the user guide's Outputs table (first and last
/// column).
fn documented() -> BTreeSet<String> {
    let guide =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/guide.md"))
            .unwrap();
    let section = guide
        .split("\n## Outputs\n")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("docs/guide.md has an Outputs section");
    let mut names = BTreeSet::new();
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.split(" | ").collect();
        assert!(cells.len() >= 4, "{line}");
        assert!(!cells[2].trim().is_empty(), "no unit: {line}");
        // The first column's names; `stopped` and `final` name their fields
        // (with units) in the last.
        for cell in [cells[0], cells[cells.len() - 1]] {
            for name in cell.split('`').skip(1).step_by(2) {
                names.insert(name.to_string());
            }
        }
    }
    names
}

fn keys(v: &serde_json::Value, out: &mut BTreeSet<String>) {
    if let Some(o) = v.as_object() {
        for (k, x) in o {
            out.insert(k.clone());
            keys(x, out);
        }
    } else if let Some(a) = v.as_array() {
        a.iter().for_each(|x| keys(x, out));
    }
}

#[test]
fn every_written_column_and_key_has_a_unit_in_the_guide() {
    let doc = documented();
    let dir = tempfile::tempdir().unwrap();
    let mut written = BTreeSet::new();
    for (scene, args) in [
        ("scenarios/torque_sphere.toml", vec!["--t-end", "0.01"]),
        ("scenarios/single_fibre.toml", vec!["--t-end", "1e-4"]),
        // A stop, so that `stopped` carries its fields.
        (
            "scenarios/stress/spin.toml",
            vec!["--rotator", "euler", "--allow-large-dt"],
        ),
    ] {
        let out = dir.path().join(scene.replace('/', "_"));
        let mut a = vec!["run", scene, "-q", "--out", out.to_str().unwrap()];
        a.extend(args);
        let o = fibresim(&a);
        assert!(
            matches!(o.status.code(), Some(0 | 3)),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        for csv in ["energy.csv", "orientation.csv"] {
            if let Ok(text) = std::fs::read_to_string(out.join(csv)) {
                written.extend(text.lines().next().unwrap().split(',').map(str::to_string));
            }
        }
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        keys(&s, &mut written);
    }
    assert!(written.contains("err_rad") && written.contains("max_overlap_ratio"));
    assert!(
        written.contains("limit"),
        "the stop's fields are among them"
    );
    let missing: Vec<&String> = written.iter().filter(|k| !doc.contains(*k)).collect();
    assert!(
        missing.is_empty(),
        "not in docs/guide.md's Outputs table: {missing:?}"
    );
}
