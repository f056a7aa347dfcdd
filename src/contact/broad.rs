//! Broad phase: candidate pairs from axis-aligned bounding boxes.
//!
//! [`candidate_pairs`]: brute force for `n ≤ BRUTE_FORCE_MAX`, otherwise
//! sort-and-sweep along the axis of largest centre spread. [`grid_pairs`]: a
//! uniform grid of cells as wide as the largest box, O(N) for boxes of
//! similar size (the sweep is O(N^{5/3}) in a filled box); the neighbour list
//! uses it above `BRUTE_FORCE_MAX` and keeps only the pairs whose axis
//! segments come within reach. Output is always sorted `(i, j)` with `i < j`,
//! so contact order (and hence floating-point summation order) is
//! deterministic.

use super::fibre_fibre::{segment_closest_params, PairMemory};
use super::memory::{entries, place};
use super::shape::{ColliderPose, Shapes};
use super::Wall;
use crate::body::Shape;
use glam::{DVec3, Vec3};

/// Up to this many boxes the O(N²) loop is cheaper than sorting.
pub const BRUTE_FORCE_MAX: usize = 32;

/// Exact axis-aligned bounds of a body of shape `shape` centred at `centre`
/// with unit symmetry axis `axis` (ignored for a sphere). A flat-ended
/// cylinder's box is that of its two end discs: half-extent along world
/// axis k `h|a_k| + r √(1 − a_k²)`. (The neighbour list boxes the capsule
/// of the axis instead.)
#[inline]
pub fn aabb(shape: &Shape, centre: DVec3, axis: DVec3) -> (DVec3, DVec3) {
    let half = match *shape {
        Shape::Sphere { diameter } => DVec3::splat(0.5 * diameter),
        // Contact-free only (the scenario refuses it elsewhere): its bounding sphere.
        Shape::Rigid { semi_axes } => DVec3::splat(semi_axes.max_element()),
        Shape::Fibre { diameter, length } => {
            let disc = DVec3::from_array(
                (DVec3::ONE - axis * axis)
                    .max(DVec3::ZERO)
                    .to_array()
                    .map(f64::sqrt),
            );
            0.5 * length * axis.abs() + 0.5 * diameter * disc
        }
    };
    (centre - half, centre + half)
}

