//! Smooth blending of tied depths: the C¹ and C² smooth minima, their tie
//! bands, and [`Blend`], a depth that is a smooth minimum of candidate
//! contacts pushed as weighted parts whose forces sum to its exact
//! gradient. Why smooth minima, and the events that set the bands:
//! docs/contacts.md, "Ties".

use super::Cand;
use crate::contact::{ContactPoint, FibreGeom};
use glam::DVec3;

/// Width ε (m) of the C¹ smooth minima and maxima of the side–side model
/// (the two ends of a line contact, the axial escape): a tie moves each
/// depth by ε/4 (0.25 µm).
pub const TIE_BAND: f64 = 1e-6;

/// Width ε (m) of the C² smooth minimum of two tied local minima of the
/// end-involved depth: at an exact tie the depth is under-estimated by
/// 3ε/16 (1.9 µm, less than the domes' over-estimate σ_A + σ_B), less
/// inside `|δ1 − δ2| < ε`, and exact outside.
pub const END_TIE_BAND: f64 = 1e-5;

/// The plain minimum of `x` and `y` with its two derivatives when they are
/// at least `eps` apart (`d = y − x`), else `None` (inside the band).
#[inline]
fn outside_band(x: f64, y: f64, d: f64, eps: f64) -> Option<(f64, f64, f64)> {
    if d >= eps {
        Some((x, 1.0, 0.0))
    } else if d <= -eps {
        Some((y, 0.0, 1.0))
    } else {
        None
    }
}

/// Smooth minimum of `x` and `y` (C¹; the plain min outside `|x − y| < ε`):
/// `(m, ∂m/∂x, ∂m/∂y)` with `m = (x + y)/2 − (ε² + d²)/(4ε)`, `d = y − x`.
#[inline]
pub(super) fn smooth_min(x: f64, y: f64, eps: f64) -> (f64, f64, f64) {
    let d = y - x;
    if let Some(m) = outside_band(x, y, d, eps) {
        return m;
    }
    let w = 0.5 + d / (2.0 * eps);
    (
        0.5 * (x + y) - (eps * eps + d * d) / (4.0 * eps),
        w,
        1.0 - w,
    )
}

/// C² smooth minimum of `x` and `y` over `eps` (the plain min outside
/// `|x − y| < eps`): `(m, ∂m/∂x, ∂m/∂y)` with `∂m/∂y = S(t)`, the
/// smoothstep `S = 3t² − 2t³` of `t = (eps − d)/(2 eps)`, `d = y − x`, so
/// `m = x − 2 eps (t³ − t⁴/2)`: at a tie `m = x − 3 eps/16`.
#[inline]
pub(super) fn smooth_min_c2(x: f64, y: f64, eps: f64) -> (f64, f64, f64) {
    let d = y - x;
    if let Some(m) = outside_band(x, y, d, eps) {
        return m;
    }
    let t = (eps - d) / (2.0 * eps);
    let wy = t * t * (3.0 - 2.0 * t);
    (x - 2.0 * eps * t * t * t * (1.0 - 0.5 * t), 1.0 - wy, wy)
}

/// One candidate of a [`Blend`]: contact, gradient if not a single force
/// line, weight.
type Part = (Cand, Option<Wrench>, f64);
const EMPTY_PART: Part = (
    Cand {
        depth: 0.0,
        point: DVec3::ZERO,
        normal: DVec3::ZERO,
    },
    None,
    0.0,
);

/// Most parts of a [`Blend`]: the side–side main contact is a smooth
/// maximum of the crossing and of the smooth maximum of the two overlap ends
/// (three), smoothly minimised with the axial escape (four).
const MAX_PARTS: usize = 4;

/// A depth that is a smooth minimum (or maximum) of up to [`MAX_PARTS`]
/// candidate depths: every
/// part is pushed at the blended depth `depth` with its weight `∂depth/∂δ_i`
/// (the weights sum to 1), so the energy is `U(depth)` and the parts'
/// forces sum to its exact gradient `F(depth) Σ_i w_i ∇δ_i`. A part with a
/// [`Wrench`] carries a gradient that is not a single force line.
#[derive(Clone, Copy)]
pub(super) struct Blend {
    parts: [Part; MAX_PARTS],
    /// The blended depth (m).
    pub(super) depth: f64,
}

impl Blend {
    /// One candidate, weight 1.
    #[inline]
    pub(super) fn single(c: Cand) -> Self {
        Self {
            parts: [(c, None, 1.0), EMPTY_PART, EMPTY_PART, EMPTY_PART],
            depth: c.depth,
        }
    }

