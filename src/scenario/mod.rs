//! Scenario files: the raw TOML mirror ([`file`]) and its validation into a
//! ready-to-run [`Scene`] ([`build`]). Every check happens here, once.

pub mod build;
pub mod file;
pub mod locate;

pub use build::{load, parse_str, ClosedForm, Guards, Scene, SimParams, Walls};
pub use locate::locate;
