//! The opening and closing stages on the thread pool, for scenes of many
//! bodies ([`crate::contact::stage::parallel`]). Each body is advanced
//! exactly as the one-thread stages advance it; the energy ledger is summed
//! in body order, so the bits do not depend on the thread count.

use super::rotate::{AuxState, Rotator};
use super::step::{body_is_sound, torque_source};
use super::verlet;
use super::world::World;
use crate::body::BodyState;
use crate::energy::Ledger;
use crate::scenario::scene::prescribed_on;
use glam::DVec3;
use rayon::prelude::*;

impl World<'_> {
    /// [`Self::open`] on the thread pool, for rotators that never refuse a
    /// step ([`Rotator::MAY_FAULT`]).
    pub(super) fn open_par<R: Rotator>(&mut self, start: f64, h: f64) {
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t = (self.step as f64 + start) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let (force, torque) = (&self.force, &self.torque);
        par_bodies::<R>(&mut self.states, &mut self.aux, |i, s, a| {
            let body = &scene.bodies[i];
            verlet::kick_drift(&mut s.x, &mut s.v, force[i] * body.inv_mass + g, dt);
            let tau = pooled(torque_source(prescribed_on(&scene.torques, i), torque[i]));
            let _ = R::advance(&mut s.rot, a, &body.inertia, tau, t, dt);
            true // (no guard in the opening pass)
        });
    }

    /// [`Self::close`] on the thread pool: the per-body work in parallel,
    /// the ledger summed in body order afterwards.
    pub(super) fn close_par<R: Rotator>(&mut self, end: f64, h: f64, last: bool) -> bool {
        let scene = self.scene;
        let dt = h * scene.sim.dt();
        let t_end = (self.step as f64 + end) * scene.sim.dt();
        let g = scene.gravity.unwrap_or(DVec3::ZERO);
        let (force, torque) = (&self.force, &self.torque);
        // The per-body guard in the same pass (a pool stage fewer).
        let sound = par_bodies::<R>(&mut self.states, &mut self.aux, |i, s, a| {
            let body = &scene.bodies[i];
            verlet::kick(&mut s.v, force[i] * body.inv_mass + g, dt);
            let tau = pooled(torque_source(prescribed_on(&scene.torques, i), torque[i]));
            R::finish(&mut s.rot, a, &body.inertia, tau, t_end, dt);
            !last || body_is_sound(s)
        });
        if !last {
            return true;
        }
        // Summed in body order: the bits of the one-thread pass.
        let mut ledger = Ledger {
            elastic: self.elastic(),
            dissipated: self.dissipated(),
            ..Ledger::default()
        };
        for (body, s) in scene.bodies.iter().zip(&self.states) {
            ledger.add_body(body, s, g);
        }
        self.ledger = ledger;
        sound
    }
}

/// The same torque under a closure type of its own. The pool's stages then
/// get their own instance of each rotator's `advance`/`finish`, and the
/// one-thread loop keeps its single call site, which the compiler inlines
/// (shared, it did not, and test case 2 paid for the calls: `cargo bench
/// --bench contacts`).
#[inline]
fn pooled(torque: impl Fn(f64) -> DVec3) -> impl Fn(f64) -> DVec3 {
    move |t| torque(t)
}

/// Run `f(index, state, aux)` for every body on the thread pool; whether
/// it returned true for all (each body runs, whatever the others return).
fn par_bodies<R: Rotator>(
    states: &mut [BodyState],
    aux: &mut [f64],
    f: impl Fn(usize, &mut BodyState, &mut R::Aux) -> bool + Sync,
) -> bool {
    let len = R::Aux::LEN;
    let all = || true;
    let and = |x: bool, y: bool| x && y;
    if len == 0 {
        states
            .par_iter_mut()
            .enumerate()
            .map(|(i, s)| f(i, s, &mut R::Aux::default()))
            .reduce(all, and)
    } else {
        states
            .par_iter_mut()
            .zip(aux.par_chunks_mut(len))
            .enumerate()
            .map(|(i, (s, slot))| {
                let mut a = R::Aux::read(slot);
                let ok = f(i, s, &mut a);
                a.write(slot);
                ok
            })
            .reduce(all, and)
    }
}
