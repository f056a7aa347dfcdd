//! `nosquish`: the symplectic quaternion splitting of Miller, Eleftheriou,
//! Pattnaik, Ndirango, Newns & Martyna, J. Chem. Phys. 116 (2002) 8649,
//! "NO_SQUISH" (LAMMPS `fix rigid/nve`).
//!
//! Miller et al. write the free rotor in the quaternion `q` and its conjugate
//! momentum `p = 2 S(q) (0, L_b)` as `T = Σₖ (p·Pₖq)²/(8Iₖ)` (their Eq. 2.5),
//! `Pₖq = q ⊗ eₖ`, and split it into the three terms. The flow of term `k`
//! over time `τ` is exact (their Eqs. 2.14–2.15): `q ← cos ζ q + sin ζ Pₖq`,
//! `p ← cos ζ p + sin ζ Pₖp`, `ζ = τ (p·Pₖq)/(4Iₖ) = τ Lₖ/(2Iₖ)`. In body
//! terms that is a rotation of the body by the angle `τ Lₖ/Iₖ` about its
//! axis `k`, `q ← q ⊗ exp(τ Lₖ/Iₖ eₖ)`, with `L_b` turned back by the same
//! angle about `eₖ` (`Lₖ` unchanged), which is what is computed here: the
//! same map, without the 4-vector `p`.
//!
//! A step is kick–free–kick (their Eq. 2.18): `L_b ← L_b + (h/2) q* τ q`, the
//! symmetric sequence `R_a(h/2) R_b(h/2) R_c(h) R_b(h/2) R_a(h/2)`, then the
//! closing kick with the torque of the new configuration. Symmetric and
//! composed of exact Hamiltonian flows: symplectic, time-reversible, second
//! order, one torque evaluation per step ([`Fsal`]).
//!
//! **Which axis gets the full central sub-step.** Measured against the
//! exact torque-free motion (`nosquish_axis_order` in this file's tests,
//! 1 s at δt = 1e-3 s): the axis of *largest* moment in the centre (LAMMPS's
//! choice) errs 2.7e-5 rad → 5.6e-6 rad on the asymmetric top
//! (2:3:4) and 2.4e-3 → 3.5e-4 rad on a fibre-like symmetric top (1:5:5)
//! against the smallest moment in the centre, which is also plain x-y-z
//! order for both bodies: 4.8× and 7× better. So the largest moment takes
//! the centre.
//! Renormalisation: none (products of unit quaternions).

use super::{Fsal, Rotator, RotatorFault, RotatorInfo};
use crate::body::{Inertia, RotState};
use glam::{DQuat, DVec3};

/// Miller et al.'s NO_SQUISH splitting.
pub struct NoSquish;

/// Which principal axis takes the full central sub-step.
// `Smallest` and `BodyX` exist to be measured against (`nosquish_axis_order`).
#[cfg_attr(not(test), allow(dead_code))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Centre {
    /// The smallest moment.
    Smallest,
    /// The largest moment (our choice, and LAMMPS's `fix rigid`).
    Largest,
    /// Body x, with y and z outside (plain x-y-z order).
    BodyX,
}

/// The centre used by `nosquish`.
const CENTRE: Centre = Centre::Largest;

/// `(sin x, cos x)` for the small half-angles of DEM steps, by series below
/// `|x| < 1e-2` (remainders below 1e-20 relative, as in `math::exp_map`).
#[inline]
fn sin_cos_small(x: f64) -> (f64, f64) {
    let x2 = x * x;
    if x2 < 1e-4 {
        const S: [f64; 3] = [1.0 / 6.0, 1.0 / 20.0, 1.0 / 42.0];
        const C: [f64; 4] = [0.5, 1.0 / 12.0, 1.0 / 30.0, 1.0 / 56.0];
        let s = x * (1.0 - x2 * S[0] * (1.0 - x2 * S[1] * (1.0 - x2 * S[2])));
        let c = 1.0 - x2 * C[0] * (1.0 - x2 * C[1] * (1.0 - x2 * C[2] * (1.0 - x2 * C[3])));
        (s, c)
    } else {
        x.sin_cos()
    }
}

/// The exact flow of `T_k = L_k²/(2I_k)` over `tau`: the body turns by
/// `α = tau L_k/I_k` about its axis `k`, its momentum by `−α`.
#[inline]
fn rotate_about(q: &mut DQuat, l: &mut DVec3, inv_inertia: DVec3, k: usize, tau: f64) {
    let alpha = tau * l[k] * inv_inertia[k];
    let (s, c) = sin_cos_small(0.5 * alpha);
    let mut r = [0.0; 3];
    r[k] = s;
    *q *= DQuat::from_xyzw(r[0], r[1], r[2], c);
    // Turn the other two components by −α: cos α = c² − s², sin α = 2sc.
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let (ca, sa) = (c * c - s * s, 2.0 * s * c);
    let (li, lj) = (l[i], l[j]);
    l[i] = ca * li + sa * lj;
    l[j] = -sa * li + ca * lj;
}

