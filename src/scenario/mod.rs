//! Scenario files: the raw TOML mirror ([`file`](mod@file)) and its validation, once,
//! into a ready-to-run [`Scene`] ([`build`], with the checks of bodies,
//! numerical parameters and references in their own files).

mod bodies;
pub mod build;
mod check;
pub mod file;
pub mod locate;
pub mod output;
pub mod reference;
pub mod scene;
pub mod sim;

pub use bodies::{aabb, SPEED_OF_LIGHT};
pub use build::{load, parse_str};
pub use locate::locate;
pub use output::OutputRequest;
pub use reference::ClosedForm;
pub use scene::{Prescribed, Scene, Walls};
pub use sim::{Guards, SimParams};
