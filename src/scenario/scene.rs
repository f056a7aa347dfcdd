//! A checked scene, ready to run: what the step reads.

use super::reference::ClosedForm;
use super::sim::{Guards, SimParams};
use crate::body::{Body, BodyState, Material};
use crate::torque::PrescribedTorque;
use glam::DVec3;

/// The six walls of an axis-aligned box (defined with the contacts).
pub use crate::contact::Walls;

/// A prescribed world torque on one body.
#[derive(Debug, Clone)]
pub struct Prescribed {
    /// Storage index of the body.
    pub body: usize,
    pub torque: PrescribedTorque,
}

/// A checked scene, ready to run.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Where it came from (a path, or `<built-in>`), for messages.
    pub source: String,
    /// The scenario text as read (embedded in checkpoints).
    pub text: String,
    pub sim: SimParams,
    /// Per-body constants, by storage index.
    pub bodies: Vec<Body>,
    /// Stable global id of each body (the `body` column of the outputs,
    /// diagnoses, checkpoints), by storage index.
    pub ids: Vec<u64>,
    /// Each body's `name`, by storage index.
    pub names: Vec<String>,
    pub materials: Vec<Material>,
    pub initial: Vec<BodyState>,
    /// Prescribed torques, sparse, in storage order of their bodies.
    pub torques: Vec<Prescribed>,
    pub gravity: Option<DVec3>,
    pub walls: Option<Walls>,
    pub reference: Option<ClosedForm>,
    pub guards: Guards,
}

impl Scene {
    /// Contacts are needed when bodies can touch something: walls or each other.
    pub fn needs_contacts(&self) -> bool {
        self.walls.is_some() || self.bodies.len() > 1
    }

    pub fn has_prescribed_torque(&self) -> bool {
        !self.torques.is_empty()
    }

    /// The material of body `i`.
    pub fn material(&self, i: usize) -> &Material {
        &self.materials[self.bodies[i].material as usize]
    }
}
