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
//! The force itself is made by the contact law (`contact/law/`), whose
//! non-conservative part it is; its work is accounted by the ledger of
//! every non-conservative load (`contact/ledger.rs`).

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
