//! Scenario files: the table of known keys ([`keys`]), a pre-check of the
//! parsed document against it (every problem at once), the raw TOML mirror
//! ([`file`](mod@file)) and its validation, once, into a ready-to-run
//! [`Scene`] ([`build`], with the checks of bodies, numerical parameters and
//! references in their own files).

pub mod axis;
mod bodies;
pub mod body_file;
pub mod build;
pub(crate) mod check;
pub mod file;
mod ids;
pub mod keys;
pub mod locate;
pub mod output;
mod precheck;
pub mod reference;
pub mod scene;
pub mod sim;
mod spell;
pub mod write;

pub use bodies::{aabb, SPEED_OF_LIGHT};
pub use build::{load, load_with_warnings, parse_str, parse_with_warnings};
pub use ids::{Ids, IdsIter};
pub use locate::locate;
pub use output::OutputRequest;
pub use reference::ClosedForm;
pub use scene::{Prescribed, Scene, Walls};
pub use sim::{Guards, SimParams};

/// The scene of `fibresim run` with no scenario (the paper's test case 2),
/// by the name its outputs record: `render` reads it back by that name.
pub const DEFAULT_SCENE: (&str, &str) = (
    "<built-in nine_fibres>",
    include_str!("../../scenarios/nine_fibres.toml"),
);
