//! Jacobi elliptic functions and Carlson's symmetric elliptic integrals, in
//! f64 to rounding, for the torque-free rigid body ([`super::torque_free`]).
//!
//! - `sn, cn, dn, am` by the arithmetic–geometric mean and its descending
//!   Landen recursion (Abramowitz & Stegun 16.4; DLMF 22.20(ii)).
//! - `R_F`, `R_C`, `R_J` by Carlson's duplication algorithms (B. C. Carlson,
//!   *Numerical computation of real or complex elliptic integrals*, Numer.
//!   Algorithms 10 (1995) 13–26, Eqs. 2.2–2.3, 2.14–2.15, 2.36–2.39;
//!   DLMF 19.36(i)), and from them Legendre's incomplete integrals
//!   `F(φ|m)` and `Π(n; φ|m)` for any real amplitude (DLMF 19.25.5, 19.25.14,
//!   continued by quasi-periodicity, DLMF 19.2.10).
//!
//! Parameters are `m = k²` and its complement `m1 = 1 − m`, passed apart so
//! that a motion near the separatrix (`m1 → 0`) keeps its digits.

use std::f64::consts::{FRAC_PI_2, PI};

/// Relative tolerance of the duplication algorithms: their truncated series
/// then err by less than rounding (Carlson 1995, Eq. 2.2 with `r = 1e-16`
/// gives a relative error below `r`).
const TOL: f64 = 1e-16;

/// The AGM stops when `|a − b| ≤ AGM_TOL a`: it converges quadratically, so
/// what is left, `(a − b)²/(8a)`, is below 1e-30 relative. (A tolerance
/// below the spacing of doubles could wait forever on a one-ulp gap.)
const AGM_TOL: f64 = 1e-15;

/// `sn`, `cn`, `dn` and the amplitude `am` of one argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jacobi {
    /// `sn(u|m) = sin am(u)`.
    pub sn: f64,
    /// `cn(u|m) = cos am(u)`.
    pub cn: f64,
    /// `dn(u|m) = √(1 − m sn²)`.
    pub dn: f64,
    /// The amplitude `am(u|m)`, continuous in `u` (not reduced to a period).
    pub am: f64,
}

/// Jacobi's elliptic functions of `u` with parameter `m ∈ [0, 1]`
/// (complement `m1`). The AGM of `(1, √m1)` converges quadratically (six
/// steps for `m1 = 1e-8`); the amplitude comes back down the descending Landen
/// recursion `φ_{n−1} = (φ_n + asin(c_n sin φ_n / a_n))/2` from
/// `φ_N = 2^N a_N u` (A&S 16.4.2–3), so it is continuous in `u`. At `m1 = 0`
/// the functions are `tanh`, `sech`, `sech` and `am = gd(u)`.
pub fn jacobi(u: f64, m: f64, m1: f64) -> Jacobi {
    if m1 <= 0.0 {
        let (sn, sech) = (u.tanh(), 1.0 / u.cosh());
        return Jacobi {
            sn,
            cn: sech,
            dn: sech,
            am: sn.atan2(sech),
        };
    }
    if m <= 0.0 {
        let (s, c) = u.sin_cos();
        return Jacobi {
            sn: s,
            cn: c,
            dn: 1.0,
            am: u,
        };
    }
    const N: usize = 16;
    let mut a = [0.0; N + 1];
    let mut c = [0.0; N + 1];
    a[0] = 1.0;
    let mut b = m1.sqrt();
    c[0] = m.sqrt();
    let mut n = 0;
    while n < N && c[n].abs() > AGM_TOL * a[n] {
        a[n + 1] = 0.5 * (a[n] + b);
        c[n + 1] = 0.5 * (a[n] - b);
        b = (a[n] * b).sqrt();
        n += 1;
    }
    let mut phi = f64::powi(2.0, n as i32) * a[n] * u;
    for k in (1..=n).rev() {
        phi = 0.5 * (phi + (c[k] / a[k] * phi.sin()).asin());
    }
    let (sn, cn) = phi.sin_cos();
    // dn² = 1 − m sn² = m1 + m cn²: no cancellation, and dn errs by no more
    // than cn does (absolute). A&S 16.4.4's cos φ₀ / cos(φ₁ − φ₀) is 0/0 at
    // u = K near the separatrix.
    let dn = (m1 + m * cn * cn).sqrt();
    Jacobi {
        sn,
        cn,
        dn,
        am: phi,
    }
}