/// The axes `(outer, middle, centre)` for `centre`.
#[inline]
fn axes(principal: DVec3, centre: Centre) -> [usize; 3] {
    // Sort the three axes by moment (a sorting network; ties keep order).
    let mut o = [0usize, 1, 2];
    let p = principal;
    if p[o[1]] < p[o[0]] {
        o.swap(0, 1);
    }
    if p[o[2]] < p[o[1]] {
        o.swap(1, 2);
    }
    if p[o[1]] < p[o[0]] {
        o.swap(0, 1);
    }
    let [lo, mid, hi] = o;
    match centre {
        Centre::Smallest => [hi, mid, lo],
        Centre::Largest => [lo, mid, hi],
        Centre::BodyX => [2, 1, 0],
    }
}

/// The free rotation of one step: `R_a(h/2) R_b(h/2) R_c(h) R_b(h/2) R_a(h/2)`.
pub(crate) fn free_rotation_with(
    q: DQuat,
    l_b: DVec3,
    inertia: &Inertia,
    h: f64,
    centre: Centre,
) -> (DQuat, DVec3) {
    let [a, b, c] = axes(inertia.principal, centre);
    let (mut q, mut l) = (q, l_b);
    let inv = inertia.inverse;
    rotate_about(&mut q, &mut l, inv, a, 0.5 * h);
    rotate_about(&mut q, &mut l, inv, b, 0.5 * h);
    rotate_about(&mut q, &mut l, inv, c, h);
    rotate_about(&mut q, &mut l, inv, b, 0.5 * h);
    rotate_about(&mut q, &mut l, inv, a, 0.5 * h);
    (q, l)
}

/// `nosquish`'s free rotation over `h` from `(q, L_b)`.
#[inline]
pub(crate) fn free_rotation(q: DQuat, l_b: DVec3, inertia: &Inertia, h: f64) -> (DQuat, DVec3) {
    free_rotation_with(q, l_b, inertia, h, CENTRE)
}

impl Rotator for NoSquish {
    type Aux = Fsal;

    const INFO: RotatorInfo = RotatorInfo {
        name: "nosquish",
        title: "NO_SQUISH symplectic splitting (LAMMPS fix rigid/nve): half-kick, five exact single-axis rotations, half-kick",
        equations: "Miller et al. 2002, Eqs. 2.14-2.18",
        order: 2,
        order_free: 2,
        symplectic: true,
        reversible: true,
        torque_evals: 1,
        torque_contract: super::KDK_TORQUE_CONTRACT,
        contact_contract: super::KDK_CONTACT_CONTRACT,
        closing_kick: true,
        diagnostic: false,
    };

    #[inline]
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut Fsal,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault> {
        let tau = aux.at(t, &torque);
        let l = inertia.principal * rot.omega_b + (0.5 * h) * crate::math::torque_to_body(rot.q, tau);
        let (q, l) = free_rotation(rot.q, l, inertia, h);
        rot.q = q;
        rot.omega_b = inertia.inverse * l;
        Ok(())
    }

    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut Fsal,
        inertia: &Inertia,
        torque: T,
        t_end: f64,
        h: f64,
    ) {
        aux.closing_half_kick(rot, inertia, &torque, t_end, h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_sort_the_moments() {
        let p = DVec3::new(2.0, 1.0, 3.0);
        assert_eq!(axes(p, Centre::Smallest), [2, 0, 1]);
        assert_eq!(axes(p, Centre::Largest), [1, 0, 2]);
        let fibre = DVec3::new(1.0, 5.0, 5.0);
        let [a, b, c] = axes(fibre, Centre::Smallest);
        assert_eq!(c, 0);
        assert!(a != b && a != 0 && b != 0);
    }

    /// Which axis takes the full central sub-step, measured: the final
    /// orientation error against the exact torque-free motion
    /// ([`crate::reference::TorqueFree`]) after 1 s at δt = 1e-3 s, for the
    /// asymmetric top of `scenarios/asymmetric_top.toml` and a precessing
    /// fibre-like symmetric top (1:5:5, ω with an axial part). The largest
    /// moment in the centre is our choice, so it must be the best of the
    /// three on both (`cargo test --release --lib nosquish -- --nocapture` prints them).
    #[test]
    fn nosquish_axis_order() {
        use crate::math::geodesic_angle;
        use crate::reference::TorqueFree;
        let cases = [
            ("asymmetric top", DVec3::new(2e-3, 3e-3, 4e-3), DVec3::new(5.0, 8.0, -6.0)),
            ("fibre-like 1:5:5", DVec3::new(1e-3, 5e-3, 5e-3), DVec3::new(60.0, 25.0, -15.0)),
        ];
        let (dt, steps) = (1e-3, 1000);
        let mut results = vec![];
        for (name, moments, omega) in cases {
            let inertia = Inertia::new(moments);
            let q0 = DQuat::from_xyzw(0.3, -0.2, 0.2449489742783178, 0.9);
            let exact = TorqueFree::new(moments, q0, omega).unwrap().orientation(dt * steps as f64);
            let err = |centre: Centre| {
                let (mut q, mut l) = (q0, moments * omega);
                for _ in 0..steps {
                    (q, l) = free_rotation_with(q, l, &inertia, dt, centre);
                }
                geodesic_angle(q, exact)
            };
            let (s, b, x) = (err(Centre::Smallest), err(Centre::Largest), err(Centre::BodyX));
            println!("{name}: centre smallest {s:.3e} rad, largest {b:.3e}, body x-y-z {x:.3e}");
            results.push((name, s, b, x));
        }
        for (name, s, b, x) in results {
            assert!(b < s && b < x, "{name}: largest {b:e} vs smallest {s:e}, x-y-z {x:e}");
        }
    }
}
