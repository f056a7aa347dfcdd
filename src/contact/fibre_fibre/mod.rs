//! Fibre–fibre contact of rigid flat-ended cylinders: the regime dispatch.
//!
//! For the end-involved regimes each end face is a very shallow spherical
//! cap through its rim ([`END_FACE_DOME_SIN`], sag 2.5 µm for r = 5 mm), so
//! the body stays convex and its depth is a true penetration depth. After
//! the capsule bound (`r_A + r_B − d_seg ≤ 0`: no contact), in this order:
//! 1. **Near-coaxial end to end** (`|a×b| <` [`COAXIAL_SIN`], A's facing
//!    face centre over B's face): the end-involved depth of regime 3 (kept
//!    apart only so that side–side does not claim these pairs).
//! 2. **Side–side** (closest points of the axis segments interior to both,
//!    or `|a×b| <` [`PARALLEL_SIN`] with overlapping axial projections):
//!    analytic (`side_side.rs`), blended with regime 3 over
//!    `|a×b| ∈ [`[`PARALLEL_BLEND_SIN`]`, `[`PARALLEL_SIN`]`]` by a weight
//!    whose gradient is a pure couple ([`ContactPoint::weight_grad`]).
//! 3. **End involved** (T-junction, L corner, rim on rim): the penetration
//!    depth of the domed cylinders as the least of the stationary values of
//!    the feature pairs near the contact (`end_involved.rs`, `features/`:
//!    face–face, rim–face, face–side, rim–side, rim–rim), tied minima
//!    blended (`blend.rs`). Where that scan cannot certify its answer, the
//!    iterative search (`search.rs`) seeded by parry's checked normal
//!    (`parry_check.rs`) decides, counted in `KernelCounters::fallbacks`.
//!
//! Forces and torques are the exact gradient of the potential except on
//! measure-zero switching sets. Models, limits and the history behind
//! them: docs/contacts.md, "Fibre–fibre".

mod blend;
mod coherence;
mod end_involved;
mod features;
mod parry_check;
mod search;
mod segment;
mod side_side;
mod support;
#[cfg(test)]
mod uniform;

use blend::push_weighted;
pub use blend::{END_TIE_BAND, TIE_BAND};
use coherence::memory_unit;
pub use coherence::PairMemory;
pub use segment::segment_closest_params;
pub use support::{dome_sag, domed_projection_overlap, projection_overlap, END_FACE_DOME_SIN};

use super::{ContactPoint, FibreGeom, KernelCounters};
use end_involved::{penetration_smoothed, remembered_in_regime};
use glam::DVec3;
use segment::{axial_overlap, room_off_interior};
use side_side::{side_side, SideSide};

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

/// How far `a` and `b` may move (the sum of their motion bounds) with
/// their axes kept at `|a×b| ≥` [`PARALLEL_SIN`] (0 when they are not):
/// `||a'×b'| − |a×b|| ≤ |Δa| + |Δb|`, and a body moving by `m` turns its
/// axis by at most `m/h` (its motion bound counts a reach `ρ ≥ h`). While
/// they are, the parallel weight is 0, so the side–side regime contributes
/// only for interior closest points, whose contact (`bound > 0`) is a true
/// overlap (the point `p_A − t n`, `t ∈ [d − r_B, r_A]`, lies in both
/// finite cylinders), and regime 1 not at all: a pair whose cylinders are
/// apart can only be regime 3's, which answers nothing for it either.
/// (Inside the band the side–side end model, capsule-like near the other's
/// end, can touch such a pair: given weight 1 up to |sin| 0.1, it touches
/// one 65 µm apart, and `tests/suite/contact_memory.rs`'s premise test fails.)
#[inline]
pub(super) fn room_beyond_parallel(a: &FibreGeom, b: &FibreGeom) -> f64 {
    let sin = a.axis.cross(b.axis).length();
    ((sin - PARALLEL_SIN) * a.half_length.min(b.half_length)).max(0.0)
}

/// How far `a` and `b` may move (the sum of their motion bounds) while
/// [`contact_fibre_fibre_remembering`] sends them to regime 3 at full
/// weight: axes out of the parallel band (so neither regime 1 nor the
/// parallel blend) and the segments' closest points off the interior (so
/// not regime 2); 0 when it does not now.
pub(super) fn room_in_regime(a: &FibreGeom, b: &FibreGeom) -> f64 {
    room_beyond_parallel(a, b).min(room_off_interior(a, b))
}

/// A candidate contact with A's force normal.
#[derive(Clone, Copy)]
struct Cand {
    depth: f64,
    point: DVec3,
    normal: DVec3,
}