/// The complete integral `K(m) = π / (2 AGM(1, √m1))` (DLMF 19.8.5).
pub fn complete_k(m1: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, m1.sqrt());
    if b == 0.0 {
        return f64::INFINITY;
    }
    for _ in 0..40 {
        if (a - b).abs() <= AGM_TOL * a {
            break;
        }
        let an = 0.5 * (a + b);
        b = (a * b).sqrt();
        a = an;
    }
    // (a + b)/2 is the AGM to (a − b)²/(8a).
    PI / (a + b)
}

/// Carlson's `R_F(x, y, z)`, `x, y, z ≥ 0`, at most one zero (Carlson 1995,
/// Eqs. 2.2–2.3).
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (mut x, mut y, mut z) = (x, y, z);
    let a0 = (x + y + z) / 3.0;
    let q = (3.0 * TOL).powf(-1.0 / 6.0) * (a0 - x).abs().max((a0 - y).abs()).max((a0 - z).abs());
    let (x0, y0) = (x, y);
    let mut a = a0;
    let mut fac = 1.0; // 4^-m
                       // Each pass divides the spread by 4; 60 passes exceed any f64 range,
                       // and end the loop on invalid (NaN, infinite) arguments.
    for _ in 0..60 {
        if fac * q < a.abs() {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * sy + sx * sz + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        a = 0.25 * (a + lam);
        fac *= 0.25;
    }
    let xx = (a0 - x0) * fac / a;
    let yy = (a0 - y0) * fac / a;
    let zz = -xx - yy;
    let e2 = xx * yy - zz * zz;
    let e3 = xx * yy * zz;
    (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / a.sqrt()
}

/// `R_C(1, 1 + e)` for `e > −1`: `atan(√e)/√e`, or `atanh(√−e)/√−e` for
/// `e < 0` (DLMF 19.2.18–19); for small `|e|` the Taylor series of the same
/// function, whose closed forms lose digits there.
fn rc_one(e: f64) -> f64 {
    if e.abs() < 1e-3 {
        // atan(√e)/√e = Σ (−e)^k / (2k + 1): 7 terms leave < 1e-21.
        let mut term = 1.0;
        let mut sum = 1.0;
        for k in 1..8 {
            term *= -e;
            sum += term / (2 * k + 1) as f64;
        }
        sum
    } else if e > 0.0 {
        let s = e.sqrt();
        s.atan() / s
    } else {
        let s = (-e).sqrt();
        s.atanh() / s
    }
}

/// Carlson's `R_J(x, y, z, p)`, `x, y, z ≥ 0` (at most one zero), `p > 0`
/// (Carlson 1995, Eqs. 2.36–2.39; the `R_C` terms as [`rc_one`]).
pub fn carlson_rj(x: f64, y: f64, z: f64, p: f64) -> f64 {
    let (mut x, mut y, mut z, mut p) = (x, y, z, p);
    let a0 = (x + y + z + 2.0 * p) / 5.0;
    let delta = (p - x) * (p - y) * (p - z);
    let q = (0.25 * TOL).powf(-1.0 / 6.0)
        * (a0 - x)
            .abs()
            .max((a0 - y).abs())
            .max((a0 - z).abs())
            .max((a0 - p).abs());
    let (x0, y0, z0) = (x, y, z);
    let mut a = a0;
    let mut fac = 1.0; // 4^-m
    let mut sum = 0.0;
    for _ in 0..60 {
        if fac * q < a.abs() {
            break;
        }
        let (sx, sy, sz, sp) = (x.sqrt(), y.sqrt(), z.sqrt(), p.sqrt());
        let lam = sx * sy + sx * sz + sy * sz;
        let d = (sp + sx) * (sp + sy) * (sp + sz);
        let e = fac * fac * fac * delta / (d * d);
        sum += fac * rc_one(e) / d;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
        p = 0.25 * (p + lam);
        a = 0.25 * (a + lam);
        fac *= 0.25;
    }
    let xx = (a0 - x0) * fac / a;
    let yy = (a0 - y0) * fac / a;
    let zz = (a0 - z0) * fac / a;
    let pp = -0.5 * (xx + yy + zz);
    let e2 = xx * yy + xx * zz + yy * zz - 3.0 * pp * pp;
    let e3 = xx * yy * zz + 2.0 * e2 * pp + 4.0 * pp * pp * pp;
    let e4 = (2.0 * xx * yy * zz + e2 * pp + 3.0 * pp * pp * pp) * pp;
    let e5 = xx * yy * zz * pp * pp;
    let series = 1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0
        + 3.0 * e5 / 26.0;
    fac * series / (a * a.sqrt()) + 6.0 * sum
}

/// Legendre's complete integrals of one parameter, kept with it so the
/// incomplete ones can be continued past `|φ| = π/2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Legendre {
    /// `m = k²`.
    pub m: f64,
    /// `1 − m`.
    pub m1: f64,
    /// The characteristic `n` of `Π` (DLMF's `α²`).
    pub n: f64,
    /// `K(m)`.
    pub k: f64,
    /// `Π(n|m)`, the complete integral of the third kind.
    pub pi: f64,
}

