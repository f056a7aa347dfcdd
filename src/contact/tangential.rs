//! The tangential part of a contact law: Coulomb friction with a tangential
//! spring, the standard of DEM codes (Cundall & Strack, Géotechnique 29
//! (1979) 47), with Mindlin's no-slip stiffness (Mindlin, J. Appl. Mech. 16
//! (1949) 259; as in Di Renzo & Di Maio, Chem. Eng. Sci. 59 (2004) 525) and
//! the spring kept in the tangent plane (Luding, Granular Matter 10 (2008)
//! 235, §2.2).
//!
//! Per contact point and step, with `n` the contact normal (from B to A),
//! `v = v_A(p) − v_B(p)` the relative velocity of the bodies' material
//! points at the point and `ξ` the spring (the contact's history record):
//! 1. `ξ` is turned into the new tangent plane, its length kept (Luding's
//!    Eq. 11): `ξ ← |ξ| ξ_⊥/|ξ_⊥|`, `ξ_⊥ = ξ − (n·ξ) n`.
//! 2. It stretches with the tangential motion: `v_t = v − (n·v) n`,
//!    `ξ ← ξ + v_t δt`.
//! 3. The spring's force `f_s = −k_t ξ`, and the trial force `f = f_s −
//!    η_t v_t` (Eq. 12).
//! 4. Coulomb, decided on the spring's force alone (as LIGGGHTS'
//!    `tangential_model_history`): if `|f_s| > μ F_n` the contact slides:
//!    `f ← μ F_n f_s/|f_s|`, and the spring is reset to hold that whole
//!    force, `ξ ← −f/k_t`: while it slides the damping takes no part
//!    (Cundall & Strack's spring at the slip limit). Otherwise it sticks
//!    and keeps its spring; its force is the trial `f`, scaled to `μ F_n`
//!    along itself where the damping takes it beyond (which LIGGGHTS does
//!    not do). The total tangential force, damping included, never exceeds
//!    `μ F_n`.
//!
//! Why decide on the spring: the spring is an integral of the motion (it
//! sums `v_t δt`), the damping term the instantaneous velocity at the half
//! step. A test on the whole trial force resets the spring whenever the
//! damping tips it over the cap, and on a resting damped contact, whose
//! spring sits near the cap while its velocity jitters about zero, that
//! tips it between sticking and sliding from step to step, differently at
//! each δt: the reset, a jump of the spring, then follows the velocity's
//! noise and the trajectories stop converging in δt. Decided on the
//! spring, a contact slides only once its accumulated displacement loads
//! the spring to the cap; the damping's excess over the cap is still cut
//! (a sticking force above it is scaled down), and the spring is left as
//! the motion made it.
//!
//! Why not Luding's Eq. 13, `ξ ← −(f + η_t v_t)/k_t` (the spring with the
//! damping gives the capped force, as LAMMPS's `gran/hertz/history`):
//! where the damping term alone exceeds the cap, early in a damped impact,
//! it stores the spring *along* the slip, and as `k_t ∝ δ^{1/2}` grows
//! faster than `η_t ∝ δ^{1/4}` while the contact loads, the next trial
//! force points along the slip and friction pushes the sliding contact
//! forward. With the spring holding `−f/k_t`, the next spring force is
//! `(k_t'/k_t) f − k_t' δt v_t` and the next trial adds `−η_t v_t`: every
//! part of either opposes a slip that keeps its direction, so a sliding
//! contact is always braked.
//!
//! `k_t = 8 G* a` with the contact radius `a = √(R* δ)` and
//! `1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂`, `G = E/(2(1+ν))`. The tangential damping
//! follows the normal one: both are `α √(m* S)` with `S` the linearised
//! stiffness (`S_n = 2 E* a`, `S_t = 8 G* a`), so `η_t = η_n √(S_t/S_n) =
//! 2 η_n √(G*/E*)`.

use glam::DVec3;

