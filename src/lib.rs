//! fibresim: a DEM simulator for rigid cylindrical fibres (and spheres) with
//! Hertzian contacts and optional Coulomb friction, built to compare quaternion rotation integrators (Zhao & van Wachem 2013).
//!
//! Conventions (docs/physics.md §1):
//! - SI units everywhere; gravity along −z by default; the box floor is z = 0.
//! - Unit quaternions `q = [w, x, y, z]`, Hamilton product (paper Eq. 14), scalar
//!   first in every file fibresim reads or writes (glam stores them `xyzw` in memory).
//! - `q` maps body to world: `v_world = q v_body q*`.
//!   Kinematics `dq/dt = ½ ω_world ⊗ q = ½ q ⊗ ω_body`.
//! - The time of step `n` is `t_n = n·δt`, computed by multiplication.
//!
//! ```
//! use fibresim::math::{exp_map, geodesic_angle};
//! use glam::{DQuat, DVec3};
//! // A quarter turn about z maps body x onto world y (v_world = q v_body q*).
//! let q = exp_map(DVec3::Z * std::f64::consts::FRAC_PI_2);
//! assert!((q * DVec3::X - DVec3::Y).length() < 1e-15);
//! assert!((geodesic_angle(DQuat::IDENTITY, q) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
//! ```
//!
//! Data flows one way: [`scenario`] (raw TOML → checked [`scenario::Scene`]) →
//! [`integrate`] (the fixed step sequence) → [`output`] (observers).

#![warn(missing_docs)]

pub mod advice;
pub mod body;
pub mod cli;
pub mod contact;
pub mod energy;
pub mod error;
pub mod fmt;
pub mod generate;
pub mod integrate;
pub mod math;
pub mod output;
pub mod plot;
#[cfg(feature = "mpi")]
pub mod ranks;
pub mod reference;
pub mod render;
pub mod run;
pub mod scenario;
pub mod stop;
pub mod study;
pub mod torque;
