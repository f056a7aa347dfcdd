//! Broad phase: candidate pairs from axis-aligned bounding boxes.
//!
//! Brute force for `n ≤ BRUTE_FORCE_MAX`, otherwise sort-and-sweep along the
//! axis of largest centre spread (O(N log N + k) for k overlaps along it).
//! Output is always sorted `(i, j)` with `i < j`, so contact order (and hence
//! floating-point summation order) is deterministic.

use super::FibreGeom;
use glam::DVec3;

/// Up to this many boxes the O(N²) loop is cheaper than sorting.
pub const BRUTE_FORCE_MAX: usize = 32;

/// Exact AABB of a flat-ended cylinder: the two end discs' extents.
/// Half-extent along world axis k: `h|a_k| + r √(1 − a_k²)`.
#[inline]
pub fn fibre_aabb(f: &FibreGeom) -> (DVec3, DVec3) {
    let a = f.axis;
    let disc = f.radius
        * DVec3::from_array(
            (DVec3::ONE - a * a)
                .max(DVec3::ZERO)
                .to_array()
                .map(f64::sqrt),
        );
    let half = f.half_length * a.abs() + disc;
    (f.centre - half, f.centre + half)
}

#[inline]
fn overlaps(a: &(DVec3, DVec3), b: &(DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// All pairs `(i, j)`, `i < j`, whose closed boxes overlap, sorted; `out`
/// is cleared first. Allocates a sort buffer for large `n`: use
/// [`candidate_pairs_with`] to reuse one across steps.
pub fn candidate_pairs(aabbs: &[(DVec3, DVec3)], out: &mut Vec<(u32, u32)>) {
    let mut order = Vec::new();
    candidate_pairs_with(aabbs, &mut order, out);
}

/// [`candidate_pairs`] with a caller-owned sort buffer (no allocation once
/// the buffers have grown).
pub fn candidate_pairs_with(
    aabbs: &[(DVec3, DVec3)],
    order: &mut Vec<u32>,
    out: &mut Vec<(u32, u32)>,
) {
    out.clear();
    let n = aabbs.len();
    if n <= BRUTE_FORCE_MAX {
        for i in 0..n {
            for j in i + 1..n {
                if overlaps(&aabbs[i], &aabbs[j]) {
                    out.push((i as u32, j as u32));
                }
            }
        }
        return;
    }
    // Sweep along the axis with the largest spread of box centres.
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for b in aabbs {
        let c = 0.5 * (b.0 + b.1);
        lo = lo.min(c);
        hi = hi.max(c);
    }
    let spread = hi - lo;
    let k = if spread.x >= spread.y && spread.x >= spread.z {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    };
    order.clear();
    order.extend(0..n as u32);
    order.sort_unstable_by(|&i, &j| {
        aabbs[i as usize].0[k]
            .total_cmp(&aabbs[j as usize].0[k])
            .then(i.cmp(&j))
    });
    for (idx, &i) in order.iter().enumerate() {
        let bi = &aabbs[i as usize];
        for &j in &order[idx + 1..] {
            let bj = &aabbs[j as usize];
            if bj.0[k] > bi.1[k] {
                break;
            }
            if overlaps(bi, bj) {
                out.push((i.min(j), i.max(j)));
            }
        }
    }
    out.sort_unstable();
}
