//! Sphere–fibre contact: exact, analytic, one contact, on the true
//! flat-ended cylinder (no end-face domes: those belong to fibre–fibre).
//!
//! With `d = c_s − c_f`, `z = d·a`, `ρ = |d − z a|`, the signed distance
//! from the sphere's centre to the solid cylinder is, with `s = ρ − r_f`
//! and `t = |z| − h` (both positive outside their slab):
//!
//! - side (`s > 0 ≥ t`): `s`, normal `u = (d − z a)/ρ`;
//! - face (`t > 0 ≥ s`): `t`, normal `σ a`, `σ = sign z` (+1 at `z = 0`);
//! - rim (`s, t > 0`): `√(s² + t²)`, normal `(s u + t σ a)/√(s² + t²)`;
//! - centre inside (`s, t ≤ 0`): `max(s, t)`, the nearer surface, side on
//!   a tie.
//!
//! and the depth is `δ = r_s − dist`; the normal is `∂dist/∂c_s = −∂δ/∂c_s`,
//! the direction of the force on the sphere; the point is midway between
//! the sphere's surface point `c_s − r_s n` and the cylinder's nearest
//! surface point `c_s − dist n`. Every point of the line `c_s + λ n` gives
//! the fibre the exact torque of the potential: rotating the fibre by `ω`
//! about its centre moves `c_s` relative to it by `−ω × d`.
//!
//! `dist` is 1-Lipschitz everywhere (continuous across every feature and
//! the surface) and C¹ with the centre outside (distance to a convex set).
//! Its gradient jumps, measure zero, only with the centre inside: on the
//! side/face ties `r_f − ρ = h − |z|`; on the plane `z = 0` where both
//! faces are the nearest (fibres with `h < r_f`), there `+a`; and on the
//! axis where the side is the nearest (a cone point, every radial
//! direction a subgradient), there the fixed `a.any_orthonormal_vector()`.

use super::{ContactPoint, FibreGeom, SphereGeom};
use glam::DVec3;

/// The feature of the fibre that a sphere touches (the nearest feature to
/// its centre), the contact's identity for a per-contact history. The rim
/// and face variants name the end: `Minus` is at `centre − h axis`, `Plus`
/// at `centre + h axis`. A centre inside the fibre is classified by the
/// nearest surface (side or face), never rim. `as u8` gives a code 0–4.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum SphereFibreFeature {
    /// The cylindrical side.
    Side = 0,
    /// The end face at `centre − h axis`.
    FaceMinus = 1,
    /// The end face at `centre + h axis`.
    FacePlus = 2,
    /// The rim circle of the end at `centre − h axis`.
    RimMinus = 3,
    /// The rim circle of the end at `centre + h axis`.
    RimPlus = 4,
}

/// The signed depth of a sphere against a fibre and what it acts through,
/// whether or not they overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereFibreDepth {
    /// `r_s −` the signed distance from the sphere's centre to the
    /// cylinder: the overlap if positive, minus the gap if negative (m).
    pub depth: f64,
    /// Unit direction of the force on the sphere, `−∂depth/∂c_s`.
    pub normal: DVec3,
    /// Midway between the sphere's surface and the cylinder's along
    /// `normal` (world).
    pub point: DVec3,
    /// The feature nearest the sphere's centre.
    pub feature: SphereFibreFeature,
}

/// The signed depth of sphere `s` against fibre `f` (see the module
/// documentation), for any pose.
#[inline]
pub fn sphere_fibre_depth(s: &SphereGeom, f: &FibreGeom) -> SphereFibreDepth {
    use SphereFibreFeature::*;
    let d = s.centre - f.centre;
    let z = d.dot(f.axis);
    let radial = d - z * f.axis;
    let rho = radial.length();
    let side = rho - f.radius;
    let face = z.abs() - f.half_length;
    let (axial, face_f, rim_f) = if z >= 0.0 {
        (f.axis, FacePlus, RimPlus)
    } else {
        (-f.axis, FaceMinus, RimMinus)
    };
    // Outward radial unit vector; on the axis (the cone point of ρ, used
    // only with the centre inside, side nearest) a fixed perpendicular.
    let u = || {
        if rho > 0.0 {
            radial / rho
        } else {
            f.axis.any_orthonormal_vector()
        }
    };
    let (dist, normal, feature) = if side > 0.0 && face > 0.0 {
        let dist = side.hypot(face);
        (dist, (side * u() + face * axial) / dist, rim_f)
    } else if side > 0.0 {
        (side, u(), Side)
    } else if face > side {
        // Beyond a face (side ≤ 0 < face), or inside nearer a face.
        (face, axial, face_f)
    } else {
        (side, u(), Side)
    };
    SphereFibreDepth {
        depth: s.radius - dist,
        normal,
        point: s.centre - (0.5 * (s.radius + dist)) * normal,
        feature,
    }
}