/// A scene's Coulomb coefficients: body–body and body–wall, the defaults
/// of materials without their own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// μ of body–body contacts.
    pub body: f64,
    /// μ of body–wall contacts, the walls' own.
    pub wall: f64,
}

impl Friction {
    /// μ of a contact between two bodies whose materials have their own
    /// coefficients `a`, `b` (`None`: [`Friction::body`]): the smaller,
    /// as Yade's `FrictMat` takes the smaller friction angle (`tan` is
    /// increasing): a pair slides as soon as its slipperier surface lets
    /// it, and each material's μ is what it shows against itself.
    pub fn pair(&self, a: Option<f64>, b: Option<f64>) -> f64 {
        a.unwrap_or(self.body).min(b.unwrap_or(self.body))
    }

    /// μ of a contact between a body whose material has its own
    /// coefficient `a` (`None`: [`Friction::wall`]) and a wall: the
    /// smaller of it and the walls' [`Friction::wall`].
    pub fn against_wall(&self, a: Option<f64>) -> f64 {
        a.unwrap_or(self.wall).min(self.wall)
    }
}

/// The tangential constants of a pair of materials.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangential {
    /// Coulomb coefficient μ.
    pub mu: f64,
    /// Effective shear modulus G*, Pa.
    pub g_star: f64,
}

/// `G = E/(2(1+ν))`.
fn shear_modulus(e: f64, nu: f64) -> f64 {
    e / (2.0 * (1.0 + nu))
}

impl Tangential {
    /// The law of two materials `(E₁, ν₁)`, `(E₂, ν₂)` with coefficient `mu`:
    /// `1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂`.
    pub fn new(mu: f64, e1: f64, nu1: f64, e2: f64, nu2: f64) -> Self {
        let inv = (2.0 - nu1) / shear_modulus(e1, nu1) + (2.0 - nu2) / shear_modulus(e2, nu2);
        Tangential {
            mu,
            g_star: 1.0 / inv,
        }
    }

    /// Mindlin's no-slip stiffness `k_t = 8 G* √(R* δ)`, N/m; 0 out of
    /// contact.
    pub fn stiffness(&self, r_star: f64, overlap: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        8.0 * self.g_star * (r_star * overlap).sqrt()
    }
}

/// A step's tangential force at a contact point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentialForce {
    /// The force on A (B gets minus it), N.
    pub force: DVec3,
    /// Whether the contact slides this step: its spring reached the Coulomb
    /// cap and was reset to it (a sticking contact's force can be at the
    /// cap too, its damping cut).
    pub sliding: bool,
}

/// One step of the spring `xi` of a contact with normal `n` (unit),
/// relative velocity `v`, stiffness `k_t > 0`, damping `eta_t ≥ 0` and
/// Coulomb cap `cap = μ F_n ≥ 0`: steps 1–4 of the module documentation.
/// A spring along the new normal (a contact whose plane turned by a right
/// angle in one step) has no direction in the new plane and is dropped.
#[inline]
pub fn step_spring(
    xi: &mut DVec3,
    n: DVec3,
    v: DVec3,
    dt: f64,
    k_t: f64,
    eta_t: f64,
    cap: f64,
) -> TangentialForce {
    // (Lengths compared and scaled squared: one square root where two
    // would do the same.)
    let length2 = xi.length_squared();
    let turned = *xi - n.dot(*xi) * n;
    let across2 = turned.length_squared();
    *xi = if across2 > 0.0 {
        turned * (length2 / across2).sqrt()
    } else {
        DVec3::ZERO
    };
    let v_t = v - n.dot(v) * n;
    *xi += v_t * dt;
    let spring = -k_t * *xi;
    let spring2 = spring.length_squared();
    if spring2 <= cap * cap {
        let trial = spring - eta_t * v_t;
        let trial2 = trial.length_squared();
        return TangentialForce {
            force: if trial2 <= cap * cap {
                trial
            } else {
                trial * (cap / trial2.sqrt())
            },
            sliding: false,
        };
    }
    let force = spring * (cap / spring2.sqrt());
    *xi = -force / k_t;
    TangentialForce {
        force,
        sliding: true,
    }
}

