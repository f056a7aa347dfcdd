//! Fibre–fibre contact.
//!
//! Bodies: flat-ended cylinders, except that for fibre–fibre contact each
//! end face is a very shallow spherical cap through its rim (sag 2.5 µm for
//! r = 5 mm, see [`END_FACE_DOME_SIN`]). The domed fibre is still convex,
//! so its penetration depth is well defined, and its support point moves
//! smoothly over the cap instead of jumping across a flat face.
//!
//! Regimes, tested in this order (the capsule bound `r_a + r_b − d_seg ≤ 0`
//! rejects first, since a (domed) cylinder lies inside the capsule of its
//! axis):
//! 1. **Near-coaxial end to end** (`|a×b| <` [`COAXIAL_SIN`], axes overlap
//!    axially by less than `min(r)`, A's facing face centre over B's face):
//!    the regime-3 depth seeded with the two face normals, without parry
//!    (parry is wrong for exactly coaxial pairs), see [`coaxial`].
//! 2. **Side–side** (closest points of the axis segments interior to both, or
//!    `|a×b| <` [`PARALLEL_SIN`] with overlapping axial projections): analytic,
//!    see [`side_side`]. Its second contact, and (closest points not
//!    interior) its main contact, are blended with regime 3 over
//!    `|a×b| ∈ [`[`PARALLEL_BLEND_SIN`]`, `[`PARALLEL_SIN`]`]` by an
//!    orientation-dependent weight whose gradient is a pure couple
//!    ([`ContactPoint::weight_grad`]), so the potential is continuous at
//!    `PARALLEL_SIN`.
//! 3. **End involved** (T-junction, L corner, rim on rim):
//!    `parry3d_f64::query::contact` on the flat cylinders, with a prediction
//!    margin of the two sags, gives a seed normal; the depth is the
//!    penetration depth of the domed cylinders, `min_n h̃_B(n) + h̃_A(−n)`
//!    (closed-form support functions), found by a local search over the
//!    feature manifolds, see [`penetration`]; where two of its local
//!    minima (escape directions) tie, their C² smooth minimum over
//!    [`END_TIE_BAND`], see [`penetration_smoothed`]. parry's depth is
//!    only checked ([`PARRY_REJECTS`] counts disagreements above
//!    [`PARRY_REL_TOL`]); its
//!    "no contact" verdict is checked by [`confirm_separated`] (a separating
//!    axis with a gap above the margin; [`PARRY_UNCONFIRMED`] counts
//!    failures, none in the tests or in test case 2).
//!
//! Regimes 1 and 3 share one depth function (its ties smoothed), and the
//! axial escape of regime 2 its plain minimum, so their acceptance tests
//! change only how its minimum is seeded. Forces and torques are the exact
//! gradient of the potential (tests/contact_geometry.rs,
//! tests/contact_oracle.rs, tests/contact_ties.rs) except on measure-zero
//! switching sets.
//!
//! Limits:
//! * Depth error of the domes: a contact whose normal is within θc
//!   (0.057°) of a face normal (face on face, face on rim or side) is
//!   deeper by at most `σ_A + σ_B` (5 µm); any other contact is exact.
//! * The penetration depth is a minimum over directions; where two local
//!   minima tie (a corner that can escape sideways or axially) the plain
//!   minimum is continuous but its gradient, the force direction, switches:
//!   a concave kink crossed in one step (test case 2 with `leapfrog`,
//!   fibres 1 and 3 nearly end to end at t = 0.7559247 s: B's face cap
//!   against A's side circle, normals 86° apart, +5.06e-3 % of the energy;
//!   fibres 1 and 2 at 53°, t = 0.9760216 s: A's cap against B's cap,
//!   −3.94e-3 %). Regimes 1 and 3 use the C² smooth minimum of the two
//!   lowest distinct local minima over [`END_TIE_BAND`] (10 µm): the depth
//!   is under-estimated by at most 3ε/16 (1.9 µm) and only while they are
//!   within ε; forces stay its exact gradient (two contacts). The second
//!   minimum is searched from every face normal within the bowl + ε and
//!   from the closest-point normal's side circles, whichever minimum wins; a
//!   tie with a minimum none of these reaches (a rim-on-rim minimum away
//!   from every face) keeps its kink, and one that a search reaches on one
//!   side of a seed switch only (a face leaving the screen, the closest
//!   feature changing) inside the band leaves a jump of at most 3ε/16 in
//!   depth. Three-way ties blend the lowest two only. Leap-frog's energy
//!   error follows the band's curvature (~1/ε): test case 2 peaks at
//!   4.0e-5 % inside the band at t = 0.7559 s and keeps nothing after it.
//! * In regime 2's axial escape (ends of a near-parallel pair overlapping
//!   axially by less than twice the depth) these ties are smoothed over
//!   1 µm ([`TIE_BAND`], C¹), and its `δ_pd` ([`penetration`]) is the plain
//!   minimum.
//! * Across the regime-2/3 boundary where a crossing point slides off an
//!   end, the models agree only to first order.
//! * The near-coaxial acceptance at [`COAXIAL_SIN`] switches between
//!   seeds, not potentials, but regime 2's side–side depth (a capsule-like
//!   end model near the other fibre's end) can differ from regime 3 there.

