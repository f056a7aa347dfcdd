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
use glam::{DQuat, DVec3};

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

/// A fibre's pose at a list build, in f32 (28 bytes instead of 56): the
/// reference of the skin test.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SkinRef {
    x: [f32; 3],
    q: [f32; 4],
}

impl SkinRef {
    /// The pose `(x, q)`, each number rounded to the nearest f32.
    pub(crate) fn at(x: DVec3, q: DQuat) -> Self {
        SkinRef {
            x: x.as_vec3().to_array(),
            q: [q.x as f32, q.y as f32, q.z as f32, q.w as f32],
        }
    }

    /// `|x − x₀|² + 4h²‖q − q₀‖²` from this reference, for a fibre of half
    /// length `h` (the square-root-free test above).
    #[inline(always)]
    pub(crate) fn moved2(&self, x: DVec3, q: DQuat, h: f64) -> f64 {
        let x0 = DVec3::new(self.x[0].into(), self.x[1].into(), self.x[2].into());
        let q0 = DQuat::from_xyzw(
            self.q[0].into(),
            self.q[1].into(),
            self.q[2].into(),
            self.q[3].into(),
        );
        // (A sphere's `h` is 0: its turning moves no point of it, and the
        // term, 0 for any finite `q`, is not worked out.)
        let turn = if h == 0.0 {
            0.0
        } else {
            4.0 * h * h * (q - q0).length_squared()
        };
        x.distance_squared(x0) + turn
    }

    /// How far this reference may be from the exact pose in the end-point
    /// bound `|Δx| + 2h‖Δq‖`: round-to-nearest moves each number by at
    /// most 2⁻²⁴ of it, so `x₀` by `2⁻²⁴|x₀|` and the unit `q₀` by `2⁻²⁴`
    /// (doubled, and rounded up, for the rounding of this sum).
    fn rounding(&self, h: f64) -> f64 {
        let x0 = DVec3::new(self.x[0].into(), self.x[1].into(), self.x[2].into());
        2.0 * (x0.length() + 2.0 * h) / (1u64 << 24) as f64
    }
}

