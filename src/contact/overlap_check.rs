//! The start-up overlap check of a scene, in O(N): a uniform cell grid over
//! the boxes of the fibres' axis capsules, a capsule test (exact bound: the
//! cylinder lies inside the capsule, and penetration depth only grows with
//! the bodies), and the stage's own kernels for the pairs whose capsules
//! overlap by more than the tolerance.
//!
//! The grid: cell side `h = max(mean box extent, (V / 2N)^{1/3})`, so a box
//! spans a few cells and the grid has at most ~2N cells; boxes are counted
//! into every cell they touch (a counting sort, O(N + cells)), and a pair is
//! tested only in the cell holding the larger of its two lower corners, so
//! once. The answer does not depend on the grid: it is the first overlap in
//! the order of the O(N²) check it replaces (walls first by body, then pairs
//! `(i, j)` lexicographically), so messages name the same bodies.

use super::stage::geom;
use super::{box_walls, contacts, Collider, FibreGeom, KernelCounters, Walls};
use crate::body::{Body, BodyState};
use glam::DVec3;
use rayon::prelude::*;

/// An overlap found at the start: `(body, other body or None for a wall,
/// overlap in m)`.
pub(crate) type Overlap = (usize, Option<usize>, f64);

/// The first overlap deeper than `tolerance` × the thinner diameter (any
/// overlap when `tolerance` is 0) among `bodies` at `states` and the box
/// `walls`, in the order described in the module docs.
pub(crate) fn first_overlap(
    bodies: &[Body],
    states: &[BodyState],
    walls: Option<&Walls>,
    tolerance: f64,
) -> Option<Overlap> {
    let geoms: Vec<FibreGeom> = bodies
        .par_iter()
        .zip(states)
        .map(|(b, s)| geom(b, s))
        .collect();
    let too_deep = |overlap: f64, d: f64| tolerance == 0.0 || overlap > tolerance * d;
    let walls = walls.map(box_walls).unwrap_or_default();
    // Walls: by body, in body order (cheap analytic kernel).
    let wall_hit = geoms.par_iter().enumerate().find_map_first(|(i, g)| {
        let mut pts = vec![];
        let mut k = KernelCounters::default();
        walls
            .iter()
            .find_map(|w| {
                pts.clear();
                contacts(Collider::Fibre(g), Collider::Wall(w), &mut pts, &mut k);
                deepest(&pts).filter(|&o| too_deep(o, 2.0 * g.radius))
            })
            .map(|o| (i, None, o))
    });
    if wall_hit.is_some() {
        return wall_hit;
    }
    let grid = Grid::new(&geoms);
    // Every pair whose capsules overlap by more than the tolerance goes to
    // the kernels; the first in (i, j) order wins.
    let found = (0..grid.cells())
        .into_par_iter()
        .filter_map(|c| {
            let mut pts = vec![];
            let mut k = KernelCounters::default();
            let mut best: Option<Overlap> = None;
            let members = grid.members(c);
            for (x, &i) in members.iter().enumerate() {
                for &j in &members[x + 1..] {
                    let (i, j) = (i.min(j) as usize, i.max(j) as usize);
                    if best.is_some_and(|(bi, bj, _)| (bi, bj) < (i, Some(j))) {
                        continue;
                    }
                    if !grid.owns(c, i, j) {
                        continue;
                    }
                    let (a, b) = (&geoms[i], &geoms[j]);
                    let d = 2.0 * a.radius.min(b.radius);
                    let capsule = a.radius + b.radius - segment_distance(a, b);
                    if capsule <= 0.0 || (tolerance > 0.0 && capsule <= tolerance * d) {
                        continue;
                    }
                    pts.clear();
                    contacts(Collider::Fibre(a), Collider::Fibre(b), &mut pts, &mut k);
                    if let Some(o) = deepest(&pts).filter(|&o| too_deep(o, d)) {
                        best = Some((i, Some(j), o));
                    }
                }
            }
            best
        })
        .min_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)));
    found
}