/// Parallel blend weight `w(sin)` (see [`PARALLEL_BLEND_SIN`]) and its
/// gradient with respect to a rotation of A: `dw/dsin · ∂sin/∂φ_A` with
/// `∂|a×b|/∂φ_A = −(a·b) (a×b)/|a×b|`.
#[inline]
pub(super) fn parallel_weight(a: &FibreGeom, b: &FibreGeom, sin: f64) -> (f64, DVec3) {
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

/// Whether a near-coaxial pair is end to end (regime 1): axial overlap below
/// the smaller radius and A's facing face centre over B's face. Such pairs
/// get the end-involved depth; the others (rim on rim, side by side) go on
/// to regimes 2 and 3. Regimes 1–3 share one depth function, so this test
/// switches only which regime claims a pair, not the potential.
fn end_to_end(a: &FibreGeom, b: &FibreGeom) -> bool {
    let w = a.centre - b.centre;
    let axial = w.dot(b.axis);
    let axial_overlap = a.half_length + b.half_length - axial.abs();
    if axial_overlap >= a.radius.min(b.radius) {
        return false;
    }
    let side = a.axis.dot(w).signum();
    let face = a.centre - side * a.half_length * a.axis;
    let lateral = face - b.centre;
    (lateral - lateral.dot(b.axis) * b.axis).length() <= b.radius
}

/// Fibre–fibre contacts of `a` with `b`, appended to `out` (none when
/// apart; a blended or split depth is several weighted points); normal =
/// direction of the force on A. `counters` counts the end-involved scans,
/// their fallbacks and the parry calls and checks.
pub fn contact_fibre_fibre(
    a: &FibreGeom,
    b: &FibreGeom,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
) {
    contact_fibre_fibre_remembering(a, b, out, counters, None);
}

/// [`contact_fibre_fibre`] with the pair's memory of its last end-involved
/// scan and the sum of both bodies' motion bounds since the last call
/// (`coherence.rs`): spent, then used where it still holds, renewed by a
/// scan where it does not.
#[inline]
pub fn contact_fibre_fibre_remembering(
    a: &FibreGeom,
    b: &FibreGeom,
    out: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
    memory: Option<(&mut PairMemory, f64)>,
) {
    let memory = match memory {
        Some((m, motion)) => {
            m.spend(motion, memory_unit(a, b));
            if m.passed_over() {
                counters.passed_over += 1;
                return;
            }
            if m.in_regime() && remembered_in_regime(a, b, m, out, counters) {
                return;
            }
            Some(m)
        }
        None => None,
    };
    let (s, t) = segment_closest_params(a, b);
    let d_seg = (a.centre + s * a.axis - b.centre - t * b.axis).length();
    let bound = a.radius + b.radius - d_seg;
    if bound <= 0.0 {
        // Each body's motion bound also bounds its segment points' (their
        // reach is within ρ), so `d_seg` shrinks by at most their sum.
        if let Some(m) = memory {
            m.note_capsules_apart(-bound, memory_unit(a, b));
        }
        return;
    }
    let sin = a.axis.cross(b.axis).length();

    // 1. Near-coaxial end to end.
    if sin < COAXIAL_SIN && end_to_end(a, b) {
        penetration_smoothed(a, b, (s, t), out, 1.0, DVec3::ZERO, counters, memory);
        return;
    }

    // 2. Side–side (the axial overlap of the segments, measured along A,
    // only for non-interior near-parallel pairs).
    let interior = s.abs() < a.half_length && t.abs() < b.half_length;
    let mut w_side = 0.0;
    let mut w_grad = DVec3::ZERO;
    if interior || (sin < PARALLEL_SIN && axial_overlap(a, b).len > 0.0) {
        let line = side_side(a, b, s, t, counters);
        if let SideSide::Crossing(c) = line {
            // `SideSide::push` of a crossing, without moving the enum.
            push_weighted(out, c, 1.0, DVec3::ZERO);
            return;
        }
        // Parallel blend: potential U(δ_main) + w·U(δ_2) when interior,
        // else w·(U(δ_main) + U(δ_2)) + (1 − w)·U(δ_pd) (regime 3's depth),
        // so the second contact and the model switch fade in/out
        // continuously.
        let (w_par, g_par) = parallel_weight(a, b, sin);
        w_grad = g_par;
        let main = if interior {
            (1.0, DVec3::ZERO)
        } else {
            (w_par, w_grad)
        };
        line.push(out, a, main, (w_par, w_grad));
        if interior || w_par >= 1.0 {
            return;
        }
        w_side = w_par;
    }

    // 3. End involved: the feature-pair kernels near the contact.
    let (w_pd, g_pd) = if w_side > 0.0 {
        (1.0 - w_side, -w_grad)
    } else {
        (1.0, DVec3::ZERO)
    };
    penetration_smoothed(a, b, (s, t), out, w_pd, g_pd, counters, memory);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::stage::motion_bound;
    use glam::DQuat;

    /// Reference: the definition of the room. B turned about its centre
    /// straight towards A's axis (the fastest way into the band) by as
    /// much as a motion bound of `room_beyond_parallel` allows stays out
    /// of the band.
    #[test]
    fn the_room_keeps_the_axes_out_of_the_parallel_band() {
        let a = FibreGeom {
            centre: DVec3::ZERO,
            axis: DVec3::X,
            radius: 0.005,
            half_length: 0.015,
        };
        for sin in [0.036, 0.05, 0.2, 0.7, 1.0] {
            let tilt = f64::asin(sin);
            let b = |angle: f64| FibreGeom {
                centre: DVec3::new(0.01, 0.02, 0.0),
                axis: DQuat::from_rotation_z(angle) * DVec3::X,
                radius: 0.004,
                half_length: 0.012,
            };
            let room = room_beyond_parallel(&a, &b(tilt));
            // The largest turn whose motion bound is within the room.
            let (mut lo, mut hi) = (0.0, tilt);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if f64::from(motion_bound(&b(tilt), &b(tilt - mid))) <= room {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let turned = b(tilt - lo);
            let sin_after = a.axis.cross(turned.axis).length();
            assert!(
                sin_after >= PARALLEL_SIN,
                "{sin}: {sin_after} after {lo} rad"
            );
            // (Near the band the turn is nearly all lost sine: tight.)
            if sin <= 0.05 {
                assert!(
                    sin_after < PARALLEL_SIN + 0.1 * (sin - PARALLEL_SIN),
                    "{sin}: loose"
                );
            }
        }
        let parallel = FibreGeom {
            axis: DVec3::new(1.0, 0.03, 0.0).normalize(),
            ..a
        };
        assert_eq!(room_beyond_parallel(&a, &parallel), 0.0);
    }
}