/// The energy the spring `xi` of stiffness `k_t` holds and can give back,
/// J: `½ k_t |ξ|²`. No spring holds more than the cap's `½ (μ F_n)²/k_t`
/// (step 4): a sliding contact's holds exactly that, a sticking one's
/// force `k_t |ξ|` is within the cap by the very test that keeps it.
/// Where a sticking force is cut to the cap, the work done against it in
/// the step, `μ F_n u·v_t δt` with `u` the unit `k_t ξ + η_t v_t`, is at
/// least the spring's gain `k_t ξ·v_t δt − ½ k_t |v_t δt|²`: `u` lies
/// between `ξ` and `v_t` in angle and at most a right angle from `v_t`
/// (`|k_t ξ + η_t v_t| > μ F_n ≥ k_t |ξ|`), so the cut is a loss.
pub fn spring_energy(xi: DVec3, k_t: f64) -> f64 {
    0.5 * k_t * xi.length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f64 = 1e-6;

    /// `G*` of two equal materials: `G/(2(2−ν))` (the formula written out).
    #[test]
    fn effective_shear_modulus_of_equal_materials() {
        let (e, nu) = (5e7, 0.35);
        let g = e / (2.0 * 1.35);
        let t = Tangential::new(0.3, e, nu, e, nu);
        assert!((t.g_star / (g / (2.0 * (2.0 - nu))) - 1.0).abs() < 1e-15);
        // k_t = 8 G* a, a = √(R* δ): R* = 2.5 mm, δ = 10 µm → a = 1.58e-4 m.
        let a = (2.5e-3f64 * 1e-5).sqrt();
        assert!((t.stiffness(2.5e-3, 1e-5) / (8.0 * t.g_star * a) - 1.0).abs() < 1e-15);
        assert_eq!(t.stiffness(2.5e-3, -1e-9), 0.0);
    }

    /// A spring in the old tangent plane, the normal turned by 30°: the
    /// spring lies in the new plane with its length (Luding 2008, Eq. 11).
    #[test]
    fn the_spring_turns_with_the_plane_and_keeps_its_length() {
        let mut xi = DVec3::new(3e-6, 4e-6, 0.0);
        let (s, c) = 30f64.to_radians().sin_cos();
        let n = DVec3::new(s, 0.0, c);
        let f = step_spring(&mut xi, n, DVec3::ZERO, DT, 1e4, 0.0, 1.0);
        assert!((xi.length() / 5e-6 - 1.0).abs() < 1e-15, "{xi}");
        assert!(xi.dot(n).abs() < 1e-21, "{xi}");
        assert_eq!(f.force, -1e4 * xi);
        assert!(!f.sliding);
        // Turned by a right angle: nothing is left to turn.
        let mut xi = DVec3::new(0.0, 0.0, 1e-6);
        let f = step_spring(&mut xi, DVec3::Z, DVec3::ZERO, DT, 1e4, 0.0, 1.0);
        assert_eq!((xi, f.force), (DVec3::ZERO, DVec3::ZERO));
    }

    /// Sticking: a constant tangential speed `u` stretches the spring by
    /// `u δt` a step, the force is `−k_t ξ − η_t v_t`, and the normal part
    /// of the velocity does not stretch it.
    #[test]
    fn a_sticking_contact_is_a_spring_and_a_dashpot() {
        let (k, eta, u) = (2e4, 0.5, 1e-3);
        let v = DVec3::new(u, 0.0, -7.0);
        let mut xi = DVec3::ZERO;
        let mut f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, 1.0);
        for _ in 1..1000 {
            f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, 1.0);
        }
        let stretched = 1000.0 * u * DT;
        assert!((xi.x / stretched - 1.0).abs() < 1e-12 && xi.y == 0.0 && xi.z == 0.0);
        let expected = -k * stretched - eta * u;
        assert!((f.force.x / expected - 1.0).abs() < 1e-12, "{f:?}");
        assert!(!f.sliding);
    }

    /// Sliding: the total force, damping included, is exactly the cap,
    /// along the spring's force; the spring alone holds it, and the
    /// damping takes no part (the same bits without it).
    #[test]
    fn a_sliding_contact_pulls_with_the_cap() {
        let (k, eta, cap) = (2e4, 0.5, 1e-3);
        let v = DVec3::new(0.3, -0.4, 0.0);
        let start = DVec3::new(1e-4, 0.0, 0.0);
        let spring = -k * (start + v * DT);
        let mut xi = start;
        let f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, cap);
        assert!(f.sliding);
        assert!((f.force.length() / cap - 1.0).abs() < 1e-15, "{f:?}");
        assert!(
            (f.force.normalize() - spring.normalize()).length() < 1e-15,
            "{f:?} {spring}"
        );
        let back = -k * xi;
        assert!((back - f.force).length() < 4e-16 * cap, "{back} {f:?}");
        assert!(
            (spring_energy(xi, k) / (cap * cap / (2.0 * k)) - 1.0).abs() < 1e-15,
            "the spring holds the cap"
        );
        let mut undamped = start;
        let g = step_spring(&mut undamped, DVec3::Z, v, DT, k, 0.0, cap);
        assert_eq!((g, undamped), (f, xi));
        // No normal force, no tangential force.
        let g = step_spring(&mut xi, DVec3::Z, v, DT, k, 0.0, 0.0);
        assert_eq!((g.force, xi), (DVec3::ZERO, DVec3::ZERO));
    }

    /// Sticking is decided on the spring: a contact whose spring is within
    /// the cap, `|k_t ξ| < μ F_n`, but whose damping takes the trial over
    /// it, `|k_t ξ + η_t v_t| > μ F_n`, sticks: its force is the cap along
    /// the trial force and its spring is the one the motion made, `ξ + v_t
    /// δt` (a test on the whole trial force would slide it and reset the
    /// spring to `−f/k_t`).
    #[test]
    fn the_damping_does_not_make_a_contact_slide() {
        let (k, eta, cap) = (2e4, 0.5, 1e-3);
        // The spring at 0.8 of the cap along x, the velocity across it:
        // the stretch adds 0.024 cap along y to the spring (|f_s| = 0.8004
        // cap), the damping η_t |v_t| = 0.6 cap (|f| = 1.015 cap).
        let start = DVec3::new(0.8 * cap / k, 0.0, 0.0);
        let v = DVec3::new(0.0, 1.2e-3, 0.0);
        let moved = start + v * DT;
        let spring = -k * moved;
        let trial = spring - eta * v;
        assert!(
            spring.length() < cap && trial.length() > cap,
            "{spring} {trial}"
        );
        let mut xi = start;
        let f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, cap);
        assert!(!f.sliding, "{f:?}");
        assert_eq!(xi, moved, "the spring is kept");
        assert!((f.force.length() / cap - 1.0).abs() < 1e-15, "{f:?}");
        assert!(
            (f.force.normalize() - trial.normalize()).length() < 1e-15,
            "{f:?} {trial}"
        );
        assert!(spring_energy(xi, k) < cap * cap / (2.0 * k));
        // The cut is a loss: the work done against the force is at least
        // what the spring gained (module documentation, `spring_energy`).
        let gained = spring_energy(xi, k) - spring_energy(start, k);
        assert!(-f.force.dot(v) * DT >= gained, "{gained:e}");
    }

    /// A resting damped contact whose spring sits near the cap while its
    /// velocity jitters about zero (±u on alternate steps, the damping's
    /// term `η_t u` = 0.3 of the cap): the spring comes back to where it
    /// was every second step and never slides, whatever the jitter's phase.
    /// (A test on the whole trial force slides it on every step whose
    /// damping adds to the spring, resetting the spring each time: it
    /// drifts, by the jitter.)
    #[test]
    fn a_jittering_contact_near_the_cap_keeps_its_spring() {
        let (k, eta, cap) = (2e4, 0.5, 1e-3);
        let u = 0.3 * cap / eta;
        let start = DVec3::new(0.9 * cap / k, 0.0, 0.0);
        for first in [1.0, -1.0] {
            let mut xi = start;
            for step in 0..1000 {
                let sign = if step % 2 == 0 { first } else { -first };
                let f = step_spring(
                    &mut xi,
                    DVec3::Z,
                    DVec3::new(sign * u, 0.0, 0.0),
                    DT,
                    k,
                    eta,
                    cap,
                );
                assert!(!f.sliding, "step {step}, first {first}: {f:?}");
                assert!(f.force.length() <= cap * (1.0 + 1e-15), "{f:?}");
            }
            assert!(
                (xi - start).length() < 1e-12 * start.length(),
                "first {first}: {xi} against {start}"
            );
        }
    }

    /// Reversal (η = 0): from sliding at +cap, moving back by `s` takes the
    /// force down by `k_t s` (the spring's line); it slides again, the other
    /// way, once `s = 2 cap / k_t`.
    #[test]
    fn a_reversed_contact_unloads_along_the_spring_then_slides_back() {
        let (k, cap, u) = (2e4, 1e-3, 1e-2);
        let mut xi = DVec3::ZERO;
        for _ in 0..100 {
            step_spring(&mut xi, DVec3::Z, DVec3::new(u, 0.0, 0.0), DT, k, 0.0, cap);
        }
        assert!(
            (k * xi.x / cap - 1.0).abs() < 1e-12,
            "slid to the cap: {xi}"
        );
        let back = DVec3::new(-u, 0.0, 0.0);
        let steps_to_slide = (2.0 * cap / k / (u * DT)).round() as usize;
        for m in 1..steps_to_slide {
            let f = step_spring(&mut xi, DVec3::Z, back, DT, k, 0.0, cap);
            let expected = -cap + k * m as f64 * u * DT;
            assert!(
                (f.force.x - expected).abs() < 1e-12 * cap,
                "step {m}: {f:?}"
            );
            assert!(!f.sliding, "step {m}");
        }
        let f = step_spring(&mut xi, DVec3::Z, back, DT, k, 0.0, cap);
        assert!(
            f.force.x > 0.0 && (f.force.x / cap - 1.0).abs() < 1e-9,
            "{f:?}"
        );
        // The spring at the cap holds cap²/(2 k_t).
        let held = spring_energy(xi, k);
        assert!(
            (held / (cap * cap / (2.0 * k)) - 1.0).abs() < 1e-9,
            "{held}"
        );
    }

    /// A damped contact sliding at a constant slip while its stiffness
    /// grows faster than its damping (`k_t ∝ δ^{1/2}`, `η_t ∝ δ^{1/4}`, a
    /// loading Hertz contact) with a damping term far above the cap: the
    /// force stays the cap, against the slip, every step. (Luding's reset
    /// `ξ = −(f + η_t v_t)/k_t` stores the spring along the slip here and
    /// pushes the contact forward from the second step on.)
    #[test]
    fn a_damped_sliding_contact_is_braked_while_it_loads() {
        let v = DVec3::new(1.5, 0.0, 0.0);
        let mut xi = DVec3::ZERO;
        for step in 1..=200 {
            let delta = step as f64 * 1e-8;
            let (k, eta, cap) = (
                1e7 * delta.sqrt(),
                30.0 * delta.sqrt().sqrt(),
                1e6 * delta.powf(1.5),
            );
            assert!(eta * v.length() > cap);
            let f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, cap);
            assert!(f.sliding, "step {step}");
            assert!(
                f.force.x < 0.0 && (f.force.length() / cap - 1.0).abs() < 1e-12,
                "step {step}: {f:?}, cap {cap:e}"
            );
        }
    }
}
