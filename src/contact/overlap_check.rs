//! The start-up overlap check of a scene, in O(N): a uniform cell grid over
//! the boxes of the bodies' axis capsules (a sphere's: zero length), a capsule test (exact bound: the
//! cylinder lies inside the capsule, and penetration depth only grows with
//! the bodies), and the stage's own kernels for the pairs whose capsules
//! overlap by more than the tolerance.
//!
//! The grid: cell side `h = max(widest box, (V / 2N)^{1/3})`, so the grid
//! has at most ~2N cells and two touching boxes have their lower corners in
//! neighbouring cells; each box is filed once under its lower corner's cell
//! (a counting sort, O(N + cells)) and meets the boxes of the 27 cells
//! around, each pair from its lower body only. O(N) for beds of bounded
//! density and aspect ratio (one very long fibre widens every cell). The answer does not depend on the grid: it is the first overlap in
//! the order of the O(N²) check it replaces (walls first by body, then pairs
//! `(i, j)` lexicographically), so messages name the same bodies.

use super::shape::{shapes, ColliderPose, Shapes};
use super::{box_walls, contacts, Collider, FibreGeom, KernelCounters, Walls};
use crate::body::{Bodies, BodyState};
use glam::DVec3;
use rayon::prelude::*;

/// An overlap found at the start: `(body, other body or None for a wall,
/// overlap in m)`.
pub(crate) type Overlap = (usize, Option<usize>, f64);

/// The first overlap deeper than `tolerance` × the thinner diameter (any
/// overlap when `tolerance` is 0) among `bodies` at `states` and the box
/// `walls`, in the order described in the module docs.
pub(crate) fn first_overlap(
    bodies: &Bodies,
    states: &[BodyState],
    walls: Option<&Walls>,
    tolerance: f64,
) -> Option<Overlap> {
    let table = shapes(bodies);
    let shapes = Shapes::new(&table, bodies);
    let geoms: Vec<FibreGeom> = (states.par_iter().enumerate())
        .map(|(i, s)| {
            let shape = shapes.get(i);
            shape.fibre(&ColliderPose::of(shape.kind, s))
        })
        .collect();
    let body = |i: usize| shapes.get(i).collider(&pose(&geoms[i]));
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
                contacts(body(i), Collider::Wall(w), &mut pts, &mut k);
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
    (0..grid.start.len() - 1)
        .into_par_iter()
        .filter_map(|c| {
            let mut pts = vec![];
            let mut k = KernelCounters::default();
            let mut best: Option<Overlap> = None;
            grid.pairs_from(c, |i, j| {
                if best.is_some_and(|(bi, bj, _)| (bi, bj) < (i, Some(j))) {
                    return;
                }
                let (a, b) = (&geoms[i], &geoms[j]);
                let d = 2.0 * a.radius.min(b.radius);
                let capsule = a.radius + b.radius - segment_distance(a, b);
                if capsule <= 0.0 || (tolerance > 0.0 && capsule <= tolerance * d) {
                    return;
                }
                pts.clear();
                contacts(body(i), body(j), &mut pts, &mut k);
                if let Some(o) = deepest(&pts).filter(|&o| too_deep(o, d)) {
                    best = Some((i, Some(j), o));
                }
            });
            best
        })
        .min_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)))
}

