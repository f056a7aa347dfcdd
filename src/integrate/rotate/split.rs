//! `split`: kick – exact torque-free rotation – kick (the rigid-body
//! analogue of velocity Verlet; Dullweber, Leimkuhler & McLachlan, J. Chem.
//! Phys. 107 (1997) for the splitting, Celledoni, Fassò, Säfström & Zanna,
//! SIAM J. Sci. Comput. 30 (2008) for its exact free flow).
//!
//! The Hamiltonian `H = T(L) + V(q)` splits into the free rigid body `T` and
//! the potential `V`, whose flow is a kick of the world angular momentum:
//! 1. `L ← L + (h/2) τ(t)` (world frame, so no gyroscopic term appears);
//! 2. the exact flow of `T` over `h`:
//!    - two equal moments (fibres, spheres; symmetry axis `e_s`):
//!      `q ← exp(h L/I⊥) ⊗ q ⊗ exp(h ν e_s)`, `ν = (1/I_s − 1/I⊥) L_s`, two
//!      sin/cos pairs (Landau–Lifshitz §33: the generators commute);
//!    - three distinct moments: the elliptic-function flow of
//!      [`crate::reference::Polhode::flow`];
//! 3. `L ← L + (h/2) τ(t + h)` at the new configuration (after forces).
//!
//! Each part is the exact flow of a Hamiltonian, so the step is symplectic,
//! and it is symmetric, so time-reversible and second order under any torque;
//! with no torque it is the exact solution to rounding. The closing torque is
//! kept ([`Fsal`]) and reused by the next opening kick: one evaluation per
//! step, as velocity Verlet needs one force evaluation.
//!
//! **What is carried.** Rounding must not feed the frequencies of the free
//! flow, or a phase error would grow like `ε N^{3/2}`. So the step carries
//! the world angular momentum `L` (a zero kick leaves it bit for bit) and
//! the other conserved numbers of the flow: `L_s` for two equal moments
//! (kicks add their axial impulse), the gaps `Dᵢ = M² − 2E Iᵢ` for three
//! distinct ones (a kick recomputes them from the state) and the polhode's
//! argument. The body angular velocity is derived from them.
//!
//! **Renormalisation, after every free flow.** The flow is a product of unit
//! quaternions (`exp_map` factors, the alignments `B(l)`, the working frame),
//! each unit only to rounding, and their product's norm drifts with a bias:
//! −6.9e-17 per step on the precessing fibre (−6.2e-11 after 9·10⁵ steps).
//! A non-unit `q` scales `q* L q` by `|q|²`, so the body momentum, and the
//! gaps `Dᵢ` a kick derives from it, disagree with `M = |L|`: the elliptic
//! flow's precession rate then errs by ~`|q|² − 1` (3.8e-11 rad per second of
//! flow on the manufactured case after 10⁴ steps, the floor that kept
//! `split4` from fourth order), and `ω_b` by the same factor (energy errors of
//! 2.8e-10 on the fibre, in orientation-error-free runs). Dividing by `|q|`
//! removes only that rounding (docs/rotators.md, `split`).

