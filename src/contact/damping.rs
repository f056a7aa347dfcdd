//! Normal dissipation: Hertzian damping set by a coefficient of restitution
//! `e` (a scene's `[contact] restitution`; docs/physics.md §3).
//!
//! **Model** (Tsuji, Tanaka & Ishida, Powder Technol. 71 (1992) 239; the
//! form of LIGGGHTS's `hertz` model): at a contact point of overlap `δ` the
//! normal force is `F = k δ^{3/2} + η(δ) δ̇`, `k = (4/3) E* √R*` (the Hertz
//! stiffness), `η(δ) = α √(m* k) δ^{1/4}`, `δ̇` the rate of overlap and `m*`
//! the translational reduced mass (`m_a m_b / (m_a + m_b)`, `m` on a wall).
//!
//! **e(v).** In `X = δ/s`, `τ = t/T` with `s^{5/4} = v₀ √(m*/k)` and
//! `T² = m*/(k s^{1/2})`, a collision at speed `v₀` is `X'' = −X^{3/2} −
//! α X^{1/4} X'`, `X(0) = 0`, `X'(0) = 1`, whatever `v₀`: `e` depends on `α`
//! only, so it does not depend on the impact speed. Antypov & Elliott (EPL
//! 94 (2011) 50004) solved it: `α = √5 (−ln e) / √(ln² e + π²)`, which is
//! LIGGGHTS's `2 √(5/6) β √(S_n m*)` with `S_n = 2 E* √(R* δ)` and `β = ln e /
//! √(ln² e + π²)` (`√(S_n) = √(3k/2) δ^{1/4}`, so `α = √5 |β|`). Checked
//! here by integrating that equation (test below). The force is not clipped
//! at zero (LIGGGHTS's default): near the end of a contact the damping can
//! pull, as the calibration assumes; clipping would raise `e` (0.3 → 0.40).
//!
//! `e` is the restitution of one central contact point (a fibre dropped
//! end-on). A body that lands on `n` equal points at once (a fibre flat on
//! a wall: one per end) has `n` dampers on `m/n` each, so `α√n`: it rebounds
//! with `e_n = exp(−α√n π / √(5 − nα²))` (0 when `nα² ≥ 5`).
//!
//! **Velocity.** The force stage of velocity Verlet sees the half-step
//! velocity `v_{n+½}` (after the opening half-kick and drift; as LIGGGHTS),
//! and the angular velocity the rotator left after its `advance`.
//!
//! **Ledger.** A force `D_k` computed at step k acts in two half-kicks
//! around `v_k`, so its exact translational work is `δt D_k·v_k`, `v_k =
//! v_{k−½} + (δt/2)(F_k/m + g)` (the two half-kicks use the same force;
//! rotation: `δt τ_k·ω`). The ledger at step k holds every earlier stage's
//! work and the closing half-kick's share of stage k's; so `E + E_dissipated`
//! closes as well as the elastic budget does for translation.
//!
//! **Checkpoint.** Between steps a damped stage carries, beyond the
//! states, its last total force and torque per body (computed from
//! `v_{k+½}`, which the full-step states cannot give back) and the ledger's
//! `done` and `dissipated` ([`Damping::ledger_state`]); the loads are
//! zeroed by every pass and `first` is false once step 0's forces exist.
//! `src/output/checkpoint.rs` stores exactly these.

use crate::body::{Body, BodyState};
use glam::DVec3;

/// Declared normal restitution of the two kinds of contact (each in (0, 1]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Restitution {
    /// Fibre–fibre.
    pub fibre: f64,
    /// Fibre–wall.
    pub wall: f64,
}

/// Damping constant `α(e) = √5 (−ln e) / √(ln² e + π²)` (module docs).
pub fn damping_constant(e: f64) -> f64 {
    let l = -e.ln();
    5f64.sqrt() * l / (l * l + std::f64::consts::PI * std::f64::consts::PI).sqrt()
}

/// The restitution of a body landing on `n` equal points at once with the
/// damping constant `alpha` per point: `exp(−α√n π / √(5 − nα²))`.
pub fn restitution_of(alpha: f64, n: f64) -> f64 {
    let a = alpha * n.sqrt();
    if a * a >= 5.0 {
        0.0
    } else {
        (-a * std::f64::consts::PI / (5.0 - a * a).sqrt()).exp()
    }
}