/// `(half_skin − largest rounding)² / 2` of the references `built` of
/// fibres of half lengths `h` (see [`NeighbourList::still_valid`]).
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
/// The end points are not formed every step: an end point `x ± h R(q) eₓ`
/// moves by at most `|Δx| + 2h ‖Δq‖`, since `‖R(q) − R(p)‖ = 2 sin(θ/2) ≤
/// 4 sin(θ/4) = 2 ‖q − p‖` for unit quaternions (θ the angle between them;
/// for the other sign of `p` the bound only grows). With
/// `(a + b)² ≤ 2 (a² + b²)` the test needs no square root. The poses of
/// the last build are kept in f32 ([`SkinRef`]), their rounding taken off
/// the half skin. Between builds only the fibres in a candidate
/// ([`Self::active`]) need their geometry.
#[derive(Debug, Clone)]
pub(crate) struct NeighbourList {
    half_skin: f64,
    /// Centre and orientation of each fibre at the last build.
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
    /// Bodies in any candidate, ascending.
    pub(crate) active: Vec<u32>,
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
            active: vec![],
            boxes: vec![],
            order: vec![],
            grid: GridScratch::default(),
            builds: 0,
        }
    }

    /// Whether the list still holds every possible contact of the bodies at
    /// these poses (centre, orientation, half length).
    #[inline]
    pub(crate) fn still_valid(
        &self,
        poses: impl ExactSizeIterator<Item = (DVec3, DQuat, f64)>,
    ) -> bool {
        // `q − q0` only: a sign flip of q (no rotator makes one) just costs
        // a rebuild.
        self.built.len() == poses.len()
            && poses
                .zip(&self.built)
                .all(|((x, q, h), r)| self.kept(r, x, q, h))
    }

    /// The test of one body of [`Self::still_valid`]: at `(x, q)`, of half
    /// length `h`, still within the skin of its pose `r` at the build.
    #[inline(always)]
    fn kept(&self, r: &SkinRef, x: DVec3, q: DQuat, h: f64) -> bool {
        r.moved2(x, q, h) <= self.limit2
    }

    /// [`Self::still_valid`] one body at a time, for a pass that also does
    /// other per-body work (the pool's geometry update): `None` when the
    /// list was built for another number of bodies (`n`), else the test of
    /// body `i` at `(x, q)`, of half length `h`.
    #[inline]
    pub(crate) fn within_skin(
        &self,
        n: usize,
    ) -> Option<impl Fn(usize, DVec3, DQuat, f64) -> bool + Sync + '_> {
        (self.built.len() == n)
            .then_some(move |i: usize, x, q, h| self.kept(&self.built[i], x, q, h))
    }

    /// The skin width, m.
    #[cfg(feature = "mpi")]
    pub(crate) fn skin(&self) -> f64 {
        2.0 * self.half_skin
    }

    /// Whether one fibre at `(x, q)`, of half length `h`, is still within
    /// the skin of its pose `built` at the last build, `limit2` being its
    /// [`skin_limit2`]: the test of [`Self::still_valid`] for one body (an
    /// MPI rank tests the bodies it owns).
    #[cfg(feature = "mpi")]
    #[inline]
    pub(crate) fn body_within_skin(
        x: DVec3,
        q: DQuat,
        h: f64,
        built: &SkinRef,
        limit2: f64,
    ) -> bool {
        built.moved2(x, q, h) <= limit2
    }

    /// Build the list for the bodies at `poses`, of collider `shapes`,
    /// at orientations `rotations`. (Once per ~2000 steps: kept out of the
    /// stage's per-step code.)
    #[inline(never)]
    pub(crate) fn build(
        &mut self,
        poses: &[ColliderPose],
        shapes: Shapes,
        rotations: impl Iterator<Item = DQuat>,
        walls: &[Wall],
    ) {
        self.builds += 1;
        self.built.clear();
        self.built.extend(
            poses
                .iter()
                .zip(rotations)
                .map(|(p, q)| SkinRef::at(p.centre, q)),
        );
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
        // The bodies in a candidate, in order, in a vector of their exact
        // count (a body a bed holds for the whole run: no spare capacity).
        let mut marked = vec![false; poses.len()];
        for i in
            (self.walls.iter().map(|&(i, _)| i)).chain(self.pairs.iter().flat_map(|&(i, j)| [i, j]))
        {
            marked[i as usize] = true;
        }
        let count = marked.iter().filter(|&&m| m).count();
        self.active = Vec::with_capacity(count);
        self.active
            .extend((0..poses.len() as u32).filter(|&i| marked[i as usize]));
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

    /// The skin test's turn term is a true bound: a fibre turned about its
    /// centre (no shift) moves its ends by `h |R(q) eₓ − R(q₀) eₓ|` (the
    /// closed form of a rigid turn), and `√moved2` is at least that, for
    /// turns about every kind of axis (across the fibre, along it, oblique)
    /// from 10⁻³ rad to π/2. Without the turn term, or with `h²‖Δq‖²` in
    /// place of `4h²‖Δq‖²`, a turn across the fibre escapes it.
    #[test]
    fn the_skin_test_bounds_a_turn_of_the_end_points() {
        let (x, h) = (DVec3::new(0.1, -0.2, 0.3), 0.015);
        let q0 = DQuat::from_euler(glam::EulerRot::ZYX, 0.3, -0.7, 1.1);
        let reference = SkinRef::at(x, q0);
        let mut turned_across = 0;
        for k in 0..200 {
            let angle = 1e-3 * (1.5708e3f64).powf(k as f64 / 199.0);
            let phi = 0.61 * k as f64;
            let n = DVec3::new(phi.cos(), phi.sin(), ((k % 7) as f64 - 3.0) / 3.0).normalize();
            let q = DQuat::from_axis_angle(n, angle) * q0;
            let a0 = crate::math::body_x_axis(q0);
            let moved = h * (crate::math::body_x_axis(q) - a0).length();
            let bound = reference.moved2(x, q, h).sqrt();
            // The reference's f32 rounding: ~2⁻²⁴ of |x| and of h.
            assert!(
                bound >= moved - 1e-7,
                "turn {angle} rad about {n}: bound {bound} m, end moved {moved} m"
            );
            if n.dot(q0 * DVec3::X).abs() < 0.5 && moved > 1e-5 {
                turned_across += 1;
            }
        }
        assert!(turned_across > 50, "{turned_across} turns across the fibre");
    }
}
