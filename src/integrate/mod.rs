//! Time integration: the fixed step sequence ([`step`]), translation by velocity
//! Verlet ([`verlet`]) and the quaternion rotators ([`rotate`]).

pub mod rotate;
pub mod step;
pub mod verlet;
