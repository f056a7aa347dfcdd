//! What `render` draws: one frame of fibres (pose, size and the per-fibre
//! fields a colour can show) and the box, from any of fibresim's files.

use crate::body::{Body, BodyState, Shape};
use crate::math::{body_x_axis, to_world};
use crate::scenario::Scene;
use glam::DVec3;

/// One fibre as drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fibre {
    /// Centre of mass, m.
    pub centre: DVec3,
    /// Unit axis (body x) in the world.
    pub axis: DVec3,
    /// D, m.
    pub diameter: f64,
    /// L, m (0 for a sphere).
    pub length: f64,
    /// m/s, world.
    pub velocity: DVec3,
    /// World angular velocity, rad/s.
    pub omega: DVec3,
    /// Translational + rotational kinetic energy, J.
    pub kinetic_energy: f64,
    /// Live contacts (bodies and walls touched).
    pub contacts: u32,
    /// Material index.
    pub material: u32,
    /// Global id.
    pub id: u64,
}

/// One frame: a time, its fibres, the box.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Step of the run.
    pub step: u64,
    /// Time, s.
    pub t: f64,
    /// The fibres.
    pub fibres: Vec<Fibre>,
    /// The box (lower, upper corner), if the scene has walls.
    pub walls: Option<(DVec3, DVec3)>,
    /// Material names, by index.
    pub materials: Vec<String>,
}

impl Frame {
    /// The frame of `scene`'s bodies at `states` (storage order), with the
    /// contact counts recounted.
    pub fn of_states(scene: &Scene, states: &[BodyState], step: u64, t: f64) -> Self {
        let contacts = crate::output::contact_count::contacts_at(scene, states);
        let fibres = scene
            .bodies
            .iter()
            .zip(states)
            .enumerate()
            .map(|(i, (b, s))| fibre_of(b, s, contacts[i], scene.ids.get(i)))
            .collect();
        Frame {
            step,
            t,
            fibres,
            walls: scene.walls.as_ref().map(|w| (w.min, w.max)),
            materials: scene.materials.iter().map(|m| m.name.clone()).collect(),
        }
    }
}

fn fibre_of(b: &Body, s: &BodyState, contacts: u32, id: u64) -> Fibre {
    let length = match b.shape {
        Shape::Fibre { length, .. } => length,
        Shape::Sphere { .. } => 0.0,
        // Drawn as its equivalent ellipsoid's body-x extent.
        Shape::Rigid { semi_axes } => 2.0 * semi_axes.x,
    };
    Fibre {
        centre: s.x,
        axis: body_x_axis(s.rot.q),
        diameter: b.shape.diameter(),
        length,
        velocity: s.v,
        omega: to_world(s.rot.q, s.rot.omega_b),
        kinetic_energy: 0.5 * b.mass * s.v.length_squared()
            + b.inertia.kinetic_energy(s.rot.omega_b),
        contacts,
        material: b.material,
        id,
    }
}