    /// One candidate whose depth gradient is the wrench `wr`, not a force
    /// along `c.normal` (pushed by [`push_wrench`]).
    #[inline]
    pub(super) fn with_wrench(c: Cand, wr: Wrench) -> Self {
        Self {
            parts: [(c, Some(wr), 1.0), EMPTY_PART, EMPTY_PART, EMPTY_PART],
            depth: c.depth,
        }
    }

    /// `smooth_min(self, other)` over [`TIE_BAND`], weights by the chain
    /// rule.
    #[inline]
    pub(super) fn smin(self, other: Blend) -> Blend {
        self.smin_by(other, |x, y| smooth_min(x, y, TIE_BAND))
    }

    /// `smooth_max(self, other)` over `eps` (C¹, `−smooth_min(−x, −y)`; the
    /// plain max outside the band, `(x + y)/2 + ε/4` at a tie), weights by
    /// the chain rule. With the same band, `smax + smin = x + y`.
    #[inline]
    pub(super) fn smax(self, other: Blend, eps: f64) -> Blend {
        self.smin_by(other, |x, y| {
            let (m, wx, wy) = smooth_min(-x, -y, eps);
            (-m, wx, wy)
        })
    }

    /// The smooth minimum (or maximum) `blend(self, other)` (value and its
    /// two derivatives), weights by the chain rule.
    pub(super) fn smin_by(
        self,
        other: Blend,
        blend: impl Fn(f64, f64) -> (f64, f64, f64),
    ) -> Blend {
        let (m, wx, wy) = blend(self.depth, other.depth);
        if wy == 0.0 {
            return self;
        }
        if wx == 0.0 {
            return other;
        }
        let mut parts = [EMPTY_PART; MAX_PARTS];
        let mut k = 0;
        for (p, w) in self
            .parts
            .iter()
            .map(|p| (p, wx))
            .chain(other.parts.iter().map(|p| (p, wy)))
        {
            if p.2 > 0.0 {
                debug_assert!(k < MAX_PARTS, "a blend of more than {MAX_PARTS} parts");
                if k < MAX_PARTS {
                    parts[k] = (p.0, p.1, p.2 * w);
                    k += 1;
                }
            }
        }
        Blend { parts, depth: m }
    }

    /// Push with an overall weight (and its couple), see [`push_weighted`].
    pub(super) fn push(
        &self,
        out: &mut Vec<ContactPoint>,
        a: &FibreGeom,
        weight: f64,
        weight_grad: DVec3,
    ) {
        for &(c, wrench, w) in &self.parts {
            if w > 0.0 {
                let c = Cand {
                    depth: self.depth,
                    ..c
                };
                match wrench {
                    Some(wr) => push_wrench(out, c, wr, a, w * weight, w * weight_grad),
                    None => push_weighted(out, c, w * weight, w * weight_grad),
                }
            }
        }
    }
}

/// `−∇_A δ` of a contact depth whose gradient is not a force along one
/// line: force (per unit Hertz force) and torque about A's centre.
#[derive(Clone, Copy)]
pub(super) struct Wrench {
    /// `−∇_{x_A} δ`.
    pub(super) force: DVec3,
    /// `−∇_{φ_A} δ` (rotation vector about A's centre).
    pub(super) torque: DVec3,
}

/// Push a contact of depth `c.depth`, weight `weight`, whose exact force on
/// A is `weight F(δ) wr.force` and torque `weight F(δ) wr.torque` (plus the
/// weight's couple). A force along one line carries a torque only ⊥ the
/// force, so the wrench is split between two points of weight `weight/2`
/// at `c.point ± d` with directions `N ± M` (not unit: the stage applies
/// `weight F(δ) normal`): forces sum to `N`, torques to `arm × N + d × M`,
/// and `d ⊥ T`, `M = T × d/|d|²` gives `d × M = T`, the residual torque.
/// The energy is `weight U(δ)` as for any contact.
pub(super) fn push_wrench(
    out: &mut Vec<ContactPoint>,
    c: Cand,
    wr: Wrench,
    a: &FibreGeom,
    weight: f64,
    weight_grad: DVec3,
) {
    if !(c.depth > 0.0 && weight > 0.0) {
        return;
    }
    let n = wr.force;
    let residual = wr.torque - (c.point - a.centre).cross(n);
    let scale = a.radius;
    if residual.length() <= 1e-14 * scale * n.length().max(1.0) {
        out.push(ContactPoint {
            point: c.point,
            normal: n,
            overlap: c.depth,
            weight,
            weight_grad,
        });
        return;
    }
    let d = scale * residual.normalize().any_orthonormal_vector();
    let m = residual.cross(d) / (scale * scale);
    for sign in [1.0, -1.0] {
        out.push(ContactPoint {
            point: c.point + sign * d,
            normal: n + sign * m,
            overlap: c.depth,
            weight: 0.5 * weight,
            weight_grad: 0.5 * weight_grad,
        });
    }
}