/// The deepest overlap of a pair's contact points.
fn deepest(pts: &[super::ContactPoint]) -> Option<f64> {
    pts.iter().map(|c| c.overlap).reduce(f64::max)
}

/// Distance between the axis segments of two fibres.
fn segment_distance(a: &FibreGeom, b: &FibreGeom) -> f64 {
    let (s, t) = super::fibre_fibre::segment_closest_params(a, b);
    (a.centre + s * a.axis).distance(b.centre + t * b.axis)
}

/// A uniform grid of cells over the capsule boxes, each cell listing the
/// boxes that touch it (compressed rows: `start[c]..start[c + 1]`).
struct Grid {
    lo: DVec3,
    h: f64,
    dims: [usize; 3],
    boxes: Vec<(DVec3, DVec3)>,
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    fn new(geoms: &[FibreGeom]) -> Self {
        let boxes: Vec<(DVec3, DVec3)> = geoms
            .iter()
            .map(|g| {
                let half = g.half_length * g.axis;
                let (a, b) = (g.centre - half, g.centre + half);
                let r = DVec3::splat(g.radius);
                (a.min(b) - r, a.max(b) + r)
            })
            .collect();
        let n = boxes.len().max(1);
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let mut extent = 0.0;
        for (a, b) in &boxes {
            lo = lo.min(*a);
            hi = hi.max(*b);
            extent += (*b - *a).max_element();
        }
        if boxes.is_empty() {
            lo = DVec3::ZERO;
            hi = DVec3::ONE;
        }
        let span = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        let volume = span.x * span.y * span.z;
        let h = (extent / n as f64)
            .max((volume / (2.0 * n as f64)).cbrt())
            .max(span.max_element() * 1e-6);
        let dims = [0, 1, 2].map(|k| ((span[k] / h).floor() as usize + 1).max(1));
        let cells = dims[0] * dims[1] * dims[2];
        let mut g = Grid {
            lo,
            h,
            dims,
            boxes,
            start: vec![0; cells + 1],
            items: vec![],
        };
        // Counting sort of (cell, box) entries.
        for b in &g.boxes {
            let start = &mut g.start;
            Self::cells_of(b, g.lo, g.h, g.dims, |c| start[c + 1] += 1);
        }
        for c in 0..cells {
            g.start[c + 1] += g.start[c];
        }
        let mut fill = g.start.clone();
        g.items = vec![0; g.start[cells] as usize];
        for b in 0..g.boxes.len() {
            let (items, fill) = (&mut g.items, &mut fill);
            Self::cells_of(&g.boxes[b], g.lo, g.h, g.dims, |c| {
                items[fill[c] as usize] = b as u32;
                fill[c] += 1;
            });
        }
        g
    }

    fn cells(&self) -> usize {
        self.start.len() - 1
    }