impl Legendre {
    /// The complete integrals for parameter `m` (complement `m1`) and
    /// characteristic `n < 1`.
    pub fn new(m: f64, m1: f64, n: f64) -> Self {
        let k = complete_k(m1);
        // DLMF 19.25.2 at φ = π/2: Π = R_F(0, m1, 1) + (n/3) R_J(0, m1, 1, 1 − n).
        let pi = k + n / 3.0 * carlson_rj(0.0, m1, 1.0, 1.0 - n);
        Legendre { m, m1, n, k, pi }
    }

    /// `F(φ|m) = ∫₀^φ dθ / √(1 − m sin²θ)` for any real `φ`.
    pub fn f(&self, phi: f64) -> f64 {
        let (j, r) = reduce(phi);
        let (s, c) = r.sin_cos();
        // 1 − m s² as m1 + m c²: no cancellation near the separatrix.
        2.0 * j * self.k + s * carlson_rf(c * c, self.m1 + self.m * c * c, 1.0)
    }

    /// `Π(n; φ|m) = ∫₀^φ dθ / ((1 − n sin²θ) √(1 − m sin²θ))` for any real `φ`
    /// (DLMF 19.25.14 in the sine form).
    pub fn pi(&self, phi: f64) -> f64 {
        let (j, r) = reduce(phi);
        let (s, c) = r.sin_cos();
        let s2 = s * s;
        let delta2 = self.m1 + self.m * c * c;
        2.0 * j * self.pi
            + s * carlson_rf(c * c, delta2, 1.0)
            + self.n / 3.0 * s * s2 * carlson_rj(c * c, delta2, 1.0, 1.0 - self.n * s2)
    }
}

