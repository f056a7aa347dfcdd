//! Time integration: the state ([`world`]), the step as a stage sequence
//! ([`scheme`], [`step`]), translation by velocity Verlet ([`verlet`]) and the
//! quaternion rotators ([`rotate`]).

mod parallel;
pub mod rotate;
pub mod scheme;
pub mod step;
pub mod verlet;
pub mod world;
