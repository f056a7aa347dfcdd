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
//! 3. The trial force `f = −k_t ξ − η_t v_t` (Eq. 12).
//! 4. Coulomb: if `|f| > μ F_n` the contact slides: `f ← μ F_n f/|f|`, and
//!    the spring is reset to hold that whole force, `ξ ← −f/k_t`: while
//!    it slides the damping takes no part (LIGGGHTS'
//!    `tangential_model_history`; Cundall & Strack's spring at the slip
//!    limit). The total tangential force, damping included, never exceeds
//!    `μ F_n`.
//!
//! Why not Luding's Eq. 13, `ξ ← −(f + η_t v_t)/k_t` (the spring with the
//! damping gives the capped force, as LAMMPS's `gran/hertz/history`):
//! where the damping term alone exceeds the cap, early in a damped impact,
//! it stores the spring *along* the slip, and as `k_t ∝ δ^{1/2}` grows
//! faster than `η_t ∝ δ^{1/4}` while the contact loads, the next trial
//! force points along the slip and friction pushes the sliding contact
//! forward. With the spring holding `−f/k_t`, the next trial is
//! `(k_t'/k_t) f − (k_t' δt + η_t) v_t`: every part of it opposes a slip
//! that keeps its direction, so a sliding contact is always braked.
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
    /// Whether the contact slides this step (the Coulomb cap holds).
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
    let trial = -k_t * *xi - eta_t * v_t;
    let size2 = trial.length_squared();
    if size2 <= cap * cap {
        return TangentialForce {
            force: trial,
            sliding: false,
        };
    }
    let force = trial * (cap / size2.sqrt());
    *xi = -force / k_t;
    TangentialForce {
        force,
        sliding: true,
    }
}

/// The energy the spring `xi` of stiffness `k_t` holds and can give back,
/// J: `½ k_t |ξ|²`. A sliding contact's spring holds the cap, `½ (μ
/// F_n)²/k_t` (step 4); a sticking one can hold more only while its
/// damping opposes the spring, that is while the spring unloads and gives
/// that energy back.
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
    /// along the trial force; the spring alone holds it.
    #[test]
    fn a_sliding_contact_pulls_with_the_cap() {
        let (k, eta, cap) = (2e4, 0.5, 1e-3);
        let v = DVec3::new(0.3, -0.4, 0.0);
        let mut xi = DVec3::new(1e-4, 0.0, 0.0);
        let trial = -k * (xi + v * DT) - eta * v;
        let f = step_spring(&mut xi, DVec3::Z, v, DT, k, eta, cap);
        assert!(f.sliding);
        assert!((f.force.length() / cap - 1.0).abs() < 1e-15, "{f:?}");
        assert!(
            (f.force.normalize() - trial.normalize()).length() < 1e-15,
            "{f:?} {trial}"
        );
        let back = -k * xi;
        assert!((back - f.force).length() < 4e-16 * cap, "{back} {f:?}");
        assert!(
            (spring_energy(xi, k) / (cap * cap / (2.0 * k)) - 1.0).abs() < 1e-15,
            "the spring holds the cap"
        );
        // No normal force, no tangential force.
        let g = step_spring(&mut xi, DVec3::Z, v, DT, k, 0.0, 0.0);
        assert_eq!((g.force, xi), (DVec3::ZERO, DVec3::ZERO));
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