/// Contact of sphere `s` (body A) with fibre `f` (body B), appended to `out`
/// if they overlap: one point, weight 1, normal = the direction of the force
/// on the sphere. Returns the touched feature, `None` without contact.
#[inline]
pub fn contact_sphere_fibre(
    s: &SphereGeom,
    f: &FibreGeom,
    out: &mut Vec<ContactPoint>,
) -> Option<SphereFibreFeature> {
    // Cheap reject: the centre is farther than r_s from the cylinder's
    // bounding sphere.
    let reach = s.radius + f.radius.hypot(f.half_length);
    if (s.centre - f.centre).length_squared() >= reach * reach {
        return None;
    }
    let c = sphere_fibre_depth(s, f);
    (c.depth > 0.0).then(|| {
        out.push(ContactPoint {
            point: c.point,
            normal: c.normal,
            overlap: c.depth,
            weight: 1.0,
            weight_grad: DVec3::ZERO,
        });
        c.feature
    })
}

/// [`contact_sphere_fibre`] seen from the fibre (body A): the same point and
/// depth, the force reversed (Newton's third law).
#[inline]
pub fn contact_fibre_sphere(
    f: &FibreGeom,
    s: &SphereGeom,
    out: &mut Vec<ContactPoint>,
) -> Option<SphereFibreFeature> {
    let from = out.len();
    let feature = contact_sphere_fibre(s, f, out);
    for c in &mut out[from..] {
        c.normal = -c.normal;
    }
    feature
}

