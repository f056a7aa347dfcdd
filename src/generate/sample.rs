//! Random draws of a generated bed: a seeded generator, size distributions
//! and orientation distributions. Same seed, same draws, same bytes (the
//! generator is integer arithmetic; the draws use libm's `ln`, `sin`, `cos`).

use glam::{DQuat, DVec3};
use std::f64::consts::PI;

/// SplitMix64 (Steele, Lea & Flood, OOPSLA 2014): a 64-bit state, passes
/// BigCrush, and one seed gives one stream everywhere.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// The stream of `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.uniform(); // (0, 1]
        let v = self.uniform();
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    }

    /// A unit vector uniform on the sphere (Marsaglia's z and azimuth).
    pub fn unit_vector(&mut self) -> DVec3 {
        let z = 2.0 * self.uniform() - 1.0;
        let phi = 2.0 * PI * self.uniform();
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// A size (diameter or length) distribution, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Size {
    /// Every fibre the same.
    Fixed(f64),
    /// Uniform in `[lo, hi]`.
    Uniform(f64, f64),
    /// Normal of mean and standard deviation, cut at ±3 standard deviations
    /// (redrawn outside; the mean must be > 3 sd so sizes stay positive).
    Normal(f64, f64),
}

impl Size {
    /// Parse `0.01`, `uniform:0.008:0.012` or `normal:0.01:0.001`.
    pub fn parse(s: &str) -> Option<Size> {
        let num = |t: &str| {
            t.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x > 0.0)
        };
        let parts: Vec<&str> = s.split(':').collect();
        let size = match parts.as_slice() {
            [x] => Size::Fixed(num(x)?),
            ["uniform", a, b] => {
                let (a, b) = (num(a)?, num(b)?);
                (a <= b).then_some(Size::Uniform(a, b))?
            }
            ["normal", m, sd] => {
                let (m, sd) = (num(m)?, num(sd)?);
                (m > 3.0 * sd).then_some(Size::Normal(m, sd))?
            }
            _ => return None,
        };
        Some(size)
    }

    /// The largest size this can draw.
    pub fn max(&self) -> f64 {
        match *self {
            Size::Fixed(x) => x,
            Size::Uniform(_, b) => b,
            Size::Normal(m, sd) => m + 3.0 * sd,
        }
    }

    /// The mean size.
    pub fn mean(&self) -> f64 {
        match *self {
            Size::Fixed(x) | Size::Normal(x, _) => x,
            Size::Uniform(a, b) => 0.5 * (a + b),
        }
    }

    /// One draw (a fixed size draws nothing, so it leaves the stream as is).
    pub fn draw(&self, r: &mut Rng) -> f64 {
        match *self {
            Size::Fixed(x) => x,
            Size::Uniform(a, b) => a + (b - a) * r.uniform(),
            Size::Normal(m, sd) => loop {
                let z = r.normal();
                if z.abs() <= 3.0 {
                    break m + sd * z;
                }
            },
        }
    }
}

/// How the fibre axes are distributed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Orientation {
    /// Uniform on the sphere.
    Isotropic,
    /// All along one unit axis.
    Aligned(DVec3),
    /// Uniform in the plane normal to a unit vector.
    Planar(DVec3),
}

impl Orientation {
    /// The body → world rotation of one fibre (body x = its axis; the
    /// roll about the axis is irrelevant for a solid of revolution and is
    /// that of the shortest arc from x).
    pub fn draw(&self, r: &mut Rng) -> DQuat {
        let axis = match *self {
            Orientation::Isotropic => r.unit_vector(),
            Orientation::Aligned(a) => a,
            Orientation::Planar(n) => {
                let (e1, e2) = n.any_orthonormal_pair();
                let phi = 2.0 * PI * r.uniform();
                e1 * phi.cos() + e2 * phi.sin()
            }
        };
        DQuat::from_rotation_arc(DVec3::X, axis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the moments of the uniform and the cut normal, and the
    /// isotropy of the unit vectors (each <a_k²> = 1/3), on 2e5 draws.
    #[test]
    fn draws_have_their_distributions_moments() {
        let mut r = Rng::new(7);
        let n = 200_000;
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let x = r.uniform();
            assert!((0.0..1.0).contains(&x));
            s1 += x;
            s2 += x * x;
        }
        let (m, v) = (s1 / n as f64, s2 / n as f64 - (s1 / n as f64).powi(2));
        assert!(
            (m - 0.5).abs() < 3e-3 && (v - 1.0 / 12.0).abs() < 2e-3,
            "{m} {v}"
        );
        let sz = Size::Normal(1.0, 0.1);
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let x = sz.draw(&mut r);
            assert!((0.7..=1.3).contains(&x));
            s1 += x;
            s2 += x * x;
        }
        // The ±3σ cut normal has variance σ² (1 − 6φ(3)/(2Φ(3) − 1)) = 0.9733 σ².
        let (m, v) = (s1 / n as f64, s2 / n as f64 - (s1 / n as f64).powi(2));
        assert!(
            (m - 1.0).abs() < 1e-3 && (v / 0.01 - 0.9733).abs() < 0.02,
            "{m} {v}"
        );
        let mut sq = DVec3::ZERO;
        for _ in 0..n {
            let a = r.unit_vector();
            assert!((a.length() - 1.0).abs() < 1e-12);
            sq += a * a;
        }
        let sq = sq / n as f64;
        assert!(
            (sq - DVec3::splat(1.0 / 3.0)).abs().max_element() < 4e-3,
            "{sq}"
        );
        let q = Orientation::Planar(DVec3::Z).draw(&mut r);
        assert!((q * DVec3::X).z.abs() < 1e-15);
        assert_eq!(
            Size::parse("uniform:0.008:0.012"),
            Some(Size::Uniform(0.008, 0.012))
        );
        assert_eq!(Size::parse("normal:0.01:0.004"), None);
        assert_eq!(Size::parse("-1"), None);
    }
}