/// `φ = jπ + r` with `|r| ≤ π/2`: both integrands have period π in θ.
fn reduce(phi: f64) -> (f64, f64) {
    let j = (phi / PI).round();
    let r = phi - j * PI;
    // Rounding can leave |r| a hair above π/2; sin and cos are fine there.
    debug_assert!(r.abs() <= FRAC_PI_2 + 1e-12);
    (j, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Gauss–Legendre (8 points per panel) of `f` on `[a, b]`: an
    /// independent evaluation of the integrals' definitions.
    fn quad(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
        const X: [f64; 4] = [
            0.183_434_642_495_649_8,
            0.525_532_409_916_329,
            0.796_666_477_413_626_7,
            0.960_289_856_497_536_3,
        ];
        const W: [f64; 4] = [
            0.362_683_783_378_362,
            0.313_706_645_877_887_3,
            0.222_381_034_453_374_5,
            0.101_228_536_290_376_3,
        ];
        let h = (b - a) / panels as f64;
        // Neumaier's compensated sum: 10⁵ plain additions would round to
        // ~1e-13, above what is being tested.
        let (mut s, mut comp) = (0.0f64, 0.0f64);
        for p in 0..panels {
            let mid = a + (p as f64 + 0.5) * h;
            for (x, w) in X.iter().zip(W) {
                let term = w * (f(mid - 0.5 * h * x) + f(mid + 0.5 * h * x));
                let t = s + term;
                comp += if s.abs() >= term.abs() {
                    (s - t) + term
                } else {
                    (term - t) + s
                };
                s = t;
            }
        }
        0.5 * h * (s + comp)
    }

    /// Carlson 1995, §3 test values (printed to 14 digits there), and
    /// `R_F(1, 2, 0) = K(1/2)/√2 = Γ(1/4)²/(4√(2π))` in closed form.
    #[test]
    fn carlson_test_values() {
        let cases = [
            (carlson_rf(1.0, 2.0, 0.0), 1.311_028_777_146_059_9),
            (carlson_rf(2.0, 3.0, 4.0), 0.584_082_841_677_15),
            (carlson_rj(0.0, 1.0, 2.0, 3.0), 0.776_886_237_785_82),
            (carlson_rj(2.0, 3.0, 4.0, 5.0), 0.142_975_796_671_57),
        ];
        for (got, want) in cases {
            assert!((got - want).abs() < 2e-14, "{got} vs {want}");
        }
    }

    /// F and Π against quadrature of their definitions, over parameters from
    /// the circle to the separatrix, amplitudes past several half-periods,
    /// and the characteristics the torque-free top uses (n < 0).
    #[test]
    fn legendre_integrals_match_quadrature() {
        let mut worst: f64 = 0.0;
        for &m1 in &[1.0, 0.9, 0.5, 0.1, 1e-3, 1e-6] {
            let m = 1.0 - m1;
            for &n in &[0.0, -0.3, -2.5, -40.0, 0.6] {
                let l = Legendre::new(m, m1, n);
                for &phi in &[0.3, 1.2, FRAC_PI_2, 2.9, -4.0, 11.0] {
                    // 1 − m sin² as m1 + m cos²: no cancellation at the peak.
                    let df = |t: f64| 1.0 / (m1 + m * t.cos().powi(2)).sqrt();
                    let dp = |t: f64| df(t) / (1.0 - n * t.sin().powi(2));
                    // The integrands peak at θ = π/2 with width √m1: panels
                    // well below that width, or the quadrature is the error.
                    let refine = (0.03 / m1.sqrt()).max(1.0);
                    let panels = ((400.0 + phi.abs() * 400.0) * refine) as usize;
                    let (qf, qp) = (quad(df, 0.0, phi, panels), quad(dp, 0.0, phi, panels));
                    // At m1 = 1e-6 the quadrature itself is good to ~2e-14
                    // (the peak is ill-conditioned in θ); spot checks there
                    // against mpmath 1.3 `ellipf`/`ellippi` at 30 digits
                    // agree to 2e-15 (F(11|m), Π(−40; 2.9|m), Π(0.6; 11|m)).
                    let scale = if m1 < 1e-3 { 0.15 } else { 1.0 };
                    worst = worst
                        .max(scale * ((l.f(phi) - qf) / qf).abs())
                        .max(scale * ((l.pi(phi) - qp) / qp).abs());
                }
            }
        }
        assert!(worst < 5e-15, "{worst:e}");
    }

    /// sn, cn, dn, am: the identities, `F(am u) = u` to rounding of the
    /// amplitude (Carlson's algorithm
    /// against the AGM), `sn(K) = 1`, and `d am/du = dn` by a 6th-order
    /// central difference.
    #[test]
    fn jacobi_functions_are_consistent() {
        let mut worst: f64 = 0.0;
        for &m1 in &[1.0, 0.75, 0.3, 1e-2, 1e-5, 1e-9] {
            let m = 1.0 - m1;
            let l = Legendre::new(m, m1, 0.0);
            let j = jacobi(l.k, m, m1);
            worst = worst
                .max((j.sn - 1.0).abs())
                .max(j.cn.abs())
                .max((j.dn - m1.sqrt()).abs());
            for i in -40..=40 {
                let u = 0.37 * i as f64;
                let j = jacobi(u, m, m1);
                worst = worst
                    .max((j.sn * j.sn + j.cn * j.cn - 1.0).abs())
                    .max((j.dn * j.dn + m * j.sn * j.sn - 1.0).abs())
                    // In amplitude: dF/dφ = 1/dn, so a rounding of am by ε
                    // moves F by ε/dn (3e4 ε at m1 = 1e-9).
                    .max((l.f(j.am) - u).abs() * j.dn / u.abs().max(1.0));
                let h = 1e-3;
                let am = |v: f64| jacobi(v, m, m1).am;
                let d = (45.0 * (am(u + h) - am(u - h))
                    - 9.0 * (am(u + 2.0 * h) - am(u - 2.0 * h))
                    + (am(u + 3.0 * h) - am(u - 3.0 * h)))
                    / (60.0 * h);
                // The difference quotient itself errs by ~1e-13 (rounding / h).
                assert!((d - j.dn).abs() < 1e-11, "m1 {m1:e} u {u}: {d} vs {}", j.dn);
            }
        }
        assert!(worst < 4e-15, "{worst:e}");
    }
}