/// The damping of a contact stage: constants, this stage's damping loads
/// per body, and the dissipated energy.
#[derive(Debug, Clone)]
pub(crate) struct Damping {
    alpha_pair: f64,
    alpha_wall: f64,
    dt: f64,
    gravity: DVec3,
    /// Damping force and torque (world) of this stage on each body.
    force: Vec<DVec3>,
    torque: Vec<DVec3>,
    /// Work done against the damping forces of every earlier stage, J.
    done: f64,
    /// Whether the next computation is the first (step 0: full-step velocities).
    first: bool,
    /// Dissipated energy at the state of the last computation, J.
    pub(crate) dissipated: f64,
}

/// What a damping force needs to read: the constants and the velocities
/// (shared by the serial stage and the parallel one's threads).
#[derive(Clone, Copy)]
pub(crate) struct DampingView<'a> {
    alpha_pair: f64,
    alpha_wall: f64,
    bodies: &'a [Body],
    states: &'a [BodyState],
}

/// One serial force computation's view of the damping: the velocities, and
/// the per-body loads it adds to.
pub(crate) struct DampingPass<'a> {
    view: DampingView<'a>,
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
}

impl Damping {
    /// Damping of `e` on `n` bodies stepped by `dt` under `gravity`.
    pub(crate) fn new(e: Restitution, n: usize, dt: f64, gravity: Option<DVec3>) -> Self {
        Damping {
            alpha_pair: damping_constant(e.fibre),
            alpha_wall: damping_constant(e.wall),
            dt,
            gravity: gravity.unwrap_or(DVec3::ZERO),
            force: vec![DVec3::ZERO; n],
            torque: vec![DVec3::ZERO; n],
            done: 0.0,
            first: true,
            dissipated: 0.0,
        }
    }

    /// Start a force computation at `states`.
    pub(crate) fn pass<'a>(
        &'a mut self,
        bodies: &'a [Body],
        states: &'a [BodyState],
    ) -> DampingPass<'a> {
        let view = self.view(bodies, states);
        let (force, torque) = self.loads();
        DampingPass {
            view,
            force,
            torque,
        }
    }

    /// The constants and velocities of a computation at `states`.
    pub(crate) fn view<'a>(&self, bodies: &'a [Body], states: &'a [BodyState]) -> DampingView<'a> {
        DampingView {
            alpha_pair: self.alpha_pair,
            alpha_wall: self.alpha_wall,
            bodies,
            states,
        }
    }

    /// This computation's damping force and torque per body (world),
    /// zeroed, for the stage to add to in its summation order.
    pub(crate) fn loads(&mut self) -> (&mut [DVec3], &mut [DVec3]) {
        self.force.fill(DVec3::ZERO);
        self.torque.fill(DVec3::ZERO);
        (&mut self.force, &mut self.torque)
    }

    /// What the ledger carries from one step to the next: `[done,
    /// dissipated]`, J. With the stage's last total force and torque per
    /// body (the step's open reads them) this is all a damped step keeps
    /// between steps: the loads are zeroed by every pass, and `first` is
    /// false after the force computation of step 0 (`World::from_states`).
    pub(crate) fn ledger_state(&self) -> [f64; 2] {
        [self.done, self.dissipated]
    }

    /// Put back a [`Damping::ledger_state`] (resuming from a checkpoint).
    pub(crate) fn set_ledger_state(&mut self, [done, dissipated]: [f64; 2]) {
        self.done = done;
        self.dissipated = dissipated;
        self.first = false;
    }

    /// Close the computation: `force` holds the stage's total contact force
    /// per body. The ledger's share and the full work (module docs).
    pub(crate) fn account(&mut self, bodies: &[Body], states: &[BodyState], force: &[DVec3]) {
        let (dt, g) = (self.dt, self.gravity);
        let (mut closing, mut full) = (0.0, 0.0);
        for (((b, s), (&d, &dtau)), &f) in bodies
            .iter()
            .zip(states)
            .zip(self.force.iter().zip(&self.torque))
            .zip(force)
        {
            if d == DVec3::ZERO && dtau == DVec3::ZERO {
                continue;
            }
            let spin = dtau.dot(s.rot.q * s.rot.omega_b);
            let kick = 0.5 * dt * (f * b.inv_mass + g);
            if self.first {
                // Step 0: `v` is v₀; only the opening half-kick is to come.
                full += 0.25 * dt * d.dot(2.0 * s.v + kick) + 0.5 * dt * spin;
            } else {
                let v_full = s.v + kick;
                closing += 0.25 * dt * d.dot(s.v + v_full) + 0.5 * dt * spin;
                full += dt * (d.dot(v_full) + spin);
            }
        }
        // Work of the damping forces is negative; the ledger keeps it positive.
        self.dissipated = self.done - closing;
        self.done -= full;
        self.first = false;
    }
}

