//! Exact references for rigid-body rotation: the torque-free body in closed
//! form (regular precession; Jacobi's elliptic functions for three distinct
//! moments, with the Dzhanibekov flip period), a manufactured solution under
//! a time-dependent torque, and the special functions they need. Scenes
//! declare them with `[reference]` (`crate::scenario::reference`); the
//! order harness (`crate::study::order`) measures every rotator against them.

pub mod elliptic;
pub mod manufactured;
pub mod torque_free;

pub use manufactured::{Manufactured, Wave};
pub use torque_free::{Polhode, TorqueFree, TorqueFreeError};
