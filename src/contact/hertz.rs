//! Hertzian normal force law: the one place where force and energy of a
//! contact are computed from an overlap.
//!
//! F(δ) = (4/3) E* √R* δ^{3/2},  U(δ) = (8/15) E* √R* δ^{5/2}, so F = dU/dδ
//! (the force pushes the bodies apart, i.e. F = −dU/d(separation)).

/// Constant of the Hertz collision duration `t = C (m*²/(R* E*² v))^{1/5}`
/// for `F = (4/3)E*√R* δ^{3/2}`.
///
/// Derivation: with `k = (4/3)E*√R*`, energy conservation
/// `½ m v² = (2/5) k δ_m^{5/2}` gives `δ_m = (15 m v²/(16 E*√R*))^{2/5}`;
/// `t = 2 ∫₀^{δ_m} dδ / √(v² − (4k/5m) δ^{5/2}) = 2 I δ_m / v` with
/// `I = ∫₀¹ (1 − x^{5/2})^{−1/2} dx = (2/5) B(2/5, 1/2) = 1.4716375921623523`.
/// Hence `C = 2 I (15/16)^{2/5} = 2.8682656991953315`.
pub const HERTZ_CONTACT_TIME_CONSTANT: f64 = 2.868_265_699_195_331_5;

/// Hertz law for one contact: effective modulus and effective radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzLaw {
    /// Effective modulus, 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2 (Pa).
    pub e_star: f64,
    /// Effective radius R* (m).
    pub r_star: f64,
}

/// 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2.
fn effective_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

impl HertzLaw {
    /// Fibre–fibre: 1/R* = 2/D1 + 2/D2 (two crossed cylinders treated as spheres
    /// of the fibre radii: a modelling choice, docs/physics.md §3).
    pub fn fibre_fibre(d1: f64, e1: f64, nu1: f64, d2: f64, e2: f64, nu2: f64) -> Self {
        Self {
            e_star: effective_modulus(e1, nu1, e2, nu2),
            r_star: 1.0 / (2.0 / d1 + 2.0 / d2),
        }
    }

    /// Fibre–wall: R* = D/2 (the wall is flat).
    pub fn fibre_wall(d: f64, e: f64, nu: f64, e_wall: f64, nu_wall: f64) -> Self {
        Self {
            e_star: effective_modulus(e, nu, e_wall, nu_wall),
            r_star: 0.5 * d,
        }
    }

    /// Stiffness k in F = k δ^{3/2}: k = (4/3) E* √R*.
    #[inline]
    pub fn stiffness(&self) -> f64 {
        4.0 / 3.0 * self.e_star * self.r_star.sqrt()
    }

    /// Repulsive force magnitude F = (4/3) E* √R* δ^{3/2}; 0 for δ ≤ 0.
    #[inline]
    pub fn force(&self, overlap: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        self.stiffness() * overlap * overlap.sqrt()
    }

    /// Stored energy U = (8/15) E* √R* δ^{5/2} = (2/5) k δ^{5/2}; 0 for δ ≤ 0.
    #[inline]
    pub fn energy(&self, overlap: f64) -> f64 {
        if overlap <= 0.0 {
            return 0.0;
        }
        0.4 * self.stiffness() * overlap * overlap * overlap.sqrt()
    }

    /// Closed-form duration of a head-on Hertz collision of reduced mass
    /// `m_eff` at approach speed `v_impact`:
    /// `t = C (m*²/(R* E*² v))^{1/5}`, `C` = [`HERTZ_CONTACT_TIME_CONSTANT`].
    pub fn contact_time(&self, m_eff: f64, v_impact: f64) -> f64 {
        HERTZ_CONTACT_TIME_CONSTANT
            * (m_eff * m_eff / (self.r_star * self.e_star * self.e_star * v_impact)).powf(0.2)
    }
}
