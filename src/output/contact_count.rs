//! Live contacts per body, counted only when a frame is written (VTK cell
//! data, `fibresim render --color contacts`): a run that writes no frame
//! pays nothing. The count is the contact stage's own candidates asked again
//! through its kernels ([`ContactStage::touching_per_body`]), so it is
//! exactly what the force stage saw; it sums to `2 × fibre–fibre +
//! fibre–wall` touching pairs.

use crate::body::BodyState;
use crate::contact::stage::ContactStage;
use crate::integrate::step::World;
use crate::scenario::Scene;
use glam::DVec3;

/// Touching bodies and walls per body of `world` (storage order); zeros in
/// a scene without contacts.
pub fn contacts_of_world(world: &World) -> Vec<u32> {
    world.contacts.as_ref().map_or_else(
        || vec![0; world.states.len()],
        |c| c.touching_per_body(&world.scene.bodies),
    )
}

/// The same for `scene`'s bodies at `states` (a checkpoint, a trajectory
/// row, a scenario's start): one force computation by a stage of its own.
pub fn contacts_at(scene: &Scene, states: &[BodyState]) -> Vec<u32> {
    if !scene.needs_contacts() {
        return vec![0; states.len()];
    }
    let mut stage = ContactStage::new(&scene.bodies, &scene.materials, scene.walls.as_ref());
    let (mut f, mut t) = (
        vec![DVec3::ZERO; states.len()],
        vec![DVec3::ZERO; states.len()],
    );
    stage.compute(&scene.bodies, states, &mut f, &mut t);
    stage.touching_per_body(&scene.bodies)
}
