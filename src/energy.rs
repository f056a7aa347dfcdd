//! Energy ledger with named terms (docs/physics.md §5, paper Eq. 64–65).

use crate::body::{Bodies, Body, BodyState};
use glam::DVec3;

/// Energy terms of the whole system at one instant, J.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct Ledger {
    /// `Σ m g h` with `h` the height of the centre of mass above z = 0
    /// (in general `−Σ m g·x`).
    pub gravity: f64,
    /// `Σ ½ m v²`.
    pub translation: f64,
    /// `Σ ½ ω_b · I ω_b`.
    pub rotation: f64,
    /// `Σ U` over live contacts (Hertz, docs/physics.md §3).
    pub elastic: f64,
    /// Energy stored in the friction springs of live contacts,
    /// `Σ ½ k_t |ξ|²` (docs/contacts.md, "Friction"; 0 without friction), J.
    pub spring: f64,
    /// Energy removed by the contacts' damping and friction since step 0
    /// (`[contact]` restitution, friction; 0 in elastic frictionless
    /// scenes): the work done against their non-conservative forces less
    /// what the springs hold, J.
    pub dissipated: f64,
}

impl Ledger {
    /// The ledger of `states`, with the contacts' elastic energy.
    pub fn measure(
        bodies: &Bodies,
        states: &[BodyState],
        gravity: Option<DVec3>,
        elastic: f64,
    ) -> Self {
        let mut l = Ledger {
            elastic,
            ..Ledger::default()
        };
        let g = gravity.unwrap_or(DVec3::ZERO);
        for (i, s) in states.iter().enumerate() {
            l.add_body(&bodies[i], s, g);
        }
        l
    }

    /// Add one body's terms (`g` = 0 without gravity). Every component of
    /// `x`, `v` and `ω_b` enters, so a non-finite one makes the total
    /// non-finite (the step's guards rely on it).
    #[inline]
    pub fn add_body(&mut self, b: &Body, s: &BodyState, g: DVec3) {
        self.gravity -= b.mass * g.dot(s.x);
        self.translation += 0.5 * b.mass * s.v.length_squared();
        self.rotation += b.inertia.kinetic_energy(s.rot.omega_b);
    }

    /// Eq. 64: the paper's total (no elastic term).
    pub fn total(&self) -> f64 {
        self.gravity + self.translation + self.rotation
    }

    /// Eq. 64 plus the elastic and spring energy of live contacts and the
    /// energy dissipated so far: the conserved budget.
    pub fn total_full(&self) -> f64 {
        self.total() + self.elastic + self.spring + self.dissipated
    }
}

/// Eq. 65, in percent: `|E_n − E_0| / |E_0| × 100`. NaN when `E_0 = 0` (a body
/// starting at rest with no gravity, as in test cases 3–4, where the prescribed
/// torque does work and Eq. 65 has no meaning).
pub fn error_pct(e: f64, e0: f64) -> f64 {
    if e0 == 0.0 {
        f64::NAN
    } else {
        ((e - e0) / e0).abs() * 100.0
    }
}
