//! Property test of the scenario loader: arbitrary and
//! mutated input never panics; it loads or fails as bad input (exit code 2).
//! Counts: 4000 arbitrary strings + 6000 byte-level mutations of the shipped
//! scenarios per `cargo test` run (proptest's default seed varies per run),
//! printed and asserted at run time (`cargo test --release --test suite
//! loader_fuzz:: -- --nocapture`).

use fibresim::error::Error;
use fibresim::scenario::parse_str;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::cell::Cell;

const ARBITRARY_CASES: u32 = 4000;
const MUTATED_CASES: u32 = 6000;

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

/// How many inputs the loader saw, and how many it accepted.
#[derive(Default)]
struct Tally {
    tried: Cell<u32>,
    loaded: Cell<u32>,
}

impl Tally {
    fn check(&self, text: &str) {
        self.tried.set(self.tried.get() + 1);
        match parse_str(text, "<fuzz>") {
            Ok(_) => self.loaded.set(self.loaded.get() + 1),
            Err(e @ Error::BadInput { .. }) => assert_eq!(e.exit_code(), 2),
            Err(e) => panic!("loader returned a non-input error: {e}"),
        }
    }

    /// Printed at run time (`-- --nocapture`); the count is asserted so a
    /// configuration change cannot silently shrink the test.
    fn report(&self, what: &str, cases: u32) {
        let (n, ok) = (self.tried.get(), self.loaded.get());
        println!(
            "loader_fuzz: {n} {what} tried: {ok} loaded, {} rejected as bad input, no panic",
            n - ok
        );
        assert_eq!(n, cases, "{what}: every case reaches the loader");
    }
}

#[test]
fn arbitrary_text_never_panics() {
    let tally = Tally::default();
    TestRunner::new(Config::with_cases(ARBITRARY_CASES))
        .run(&"\\PC{0,200}", |s| {
            tally.check(&s);
            Ok(())
        })
        .unwrap();
    tally.report("arbitrary strings", ARBITRARY_CASES);
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
    // Misspelt tables, keys and names, and a rigid body on the edge of
    // its inertia check.
    "[simulaton]\n",
    "densty",
    "\"fiber\"",
    "\"rigid\"",
    "inertia = [2e-6, 3e-6, 5e-6]\n",
];

#[test]
fn mutated_scenarios_never_panic() {
    let texts = scenarios();
    let tally = Tally::default();
    let edits = prop::collection::vec(
        (any::<prop::sample::Index>(), 0..TOKENS.len(), 0u8..3),
        1..6,
    );
    TestRunner::new(Config::with_cases(MUTATED_CASES))
        .run(&(0usize..4, edits), |(which, edits)| {
            let mut text = texts[which].clone().into_bytes();
            for (at, tok, kind) in edits {
                let i = at.index(text.len().max(1)).min(text.len());
                match kind {
                    0 => {
                        text.splice(i..i, TOKENS[tok].bytes());
                    }
                    1 => {
                        let end = (i + 1 + tok).min(text.len());
                        text.drain(i..end);
                    }
                    _ => {
                        let end = (i + TOKENS[tok].len()).min(text.len());
                        text.splice(i..end, TOKENS[tok].bytes());
                    }
                }
            }
            tally.check(&String::from_utf8_lossy(&text));
            Ok(())
        })
        .unwrap();
    tally.report("mutated scenarios", MUTATED_CASES);
}
