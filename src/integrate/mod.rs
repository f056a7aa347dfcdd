//! Time integration: the state ([`world`]), the step as a stage sequence
//! ([`scheme`], [`step`]) whose per-body stages any walker runs (`walk.rs`:
//! one thread, the pool, an MPI rank's bodies), translation by velocity
//! Verlet ([`verlet`]) and the quaternion rotators ([`rotate`]).

pub mod rotate;
pub mod scheme;
pub mod step;
pub mod verlet;
pub(crate) mod walk;
pub mod world;
