//! Property test of the scenario loader (issue 5, item 4): arbitrary and
//! mutated input never panics; it loads or fails as bad input (exit code 2).
//! Counts: 4000 arbitrary strings + 6000 byte-level mutations of the shipped
//! scenarios per `cargo test` run (proptest's default seed varies per run).

use fibresim::error::Error;
use fibresim::scenario::parse_str;
use proptest::prelude::*;

fn scenarios() -> Vec<String> {
    [
        "torque_sphere",
        "torque_fibre",
        "single_fibre",
        "nine_fibres",
    ]
    .iter()
    .map(|n| {
        std::fs::read_to_string(format!("{}/scenarios/{n}.toml", env!("CARGO_MANIFEST_DIR")))
            .unwrap()
    })
    .collect()
}

fn check(text: &str) {
    match parse_str(text, "<fuzz>") {
        Ok(_) => {}
        Err(e @ Error::BadInput { .. }) => assert_eq!(e.exit_code(), 2),
        Err(e) => panic!("loader returned a non-input error: {e}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]
    #[test]
    fn arbitrary_text_never_panics(s in "\\PC{0,200}") {
        check(&s);
    }
}

const TOKENS: &[&str] = &[
    "-",
    "0",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "\"",
    "[",
    "]",
    "=",
    "\n",
    "#",
    "1e-300",
    "\"pi*t^t^t\"",
    "\"1/0\"",
    "((((",
    "[[body]]\n",
    "[box]\n",
    "1e13",
    "0.0",
    "\"sphere\"",
    "true",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6000))]
    #[test]
    fn mutated_scenarios_never_panic(which in 0usize..4, edits in prop::collection::vec((any::<prop::sample::Index>(), 0usize..22, 0u8..3), 1..6)) {
        let mut text = scenarios()[which].clone().into_bytes();
        for (at, tok, kind) in edits {
            let i = at.index(text.len().max(1)).min(text.len());
            match kind {
                0 => { text.splice(i..i, TOKENS[tok].bytes()); }
                1 => { let end = (i + 1 + tok).min(text.len()); text.drain(i..end); }
                _ => { let end = (i + TOKENS[tok].len()).min(text.len()); text.splice(i..end, TOKENS[tok].bytes()); }
            }
        }
        check(&String::from_utf8_lossy(&text));
    }
}
