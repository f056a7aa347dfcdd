//! A checked scene, ready to run: what the step reads.

use super::ids::Ids;
use super::reference::ClosedForm;
use super::sim::{Guards, SimParams};
use crate::body::{Bodies, BodyState, Material};
use crate::torque::PrescribedTorque;
use glam::DVec3;

/// The six walls of an axis-aligned box (defined with the contacts).
pub use crate::contact::Walls;

/// A prescribed world torque on one body.
#[derive(Debug, Clone)]
pub struct Prescribed {
    /// Storage index of the body.
    pub body: usize,
    /// Its torque as a function of time.
    pub torque: PrescribedTorque,
}

/// The prescribed torque of body `i`, from the sparse list sorted by body.
#[inline]
pub fn prescribed_on(list: &[Prescribed], i: usize) -> Option<&PrescribedTorque> {
    if list.is_empty() {
        return None;
    }
    list.binary_search_by_key(&i, |p| p.body)
        .ok()
        .map(|k| &list[k].torque)
}

/// A checked scene, ready to run.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Where it came from (a path, or `<built-in>`), for messages.
    pub source: String,
    /// The scenario text as read (embedded in checkpoints).
    pub text: String,
    /// Time step, step count, rotator, output cadence.
    pub sim: SimParams,
    /// Per-body constants, by storage index (each distinct value once).
    pub bodies: Bodies,
    /// Stable global id of each body (the `body` column of the outputs,
    /// diagnoses, checkpoints), by storage index.
    pub ids: Ids,
    /// The `name` of each `[[body]]` body, by storage index; bodies from a
    /// body file (after them) have none: see [`Scene::name`].
    pub names: Vec<String>,
    /// The material table (`Body::material` indexes it).
    pub materials: Vec<Material>,
    /// Each body's state at step 0, by storage index. `fibresim run` moves
    /// them into its world ([`crate::run::run_from`]), leaving this empty:
    /// the advice reads them before, the closed form carries its `q₀`.
    pub initial: Vec<BodyState>,
    /// Prescribed torques, sparse, in storage order of their bodies.
    pub torques: Vec<Prescribed>,
    /// Gravitational acceleration, m/s² (`None`: no gravity).
    pub gravity: Option<DVec3>,
    /// The box, if the scene has walls.
    pub walls: Option<Walls>,
    /// A closed form the scene declares.
    pub reference: Option<ClosedForm>,
    /// Limits that stop a run early.
    pub guards: Guards,
    /// Normal dissipation (`[contact]`); `None`: elastic contacts.
    pub damping: Option<crate::contact::damping::Restitution>,
    /// Coulomb friction (`[contact] friction`); `None`: frictionless.
    pub friction: Option<crate::contact::tangential::Friction>,
    /// Optional outputs (`[output]`, overridden by flags).
    pub output: super::OutputRequest,
}

impl Scene {
    /// Contacts are needed when bodies can touch something: walls or each other.
    pub fn needs_contacts(&self) -> bool {
        self.walls.is_some() || self.bodies.len() > 1
    }

    /// Whether any body has a prescribed torque.
    pub fn has_prescribed_torque(&self) -> bool {
        !self.torques.is_empty()
    }

    /// The label of body `i`: its `name`, else `body<id>`.
    pub fn name(&self, i: usize) -> String {
        match self.names.get(i) {
            Some(n) => n.clone(),
            None => format!("body{}", self.ids.get(i)),
        }
    }

    /// The material of body `i`.
    pub fn material(&self, i: usize) -> &Material {
        &self.materials[self.bodies[i].material as usize]
    }
}