#[cfg(test)]
mod tests {
    use super::SphereFibreFeature::*;
    use super::*;
    use crate::contact::HertzLaw;
    use crate::generate::sample::Rng;
    use glam::DQuat;
    use parry3d_f64::math::Pose;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Ball, Cylinder};
    use std::f64::consts::TAU;

    /// Orthonormal `(e1, e2)` with `e1 × e2 = a`, by Gram–Schmidt from the
    /// world axis least aligned with `a` (not the kernel's construction).
    fn frame(a: DVec3) -> (DVec3, DVec3) {
        let k = (0..3)
            .min_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs()))
            .unwrap();
        let e = DVec3::AXES[k];
        let e1 = (e - e.dot(a) * a).normalize();
        (e1, a.cross(e1))
    }

    /// A random fibre (centre in a 0.1 m cube, random axis, r_f in
    /// [2, 6] mm, h in [0.3, 4] r_f: squat and long) and a sphere (r_s in
    /// [0.2, 3] r_f) whose centre is drawn in the fibre's frame, uniform in
    /// a cylinder 1.2 times the reach: inside, side, faces, rims, near
    /// misses.
    fn random_pose(rng: &mut Rng) -> (SphereGeom, FibreGeom) {
        let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
        let radius = u(0.002, 0.006);
        let half_length = radius * u(0.3, 4.0);
        let rs = radius * u(0.2, 3.0);
        let centre = DVec3::new(u(-0.05, 0.05), u(-0.05, 0.05), u(-0.05, 0.05));
        let z = 1.2 * (half_length + rs) * u(-1.0, 1.0);
        let rho = 1.2 * (radius + rs) * u(0.0, 1.0).sqrt();
        let phi = u(0.0, TAU);
        let axis = rng.unit_vector();
        let (e1, e2) = frame(axis);
        let f = FibreGeom {
            centre,
            axis,
            radius,
            half_length,
        };
        let p = centre + z * axis + rho * (phi.cos() * e1 + phi.sin() * e2);
        (
            SphereGeom {
                centre: p,
                radius: rs,
            },
            f,
        )
    }

    /// The brute-force oracle's answer for a point `p` and a fibre.
    struct Nearest {
        /// Signed distance to the solid cylinder (negative inside).
        dist: f64,
        /// Nearest point of the cylinder's surface.
        q: DVec3,
        /// Where `q` is: side, face or rim (a clamped parameter).
        feature: SphereFibreFeature,
        /// Whether `p` is at least 1e-9 m from every set where the nearest
        /// feature changes (so that the feature and normal are defined).
        clear: bool,
    }

    /// A patch of the surface: parameters `(x, y)` → the point and its two
    /// tangents `∂q/∂x`, `∂q/∂y`.
    type Patch<'a> = &'a dyn Fn(f64, f64) -> (DVec3, DVec3, DVec3);

    /// Nearest point to `p` of a patch with `x` unbounded (an angle) and
    /// `y ∈ [y0, y1]`: `(x, y, |p − q|²)`. A grid of `nx × (ny + 1)` points;
    /// a pattern search from the best (8 moves, steps halved down to 1e-15
    /// of the ranges); then, since the squared distance is flat at its
    /// minimum (it resolves the parameters only to about √ε), coordinate
    /// sweeps that bisect on the sign of its derivative
    /// `∂|p − q|²/∂x = −2 (p − q)·∂q/∂x` (resolved to about ε).
    fn nearest_on(p: DVec3, patch: Patch, y0: f64, y1: f64, nx: usize, ny: usize) -> [f64; 3] {
        let g = |x: f64, y: f64| (p - patch(x, y).0).length_squared();
        let mut best = [0.0, y0, f64::INFINITY];
        for i in 0..nx {
            for j in 0..=ny {
                let y = if j == ny {
                    y1
                } else {
                    y0 + (y1 - y0) * j as f64 / ny as f64
                };
                let x = TAU * i as f64 / nx as f64;
                let v = g(x, y);
                if v < best[2] {
                    best = [x, y, v];
                }
            }
        }
        let (mut hx, mut hy) = (TAU / nx as f64, (y1 - y0) / ny as f64);
        while hx > 1e-15 * TAU || hy > 1e-15 * (y1 - y0) {
            let mut next = best;
            for (dx, dy) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let x = best[0] + dx as f64 * hx;
                let y = (best[1] + dy as f64 * hy).clamp(y0, y1);
                let v = g(x, y);
                if v < next[2] {
                    next = [x, y, v];
                }
            }
            if next[2] < best[2] {
                best = next;
            } else {
                (hx, hy) = (0.5 * hx, 0.5 * hy);
            }
        }
        // Derivative of |p − q|² along coordinate k at (x, y).
        let slope = |k: usize, x: f64, y: f64| {
            let (q, qx, qy) = patch(x, y);
            -2.0 * (p - q).dot(if k == 0 { qx } else { qy })
        };
        let [mut x, mut y, _] = best;
        for _ in 0..8 {
            for k in 0..2 {
                let at = |v: f64| {
                    if k == 0 {
                        slope(0, v, y)
                    } else {
                        slope(1, x, v)
                    }
                };
                let (c, w) = if k == 0 {
                    (x, 1e-4 * TAU)
                } else {
                    (y, 1e-4 * (y1 - y0))
                };
                let (mut lo, mut hi) = if k == 0 {
                    (c - w, c + w)
                } else {
                    ((c - w).max(y0), (c + w).min(y1))
                };
                let v = if at(lo) >= 0.0 {
                    lo
                } else if at(hi) <= 0.0 {
                    hi
                } else {
                    for _ in 0..200 {
                        let mid = 0.5 * (lo + hi);
                        if mid == lo || mid == hi {
                            break;
                        }
                        if at(mid) < 0.0 {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    0.5 * (lo + hi)
                };
                if k == 0 {
                    x = v;
                } else {
                    y = v;
                }
            }
        }
        [x, y, g(x, y).min(best[2])]
    }

    /// Reference: the definition of the signed distance to a solid
    /// cylinder, evaluated by brute force on its surface, parametrised
    /// afresh in the oracle's own frame: the side by (angle, height), each
    /// end face by (angle, radius); the nearest of the three minima is the
    /// nearest surface point, and the distance is negative if `p` is inside
    /// (`ρ ≤ r`, `|z| ≤ h` in that frame).
    fn oracle(p: DVec3, f: &FibreGeom) -> Nearest {
        let (a, c, r, h) = (f.axis, f.centre, f.radius, f.half_length);
        let (e1, e2) = frame(a);
        let radial = |x: f64| x.cos() * e1 + x.sin() * e2;
        let tangent = |x: f64| -x.sin() * e1 + x.cos() * e2;
        let side = |x: f64, t: f64| (c + t * a + r * radial(x), r * tangent(x), a);
        let face = |sig: f64| {
            move |x: f64, rr: f64| (c + sig * h * a + rr * radial(x), rr * tangent(x), radial(x))
        };
        let [x, t, vs] = nearest_on(p, &side, -h, h, 64, 32);
        // A parameter within 1e-12 of its bound is on the rim.
        let at_bound = |y: f64, bound: f64| y.abs() >= bound * (1.0 - 1e-12);
        let mut near = (vs, side(x, t).0, if at_bound(t, h) { rim(t) } else { Side });
        for sig in [-1.0, 1.0] {
            let [x, rr, v] = nearest_on(p, &face(sig), 0.0, r, 64, 16);
            if v < near.0 {
                let feature = if at_bound(rr, r) {
                    rim(sig)
                } else {
                    face_of(sig)
                };
                near = (v, face(sig)(x, rr).0, feature);
            }
        }
        let d = p - c;
        let (z, rho) = (d.dot(a), d.dot(e1).hypot(d.dot(e2)));
        let inside = rho <= r && z.abs() <= h;
        let eta = 1e-9;
        let clear = if inside {
            ((r - rho) - (h - z.abs())).abs() > eta && (z.abs() > eta || h > r)
        } else {
            (rho - r).abs() > eta && (z.abs() - h).abs() > eta
        };
        let dist = near.0.sqrt();
        Nearest {
            dist: if inside { -dist } else { dist },
            q: near.1,
            feature: near.2,
            clear,
        }
    }

    fn rim(sig: f64) -> SphereFibreFeature {
        if sig > 0.0 {
            RimPlus
        } else {
            RimMinus
        }
    }

    fn face_of(sig: f64) -> SphereFibreFeature {
        if sig > 0.0 {
            FacePlus
        } else {
            FaceMinus
        }
    }

    /// Reference: the brute-force oracle above, on 6000 random poses:
    /// depth `r_s − dist` to 1e-15 m, and where the normal is defined
    /// (`|dist|` ≥ 1 µm and clear of the switching sets) the normal (the
    /// direction from the nearest surface point towards the centre, or
    /// away from it inside) to 1e-11, the point (midway between the
    /// sphere's surface and the nearest surface point) to 1e-14 m and the
    /// feature.
    /// `contact_sphere_fibre` appends exactly the touching poses. Every
    /// feature is hit, inside and outside. (Mutants tried: the rim's
    /// distance `s + t`; `min` for `max` inside; the point on the
    /// cylinder's surface; the cheap reject without the radius.)
    #[test]
    fn agrees_with_the_brute_force_oracle_on_random_poses() {
        let mut rng = Rng::new(0x05ee_d0f5_f3e5);
        let (mut max_depth, mut max_normal, mut max_point) = (0.0f64, 0.0f64, 0.0f64);
        let mut hits = std::collections::HashMap::new();
        for i in 0..6000 {
            let (s, f) = random_pose(&mut rng);
            let k = sphere_fibre_depth(&s, &f);
            let o = oracle(s.centre, &f);
            let depth = s.radius - o.dist;
            max_depth = max_depth.max((k.depth - depth).abs());
            assert!(
                (k.depth - depth).abs() < 1e-15,
                "{i}: {} vs {depth}",
                k.depth
            );
            if o.clear && o.dist.abs() > 1e-6 {
                let sign = if o.dist < 0.0 { -1.0 } else { 1.0 };
                let n = sign * (s.centre - o.q).normalize();
                let point = 0.5 * ((s.centre - s.radius * n) + o.q);
                max_normal = max_normal.max((k.normal - n).length());
                max_point = max_point.max((k.point - point).length());
                assert!(
                    (k.normal - n).length() < 1e-11,
                    "{i}: {:?} vs {n:?}",
                    k.normal
                );
                assert!((k.point - point).length() < 1e-14, "{i}: {:?}", k.point);
                assert_eq!(k.feature, o.feature, "{i}: {s:?} {f:?}");
                let key = (k.feature as u8, o.dist < 0.0, depth > 0.0);
                *hits.entry(key).or_insert(0) += 1;
            }
            let mut out = vec![];
            let touched = contact_sphere_fibre(&s, &f, &mut out);
            if depth > 1e-12 {
                assert_eq!(touched, Some(k.feature), "{i}");
                assert_eq!(out.len(), 1, "{i}");
                assert_eq!((out[0].overlap, out[0].normal), (k.depth, k.normal));
                assert_eq!((out[0].point, out[0].weight), (k.point, 1.0));
            } else if depth < -1e-12 {
                assert!(touched.is_none() && out.is_empty(), "{i}: {out:?}");
            }
        }
        eprintln!(
            "oracle: max |Δdepth| {max_depth:.2e} m, |Δnormal| {max_normal:.2e}, \
             |Δpoint| {max_point:.2e} m; (feature, inside, touching): {hits:?}"
        );
        for feature in [Side, FaceMinus, FacePlus, RimMinus, RimPlus] {
            let n = |inside, touch| hits.get(&(feature as u8, inside, touch)).copied();
            assert!(n(false, true) >= Some(40), "{feature:?} touching: {hits:?}");
            assert!(n(false, false) >= Some(40), "{feature:?} apart: {hits:?}");
            if !matches!(feature, RimMinus | RimPlus) {
                assert!(n(true, true) >= Some(40), "{feature:?} inside: {hits:?}");
            }
        }
    }

    /// parry's contact of a ball and a cylinder (its cylinders are along
    /// local +Y): `(depth, force direction on the ball, point midway)`.
    fn parry_contact(s: &SphereGeom, f: &FibreGeom) -> (f64, DVec3, DVec3) {
        let ball = Pose::from_parts(s.centre, DQuat::IDENTITY);
        let cyl = Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis));
        let c = query::contact(
            &ball,
            &Ball::new(s.radius),
            &cyl,
            &Cylinder::new(f.half_length, f.radius),
            1.0,
        )
        .unwrap()
        .expect("within the prediction distance");
        (-c.dist, -c.normal1, 0.5 * (c.point1 + c.point2))
    }

    /// Reference: parry3d-f64 0.31's ball–cylinder contact (a closed-form
    /// projection of the centre on the cylinder, not GJK/EPA), on 4000
    /// random poses clear of the switching sets (where the normal is not
    /// defined): depth to 1e-15 m, normal to 1e-12, point to 1e-15 m
    /// (mutant tried: the face's normal `a` whatever the end). Where they
    /// differ (a centre exactly on the surface), see
    /// `outside_features_match_the_closed_form`.
    #[test]
    fn agrees_with_parry_on_random_poses() {
        let mut rng = Rng::new(0x0ba1_1c71);
        let (mut max_depth, mut max_normal, mut max_point, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        for i in 0..4000 {
            let (s, f) = random_pose(&mut rng);
            if !oracle(s.centre, &f).clear {
                continue;
            }
            let k = sphere_fibre_depth(&s, &f);
            let (depth, normal, point) = parry_contact(&s, &f);
            max_depth = max_depth.max((k.depth - depth).abs());
            max_normal = max_normal.max((k.normal - normal).length());
            max_point = max_point.max((k.point - point).length());
            n += 1;
            assert!(
                (k.depth - depth).abs() < 1e-15,
                "{i}: {} vs {depth}",
                k.depth
            );
            assert!((k.normal - normal).length() < 1e-12, "{i}: {normal:?}");
            assert!((k.point - point).length() < 1e-15, "{i}: {point:?}");
        }
        eprintln!(
            "parry ({n} poses): max |Δdepth| {max_depth:.2e} m, |Δnormal| {max_normal:.2e}, \
             |Δpoint| {max_point:.2e} m"
        );
        assert!(n > 3000, "{n}");
    }

    /// Test case 1's fibre (r = 5 mm, h = 12.5 mm), or a squat one (h = 2
    /// mm < r), along a slanted axis.
    fn fibre(half_length: f64) -> FibreGeom {
        FibreGeom {
            centre: DVec3::new(0.01, -0.02, 0.03),
            axis: DVec3::new(1.0, 2.0, -2.0) / 3.0,
            radius: 0.005,
            half_length,
        }
    }

    /// The point at height `z`, distance `rho` from the axis, azimuth `phi`
    /// in the fibre's frame, and the radial unit vector there.
    fn at(f: &FibreGeom, z: f64, rho: f64, phi: f64) -> (DVec3, DVec3) {
        let (e1, e2) = frame(f.axis);
        let u = phi.cos() * e1 + phi.sin() * e2;
        (f.centre + z * f.axis + rho * u, u)
    }

    /// Asserts depth, normal, point (midway between the sphere's surface
    /// and the surface point `q`) and feature.
    fn check(
        s: &SphereGeom,
        f: &FibreGeom,
        depth: f64,
        n: DVec3,
        q: DVec3,
        feature: SphereFibreFeature,
    ) {
        let k = sphere_fibre_depth(s, f);
        let point = 0.5 * (s.centre - s.radius * n + q);
        assert!((k.depth - depth).abs() < 1e-16, "{} vs {depth}", k.depth);
        assert!((k.normal - n).length() < 1e-12, "{:?} vs {n:?}", k.normal);
        assert!(
            (k.point - point).length() < 2e-15,
            "{:?} vs {point:?}",
            k.point
        );
        assert_eq!(k.feature, feature);
    }

    /// Reference: the closed forms of the features with the centre outside
    /// at distance `g`: side (`ρ = r + g`): normal `u`, nearest point at
    /// radius `r`; face (`|z| = h + g`): normal `±a`; rim (`ρ = r + g cos β`,
    /// `|z| = h + g sin β`): normal `cos β u ± sin β a`, nearest point on
    /// the rim. Depth `r_s − g` in each; with the centre on the side or a
    /// face (`g = 0`), the surface normal. (Mutant tried: the rim's distance
    /// `s + t`.)
    #[test]
    fn outside_features_match_the_closed_form() {
        let f = fibre(0.0125);
        let (r, h, a) = (f.radius, f.half_length, f.axis);
        let (g, rs) = (2e-5, 0.003);
        for (phi, sig) in [(0.3, 1.0), (2.0, -1.0), (4.5, 1.0)] {
            let sphere = |p: DVec3| SphereGeom {
                centre: p,
                radius: rs,
            };
            // On the surface itself: the surface normal (parry 0.31 falls
            // back to the direction from the fibre's centre there).
            let (p, u) = at(&f, 0.4 * h * sig, r, phi);
            check(&sphere(p), &f, rs, u, p, Side);
            let (p, _) = at(&f, sig * h, 0.6 * r, phi);
            let face = if sig > 0.0 { FacePlus } else { FaceMinus };
            check(&sphere(p), &f, rs, sig * a, p, face);
            let (p, u) = at(&f, 0.4 * h * sig, r + g, phi);
            check(&sphere(p), &f, rs - g, u, p - g * u, Side);
            let (p, _) = at(&f, sig * (h + g), 0.6 * r, phi);
            check(&sphere(p), &f, rs - g, sig * a, p - g * sig * a, face);
            let beta = 0.2 + phi / 7.0;
            let (p, u) = at(&f, sig * (h + g * beta.sin()), r + g * beta.cos(), phi);
            let n = beta.cos() * u + beta.sin() * sig * a;
            let rim = if sig > 0.0 { RimPlus } else { RimMinus };
            check(&sphere(p), &f, rs - g, n, at(&f, sig * h, r, phi).0, rim);
        }
    }

    /// Reference: the closed forms of a centre inside, pushed out through
    /// the nearest surface: depth `r_s +` its distance. At the centre of a
    /// long fibre the side (any radial normal), of a squat one the faces
    /// (`+a` on the mid-plane); on the axis near a face, that face; on the
    /// axis beyond a face, the face (normal exactly `±a`, no NaN); near the
    /// side, the side; on a side/face tie, the side. (Mutant tried: `min`
    /// for `max` of the side and face distances inside.)
    #[test]
    fn a_centre_inside_is_pushed_out_through_the_nearest_surface() {
        let rs = 0.002;
        let sphere = |p: DVec3| SphereGeom {
            centre: p,
            radius: rs,
        };
        let long = fibre(0.0125);
        let (r, h, a) = (long.radius, long.half_length, long.axis);
        let k = sphere_fibre_depth(&sphere(long.centre), &long);
        assert_eq!((k.depth, k.feature), (rs + r, Side));
        assert!(k.normal.dot(a).abs() < 1e-15 && (k.normal.length() - 1.0).abs() < 1e-15);
        assert!((k.point - (long.centre + 0.5 * (r - rs) * k.normal)).length() < 1e-16);
        let squat = fibre(0.002);
        check(
            &sphere(squat.centre),
            &squat,
            rs + 0.002,
            a,
            squat.centre + 0.002 * a,
            FacePlus,
        );
        let g = 0.001;
        for sig in [1.0, -1.0] {
            let (face, on_face) = if sig > 0.0 {
                (FacePlus, h * a)
            } else {
                (FaceMinus, -h * a)
            };
            let p = long.centre + sig * (h - g) * a;
            check(
                &sphere(p),
                &long,
                rs + g,
                sig * a,
                long.centre + on_face,
                face,
            );
            let p = long.centre + sig * (h + g) * a;
            check(
                &sphere(p),
                &long,
                rs - g,
                sig * a,
                long.centre + on_face,
                face,
            );
        }
        let (p, u) = at(&long, -0.3 * h, r - g, 1.0);
        check(&sphere(p), &long, rs + g, u, p + g * u, Side);
        let (p, u) = at(&long, h - 2.0 * g, r - 2.0 * g, 5.0);
        check(&sphere(p), &long, rs + 2.0 * g, u, p + 2.0 * g * u, Side);
    }

    /// Reference: Newton's third law; the fibre-first arm is the
    /// sphere-first one with the force reversed, at the same point, depth
    /// and feature, on random poses (mutant tried: the normal not reversed).
    #[test]
    fn fibre_first_is_sphere_first_reversed() {
        let mut rng = Rng::new(0x3e1d);
        let mut touching = 0;
        for _ in 0..2000 {
            let (s, f) = random_pose(&mut rng);
            let (mut sf, mut fs) = (vec![], vec![]);
            let feature = contact_sphere_fibre(&s, &f, &mut sf);
            assert_eq!(contact_fibre_sphere(&f, &s, &mut fs), feature);
            assert_eq!(sf.len(), fs.len());
            for (x, y) in sf.iter().zip(&fs) {
                assert_eq!(
                    (x.point, x.overlap, x.weight),
                    (y.point, y.overlap, y.weight)
                );
                assert_eq!(x.normal, -y.normal);
                touching += 1;
            }
        }
        assert!(touching > 500, "{touching}");
    }

    /// Reference: the sphere–fibre Hertz potential `U(δ)`; its central
    /// differences in the sphere's centre, the fibre's centre and the
    /// fibre's orientation (rotation vector about its centre) are minus the
    /// force `F n` on the sphere, the force `−F n` on the fibre and the
    /// torque `(x − c_f) × (−F n)` on the fibre, to 1e-6 of `F` (of `F` times
    /// the lever), on random touching poses 10 µm or more from the switching
    /// sets and the seams where the distance is only C¹ (mutants tried: the
    /// rim's normal not normalised; the point placed by the side's formula
    /// whatever the feature, off the line of action at a face).
    #[test]
    fn the_force_and_torque_are_the_gradient_of_the_potential() {
        let mut rng = Rng::new(0x9ad_1e47);
        let mut features = [0; 5];
        for _ in 0..100_000 {
            if features.iter().all(|&n| n >= 40) {
                break;
            }
            let (s, f) = random_pose(&mut rng);
            let d = s.centre - f.centre;
            let z = d.dot(f.axis);
            let rho = (d - z * f.axis).length();
            let (side, face) = (rho - f.radius, z.abs() - f.half_length);
            let m = 1e-5;
            let tie = side <= 0.0 && face <= 0.0 && (side - face).abs() < m;
            let k = sphere_fibre_depth(&s, &f);
            if k.depth < 1e-6 || side.abs() < m || face.abs() < m || rho < m || z.abs() < m || tie {
                continue;
            }
            let law = HertzLaw::sphere_fibre(2.0 * s.radius, 5e7, 0.23, 2.0 * f.radius, 2e8, 0.3);
            let u = |s: &SphereGeom, f: &FibreGeom| law.energy(sphere_fibre_depth(s, f).depth);
            let force = law.force(k.depth) * k.normal;
            let torque_b = (k.point - f.centre).cross(-force);
            let tol = 1e-6 * force.length();
            let (eps, turn) = (1e-9, 1e-7);
            for e in DVec3::AXES {
                let sphere_at = |t: f64| SphereGeom {
                    centre: s.centre + t * e,
                    radius: s.radius,
                };
                let fibre_at = |t: f64| FibreGeom {
                    centre: f.centre + t * e,
                    ..f
                };
                let turned = |t: f64| FibreGeom {
                    axis: DQuat::from_scaled_axis(t * e) * f.axis,
                    ..f
                };
                let fd = |u_at: &dyn Fn(f64) -> f64, h: f64| -(u_at(h) - u_at(-h)) / (2.0 * h);
                let on_a = fd(&|t| u(&sphere_at(t), &f), eps);
                let on_b = fd(&|t| u(&s, &fibre_at(t)), eps);
                let about_b = fd(&|t| u(&s, &turned(t)), turn);
                assert!(
                    (on_a - force.dot(e)).abs() < tol,
                    "{s:?} {f:?}: {on_a} vs {force}"
                );
                assert!(
                    (on_b + force.dot(e)).abs() < tol,
                    "{s:?} {f:?}: {on_b} vs {force}"
                );
                let lever = (k.point - f.centre).length();
                let t_tol = tol * lever.max(f.radius);
                assert!(
                    (about_b - torque_b.dot(e)).abs() < t_tol,
                    "{s:?} {f:?}: {about_b}"
                );
            }
            features[k.feature as usize] += 1;
        }
        assert!(features.iter().all(|&n| n >= 40), "{features:?}");
    }

    /// Reference: the depth is a signed distance, so 1-Lipschitz in the
    /// sphere's centre; across each seam (side/rim and face/rim outside;
    /// the side and face surfaces; inside, the side/face tie, the squat
    /// fibre's mid-plane and the long fibre's axis) a step of `2η` changes
    /// it by at most `2η`, and outside, where the distance is C¹, the
    /// normal turns by at most `10 · 2η/dist`. Also 4000 random steps.
    /// (Mutants tried: the side distance inside whatever the nearer
    /// surface; the rim's distance `s + t`.)
    #[test]
    fn the_depth_is_continuous_across_every_seam() {
        let rs = 0.003;
        let depth = |p: DVec3, f: &FibreGeom| {
            sphere_fibre_depth(
                &SphereGeom {
                    centre: p,
                    radius: rs,
                },
                f,
            )
        };
        let (long, squat) = (fibre(0.0125), fibre(0.002));
        let (r, g) = (long.radius, 1e-3);
        for eta in [1e-6, 1e-9] {
            for sig in [1.0, -1.0] {
                // (fibre, outside?, point on the seam, crossing direction)
                let h = long.half_length;
                let (rim_side, _) = at(&long, sig * h, r + g, 0.7);
                let (rim_face, u2) = at(&long, sig * (h + g), r, 2.1);
                let (side_surface, u3) = at(&long, sig * 0.3 * h, r, 3.3);
                let (face_surface, _) = at(&long, sig * h, 0.4 * r, 4.4);
                let (tie, u5) = at(&long, sig * (h - 0.3 * r), 0.7 * r, 5.5);
                let (axis_point, u6) = at(&long, sig * 0.1 * h, 0.0, 6.0);
                let (mid_plane, _) = at(&squat, 0.0, 0.2 * r, 1.1);
                let a = long.axis;
                let seams = [
                    (&long, true, rim_side, a),
                    (&long, true, rim_face, u2),
                    (&long, false, side_surface, u3),
                    (&long, false, face_surface, a),
                    (&long, false, tie, u5),
                    (&long, false, axis_point, u6),
                    (&squat, false, mid_plane, a),
                ];
                for (i, (f, outside, p, e)) in seams.into_iter().enumerate() {
                    let (lo, hi) = (depth(p - eta * e, f), depth(p + eta * e, f));
                    let jump = (lo.depth - hi.depth).abs();
                    assert!(
                        jump <= 2.0 * eta * (1.0 + 1e-6) + 1e-16,
                        "seam {i} {sig} {eta}: {jump}"
                    );
                    if outside {
                        let turn = (lo.normal - hi.normal).length();
                        assert!(turn <= 10.0 * 2.0 * eta / g, "seam {i} {sig} {eta}: {turn}");
                    }
                }
            }
        }
        let mut rng = Rng::new(0x11b5);
        for _ in 0..4000 {
            let (s, f) = random_pose(&mut rng);
            let step = 1e-4 * rng.uniform() * rng.unit_vector();
            let (x, y) = (depth(s.centre, &f).depth, depth(s.centre + step, &f).depth);
            assert!(
                (x - y).abs() <= step.length() * (1.0 + 1e-9) + 1e-16,
                "{s:?} {f:?}"
            );
        }
    }
}
