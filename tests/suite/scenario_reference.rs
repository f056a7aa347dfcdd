//! docs/scenario.md against the loader: every example in it (and in every
//! other page of the manual and the README) loads and runs, its key tables
//! are `fibresim keys --markdown`, and the key table names exactly the fields
//! the serde mirror accepts.

use crate::common;
use common::fibresim;

use std::collections::BTreeSet;
use std::path::Path;

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap()
}

/// The ```toml blocks of a markdown file.
fn toml_blocks(md: &str) -> Vec<String> {
    md.split("```toml\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap().to_string())
        .collect()
}

/// Every ```toml block of docs/scenario.md, of the other pages of docs/ and
/// of the README is a complete scene: it loads without a warning, and ten
/// steps of it run. (Fragments are ```text blocks.)
#[test]
fn every_example_loads_and_runs() {
    let dir = tempfile::tempdir().unwrap();
    let mut n = 0;
    let mut docs: Vec<String> =
        std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs"))
            .unwrap()
            .map(|e| format!("docs/{}", e.unwrap().file_name().to_string_lossy()))
            .filter(|f| f.ends_with(".md"))
            .collect();
    docs.sort();
    docs.push("README.md".to_string());
    assert!(docs.iter().any(|d| d == "docs/scenario.md"));
    let mut box_example = false;
    for doc in &docs {
        let blocks = toml_blocks(&read(doc));
        if doc == "docs/scenario.md" {
            assert!(!blocks.is_empty(), "{doc} has toml examples");
        }
        box_example |= blocks.iter().any(|b| b.contains("[box]"));
        for (i, text) in blocks.iter().enumerate() {
            let (scene, warnings) = fibresim::scenario::parse_with_warnings(text, doc)
                .unwrap_or_else(|e| panic!("{doc} example {i}: {e}\n{text}"));
            assert!(warnings.is_empty(), "{doc} example {i}: {warnings:?}");
            let file = dir.path().join(format!("ex{n}.toml"));
            std::fs::write(&file, text).unwrap();
            let t = format!("{:e}", 10.0 * scene.sim.dt());
            let out = dir.path().join(format!("out{n}"));
            let o = fibresim(&[
                "run",
                file.to_str().unwrap(),
                "--t-end",
                &t,
                "-q",
                "--out",
                out.to_str().unwrap(),
            ]);
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(o.status.success(), "{doc} example {i}: {err}");
            assert!(!err.contains("warning"), "{doc} example {i}: {err}");
            n += 1;
        }
    }
    // docs/scenario.md shows a scene in a box, with two bodies, with a
    // torque and with a reference.
    assert!(n >= 4, "{n} examples");
    assert!(box_example, "an example has a box");
}

/// docs/scenario.md's key tables are generated from the key table.
#[test]
fn key_tables_are_generated() {
    let o = fibresim(&["keys", "--markdown"]);
    assert!(o.status.success());
    let generated = String::from_utf8(o.stdout).unwrap();
    let doc = read("docs/scenario.md");
    let inside = doc
        .split("<!-- BEGIN keys -->\n")
        .nth(1)
        .and_then(|s| s.split("<!-- END keys -->").next())
        .expect("docs/scenario.md has the keys markers");
    assert_eq!(
        inside, generated,
        "docs/scenario.md's key tables are stale: paste `fibresim keys --markdown`"
    );
    let text = String::from_utf8(fibresim(&["keys"]).stdout).unwrap();
    for k in fibresim::scenario::keys::KEYS {
        assert!(text.contains(&format!("  {:<17} ", k.name)), "{}", k.name);
    }
}

/// The fields serde accepts in a table, from its own message for an
/// unknown key there (`unknown field `zz`, expected one of `a`, `b``).
fn serde_fields(text: &str) -> BTreeSet<String> {
    let e = toml::from_str::<fibresim::scenario::file::ScenarioFile>(text)
        .expect_err("an unknown key is refused")
        .to_string();
    let list = e
        .split("expected one of ")
        .nth(1)
        .or_else(|| e.split("expected ").nth(1))
        .unwrap_or_else(|| panic!("{e}"));
    let list = list.lines().next().unwrap();
    list.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Every field of every serde table has exactly one line in the key table,
/// and every table has a `TableSpec`: a key added to `file.rs` without a
/// line in `keys.rs` (so without documentation and pre-check) fails here.
#[test]
fn the_key_table_names_every_serde_field() {
    use fibresim::scenario::keys::{keys_of, TABLES};
    let base = "[simulation]\ndt = 1e-3\nt_end = 1e-2\n";
    let body = "[[body]]\nshape = \"fibre\"\ndiameter = 0.01\nlength = 0.02\ndensity = 1000.0\nposition = [0.0, 0.0, 0.0]\n";
    let tables: BTreeSet<String> = TABLES.iter().map(|t| t.name.to_string()).collect();
    assert_eq!(serde_fields(&format!("{base}{body}[zz_unknown]\n")), tables);
    let with_unknown = |t: &str| -> String {
        match t {
            "simulation" => {
                format!("[simulation]\ndt = 1e-3\nt_end = 1e-2\nzz_unknown = 1\n{body}")
            }
            "body" => format!("{base}{body}zz_unknown = 1\n"),
            "material" => format!("{base}{body}[material.m]\ndensity = 1.0\nzz_unknown = 1\n"),
            t => format!("{base}{body}[{t}]\nzz_unknown = 1\n"),
        }
    };
    for t in TABLES {
        let want: BTreeSet<String> = keys_of(t.name).map(|k| k.name.to_string()).collect();
        assert_eq!(
            serde_fields(&with_unknown(t.name)),
            want,
            "[{}]: serde's fields against keys.rs",
            t.name
        );
    }
}