/// Push a candidate contact with weight `weight` (and the weight's couple
/// gradient `weight_grad`) if it is touching.
#[inline]
pub(super) fn push_weighted(out: &mut Vec<ContactPoint>, c: Cand, weight: f64, weight_grad: DVec3) {
    if c.depth > 0.0 && weight > 0.0 {
        out.push(ContactPoint {
            point: c.point,
            normal: c.normal,
            overlap: c.depth,
            weight,
            weight_grad,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type SmoothMin = fn(f64, f64, f64) -> (f64, f64, f64);

    /// References: the plain minimum outside the band; inside, the
    /// derivatives the functions return against central differences of the
    /// value they return, the weights summing to 1, and the documented tie
    /// values (ε/4 for C¹, 3ε/16 for C²); C² also means the weights' slope
    /// vanishes at the band's edges (where C¹'s jumps to ±1/(2ε)).
    #[test]
    fn smooth_minima_are_what_their_docs_say() {
        let (x, eps) = (1e-4, 1e-5);
        let cases: [(SmoothMin, f64, f64); 2] = [
            (smooth_min, 0.25, 0.5 / eps),
            (smooth_min_c2, 3.0 / 16.0, 0.0),
        ];
        for (f, tie, edge_slope) in cases {
            assert_eq!(f(x, x + 1.5 * eps, eps), (x, 1.0, 0.0));
            assert_eq!(f(x, x - 1.5 * eps, eps), (x - 1.5 * eps, 0.0, 1.0));
            let (m, wx, wy) = f(x, x, eps);
            assert!((m - (x - tie * eps)).abs() < 1e-20, "{m}");
            assert_eq!((wx, wy), (0.5, 0.5));
            let h = 1e-3 * eps;
            for k in -9..=9 {
                let y = x + 0.1 * k as f64 * eps;
                let (m, wx, wy) = f(x, y, eps);
                assert!(m <= x.min(y), "above the plain min at {k}");
                assert!((wx + wy - 1.0).abs() < 1e-15);
                let dy = (f(x, y + h, eps).0 - f(x, y - h, eps).0) / (2.0 * h);
                let dx = (f(x + h, y, eps).0 - f(x - h, y, eps).0) / (2.0 * h);
                assert!(
                    (dy - wy).abs() < 1e-6 && (dx - wx).abs() < 1e-6,
                    "{k}: {dx} {dy}"
                );
            }
            // Slope of the weight of y just inside the upper edge d = ε.
            let d = 1e-4 * eps;
            let slope = (f(x, x + eps - d, eps).2 - f(x, x + eps - 2.0 * d, eps).2) / d;
            assert!((slope.abs() - edge_slope).abs() < 1e-3 / eps, "{slope}");
        }
    }

    /// Reference: the split's defining sums. The two points' forces add up
    /// to the wrench's force and their torques about A's centre to its
    /// torque, with half the weight each.
    #[test]
    fn a_split_wrench_sums_to_the_wrench() {
        let a = FibreGeom {
            centre: DVec3::new(0.1, 0.2, 0.3),
            axis: DVec3::X,
            radius: 0.005,
            half_length: 0.0125,
        };
        let c = Cand {
            depth: 1e-6,
            point: a.centre + DVec3::new(0.01, 0.004, -0.002),
            normal: DVec3::Y,
        };
        let wr = Wrench {
            force: DVec3::new(0.1, -0.9, 0.3),
            torque: DVec3::new(0.002, 0.001, -0.004),
        };
        let mut out = vec![];
        push_wrench(&mut out, c, wr, &a, 0.8, DVec3::ZERO);
        assert_eq!(out.len(), 2);
        let force: DVec3 = out.iter().map(|p| p.weight * p.normal).sum();
        let torque: DVec3 = out
            .iter()
            .map(|p| (p.point - a.centre).cross(p.weight * p.normal))
            .sum();
        assert!(
            (force - 0.8 * wr.force).length() < 1e-15 * wr.force.length(),
            "{force}"
        );
        // (Relative to the torque: the split cancels terms of the arm, 1e-2 m.)
        assert!(
            (torque - 0.8 * wr.torque).length() < 1e-13 * wr.torque.length(),
            "{torque}"
        );
        assert!(out.iter().all(|p| p.weight == 0.4 && p.overlap == c.depth));
    }
}