#[inline]
fn overlaps(a: &(DVec3, DVec3), b: &(DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// All pairs `(i, j)`, `i < j`, whose closed boxes overlap, sorted; `out`
/// is cleared first. Allocates a sort buffer for large `n` (the neighbour
/// list reuses one across steps).
pub fn candidate_pairs(aabbs: &[(DVec3, DVec3)], out: &mut Vec<(u32, u32)>) {
    let mut order = Vec::new();
    candidate_pairs_with(aabbs, &mut order, out);
}

/// [`candidate_pairs`] with a caller-owned sort buffer (no allocation once
/// the buffers have grown).
pub(crate) fn candidate_pairs_with(
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

/// All pairs `(i, j)`, `i < j`, whose closed boxes overlap, sorted (the same
/// set as [`candidate_pairs`]), by a uniform grid: boxes are binned by the
/// cell of their lower corner, cells as wide as the widest box, so two
/// overlapping boxes sit in the same or adjacent cells along each axis.
/// Cells are found by binary search in the corners sorted by cell, so an
/// empty region costs nothing.
pub fn grid_pairs(aabbs: &[(DVec3, DVec3)], scratch: &mut GridScratch, out: &mut Vec<(u32, u32)>) {
    out.clear();
    let n = aabbs.len();
    if n < 2 {
        return;
    }
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    let mut width = 0.0f64;
    for (a, b) in aabbs {
        lo = lo.min(*a);
        hi = hi.max(*a);
        width = width.max((*b - *a).max_element());
    }
    // A cell a little wider than the widest box; a degenerate (point) set
    // gets one cell.
    let cell = if width > 0.0 {
        width * (1.0 + 1e-9)
    } else {
        1.0
    };
    let dims = ((hi - lo) / cell).floor() + DVec3::ONE;
    if !dims.is_finite() || dims.x * dims.y * dims.z >= 2f64.powi(62) {
        // Boxes too spread for a grid (or not finite): the sweep handles it.
        let mut order = std::mem::take(&mut scratch.order);
        candidate_pairs_with(aabbs, &mut order, out);
        scratch.order = order;
        return;
    }
    let (ny, nz) = (dims.y as u64, dims.z as u64);
    let coords = |p: DVec3| -> (u64, u64, u64) {
        let c = ((p - lo) / cell).floor();
        (c.x as u64, c.y as u64, c.z as u64)
    };
    let key = |(x, y, z): (u64, u64, u64)| (x * ny + y) * nz + z;
    scratch.keyed.clear();
    scratch.keyed.extend(
        aabbs
            .iter()
            .enumerate()
            .map(|(i, b)| (key(coords(b.0)), i as u32)),
    );
    scratch.keyed.sort_unstable();
    let keyed = &scratch.keyed;
    for &(_, i) in keyed {
        let bi = &aabbs[i as usize];
        let (x, y, z) = coords(bi.0);
        for dx in [-1i64, 0, 1] {
            let cx = x as i64 + dx;
            if cx < 0 || cx >= dims.x as i64 {
                continue;
            }
            for dy in [-1i64, 0, 1] {
                let cy = y as i64 + dy;
                if cy < 0 || cy >= ny as i64 {
                    continue;
                }
                // The z-column of cells cz − 1 ..= cz + 1 is contiguous in key order.
                let column = (cx as u64 * ny + cy as u64) * nz;
                let first = column + z.saturating_sub(1);
                let last = column + (z + 1).min(nz - 1);
                let start = keyed.partition_point(|&(k, _)| k < first);
                for &(k, j) in &keyed[start..] {
                    if k > last {
                        break;
                    }
                    if j > i && overlaps(bi, &aabbs[j as usize]) {
                        out.push((i, j));
                    }
                }
            }
        }
    }
    out.sort_unstable();
}

/// A body's collider pose at a list build, in f32 (24 bytes instead of
/// 48): the reference of the skin test.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SkinRef {
    x: [f32; 3],
    a: [f32; 3],
}

impl SkinRef {
    /// The pose `p`, each number rounded to the nearest f32.
    pub(crate) fn at(p: &ColliderPose) -> Self {
        SkinRef {
            x: p.centre.as_vec3().to_array(),
            a: p.axis.as_vec3().to_array(),
        }
    }

    /// `|x − x₀|² + h²|a − a₀|²` from this reference to the pose `p`, for
    /// a body of half length `h` (the square-root-free test of
    /// [`NeighbourList`]).
    #[inline(always)]
    pub(crate) fn moved2(&self, p: &ColliderPose, h: f64) -> f64 {
        let x0 = Vec3::from_array(self.x).as_dvec3();
        let a0 = Vec3::from_array(self.a).as_dvec3();
        // (A sphere's `h` is 0 and its axis fixed: its turning moves no
        // point of it, and the term is not worked out.)
        let turn = if h == 0.0 {
            0.0
        } else {
            h * h * p.axis.distance_squared(a0)
        };
        p.centre.distance_squared(x0) + turn
    }

    /// How far this reference may be from the exact pose in the end-point
    /// bound `|Δx| + h|Δa|`: round-to-nearest moves each number by at
    /// most 2⁻²⁴ of it, so `x₀` by `2⁻²⁴|x₀|` and the unit `a₀` by `2⁻²⁴`
    /// (doubled, and rounded up, for the rounding of this sum).
    fn rounding(&self, h: f64) -> f64 {
        let x0 = Vec3::from_array(self.x).as_dvec3();
        2.0 * (x0.length() + h) / (1u64 << 24) as f64
    }
}

/// `(half_skin − largest rounding)² / 2` of the references `built` of
/// bodies of half lengths `h` (see [`NeighbourList::within_skin`]).
pub(crate) fn skin_limit2(half_skin: f64, built: &[SkinRef], h: impl Iterator<Item = f64>) -> f64 {
    let worst = built
        .iter()
        .zip(h)
        .map(|(r, h)| r.rounding(h))
        .fold(0.0, f64::max);
    let room = (half_skin - worst).max(0.0);
    0.5 * room * room
}

/// Buffers of [`grid_pairs`], kept between builds.
#[derive(Debug, Clone, Default)]
pub struct GridScratch {
    keyed: Vec<(u64, u32)>,
    order: Vec<u32>,
}

/// Candidate contacts kept between steps: a neighbour list with a skin (the
/// `neighbor skin` of LAMMPS and LIGGGHTS), rebuilt only when some fibre may
/// have moved far enough to reach a pair or a wall it was not listed with.
///
/// Why it is exact: a flat-ended cylinder lies inside the capsule of its axis
/// segment, and when both segment end points move by at most `d` every point
/// of the capsule moves by at most `d` (the segment moves by interpolation).
/// The list holds every wall whose capsule box, and every pair whose
/// capsules, grown by half the skin each, touched at the last build; while
/// no end point has moved more than half the skin since, every touching pair
/// and wall is in it. The kernels
/// then see the same candidates, in the same order, as a full search would
/// give them (the others have no contact), so forces are bit-identical
/// (`tests/suite/broad_phase.rs`).
///
/// The end points are not formed every step: an end point `x ± h a`
/// (`a` the unit axis) moves by exactly `|Δx ± h Δa| ≤ |Δx| + h |Δa|`,
/// so the test needs only the centre and the axis, both of which the stage
/// keeps anyway (a turn about the axis moves no end point, and the capsule
/// does not see it). With `(a + b)² ≤ 2 (a² + b²)` it needs no square
/// root. The poses of the last build are kept in f32 ([`SkinRef`]), their
/// rounding taken off the half skin.
#[derive(Debug, Clone)]
pub(crate) struct NeighbourList {
    half_skin: f64,
    /// Centre and axis of each body at the last build.
    pub(crate) built: Vec<SkinRef>,
    /// `(half skin − the largest rounding of the poses in built)² / 2`:
    /// the bound of [`SkinRef::moved2`] while the list holds.
    limit2: f64,
    /// `(body, wall)` candidates, body-major, walls in their order.
    pub(crate) walls: Vec<(u32, u32)>,
    /// `(i, j)` candidates, `i < j`, sorted.
    pub(crate) pairs: Vec<(u32, u32)>,
    /// Each pair candidate's memory of its last end-involved scan (the
    /// contact stage's; carried by pair across builds, `memory.rs`).
    pub(crate) memory: Vec<PairMemory>,
    boxes: Vec<(DVec3, DVec3)>,
    order: Vec<u32>,
    grid: GridScratch,
    /// Number of builds so far (diagnostics and tests).
    pub(crate) builds: u64,
}

impl NeighbourList {
    /// A list with skin width `skin` (m).
    pub(crate) fn new(skin: f64) -> Self {
        NeighbourList {
            half_skin: 0.5 * skin,
            built: vec![],
            limit2: 0.0,
            walls: vec![],
            pairs: vec![],
            memory: vec![],
            boxes: vec![],
            order: vec![],
            grid: GridScratch::default(),
            builds: 0,
        }
    }

    /// Whether the list still holds every possible contact of its bodies,
    /// one body at a time (for the pass that updates the bodies' poses):
    /// `None` when the list was built for another number of bodies (`n`),
    /// else the test of body `i` at pose `p`, of half length `h`: still
    /// within the skin of its pose at the build.
    #[inline]
    pub(crate) fn within_skin(
        &self,
        n: usize,
    ) -> Option<impl Fn(usize, &ColliderPose, f64) -> bool + Sync + '_> {
        (self.built.len() == n).then_some(move |i: usize, p: &ColliderPose, h| {
            self.built[i].moved2(p, h) <= self.limit2
        })
    }

    /// The skin width, m.
    #[cfg(feature = "mpi")]
    pub(crate) fn skin(&self) -> f64 {
        2.0 * self.half_skin
    }

    /// Whether one body at pose `p`, of half length `h`, is still within
    /// the skin of its pose `built` at the last build, `limit2` being its
    /// [`skin_limit2`]: the test of [`Self::within_skin`] (an MPI rank
    /// tests the bodies it owns).
    #[cfg(feature = "mpi")]
    #[inline]
    pub(crate) fn body_within_skin(p: &ColliderPose, h: f64, built: &SkinRef, limit2: f64) -> bool {
        built.moved2(p, h) <= limit2
    }

    /// Build the list for the bodies at `poses`, of collider `shapes`.
    /// (Once per ~2000 steps: kept out of the stage's per-step code.)
    #[inline(never)]
    pub(crate) fn build(&mut self, poses: &[ColliderPose], shapes: Shapes, walls: &[Wall]) {
        self.builds += 1;
        self.built.clear();
        self.built.extend(poses.iter().map(SkinRef::at));
        self.limit2 = skin_limit2(
            self.half_skin,
            &self.built,
            (0..poses.len()).map(|i| shapes.get(i).half_length),
        );
        // The boxes live only through the build (memory per fibre).
        let mut boxes = std::mem::take(&mut self.boxes);
        boxes.clear();
        boxes.extend(poses.iter().enumerate().map(|(i, p)| {
            let shape = shapes.get(i);
            let (a, b) = segment_ends(p, shape.half_length);
            let grow = DVec3::splat(shape.radius + self.half_skin);
            (a.min(b) - grow, a.max(b) + grow)
        }));
        self.walls.clear();
        for (i, (lo, hi)) in boxes.iter().enumerate() {
            for (k, w) in walls.iter().enumerate() {
                // Axis-aligned inward normal: the box corner nearest the wall.
                let reach = w.normal.dot(if w.normal.max_element() > 0.0 {
                    *lo
                } else {
                    *hi
                });
                if reach <= w.offset {
                    self.walls.push((i as u32, k as u32));
                }
            }
        }
        let old_pairs = std::mem::take(&mut self.pairs);
        if poses.len() <= BRUTE_FORCE_MAX {
            candidate_pairs_with(&boxes, &mut self.order, &mut self.pairs);
            self.boxes = boxes;
        } else {
            grid_pairs(&boxes, &mut self.grid, &mut self.pairs);
            self.grid = GridScratch::default();
        }
        // Only pairs whose capsules, grown by half the skin each, touch:
        // the boxes of long fibres overlap far more often than the fibres
        // can (a margin covers the rounding of the closest points).
        let half_skin = self.half_skin;
        let fibre = |i: u32| shapes.get(i as usize).fibre(&poses[i as usize]);
        self.pairs.retain(|&(i, j)| {
            let (a, b) = (&fibre(i), &fibre(j));
            let (s, t) = segment_closest_params(a, b);
            let gap = (a.centre + s * a.axis).distance(b.centre + t * b.axis);
            let reach = a.radius + b.radius;
            gap <= reach + 2.0 * half_skin + 1e-6 * reach
        });
        if poses.len() > BRUTE_FORCE_MAX {
            // The box pairs outnumber the kept ones several times over.
            self.pairs.shrink_to_fit();
        }
        // Every pair that can touch is in both lists, with its memory.
        let old_memory = std::mem::take(&mut self.memory);
        let kept = entries(&old_pairs, &old_memory, |m| *m != PairMemory::default());
        self.memory = place(&self.pairs, kept);
    }
}

/// Axis segment end points `c − h a`, `c + h a` of a body at `p` of half
/// length `h`.
#[inline]
fn segment_ends(p: &ColliderPose, h: f64) -> (DVec3, DVec3) {
    let h = h * p.axis;
    (p.centre - h, p.centre + h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Bodies, Body, Shape};
    use crate::contact::shape::shapes;

    /// The skin test is a true bound on the end points' motion: whenever an
    /// end point `c ± h a` (worked out directly) has moved more than half
    /// the skin since the build, the body is refused, whether it moved,
    /// turned or both; and a turn alone about the fixed centre that moves
    /// an end by half the skin and more is refused (the test sees the
    /// turn, not only the centre; a mutant without its turn term fails
    /// here), one that moves it by a third of that is kept.
    #[test]
    fn the_skin_test_bounds_the_end_points() {
        let (d, l) = (0.01, 0.03);
        let body = Body::new(
            Shape::Fibre {
                diameter: d,
                length: l,
            },
            0,
            1100.0,
        );
        let bodies = Bodies::uniform(body, 1);
        let table = shapes(&bodies);
        let shapes = Shapes::new(&table, &bodies);
        let (h, skin) = (0.5 * l, 0.2 * d);
        let start = ColliderPose {
            centre: DVec3::new(0.1, 0.2, 0.3),
            axis: DVec3::new(0.6, 0.0, 0.8),
        };
        let mut list = NeighbourList::new(skin);
        list.build(&[start], shapes, &[]);
        let within = list.within_skin(1).expect("built for one body");
        // A turn about y by θ moves each end by 2h sin(θ/2).
        let turned = |end_shift: f64| {
            let theta = 2.0 * (end_shift / (2.0 * h)).asin();
            let axis = glam::DQuat::from_rotation_y(theta) * start.axis;
            ColliderPose { axis, ..start }
        };
        assert!(
            !within(0, &turned(0.5 * skin), h),
            "an end moved by half the skin"
        );
        assert!(
            !within(0, &turned(2.0 * skin), h),
            "an end moved by the skin"
        );
        assert!(
            within(0, &turned(skin / 6.0), h),
            "an end moved by a sixth of the skin"
        );
        // Random moves and turns about the build pose.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut r = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            2.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        let (mut kept, mut refused) = (0, 0);
        for _ in 0..20_000 {
            let shift = 0.4 * skin * DVec3::new(r(), r(), r());
            let spin = 0.4 * skin / h * DVec3::new(r(), r(), r());
            let p = ColliderPose {
                centre: start.centre + shift,
                axis: glam::DQuat::from_scaled_axis(spin) * start.axis,
            };
            let ends = [1.0, -1.0]
                .map(|s| (p.centre + s * h * p.axis).distance(start.centre + s * h * start.axis));
            let moved = ends[0].max(ends[1]);
            if within(0, &p, h) {
                kept += 1;
                assert!(moved <= 0.5 * skin, "kept with an end moved by {moved} m");
            } else {
                refused += 1;
            }
        }
        assert!(
            kept > 1000 && refused > 1000,
            "{kept} kept, {refused} refused"
        );
    }
}