use super::{ContactPoint, FibreGeom};
use glam::{DQuat, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::Cylinder;
use std::sync::atomic::{AtomicU64, Ordering};

/// Below this |sin| of the inter-axis angle a pair counts as parallel for the
/// line-contact treatment (≈ 2°).
pub const PARALLEL_SIN: f64 = 0.035;
/// Lower edge of the parallel blend band: the side–side-only terms (the
/// second contact, and the side–side main contact where regime 3 takes over)
/// have weight `w(|a×b|)`, 1 up to this |sin|, 0 from [`PARALLEL_SIN`] on,
/// C¹ (smoothstep) in between; the exact-depth contact of regime 3 gets
/// `1 − w` there. The weight's gradient is a pure couple
/// ([`ContactPoint::weight_grad`]), so forces stay the exact gradient and
/// the potential is continuous across `PARALLEL_SIN` (≈ 1.15°–2°).
pub const PARALLEL_BLEND_SIN: f64 = 0.02;
/// Below this |sin| an end-to-end pair counts as coaxial (≈ 1.1°).
pub const COAXIAL_SIN: f64 = 0.02;
/// End-face dome of regimes 1 and 3 (end involved): sine of the half-angle
/// θc of a spherical cap that replaces each flat end face for fibre–fibre
/// contact. The cap passes through the rim circle (rim and side exact) and
/// bulges out by the sag `σ = r (1 − cos θc)/sin θc ≈ r θc/2` at the face
/// centre (2.5 µm for r = 5 mm); its radius is `R = r/sin θc` (5 m).
///
/// Why: the exact depth has a cone point wherever a flat face meets a
/// generator or another face (an L corner or T-junction whose axes pass
/// through perpendicular; face on face): the tilt torque jumps between the
/// two ends of the line of contact. A domed face is still a convex body,
/// so the depth stays an exact penetration depth (min over directions of
/// true support functions), but its support point now moves continuously
/// over the cap, inside the face, instead of jumping: the depth is C¹
/// except where both bodies' supports are generator lines. Cost: face
/// contacts are deeper by at most `σ_A + σ_B`; a contact whose normal is
/// more than θc from every face normal is exact. Tilt stiffness of a face
/// contact: `F R` (F r/θc).
pub const END_FACE_DOME_SIN: f64 = 1e-3;
/// Relative tolerance on parry's depth against the projection overlap along
/// its own normal (diagnostic only: the depth used is always recomputed).
/// parry's EPA depth is off by up to ~5e-9 m (≈10 % of a 6e-8 m depth),
/// its known failures (exactly coaxial pairs) by O(1).
pub const PARRY_REL_TOL: f64 = 1e-2;
/// Number of parry answers rejected by the sanity checks (diagnostics).
pub static PARRY_REJECTS: AtomicU64 = AtomicU64::new(0);
/// Number of parry "no contact" verdicts that [`confirm_separated`] could
/// not confirm (diagnostics; zero in the tests and in test case 2).
pub static PARRY_UNCONFIRMED: AtomicU64 = AtomicU64::new(0);
/// Number of parry calls (diagnostics).
pub static PARRY_CALLS: AtomicU64 = AtomicU64::new(0);

/// Closest-point parameters `(s, t)` of segments `ca + s ua` (|s| ≤ ha) and
/// `cb + t ub` (|t| ≤ hb) (Ericson, RTCD §5.1.9, centred form). For parallel
/// segments `s` is the middle of the overlap of the projections, so the
/// answer is stable instead of jumping between ends.
#[inline]
pub fn segment_closest_params(a: &FibreGeom, b: &FibreGeom) -> (f64, f64) {
    let (ha, hb) = (a.half_length, b.half_length);
    let w = a.centre - b.centre;
    let bb = a.axis.dot(b.axis);
    let d = a.axis.dot(w);
    let e = b.axis.dot(w);
    let denom = 1.0 - bb * bb;
    let mut s = if denom > 1e-14 {
        ((bb * e - d) / denom).clamp(-ha, ha)
    } else {
        let lo = (-d - hb * bb.abs()).max(-ha);
        let hi = (-d + hb * bb.abs()).min(ha);
        (0.5 * (lo + hi)).clamp(-ha, ha)
    };
    let mut t = bb * s + e;
    if t < -hb || t > hb {
        t = t.clamp(-hb, hb);
        s = (bb * t - d).clamp(-ha, ha);
    }
    (s, t)
}

/// A candidate contact with A's force normal.
#[derive(Clone, Copy)]
struct Cand {
    depth: f64,
    point: DVec3,
    normal: DVec3,
}

/// Any unit vector perpendicular to `u`.
#[inline]
fn any_perp(u: DVec3) -> DVec3 {
    u.any_orthonormal_vector()
}

/// End disc of one fibre (centre `e`, axis `ue`, radius `re`) against the
/// side of `other`: depth of the rim point deepest in `other`, i.e.
/// `max_φ (r_o − dist(rim(φ), axis_o))`. Start from the rim point facing
/// `other`'s axis (exact for a parallel pair) and polish φ with Newton steps
/// on `dist²`, so the result is the max over body-fixed rim points and its
/// gradient is the force at that point (envelope theorem). Returns the
/// normal pointing from `other` towards the end's fibre.
#[inline]
fn end_vs_side(e: DVec3, ue: DVec3, re: f64, other: &FibreGeom) -> Cand {
    let (oc, ou, oh) = (other.centre, other.axis, other.half_length);
    let t = ou.dot(e - oc).clamp(-oh, oh);
    let v = e - (oc + t * ou);
    let dist = v.length();
    let n = if dist > 1e-300 {
        v / dist
    } else {
        any_perp(ou)
    };
    let capsule_depth = other.radius + re - dist;
    if capsule_depth <= 0.0 {
        // The rim lies within `re` of `e`: no rim point can touch.
        return Cand {
            depth: capsule_depth,
            point: e,
            normal: n,
        };
    }
    let m = n - n.dot(ue) * ue;
    let ml = m.length();
    let p = if ml > 1e-12 {
        // Rim frame: e1 faces `other`, e2 = ue × e1; minimise
        // f(φ) = |A + re (cos φ B1 + sin φ B2)|², B = component ⊥ ou.
        let e1 = -m / ml;
        let e2 = ue.cross(e1);
        let perp = |x: DVec3| x - ou.dot(x) * ou;
        let (a0, b1, b2) = (perp(e - oc), perp(e1), perp(e2));
        let mut phi = 0.0f64;
        for _ in 0..3 {
            let (sn, cs) = phi.sin_cos();
            let r = a0 + re * (cs * b1 + sn * b2);
            let dr = re * (cs * b2 - sn * b1);
            let d2r = -re * (cs * b1 + sn * b2);
            let g = r.dot(dr);
            let h = dr.dot(dr) + r.dot(d2r);
            if h <= 0.0 {
                break;
            }
            let step = g / h;
            phi -= step;
            if step.abs() < 1e-14 {
                break;
            }
        }
        let (sn, cs) = phi.sin_cos();
        e + re * (cs * e1 + sn * e2)
    } else {
        e
    };
    let tp = ou.dot(p - oc).clamp(-oh, oh);
    let qp = oc + tp * ou;
    let vp = p - qp;
    let dp = vp.length();
    let (depth, normal) = if dp > 1e-300 && vp.dot(n) > 0.0 {
        (other.radius - dp, vp / dp)
    } else {
        (other.radius + dp, n)
    };
    Cand {
        depth,
        point: 0.5 * (p + qp + other.radius * normal),
        normal,
    }
}

/// Contact of one of A's ends (`sign` = ±1) against B's side.
#[inline]
fn a_end(a: &FibreGeom, b: &FibreGeom, sign: f64) -> Cand {
    end_vs_side(
        a.centre + sign * a.half_length * a.axis,
        a.axis,
        a.radius,
        b,
    )
}

/// Contact of one of B's ends against A's side, normal flipped to act on A.
#[inline]
fn b_end(a: &FibreGeom, b: &FibreGeom, sign: f64) -> Cand {
    let mut c = end_vs_side(
        b.centre + sign * b.half_length * b.axis,
        b.axis,
        b.radius,
        a,
    );
    c.normal = -c.normal;
    c
}

#[inline]
fn deeper(x: Cand, y: Cand) -> Cand {
    if y.depth > x.depth {
        y
    } else {
        x
    }
}

#[inline]
fn push_weighted(out: &mut Vec<ContactPoint>, c: Cand, weight: f64, weight_grad: DVec3) {
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

/// Parallel blend weight `w(sin)` (see [`PARALLEL_BLEND_SIN`]) and its
/// gradient with respect to a rotation of A: `dw/dsin · ∂sin/∂φ_A` with
/// `∂|a×b|/∂φ_A = −(a·b) (a×b)/|a×b|`.
#[inline]
fn parallel_weight(a: &FibreGeom, b: &FibreGeom, sin: f64) -> (f64, DVec3) {
    if sin <= PARALLEL_BLEND_SIN {
        return (1.0, DVec3::ZERO);
    }
    if sin >= PARALLEL_SIN {
        return (0.0, DVec3::ZERO);
    }
    let width = PARALLEL_SIN - PARALLEL_BLEND_SIN;
    let x = (sin - PARALLEL_BLEND_SIN) / width;
    let w = 1.0 - x * x * (3.0 - 2.0 * x);
    let dw = -6.0 * x * (1.0 - x) / width;
    let grad = (-dw * a.axis.dot(b.axis) / sin) * a.axis.cross(b.axis);
    (w, grad)
}

/// Closest-point contact of the axis segments (the deepest point of a
/// crossing), analytic; clamped parameters are handled by the end model.
#[inline]
fn closest_point_contact(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> Cand {
    let s_end = s.abs() >= a.half_length;
    let t_end = t.abs() >= b.half_length;
    match (s_end, t_end) {
        (false, false) => {
            let pa = a.centre + s * a.axis;
            let pb = b.centre + t * b.axis;
            let v = pa - pb;
            let d = v.length();
            let n = if d > 1e-300 {
                v / d
            } else {
                let c = a.axis.cross(b.axis);
                if c.length_squared() > 1e-24 {
                    c.normalize()
                } else {
                    any_perp(a.axis)
                }
            };
            Cand {
                depth: a.radius + b.radius - d,
                point: 0.5 * (pa - a.radius * n + pb + b.radius * n),
                normal: n,
            }
        }
        (true, false) => a_end(a, b, s.signum()),
        (false, true) => b_end(a, b, t.signum()),
        (true, true) => deeper(a_end(a, b, s.signum()), b_end(a, b, t.signum())),
    }
}

/// Side–side model, potential `U(δ_main) + U(min(δ_lo, δ_hi))`.
///
/// `δ_lo`/`δ_hi` are the depths at the two ends of the axial overlap (the
/// deeper of "A's end vs B's side" and "B's end vs A's side" on that side);
/// `δ_main = max(δ_cp, δ_lo, δ_hi)` with `δ_cp` the closest-point depth.
/// * Crossed pair: the ends are far apart, `δ_lo, δ_hi < 0`: one Hertz point
///   at the crossing, weight 1.
/// * Parallel pair: the segment minimum sits at an end of the overlap, so
///   `δ_main = max(δ_lo, δ_hi)` and the potential is `U(δ_lo) + U(δ_hi)`:
///   two weight-1 points at the ends of the overlap, smooth under rocking
///   (the kinks of max and min cancel), no chatter.
///
/// The potential is continuous everywhere (max/min of continuous depths);
/// forces jump only on the measure-zero set where, with an interior closest
/// point, `δ_lo = δ_hi` (scissored and rocked at once) or where the
/// end defining an overlap end switches from A to B.
///
/// Axial escape (near-parallel pairs only): when the axial overlap `ℓ` of
/// the segments is below `2δ_main` (ends sliding past each other), the
/// main depth becomes the smooth minimum ([`TIE_BAND`]) of the sideways
/// depth and the over-the-end escape ([`axial_escape`]), and the second is
/// capped at `smin(δ_small, ℓ − δ_pd)` and at `δ_pd + ε/4` (`δ_pd` =
/// [`penetration`], min over directions): the pair fades continuously to
/// zero at `ℓ = δ_pd` instead of dropping two full contacts, and nothing is
/// left when the pair is separated (`δ_pd ≤ 0`). Each blended depth is
/// pushed as its weighted parts ([`Blend`]), and `ℓ − δ_pd` with its exact
/// gradient (`∇ℓ` in closed form) as two half-weight points
/// ([`push_wrench`]): end-to-end pairs at a small tilt sit in this window
/// for whole contacts (test case 2, pcdm, t = 0.389 s). Limit: for exactly
/// parallel axes `δ_pd` is a max over the line of contact, so `ℓ − δ_pd`
/// has a rocking kink there (measure zero; the `frozen` diagnostic keeps
/// pairs exactly parallel, but ignores torque).
///
/// Returns `(main, second)`; the caller weights the second contact (and,
/// outside the interior case, the main one) by the parallel blend weight.
fn side_side(a: &FibreGeom, b: &FibreGeom, s: f64, t: f64) -> (Blend, Blend) {
    let cp = closest_point_contact(a, b, s, t);
    let sb = if a.axis.dot(b.axis) >= 0.0 { 1.0 } else { -1.0 };
    let lo = deeper(a_end(a, b, -1.0), b_end(a, b, -sb));
    let hi = deeper(a_end(a, b, 1.0), b_end(a, b, sb));
    let (big, small) = if hi.depth > lo.depth {
        (hi, lo)
    } else {
        (lo, hi)
    };
    let main = if big.depth >= cp.depth { big } else { cp };
    let sin = a.axis.cross(b.axis).length();
    let ell = axial_overlap(a, b);
    // The switch lies TIE_BAND beyond ℓ = 2δ_main so that no smooth
    // minimum below is active there (ℓ − δ_pd ≥ δ_main + ε ≥ δ_small + ε,
    // and the axial escape is ~ℓ).
    if !(sin < PARALLEL_SIN
        && main.depth > 0.0
        && ell.len < 2.0 * main.depth + TIE_BAND + (a.radius + b.radius) * sin)
    {
        return (Blend::single(main), Blend::single(small));
    }
    let pd = penetration(a, b, [main.normal, cp.normal]);
    // Main depth: smin(δ_side, δ_axial), the sideways and the over-the-end
    // escapes. The plain min (then with δ_pd) switched the force direction
    // in one step (test case 2, frozen, fibres 4 and 8 side by side, ends
    // overlapping by 0.4 mm, t = 0.328922 s: 1.2e-3 % of the energy).
    // (When the search from the face normal slid down to the sideways
    // minimum itself, the two are one contact: a plain min has no kink.)
    let ax = axial_escape(a, b);
    let main = if ax.normal.dot(main.normal) > SAME_CONTACT_COS {
        Blend::single(if ax.depth < main.depth { ax } else { main })
    } else {
        Blend::single(main).smin(Blend::single(ax))
    };
    // Second depth: min(smin(δ_small, ℓ − δ_pd), δ_pd + ε/4). The cap
    // ℓ − δ_pd fades the pair out as the ends slide past each other; it
    // carries its exact gradient (was: the end contact's force, ~10 % off
    // in torque, pcdm t = 0.3893 s): ∇ℓ in closed form, −∇_A δ_pd = the
    // force F n at pd's point. Its plain min with δ_small switched the
    // force direction in one step (frozen, t = 0.329094 s: 7.7e-4 %). The
    // cap by δ_pd removes the second contact with the first when the pair
    // separates (δ_pd ≤ 0, a separating axis exists: without it a separated
    // end-to-end pair kept a 9e-5 m contact, pcdm, t = 0.38890 s); it is a
    // plain min, offset by ε/4, because a true local depth never exceeds
    // the penetration depth (δ_small ≤ δ_pd, equal for a parallel pair: the
    // same contact), so it only bites on the end model's capsule-like
    // depths near the other fibre's end.
    let arm = pd.point - a.centre;
    let capped = Blend {
        parts: [
            (
                Cand {
                    depth: ell.len - pd.depth,
                    ..pd
                },
                Some(Wrench {
                    force: -ell.grad_x - pd.normal,
                    torque: -ell.grad_rot - arm.cross(pd.normal),
                }),
                1.0,
            ),
            EMPTY_PART,
            EMPTY_PART,
        ],
        depth: ell.len - pd.depth,
    };
    let second = Blend::single(small).smin(capped);
    let pd_cap = pd.depth + 0.25 * TIE_BAND;
    let second = if pd_cap < second.depth {
        Blend::single(Cand {
            depth: pd_cap,
            ..pd
        })
    } else {
        second
    };
    (main, second)
}

/// Width ε (m) of the smooth minima of the axial escape. At a tie a depth
/// is under-estimated by ε/4 (0.25 µm); the band is crossed in ~30 steps of
/// 1e-7 s at 0.3 m/s of relative sliding.
const TIE_BAND: f64 = 1e-6;

/// Two candidate contacts whose normals are closer than this (cos 0.1 rad)
/// are one contact found twice.
const SAME_CONTACT_COS: f64 = 0.995;

/// Smooth minimum of `x` and `y` (C¹; the plain min outside `|x − y| < ε`):
/// `(m, ∂m/∂x, ∂m/∂y)` with `m = (x + y)/2 − (ε² + d²)/(4ε)`, `d = y − x`.
#[inline]
fn smooth_min(x: f64, y: f64, eps: f64) -> (f64, f64, f64) {
    let d = y - x;
    if d >= eps {
        (x, 1.0, 0.0)
    } else if d <= -eps {
        (y, 0.0, 1.0)
    } else {
        let w = 0.5 + d / (2.0 * eps);
        (
            0.5 * (x + y) - (eps * eps + d * d) / (4.0 * eps),
            w,
            1.0 - w,
        )
    }
}

/// C² smooth minimum of `x` and `y` over `eps` (the plain min outside
/// `|x − y| < eps`): `(m, ∂m/∂x, ∂m/∂y)` with `∂m/∂y = S(t)`, the
/// smoothstep `S = 3t² − 2t³` of `t = (eps − d)/(2 eps)`, `d = y − x`, so
/// `m = x − 2 eps (t³ − t⁴/2)`: at a tie `m = x − 3 eps/16`.
#[inline]
fn smooth_min_c2(x: f64, y: f64, eps: f64) -> (f64, f64, f64) {
    let d = y - x;
    if d >= eps {
        (x, 1.0, 0.0)
    } else if d <= -eps {
        (y, 0.0, 1.0)
    } else {
        let t = (eps - d) / (2.0 * eps);
        let wy = t * t * (3.0 - 2.0 * t);
        (x - 2.0 * eps * t * t * t * (1.0 - 0.5 * t), 1.0 - wy, wy)
    }
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

/// A depth that is a smooth minimum of up to three candidate depths: every
/// part is pushed at the blended depth `depth` with its weight `∂depth/∂δ_i`
/// (the weights sum to 1), so the energy is `U(depth)` and the parts'
/// forces sum to its exact gradient `F(depth) Σ_i w_i ∇δ_i`. A part with a
/// [`Wrench`] carries a gradient that is not a single force line.
#[derive(Clone, Copy)]
struct Blend {
    parts: [Part; 3],
    depth: f64,
}

impl Blend {
    fn single(c: Cand) -> Self {
        Self {
            parts: [(c, None, 1.0), EMPTY_PART, EMPTY_PART],
            depth: c.depth,
        }
    }

    /// `smooth_min(self, other)` over [`TIE_BAND`], weights by the chain
    /// rule.
    fn smin(self, other: Blend) -> Blend {
        self.smin_by(other, |x, y| smooth_min(x, y, TIE_BAND))
    }

    /// The smooth minimum `blend(self, other)` (value and its two
    /// derivatives), weights by the chain rule.
    fn smin_by(self, other: Blend, blend: impl Fn(f64, f64) -> (f64, f64, f64)) -> Blend {
        let (m, wx, wy) = blend(self.depth, other.depth);
        if wy == 0.0 {
            return self;
        }
        if wx == 0.0 {
            return other;
        }
        let mut parts = [EMPTY_PART; 3];
        let mut k = 0;
        for (p, w) in self
            .parts
            .iter()
            .map(|p| (p, wx))
            .chain(other.parts.iter().map(|p| (p, wy)))
        {
            if p.2 > 0.0 && k < 3 {
                parts[k] = (p.0, p.1, p.2 * w);
                k += 1;
            }
        }
        Blend { parts, depth: m }
    }

    /// Push with an overall weight (and its couple), see [`push_weighted`].
    fn push(&self, out: &mut Vec<ContactPoint>, a: &FibreGeom, weight: f64, weight_grad: DVec3) {
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

/// Axial overlap `ℓ` of the segments (measured along A) and its gradient
/// with respect to A's translation and rotation (rotation vector, about
/// A's centre): `ℓ = min(m + h_B|a·b|, h_A) − max(m − h_B|a·b|, −h_A)`,
/// `m = −a·(c_A − c_B)`.
struct AxialOverlap {
    len: f64,
    grad_x: DVec3,
    grad_rot: DVec3,
}

#[inline]
fn axial_overlap(a: &FibreGeom, b: &FibreGeom) -> AxialOverlap {
    let w = a.centre - b.centre;
    let ab = a.axis.dot(b.axis);
    let bb = ab.abs();
    let mid = -a.axis.dot(w);
    let (mid_x, mid_rot) = (-a.axis, -a.axis.cross(w));
    let bb_rot = ab.signum() * a.axis.cross(b.axis);
    let (mut len, mut grad_x, mut grad_rot) = (0.0, DVec3::ZERO, DVec3::ZERO);
    let hi = mid + b.half_length * bb;
    if hi < a.half_length {
        len += hi;
        grad_x += mid_x;
        grad_rot += mid_rot + b.half_length * bb_rot;
    } else {
        len += a.half_length;
    }
    let lo = mid - b.half_length * bb;
    if lo > -a.half_length {
        len -= lo;
        grad_x -= mid_x;
        grad_rot -= mid_rot - b.half_length * bb_rot;
    } else {
        len += a.half_length;
    }
    AxialOverlap {
        len,
        grad_x,
        grad_rot,
    }
}

/// `−∇_A δ` of a contact depth whose gradient is not a force along one
/// line: force (per unit Hertz force) and torque about A's centre.
#[derive(Clone, Copy)]
struct Wrench {
    force: DVec3,
    torque: DVec3,
}

/// Push a contact of depth `c.depth`, weight `weight`, whose exact force on
/// A is `weight F(δ) wr.force` and torque `weight F(δ) wr.torque` (plus the
/// weight's couple). A force along one line carries a torque only ⊥ the
/// force, so the wrench is split between two points of weight `weight/2`
/// at `c.point ± d` with directions `N ± M` (not unit: the stage applies
/// `weight F(δ) normal`): forces sum to `N`, torques to `arm × N + d × M`,
/// and `d ⊥ T`, `M = T × d/|d|²` gives `d × M = T`, the residual torque.
/// The energy is `weight U(δ)` as for any contact.
fn push_wrench(
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

/// Near-coaxial end-to-end contact: regime 3's depth
/// ([`penetration_smoothed`], domed min over directions) started from A's
/// facing face normal, without parry (parry is wrong for exactly coaxial
/// pairs); `cp_normal` (the closest-point normal) seeds the search for a
/// tied second minimum as in regime 3. `None` when the pair is not end to
/// end (axial overlap ≥ min radius) or A's facing face centre is not over
/// B's face (rim on rim: regime 3 with parry). Regimes 1–3 share one depth
/// function, so these acceptance tests switch only how the minimum is
/// seeded, not the potential.
fn coaxial(a: &FibreGeom, b: &FibreGeom, cp_normal: DVec3) -> Option<Blend> {
    let w = a.centre - b.centre;
    let axial = w.dot(b.axis);
    let axial_overlap = a.half_length + b.half_length - axial.abs();
    if axial_overlap >= a.radius.min(b.radius) {
        return None;
    }
    let side = a.axis.dot(w).signum();
    let face = a.centre - side * a.half_length * a.axis;
    let lateral = face - b.centre;
    if (lateral - lateral.dot(b.axis) * b.axis).length() > b.radius {
        return None;
    }
    Some(penetration_smoothed(a, b, [cp_normal, side * a.axis]))
}

/// Exact support value of a cylinder in direction `n`:
/// `h(n) = n·c + h|n·a| + r|n⊥|` (closed form).
#[inline]
fn support_exact(f: &FibreGeom, n: DVec3) -> f64 {
    let na = n.dot(f.axis);
    n.dot(f.centre) + f.half_length * na.abs() + f.radius * (n - na * f.axis).length()
}

/// Dome geometry of [`END_FACE_DOME_SIN`] for radius `r`: `(R, σ, cos θc)`.
#[inline]
fn dome(r: f64) -> (f64, f64, f64) {
    let sin_c = END_FACE_DOME_SIN;
    let cos_c = (1.0 - sin_c * sin_c).sqrt();
    let big_r = r / sin_c;
    (big_r, big_r * (1.0 - cos_c), cos_c)
}

/// Sag of the end-face dome ([`END_FACE_DOME_SIN`]) of a fibre of radius
/// `r`: the largest amount by which regime 3 over-estimates a depth, per
/// face in contact.
pub fn dome_sag(r: f64) -> f64 {
    dome(r).1
}

/// Support of the domed cylinder (see [`END_FACE_DOME_SIN`]) of end
/// `sigma` = ±1, in the unit direction `n`: point `p` and value `n·p`.
/// Within θc of the face normal `sigma a` the point is on the cap
/// (`face centre + sigma (σ − R) a + R n`), elsewhere on the rim of that
/// end (`face centre + r n⊥/|n⊥|`). With `sigma = sign(n·a)` this is the
/// support of the domed body; with the other sign it is the smooth
/// continuation of the other end's branch (the support is the max of the
/// two, the kink being the side circle `n·a = 0`).
#[inline]
fn support_branch(f: &FibreGeom, n: DVec3, sigma: f64) -> (DVec3, f64) {
    let na = n.dot(f.axis);
    let face = f.centre + sigma * f.half_length * f.axis;
    let (big_r, sag, cos_c) = dome(f.radius);
    let p = if sigma * na >= cos_c {
        face + (sigma * (sag - big_r)) * f.axis + big_r * n
    } else {
        let perp = n - na * f.axis;
        let pl = perp.length();
        if pl > 0.0 {
            face + (f.radius / pl) * perp
        } else {
            face
        }
    };
    (p, n.dot(p))
}

/// Support of the domed cylinder in the unit direction `n` (the end facing
/// `n`). Unique (the gradient of the support value) except on the side
/// circle `n·a = 0`, where it is a whole generator line.
#[inline]
fn support(f: &FibreGeom, n: DVec3) -> (DVec3, f64) {
    support_branch(f, n, if n.dot(f.axis) >= 0.0 { 1.0 } else { -1.0 })
}

/// Exact overlap of the projections of A and B on the unit direction `n`
/// (pointing from B towards A): `h_B(n) + h_A(−n)`. The penetration depth
/// is the minimum of this over all directions (separating-axis theorem), so
/// a correct MTD `(depth, n)` satisfies `depth = projection_overlap(n)` and
/// `depth ≤ projection_overlap(m)` for every other `m`; a direction with
/// `projection_overlap(n) ≤ 0` proves the pair separated.
#[inline]
pub fn projection_overlap(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    support_exact(b, n) + support_exact(a, -n)
}

/// Projection overlap of the domed cylinders ([`END_FACE_DOME_SIN`]),
/// `h̃_B(n) + h̃_A(−n)`: the function whose minimum over unit `n` is the
/// depth of regimes 1 and 3. Equal to [`projection_overlap`] unless `n` is
/// within θc of a face normal, and never more than `σ_A + σ_B` above it.
#[inline]
pub fn domed_projection_overlap(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    support(b, n).1 + support(a, -n).1
}

/// Cylinder pose for parry: its cylinders are along local +Y.
#[inline]
fn parry_pose(f: &FibreGeom) -> Pose {
    Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis))
}

/// parry's cylinder–cylinder contact, checked, for pairs closer than
/// `margin` (the domes' sags: a domed pair can touch while the exact
/// cylinders are up to `margin` apart). Checks: finite unit normal;
/// `depth ≤` capsule `bound`; `depth` within [`PARRY_REL_TOL`] of the exact
/// projection overlap along its own normal (an upper bound of the true
/// depth, equal to it for a correct MTD or closest-point direction).
/// `Err(normal)` = rejected (with parry's normal if finite, as one more
/// seed). `Ok(None)` = parry sees the exact cylinders more than `margin`
/// apart: see [`confirm_separated`].
fn parry_contact(
    a: &FibreGeom,
    b: &FibreGeom,
    bound: f64,
    margin: f64,
) -> Result<Option<Cand>, DVec3> {
    PARRY_CALLS.fetch_add(1, Ordering::Relaxed);
    let ca = Cylinder::new(a.half_length, a.radius);
    let cb = Cylinder::new(b.half_length, b.radius);
    let Ok(res) = query::contact(&parry_pose(a), &ca, &parry_pose(b), &cb, margin) else {
        return Err(DVec3::ZERO);
    };
    let Some(c) = res else {
        return Ok(None);
    };
    let depth = -c.dist;
    let n = -c.normal1;
    if !(n.is_finite() && (n.length() - 1.0).abs() < 1e-9) {
        return Err(DVec3::ZERO);
    }
    let tol = PARRY_REL_TOL * depth.abs() + 1e-8 * (a.radius + b.radius);
    let proj = projection_overlap(a, b, n);
    let ok = depth.is_finite()
        && depth <= bound + tol
        && (proj - depth).abs() <= tol
        && c.point1.is_finite()
        && c.point2.is_finite();
    if !ok {
        return Err(n);
    }
    Ok(Some(Cand {
        depth,
        point: 0.5 * (c.point1 + c.point2),
        normal: n,
    }))
}

/// Whether one of the cheap axes (closest-point normal, centre line, the two
/// axes, their cross product) separates the two fibres by more than
/// `margin` (the domes' sags): an exact proof of no contact.
fn cheap_axis_separates(a: &FibreGeom, b: &FibreGeom, margin: f64, cp_normal: DVec3) -> bool {
    let w = a.centre - b.centre;
    [cp_normal, w, a.axis, b.axis, a.axis.cross(b.axis)]
        .into_iter()
        .any(|d| {
            let l = d.length();
            l > 1e-300 && l.is_finite() && {
                let d = d / l;
                projection_overlap(a, b, d).min(projection_overlap(a, b, -d)) < -margin
            }
        })
}

/// Runtime guard on parry's "no contact" verdict: true if a direction is
/// found along which the exact projections are more than `margin` apart
/// (proof that even the domed cylinders are separated: they exceed the
/// exact ones by at most `margin` in every direction). Tries the cheap axes
/// first (closest-point normal, centre line, axes, common normal), then
/// local minimisations from each of them. A `false` is counted in
/// [`PARRY_UNCONFIRMED`]; parry's verdict is still followed (GJK's
/// separation answer is the reliable part of parry; the local search is
/// not a global proof of contact).
fn confirm_separated(a: &FibreGeom, b: &FibreGeom, margin: f64, cp_normal: DVec3) -> bool {
    let w = a.centre - b.centre;
    if cheap_axis_separates(a, b, margin, cp_normal) {
        return true;
    }
    // Local searches on both side circles and on the smooth branches, from
    // each cheap axis (a separating direction of two fibres is typically
    // on a side circle: test case 2 has pairs 0.3 mm apart whose only
    // separating directions are there, far from all cheap axes).
    let sig = |d: DVec3, u: DVec3| if d.dot(u) >= 0.0 { 1.0 } else { -1.0 };
    let apart = |m: DVec3| projection_overlap(a, b, m) < -margin;
    for d in [cp_normal, w, a.axis.cross(b.axis), a.axis, b.axis] {
        let l = d.length();
        if !(l > 1e-300 && l.is_finite()) {
            continue;
        }
        for st in [d / l, -d / l] {
            for u in [a.axis, b.axis] {
                if apart(circle_min(a, b, u, st)) {
                    return true;
                }
            }
            if apart(sphere_min(a, b, st, sig(-st, a.axis), sig(st, b.axis))) {
                return true;
            }
        }
    }
    PARRY_UNCONFIRMED.fetch_add(1, Ordering::Relaxed);
    false
}

/// Fibre–fibre contacts (0–2 points); normal = direction of the force on A.
pub fn contact_fibre_fibre(a: &FibreGeom, b: &FibreGeom, out: &mut Vec<ContactPoint>) {
    let (s, t) = segment_closest_params(a, b);
    let d_seg = (a.centre + s * a.axis - b.centre - t * b.axis).length();
    let bound = a.radius + b.radius - d_seg;
    if bound <= 0.0 {
        return;
    }
    let sin = a.axis.cross(b.axis).length();

    // 1. Near-coaxial end to end.
    if sin < COAXIAL_SIN {
        let cp_normal = closest_point_contact(a, b, s, t).normal;
        if let Some(c) = coaxial(a, b, cp_normal) {
            c.push(out, a, 1.0, DVec3::ZERO);
            return;
        }
    }

    // 2. Side–side.
    let interior = s.abs() < a.half_length && t.abs() < b.half_length;
    // Axial overlap of the segments, measured along A.
    let axial_len = axial_overlap(a, b).len;
    // Parallel blend: potential U(δ_main) + w·U(δ_2) when interior, else
    // w·(U(δ_main) + U(δ_2)) + (1 − w)·U(δ_pd) (regime 3's depth), so
    // the second contact and the model switch fade in/out continuously.
    let (w_par, w_grad) = parallel_weight(a, b, sin);
    let mut w_side = 0.0;
    if interior || (sin < PARALLEL_SIN && axial_len > 0.0) {
        let (main, second) = side_side(a, b, s, t);
        second.push(out, a, w_par, w_grad);
        if interior {
            main.push(out, a, 1.0, DVec3::ZERO);
            return;
        }
        main.push(out, a, w_par, w_grad);
        if w_par >= 1.0 {
            return;
        }
        w_side = w_par;
    }

    // 3. End involved: parry's normal (checked) seeds an exact minimisation
    //    of the projection overlap over the cylinders' feature manifolds.
    let cp = closest_point_contact(a, b, s, t);
    let margin = dome_sag(a.radius) + dome_sag(b.radius);
    // A separating axis among the cheap candidates proves there is no
    // contact without asking parry (most near misses of capsules: 3x fewer
    // parry calls in test case 2).
    if cheap_axis_separates(a, b, margin, cp.normal) {
        return;
    }
    let (parry_n, parry_ok) = match parry_contact(a, b, bound, margin) {
        Ok(None) => {
            confirm_separated(a, b, margin, cp.normal);
            return;
        }
        Ok(Some(c)) => (c.normal, true),
        Err(n) => (n, false),
    };
    if !parry_ok {
        PARRY_REJECTS.fetch_add(1, Ordering::Relaxed);
    }
    let (w_pd, g_pd) = if w_side > 0.0 {
        (1.0 - w_side, -w_grad)
    } else {
        (1.0, DVec3::ZERO)
    };
    penetration_smoothed(a, b, [cp.normal, parry_n]).push(out, a, w_pd, g_pd);
}

/// The function regime 3 minimises ([`domed_projection_overlap`]).
#[inline]
fn pov(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> f64 {
    domed_projection_overlap(a, b, n)
}

/// Regime 3's depth: `min_n` [`domed_projection_overlap`]`(n)`, the
/// penetration depth of the two domed cylinders (separating-axis theorem;
/// see [`END_FACE_DOME_SIN`]): equal to the flat cylinders' depth when the
/// minimiser is more than θc from every face normal, at most `σ_A + σ_B`
/// deeper otherwise. The function is smooth except on each cylinder's side
/// great circle (`n ⊥ axis`, the support jumps between end rims) and C¹ at
/// the caps' edges. The minimum is therefore searched on each feature
/// manifold: the face normals and common normal (points), the two side
/// circles (1-D Newton), and each smooth branch on the sphere (2-D Newton:
/// rim on rim, a rim or generator on a cap), seeded by parry's normal / the
/// closest-point normal and, when a face normal is competitive, by that
/// face normal. Every value is an upper bound of the minimum; the least
/// one is returned.
///
/// Gradient: at a smooth minimum the two support points differ along `n`
/// only, and the force at either is the exact gradient (envelope theorem).
/// On one body's side circle that body's support is a whole generator, and
/// the force at the *other* body's support point is the gradient
/// (parametrise `n` in the degenerate body's frame; Danskin). On both side
/// circles (common normal, generators crossing) the force acts at the
/// crossing of the two generators.
fn penetration(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2]) -> Cand {
    let m = depth_minima(a, b, seeds, false);
    contact_along(a, b, m.best_n, m.best)
}

/// Regime 1 and 3's depth with its ties smoothed: [`penetration`]'s
/// minimum `δ1`, and, when the lowest *other* local minimum `δ2` of the
/// domed projection overlap (a different escape direction) is within
/// [`END_TIE_BAND`] of it, their C² smooth minimum `m(δ1, δ2)`
/// ([`smooth_min_c2`]), pushed as two contacts (one per minimum, its own
/// normal and point) at depth `m` with weights `∂m/∂δ_i` (summing to 1):
/// energy `U(m)`, forces `F(m) Σ ∂m/∂δ_i ∇δ_i`, its exact gradient (each
/// minimum's gradient by the envelope theorem, as for `δ1` alone). The
/// weights depend on the pose only through `δ1, δ2`, and sum to 1, so they
/// carry no [`ContactPoint::weight_grad`].
///
/// Why (test case 2, `leapfrog`, fibres 1 and 3 nearly end to end, |sin|
/// 0.073, depth 0.46 mm, t = 0.7559247 s): B's face cap (escape along B's
/// axis) rising at 1.25e-7 m per step and A's side circle (escape ⊥ A)
/// falling at 5.5e-7 m per step crossed between two steps; the plain
/// minimum turned the force by 86° in one step: +5.06e-3 % of the energy.
/// C² rather than the C¹ [`smooth_min`]: the curvature of a C¹ blend
/// jumps by ~1/ε at the band's edges, and leap-frog's energy error
/// follows the curvature, so it kept a net step (9e-5 % at ε = 1 µm);
/// the peak inside the band scales as 1/ε (4.6e-4 % at 1 µm, 4.6e-5 % at
/// 10 µm for that crossing at ~7 m/s).
fn penetration_smoothed(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2]) -> Blend {
    let m = depth_minima(a, b, seeds, true);
    let best = Blend::single(contact_along(a, b, m.best_n, m.best));
    match m.runner_up {
        Some((v, n)) if v - m.best < END_TIE_BAND => {
            let other = Blend::single(contact_along(a, b, n, v));
            best.smin_by(other, |x, y| smooth_min_c2(x, y, END_TIE_BAND))
        }
        _ => best,
    }
}

/// Width ε (m) of the smooth minimum of two tied local minima of regimes 1
/// and 3's depth ([`penetration_smoothed`]): at an exact tie the depth is
/// under-estimated by 3ε/16 (1.9 µm, less than the domes' over-estimate
/// σ_A + σ_B), less inside `|δ1 − δ2| < ε`, and exact outside. The face
/// screen of [`depth_minima`] is widened by ε so that a cap minimum within
/// ε of the winner is always searched.
pub const END_TIE_BAND: f64 = 1e-5;

/// Two local minima of the depth whose normals are closer than this
/// (cos 1e-4 rad) are one minimum found twice (different searches agree
/// to ~1e-9 rad; a smooth minimum of a minimum with itself would
/// under-estimate it by 3ε/16).
const SAME_MINIMUM_COS: f64 = 1.0 - 5e-9;

/// Result of [`depth_minima`]: the least value found (and its direction),
/// and the least *local minimum* in another direction, if any was found.
struct Minima {
    best: f64,
    best_n: DVec3,
    runner_up: Option<(f64, DVec3)>,
}

/// The searches of [`penetration`], with a record of the local minima they
/// reach: a side-circle minimum that is a local minimum on the sphere, a
/// smooth-branch minimum inside its own branch, both stationary (a search
/// stopped short is not a minimum, and the force at it is not the
/// gradient of its value: a Newton search stalled 0.9 mrad from a cap
/// minimum, 1 µm above it, test case 2 at t = 0.355104 s).
struct Search<'g> {
    a: &'g FibreGeom,
    b: &'g FibreGeom,
    best: f64,
    best_n: DVec3,
    minima: [(f64, DVec3); 16],
    count: usize,
    /// Stationarity tolerance of a local minimum: the tangential offset of
    /// the two support points (m).
    tol: f64,
}

impl Search<'_> {
    fn consider(&mut self, n: DVec3) {
        let l = n.length();
        if !(l > 1e-12 && l.is_finite()) {
            return;
        }
        for m in [n / l, -n / l] {
            let v = pov(self.a, self.b, m);
            if v < self.best {
                self.best = v;
                self.best_n = m;
            }
        }
    }

    fn record(&mut self, v: f64, n: DVec3) {
        if self.count < self.minima.len() {
            self.minima[self.count] = (v, n);
            self.count += 1;
        }
    }

    /// Minimum on the side circle ⊥ `u` (one of the axes) from `st`.
    fn circle(&mut self, u_is_a: bool, st: DVec3) {
        let (a, b) = (self.a, self.b);
        let (f, u) = if u_is_a { (a, a.axis) } else { (b, b.axis) };
        let m = circle_min(a, b, u, st);
        self.consider(m);
        // A local minimum on the sphere iff the other body's support
        // point lies between the circle's body's end planes (the one-sided
        // derivatives off the circle are h ∓ (p − c)·u); where it does not,
        // a smooth branch holds the minimum ([`Search::branch`]).
        let v = pov(a, b, m);
        let (pb, pa) = (support(b, m).0, support(a, -m).0);
        let p = if u_is_a { pb } else { pa };
        // Stationary along the circle: the supports differ along m only
        // in the circle's tangent u × m (the degenerate body's generator
        // is along u, so any of its points gives the same component).
        let stationary = (pb - pa).dot(u.cross(m)).abs() <= self.tol;
        if stationary && (p - f.centre).dot(u).abs() <= f.half_length {
            self.record(v, m);
        }
    }

    /// Minimum of the smooth branch (A's end `fa`, B's end `fb`) from `st`.
    fn branch(&mut self, st: DVec3, fa: f64, fb: f64) {
        let (a, b) = (self.a, self.b);
        let m = sphere_min(a, b, st, fa, fb);
        self.consider(m);
        // In its own branch, and stationary (the search may stop short,
        // e.g. on a cap's edge): the supports differ along m only.
        if sig(-m, a.axis) == fa && sig(m, b.axis) == fb {
            let g = support_branch(b, m, fb).0 - support_branch(a, -m, fa).0;
            if (g - g.dot(m) * m).length() <= self.tol {
                self.record(pov(a, b, m), m);
            }
        }
    }

    /// Side circles near `st` and the smooth branches of `st` (and of the
    /// other end of a body whose side circle is near).
    fn from(&mut self, st: DVec3) {
        let (a, b) = (self.a, self.b);
        // Side circles of B and of A (only when the start is near one:
        // parry's normal is accurate to far better than this), then the
        // generic sphere.
        for (u_is_a, u) in [(false, b.axis), (true, a.axis)] {
            if st.dot(u).abs() < 0.1 {
                self.circle(u_is_a, st);
            }
        }
        let (sa, sb) = (sig(-st, a.axis), sig(st, b.axis));
        let near = |u: DVec3| st.dot(u).abs() < 0.1;
        for (fa, fb) in [(sa, sb), (-sa, sb), (sa, -sb)] {
            if (fa != sa && !near(a.axis)) || (fb != sb && !near(b.axis)) {
                continue;
            }
            self.branch(st, fa, fb);
        }
    }
}

/// Sign of `d·u` (+1 for 0).
#[inline]
fn sig(d: DVec3, u: DVec3) -> f64 {
    if d.dot(u) >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// The minimisation of [`penetration`] (`seeds`: the closest-point normal,
/// and the start candidate, parry's normal or a face normal). With
/// `runner_up`, also the least other local minimum, searched so that it is
/// found whichever of two tied minima wins: besides the searches from the
/// start (parry's normal, which jumps to the winner at a tie), from every
/// face normal within the bowl plus [`END_TIE_BAND`] (instead of the most
/// competitive one within the bowl), and on the side circles near
/// `seeds[0]` (continuous through a tie). Without it the searches, and so
/// the result, are those of the plain minimum.
fn depth_minima(a: &FibreGeom, b: &FibreGeom, seeds: [DVec3; 2], runner_up: bool) -> Minima {
    let w = a.centre - b.centre;
    let mut s = Search {
        a,
        b,
        best: f64::INFINITY,
        best_n: DVec3::ZERO,
        minima: [(0.0, DVec3::ZERO); 16],
        count: 0,
        tol: 1e-6 * (a.radius + b.radius),
    };
    for d in [a.axis, b.axis, a.axis.cross(b.axis), w, seeds[0], seeds[1]] {
        s.consider(d);
    }
    // The face normals (the minimum may sit on a cap, off the normal
    // itself), most competitive first.
    let mut faces = [a.axis, -a.axis, b.axis, -b.axis].map(|u| (pov(a, b, u), u));
    faces.sort_by(|x, y| x.0.total_cmp(&y.0));
    let start = if pov(a, b, seeds[1]) <= s.best + 1e-9 * (a.radius + b.radius) {
        seeds[1]
    } else {
        s.best_n
    };
    let bowl = 2.0 * (dome_sag(a.radius) + dome_sag(b.radius));
    let screen = s.best + bowl + if runner_up { END_TIE_BAND } else { 0.0 };
    s.from(start);
    for &(v, face) in faces.iter().take(if runner_up { 4 } else { 1 }) {
        if v <= screen && (face - start).length() > 1e-12 {
            s.from(face);
        }
    }
    if runner_up {
        let st = seeds[0];
        let l = st.length();
        if l > 1e-12 && l.is_finite() && (st / l - start).length() > 1e-12 {
            for (u_is_a, u) in [(false, b.axis), (true, a.axis)] {
                if (st / l).dot(u).abs() < 0.1 {
                    s.circle(u_is_a, st / l);
                }
            }
        }
    }
    let mut runner: Option<(f64, DVec3)> = None;
    if runner_up {
        for &(v, n) in &s.minima[..s.count] {
            if n.dot(s.best_n) < SAME_MINIMUM_COS && runner.is_none_or(|r| v < r.0) {
                runner = Some((v, n));
            }
        }
    }
    Minima {
        best: s.best,
        best_n: s.best_n,
        runner_up: runner,
    }
}

/// The contact of a depth minimum `depth` at the unit direction `n` (force
/// on A): its application point.
fn contact_along(a: &FibreGeom, b: &FibreGeom, n: DVec3, depth: f64) -> Cand {
    let (sb, _) = support(b, n);
    let (sa, _) = support(a, -n);
    // Use the support point of the body whose support is the more clearly
    // unique. With domed faces the only degenerate supports are on the
    // side circles (n·axis = 0: a generator line), so the clarity is |n·axis|
    // (a sine, like the distance of the minimiser from that circle). The
    // Newton searches land *near* such circles, not on them, so "more
    // clearly" matters: a minimiser 1e-12 off B's side circle makes B's
    // "unique" support an arbitrary end of its generator.
    // History: with flat faces a face normal was degenerate too; a
    // minimiser 4e-12 off a face normal put the force at an arbitrary rim
    // point (test case 2, end on end at 16°), and a face measure 1 − |n·a|,
    // quadratic in the angle, called a rim point 3.5e-5 rad off the face
    // normal degenerate and used B's far end (test case 2, t = 0.354567 s);
    // `tests/contact_geometry.rs` keeps both poses.
    let (ca, cb) = (n.dot(a.axis).abs(), n.dot(b.axis).abs());
    let point = if ca.max(cb) < SIDE_CIRCLE_TOL {
        generator_crossing(a, b, n)
    } else if ca >= cb {
        sa + 0.5 * depth * n
    } else {
        sb - 0.5 * depth * n
    };
    Cand {
        depth,
        point,
        normal: n,
    }
}

/// Axial escape of a near-parallel pair: the local minimum of the domed
/// projection overlap reached from the most competitive face normal (over
/// the ends, as opposed to sideways). A smooth function of the pose where
/// that minimum is unique.
fn axial_escape(a: &FibreGeom, b: &FibreGeom) -> Cand {
    let mut face = a.axis;
    let mut face_v = f64::INFINITY;
    for u in [a.axis, -a.axis, b.axis, -b.axis] {
        let v = pov(a, b, u);
        if v < face_v {
            face_v = v;
            face = u;
        }
    }
    let sig = |d: DVec3, u: DVec3| if d.dot(u) >= 0.0 { 1.0 } else { -1.0 };
    let n = sphere_min(a, b, face, sig(-face, a.axis), sig(face, b.axis));
    let v = pov(a, b, n);
    if v < face_v {
        contact_along(a, b, n, v)
    } else {
        contact_along(a, b, face, face_v)
    }
}

/// Below this |n·axis| for both bodies, the depth minimiser is taken to be
/// on both side circles (generators crossing, see [`generator_crossing`]).
const SIDE_CIRCLE_TOL: f64 = 1e-7;

/// Both supports are generator lines (`n ⊥` both axes): the contact point
/// is midway between the closest points of the two generator segments.
fn generator_crossing(a: &FibreGeom, b: &FibreGeom, n: DVec3) -> DVec3 {
    let gen = |f: &FibreGeom, d: DVec3| {
        let perp = d - d.dot(f.axis) * f.axis;
        let l = perp.length();
        let u = if l > 1e-300 {
            perp / l
        } else {
            any_perp(f.axis)
        };
        FibreGeom {
            centre: f.centre + f.radius * u,
            radius: 0.0,
            ..*f
        }
    };
    let (ga, gb) = (gen(a, -n), gen(b, n));
    let (s, t) = segment_closest_params(&ga, &gb);
    0.5 * (ga.centre + s * ga.axis + gb.centre + t * gb.axis)
}

/// 1-D Newton (numerical derivatives, backtracking) on the great circle
/// `n ⊥ u`, starting from the projection of `seed`.
fn circle_min(a: &FibreGeom, b: &FibreGeom, u: DVec3, seed: DVec3) -> DVec3 {
    let mut e1 = seed - seed.dot(u) * u;
    if e1.length_squared() < 1e-24 {
        e1 = u.any_orthonormal_vector();
    }
    let e1 = e1.normalize();
    let e2 = u.cross(e1);
    let at = |th: f64| {
        let (sn, cs) = th.sin_cos();
        cs * e1 + sn * e2
    };
    let f = |th: f64| pov(a, b, at(th));
    let mut th = 0.0;
    let mut v = f(th);
    let eps = 1e-5;
    for _ in 0..30 {
        let (fp, fm) = (f(th + eps), f(th - eps));
        let d1 = (fp - fm) / (2.0 * eps);
        let d2 = (fp - 2.0 * v + fm) / (eps * eps);
        let mut step = if d2 > 0.0 {
            -d1 / d2
        } else {
            -0.05 * d1.signum()
        };
        step = step.clamp(-0.5, 0.5);
        if step.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let nv = f(th + step);
            if nv < v {
                th += step;
                v = nv;
                moved = true;
                break;
            }
            step *= 0.5;
        }
        if !moved || step.abs() < 1e-13 {
            break;
        }
    }
    at(th)
}

/// 2-D damped Newton on the sphere for one smooth branch of the domed
/// projection overlap (A's end `sigma_a`, B's end `sigma_b`; analytic
/// gradient `p̃_B(n) − p̃_A(−n)`, Hessian by central differences of it),
/// accepting only decreases. The overlap is the max of its four branches
/// (kinks on the side circles only), so its minimum is a branch minimum
/// lying in that branch's own region, or lies on a side circle
/// ([`circle_min`]). Minimising a smooth branch converges quadratically
/// even when the minimum is microradians from a side circle, where a
/// Newton iteration on the kinked function stalls.
fn sphere_min(a: &FibreGeom, b: &FibreGeom, seed: DVec3, sigma_a: f64, sigma_b: f64) -> DVec3 {
    let val = |m: DVec3| support_branch(b, m, sigma_b).1 + support_branch(a, -m, sigma_a).1;
    let mut n = seed;
    let mut best = val(n);
    for _ in 0..30 {
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let grad = |m: DVec3| {
            let g = support_branch(b, m, sigma_b).0 - support_branch(a, -m, sigma_a).0;
            (g.dot(e1), g.dot(e2))
        };
        let (g1, g2) = grad(n);
        let eps = 1e-6;
        let (p1, q1) = grad((n + eps * e1).normalize());
        let (m1, r1) = grad((n - eps * e1).normalize());
        let (p2, q2) = grad((n + eps * e2).normalize());
        let (m2, r2) = grad((n - eps * e2).normalize());
        let h11 = (p1 - m1) / (2.0 * eps);
        let h22 = (q2 - r2) / (2.0 * eps);
        let h12 = 0.25 * ((q1 - r1) + (p2 - m2)) / eps;
        let det = h11 * h22 - h12 * h12;
        let (mut d1, mut d2) = if h11 > 0.0 && det > 0.0 {
            (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
        } else {
            let gl = (g1 * g1 + g2 * g2).sqrt().max(1e-300);
            (-0.05 * g1 / gl, -0.05 * g2 / gl)
        };
        if d1.abs() + d2.abs() < 1e-11 {
            break;
        }
        let mut moved = false;
        for _ in 0..12 {
            let m = (n + d1 * e1 + d2 * e2).normalize();
            let v = val(m);
            if v < best {
                best = v;
                n = m;
                moved = true;
                break;
            }
            d1 *= 0.5;
            d2 *= 0.5;
        }
        if !moved || d1.abs() + d2.abs() < 1e-13 {
            break;
        }
    }
    n
}