/// The pose of the body of kernel record `g`.
fn pose(g: &FibreGeom) -> ColliderPose {
    ColliderPose {
        centre: g.centre,
        axis: g.axis,
    }
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

/// A uniform grid of cells at least as wide as the widest capsule box,
/// each box filed once, under the cell of its lower corner (compressed
/// rows: `start[c]..start[c + 1]`). Two boxes that touch then have lower
/// corners at most one cell apart on every axis.
struct Grid {
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
        let mut widest: f64 = 0.0;
        for (a, b) in &boxes {
            lo = lo.min(*a);
            hi = hi.max(*b);
            widest = widest.max((*b - *a).max_element());
        }
        if boxes.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ONE);
        }
        let span = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
        // At most ~2N cells, and never narrower than the widest box.
        let h = widest
            .max((span.x * span.y * span.z / (2.0 * n as f64)).cbrt())
            .max(span.max_element() * 1e-6);
        let dims = [span.x, span.y, span.z].map(|s| ((s / h) as usize + 1).max(1));
        let cells = dims[0] * dims[1] * dims[2];
        let inv_h = 1.0 / h;
        let cell_of = |p: DVec3| {
            let c = ((p - lo) * inv_h).to_array();
            let k = |x: f64, d: usize| (x.max(0.0) as usize).min(d - 1);
            ((k(c[2], dims[2]) * dims[1] + k(c[1], dims[1])) * dims[0] + k(c[0], dims[0])) as u32
        };
        let cell: Vec<u32> = boxes.iter().map(|b| cell_of(b.0)).collect();
        // Counting sort of the bodies by cell (ascending body order within).
        let mut start = vec![0u32; cells + 1];
        for &c in &cell {
            start[c as usize + 1] += 1;
        }
        for c in 0..cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; boxes.len()];
        for (b, &c) in cell.iter().enumerate() {
            items[fill[c as usize] as usize] = b as u32;
            fill[c as usize] += 1;
        }
        Grid {
            dims,
            boxes,
            start,
            items,
        }
    }

    fn members(&self, c: usize) -> &[u32] {
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// Every pair `(i, j)`, `i < j`, whose boxes touch, with `i` filed in
    /// cell `c`: each touching pair is seen once, from its lower body.
    fn pairs_from(&self, c: usize, mut f: impl FnMut(usize, usize)) {
        let [nx, ny, nz] = self.dims;
        let (cx, cy, cz) = (c % nx, (c / nx) % ny, c / (nx * ny));
        let members = self.members(c);
        if members.is_empty() {
            return;
        }
        for z in cz.saturating_sub(1)..=(cz + 1).min(nz - 1) {
            for y in cy.saturating_sub(1)..=(cy + 1).min(ny - 1) {
                for x in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                    let other = self.members((z * ny + y) * nx + x);
                    for &i in members {
                        let a = &self.boxes[i as usize];
                        for &j in other {
                            if j <= i {
                                continue;
                            }
                            let b = &self.boxes[j as usize];
                            if a.0.cmple(b.1).all() && b.0.cmple(a.1).all() {
                                f(i as usize, j as usize);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::{Body, RotState, Shape};
    use glam::DQuat;

    /// The O(N²) check this replaces: every wall, then every pair in order.
    fn brute_force(
        bodies: &Bodies,
        states: &[BodyState],
        walls: Option<&Walls>,
        tol: f64,
    ) -> Option<Overlap> {
        let geoms: Vec<FibreGeom> = bodies
            .iter()
            .zip(states)
            .map(|(b, s)| crate::contact::shape::geom(b, s))
            .collect();
        let table = shapes(bodies);
        let shapes = Shapes::new(&table, bodies);
        let body = |i: usize| shapes.get(i).collider(&pose(&geoms[i]));
        let walls = walls.map(box_walls).unwrap_or_default();
        let mut pts = vec![];
        let mut k = KernelCounters::default();
        let deep = |o: f64, d: f64| tol == 0.0 || o > tol * d;
        for (i, g) in geoms.iter().enumerate() {
            for w in &walls {
                pts.clear();
                contacts(body(i), Collider::Wall(w), &mut pts, &mut k);
                if let Some(o) = deepest(&pts).filter(|&o| deep(o, 2.0 * g.radius)) {
                    return Some((i, None, o));
                }
            }
        }
        for i in 0..geoms.len() {
            for j in i + 1..geoms.len() {
                pts.clear();
                let (a, b) = (&geoms[i], &geoms[j]);
                contacts(body(i), body(j), &mut pts, &mut k);
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

    fn scene(n: usize, side: f64, seed: u64) -> (Bodies, Vec<BodyState>) {
        let mut r = Rng(seed);
        let mut bodies = Bodies::new();
        let mut states = vec![];
        for k in 0..n {
            let d = 0.005 + 0.01 * r.next();
            let l = 0.01 + 0.05 * r.next();
            // Every third body a sphere (of up to 2 cm): fibre–fibre,
            // sphere–fibre, sphere–sphere and both wall kinds.
            let shape = match k % 3 {
                2 => Shape::Sphere { diameter: 2.0 * d },
                _ => Shape::Fibre {
                    diameter: d,
                    length: l,
                },
            };
            bodies.push(Body::new(shape, 0, 1000.0));
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

    /// Reference: the O(N²) check on random polydisperse scenes of fibres
    /// and spheres, dilute to dense, with and without walls and tolerance.
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