impl DampingPass<'_> {
    /// [`DampingView::force`], its load noted for the ledger.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn force(
        &mut self,
        (a, xa): (usize, DVec3),
        b: Option<(usize, DVec3)>,
        k: f64,
        w: f64,
        p: DVec3,
        normal: DVec3,
        overlap: f64,
    ) -> f64 {
        let f = self.view.force((a, xa), b, k, w, p, normal, overlap);
        let fv = f * normal;
        self.force[a] += fv;
        self.torque[a] += (p - xa).cross(fv);
        if let Some((b, xb)) = b {
            self.force[b] -= fv;
            self.torque[b] -= (p - xb).cross(fv);
        }
        f
    }
}

impl DampingView<'_> {
    /// The damping force `η(δ) δ̇` (to add to the Hertz force along the
    /// point's normal) of a point of weight `w` at `p` with `normal` and
    /// `overlap`, between body `a` and body `b` (or a wall), with Hertz
    /// stiffness `k`.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn force(
        &self,
        (a, xa): (usize, DVec3),
        b: Option<(usize, DVec3)>,
        k: f64,
        w: f64,
        p: DVec3,
        normal: DVec3,
        overlap: f64,
    ) -> f64 {
        let sa = &self.states[a];
        let ma = self.bodies[a].mass;
        let mut rel = sa.v + (sa.rot.q * sa.rot.omega_b).cross(p - xa);
        let (alpha, m) = match b {
            Some((b, xb)) => {
                let sb = &self.states[b];
                let mb = self.bodies[b].mass;
                rel -= sb.v + (sb.rot.q * sb.rot.omega_b).cross(p - xb);
                (self.alpha_pair, ma * mb / (ma + mb))
            }
            None => (self.alpha_wall, ma),
        };
        // δ̇ = −normal·(v_A(p) − v_B(p)) (normal = −∂δ/∂x_A).
        let rate = -normal.dot(rel);
        w * alpha * (m * k).sqrt() * overlap.sqrt().sqrt() * rate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `X'' = −X^{3/2} − α X^{1/4} X'` from `X = 0`, `X' = 1` by classical
    /// RK4 at step `h` until `X` returns to 0: the rebound speed (module docs).
    fn rebound(alpha: f64, h: f64) -> f64 {
        let acc = |x: f64, v: f64| -x.max(0.0).powf(1.5) - alpha * x.max(0.0).powf(0.25) * v;
        let (mut x, mut v, mut t) = (0.0f64, 1.0f64, 0.0);
        loop {
            let (k1x, k1v) = (v, acc(x, v));
            let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
            let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
            let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x, v + h * k3v));
            let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            t += h;
            if xn <= 0.0 && t > h {
                let s = x / (x - xn);
                return -(v + s * (vn - v));
            }
            (x, v) = (xn, vn);
        }
    }

    /// Reference: our own RK4 solution of the dimensionless collision (not
    /// the closed form) gives back the `e` the constant was made for.
    #[test]
    fn the_damping_constant_gives_its_restitution() {
        for e in [0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99] {
            let got = rebound(damping_constant(e), 2e-4);
            assert!((got - e).abs() < 2e-6, "e = {e}: rebound {got}");
            assert!((restitution_of(damping_constant(e), 1.0) - e).abs() < 1e-12);
        }
        assert_eq!(damping_constant(1.0), 0.0);
        // Two equal points at once (a fibre landing flat): α√2, by the ODE.
        let a = damping_constant(0.3);
        let got = rebound(a * 2f64.sqrt(), 2e-4);
        assert!((got - restitution_of(a, 2.0)).abs() < 2e-6, "{got}");
    }
}