    fn members(&self, c: usize) -> &[u32] {
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    fn cell_of(p: DVec3, lo: DVec3, h: f64, dims: [usize; 3]) -> [usize; 3] {
        [0, 1, 2].map(|k| (((p[k] - lo[k]) / h).floor().max(0.0) as usize).min(dims[k] - 1))
    }

    fn index(c: [usize; 3], dims: [usize; 3]) -> usize {
        (c[2] * dims[1] + c[1]) * dims[0] + c[0]
    }

    fn cells_of(b: &(DVec3, DVec3), lo: DVec3, h: f64, dims: [usize; 3], mut f: impl FnMut(usize)) {
        let (a, z) = (
            Self::cell_of(b.0, lo, h, dims),
            Self::cell_of(b.1, lo, h, dims),
        );
        for k in a[2]..=z[2] {
            for j in a[1]..=z[1] {
                for i in a[0]..=z[0] {
                    f(Self::index([i, j, k], dims));
                }
            }
        }
    }

    /// Whether the boxes of `i` and `j` touch, and cell `c` holds the larger
    /// of their lower corners (so each pair is tested in one cell only).
    fn owns(&self, c: usize, i: usize, j: usize) -> bool {
        let (a, b) = (&self.boxes[i], &self.boxes[j]);
        if !(a.0.cmple(b.1).all() && b.0.cmple(a.1).all()) {
            return false;
        }
        Self::index(
            Self::cell_of(a.0.max(b.0), self.lo, self.h, self.dims),
            self.dims,
        ) == c
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{RotState, Shape};
    use glam::DQuat;

    /// The O(N²) check this replaces: every wall, then every pair in order.
    fn brute_force(
        bodies: &[Body],
        states: &[BodyState],
        walls: Option<&Walls>,
        tol: f64,
    ) -> Option<Overlap> {
        let geoms: Vec<FibreGeom> = bodies.iter().zip(states).map(|(b, s)| geom(b, s)).collect();
        let walls = walls.map(box_walls).unwrap_or_default();
        let mut pts = vec![];
        let mut k = KernelCounters::default();
        let deep = |o: f64, d: f64| tol == 0.0 || o > tol * d;
        for (i, g) in geoms.iter().enumerate() {
            for w in &walls {
                pts.clear();
                contacts(Collider::Fibre(g), Collider::Wall(w), &mut pts, &mut k);
                if let Some(o) = deepest(&pts).filter(|&o| deep(o, 2.0 * g.radius)) {
                    return Some((i, None, o));
                }
            }
        }
        for i in 0..geoms.len() {
            for j in i + 1..geoms.len() {
                pts.clear();
                let (a, b) = (&geoms[i], &geoms[j]);
                contacts(Collider::Fibre(a), Collider::Fibre(b), &mut pts, &mut k);
                if let Some(o) = deepest(&pts).filter(|&o| deep(o, 2.0 * a.radius.min(b.radius))) {
                    return Some((i, Some(j), o));
                }
            }
        }
        None
    }

    /// xorshift64*: reproducible random scenes without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn scene(n: usize, side: f64, seed: u64) -> (Vec<Body>, Vec<BodyState>) {
        let mut r = Rng(seed);
        let mut bodies = vec![];
        let mut states = vec![];
        for _ in 0..n {
            let d = 0.005 + 0.01 * r.next();
            let l = 0.01 + 0.05 * r.next();
            bodies.push(Body::new(
                Shape::Fibre {
                    diameter: d,
                    length: l,
                },
                0,
                1000.0,
            ));
            let axis = DVec3::new(r.next() - 0.5, r.next() - 0.5, r.next() - 0.5).normalize();
            states.push(BodyState {
                x: DVec3::new(r.next(), r.next(), r.next()) * side,
                v: DVec3::ZERO,
                rot: RotState {
                    q: DQuat::from_rotation_arc(DVec3::X, axis),
                    omega_b: DVec3::ZERO,
                },
            });
        }
        (bodies, states)
    }

    /// Reference: the O(N²) check on random polydisperse scenes, dilute to
    /// dense, with and without walls and tolerance.
    #[test]
    fn the_grid_finds_what_the_full_search_finds() {
        let walls = Walls {
            min: DVec3::splat(0.02),
            max: DVec3::splat(0.5),
            young: 1e9,
            poisson: 0.3,
        };
        let mut hits = 0;
        for seed in 1..60u64 {
            let side = [0.2, 0.5, 1.0, 3.0][seed as usize % 4];
            let (b, s) = scene(40 + seed as usize, side, seed);
            for w in [None, Some(&walls)] {
                for tol in [0.0, 0.05, 0.3] {
                    let want = brute_force(&b, &s, w, tol);
                    hits += want.is_some() as usize;
                    assert_eq!(
                        first_overlap(&b, &s, w, tol),
                        want,
                        "seed {seed} side {side} tol {tol}"
                    );
                }
            }
        }
        assert!(hits > 50, "the scenes must have overlaps to find ({hits})");
    }
}