use super::{AuxState, Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use crate::math::{exp_map, is_zero, to_body, to_world};
use crate::reference::torque_free::{casimir_gaps, symmetry_axis};
use crate::reference::Polhode;
use glam::DVec3;

/// Kick – exact free rotation – kick.
pub struct Split;

/// What `split` carries between steps (module docs).
#[derive(Debug, Clone, Copy)]
pub struct SplitAux {
    /// World angular momentum, N m s.
    pub l_world: DVec3,
    /// `(L_s, 0, 0)` for two equal moments; `(D_x, D_y, D_z)` for three distinct.
    pub invariants: DVec3,
    /// The torque of the last closing kick.
    pub fsal: Fsal,
    /// Three distinct moments: the polhode argument `u` now, as the
    /// compensated sum `u_hi + u_lo` (NaN after a kick: it is then taken
    /// from the state at the next flow). Carried, not re-derived from the
    /// state each step (that adds a rounding bias every time), and summed
    /// with the lost low bits kept (a plain `u += λh` rounds the same way at
    /// every step), reduced by the period `4K` of the polhode.
    pub u_hi: f64,
    /// See [`SplitAux::u_hi`].
    pub u_lo: f64,
}

impl Default for SplitAux {
    fn default() -> Self {
        SplitAux {
            l_world: DVec3::ZERO,
            invariants: DVec3::ZERO,
            fsal: Fsal::default(),
            u_hi: f64::NAN,
            u_lo: 0.0,
        }
    }
}

impl AuxState for SplitAux {
    const LEN: usize = 12;
    #[inline]
    fn read(from: &[f64]) -> Self {
        SplitAux {
            l_world: DVec3::new(from[0], from[1], from[2]),
            invariants: DVec3::new(from[3], from[4], from[5]),
            fsal: Fsal::read(&from[6..10]),
            u_hi: from[10],
            u_lo: from[11],
        }
    }
    #[inline]
    fn write(&self, to: &mut [f64]) {
        to[..3].copy_from_slice(&self.l_world.to_array());
        to[3..6].copy_from_slice(&self.invariants.to_array());
        self.fsal.write(&mut to[6..10]);
        to[10] = self.u_hi;
        to[11] = self.u_lo;
    }
}

/// The conserved numbers of the free flow for body momentum `l_b`.
fn invariants(principal: DVec3, l_b: DVec3) -> DVec3 {
    match symmetry_axis(principal) {
        Some(s) => DVec3::new(l_b[s], 0.0, 0.0),
        None => casimir_gaps(principal, l_b),
    }
}

/// Kick the angular momentum by the world impulse `j_w` (`h/2 · τ`). Two
/// equal moments: `L_s` grows by the axial impulse (for a frictionless
/// contact torque, zero to rounding). Three distinct: the gaps of the new
/// polhode are those of the state (`L_b = q* L q`), and its argument is taken
/// afresh at the next flow.
#[inline]
pub(super) fn kick(rot: &mut RotState, aux: &mut SplitAux, inertia: &Inertia, j_w: DVec3) {
    if is_zero(j_w) {
        return;
    }
    let p = inertia.principal;
    aux.l_world += j_w;
    match symmetry_axis(p) {
        Some(s) => {
            let j_b = to_body(rot.q, j_w);
            aux.invariants.x += j_b[s];
            rot.omega_b += inertia.inverse * j_b;
        }
        None => {
            let l_b = to_body(rot.q, aux.l_world);
            aux.invariants = casimir_gaps(p, l_b);
            aux.u_hi = f64::NAN;
            rot.omega_b = inertia.inverse * l_b;
        }
    }
}

/// `(s, e)` with `s = fl(a + b)` and `a + b = s + e` exactly (Knuth's two-sum).
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// Advance the polhode argument carried in `aux` by `du`: returns its
/// value before and after.
#[inline]
fn advance_argument(aux: &mut SplitAux, du: f64, period: f64) -> (f64, f64) {
    // |u| ≥ 4K: back by a period (exact: the two are within a factor 2).
    if aux.u_hi.abs() >= period {
        aux.u_hi -= period.copysign(aux.u_hi);
    }
    let u0 = aux.u_hi;
    let (s, e) = two_sum(u0, du);
    let (hi, lo) = two_sum(s, aux.u_lo + e);
    aux.u_hi = hi;
    aux.u_lo = lo;
    (u0, hi)
}

/// The exact torque-free flow over `h` (module docs).
#[inline]
pub(super) fn free_flow(rot: &mut RotState, aux: &mut SplitAux, inertia: &Inertia, h: f64) {
    let p = inertia.principal;
    let l_w = aux.l_world;
    match symmetry_axis(p) {
        Some(s) => {
            let inv_perp = inertia.inverse[(s + 1) % 3];
            let l_s = aux.invariants.x;
            let spin = (inertia.inverse[s] - inv_perp) * l_s;
            let axis = DVec3::AXES[s];
            let q = exp_map(l_w * (h * inv_perp)) * rot.q * exp_map(axis * (spin * h));
            let mut l_b = to_body(q, l_w);
            l_b[s] = l_s;
            rot.q = q.normalize();
            rot.omega_b = inertia.inverse * l_b;
        }
        None => {
            let l_b = to_body(rot.q, l_w);
            match Polhode::new(p, l_b, l_w.length_squared(), aux.invariants) {
                Some(polhode) => {
                    // After a kick, the argument (and the start) from the state.
                    let start = aux.u_hi.is_nan().then(|| {
                        let l0 = polhode.to_working(l_b);
                        let (am0, u0) = polhode.phase(l0);
                        aux.u_hi = u0;
                        aux.u_lo = 0.0;
                        (l0, am0)
                    });
                    let period = 4.0 * polhode.legendre.k;
                    let u = advance_argument(aux, polhode.lambda * h, period);
                    let (q, l_b) = polhode.flow(rot.q, l_w, u, h, start);
                    rot.q = q.normalize();
                    rot.omega_b = inertia.inverse * l_b;
                }
                // A steady rotation about a principal axis (exact), or a
                // start exactly on the separatrix, where the elliptic
                // parameter is 1 and the period infinite: there NO_SQUISH's
                // free rotation (second order) takes the step.
                None => {
                    let (q, l_b) = super::nosquish::free_rotation(rot.q, l_b, inertia, h);
                    rot.q = q.normalize();
                    rot.omega_b = inertia.inverse * l_b;
                }
            }
        }
    }
}

impl Rotator for Split {
    type Aux = SplitAux;

    const INFO: RotatorInfo = RotatorInfo {
        name: "split",
        title: "Splitting: kick, exact torque-free rotation (closed form for two equal moments, elliptic functions for three), kick",
        equations: "Dullweber et al. 1997; free flow: Landau-Lifshitz §33, §37",
        order: 2,
        order_free: 0,
        symplectic: true,
        reversible: true,
        torque_evals: 1,
        torque_contract: "half-kicks with the torque at (t_n, q_n) and (t_n+1, q_n+1), one evaluation per step (the closing torque is reused)",
        contact_contract: super::KDK_CONTACT_CONTRACT,
        closing_kick: true,
        diagnostic: false,
    };

    fn start(rot: &RotState, inertia: &Inertia) -> SplitAux {
        let l_b = inertia.principal * rot.omega_b;
        SplitAux {
            l_world: to_world(rot.q, l_b),
            invariants: invariants(inertia.principal, l_b),
            ..SplitAux::default()
        }
    }

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        let tau = aux.fsal.at(t, &torque);
        kick(rot, aux, inertia, (0.5 * h) * tau);
        free_flow(rot, aux, inertia, h);
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut SplitAux,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        h: f64,
    ) {
        let tau = aux.fsal.take(t_end, &torque);
        kick(rot, aux, inertia, (0.5 * h) * tau);
    }
}
