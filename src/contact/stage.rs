//! The force stage of a contact scene (Yade's chain: geometry → physical
//! parameters → force law). Built only when the scene can have contacts.
//!
//! Per step: fibre poses → broad phase (a neighbour list, rebuilt when bodies
//! have moved) → kernels → Hertz force per contact point → force `w F(δ) n` at
//! `p` and torque `(p − x) × F` on each body (the opposite on body B).
//! Deterministic: fixed loop order, sorted pairs.

use super::broad::NeighbourList;
use super::{contact_fibre_fibre, contact_fibre_wall, ContactPoint, FibreGeom, HertzLaw, Wall};
use crate::body::{Body, BodyState, Material, Shape};
use crate::scenario::Walls;
use glam::DVec3;

/// What the last force computation saw.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStats {
    /// Touching pairs (body–body or body–wall).
    pub touching: usize,
    /// Largest overlap over the fibre diameter, δ/D, and the body it is on.
    pub max_overlap_ratio: f64,
    pub max_overlap_body: usize,
    /// Elastic energy of the live contacts, J.
    pub elastic: f64,
}

#[derive(Debug, Clone)]
pub struct ContactStage {
    /// The six walls, with each body's Hertz law against them.
    walls: Vec<Wall>,
    wall_law: Vec<HertzLaw>,
    geoms: Vec<FibreGeom>,
    neighbours: NeighbourList,
    points: Vec<ContactPoint>,
    pub stats: ContactStats,
}

/// Neighbour-list skin as a fraction of the thinnest fibre's diameter. Wider
/// means fewer rebuilds and more candidates to reject; at 0.2 D test case 2
/// (fibres at ≤ 5 m/s, δt = 1e-7 s) rebuilds once per ~1500 steps.
pub const SKIN_PER_DIAMETER: f64 = 0.2;

/// The six inward-facing half-spaces of an axis-aligned box.
pub fn box_walls(w: &Walls) -> Vec<Wall> {
    let mut v = Vec::with_capacity(6);
    for k in 0..3 {
        let e = DVec3::AXES[k];
        v.push(Wall {
            normal: e,
            offset: w.min[k],
        });
        v.push(Wall {
            normal: -e,
            offset: -w.max[k],
        });
    }
    v
}

fn geom(body: &Body, s: &BodyState) -> FibreGeom {
    let Shape::Fibre { diameter, length } = body.shape else {
        unreachable!("scene validation admits only fibres in contact scenes")
    };
    FibreGeom {
        centre: s.x,
        axis: crate::math::body_x_axis(s.rot.q),
        radius: 0.5 * diameter,
        half_length: 0.5 * length,
    }
}

impl ContactStage {
    pub fn new(bodies: &[Body], materials: &[Material], walls: Option<&Walls>) -> Self {
        let (walls, wall_law) = match walls {
            Some(w) => (
                box_walls(w),
                bodies
                    .iter()
                    .map(|b| {
                        let m = &materials[b.material as usize];
                        HertzLaw::fibre_wall(
                            b.shape.diameter(),
                            m.young,
                            m.poisson,
                            w.young,
                            w.poisson,
                        )
                    })
                    .collect(),
            ),
            None => (vec![], vec![]),
        };
        let thinnest = bodies
            .iter()
            .map(|b| b.shape.diameter())
            .fold(f64::INFINITY, f64::min);
        ContactStage {
            walls,
            wall_law,
            geoms: Vec::with_capacity(bodies.len()),
            neighbours: NeighbourList::new(SKIN_PER_DIAMETER * thinnest),
            points: vec![],
            stats: ContactStats::default(),
        }
    }

    /// Neighbour-list builds so far.
    pub fn neighbour_builds(&self) -> u64 {
        self.neighbours.builds
    }

    /// Contact forces and torques (world) at `states`, written into `force` and
    /// `torque` (overwritten).
    pub fn compute(
        &mut self,
        bodies: &[Body],
        materials: &[Material],
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
    ) {
        force.fill(DVec3::ZERO);
        torque.fill(DVec3::ZERO);
        let mut stats = ContactStats::default();
        // Geometry in place (the poses change every step, the count never
        // does): of every fibre when the list is rebuilt, else only of those
        // in a candidate.
        self.geoms.resize(bodies.len(), FibreGeom::default());
        if self
            .neighbours
            .still_valid(states.iter().map(|s| (s.x, s.rot.q)))
        {
            for &i in &self.neighbours.active {
                let i = i as usize;
                self.geoms[i] = geom(&bodies[i], &states[i]);
            }
        } else {
            for ((g, b), s) in self.geoms.iter_mut().zip(bodies).zip(states) {
                *g = geom(b, s);
            }
            let rotations = states.iter().map(|s| s.rot.q);
            self.neighbours.build(&self.geoms, rotations, &self.walls);
        }

        for &(i, k) in &self.neighbours.walls {
            let i = i as usize;
            let g = &self.geoms[i];
            self.points.clear();
            contact_fibre_wall(g, &self.walls[k as usize], &mut self.points);
            apply(
                &self.points,
                &self.wall_law[i],
                (g, i),
                None,
                force,
                torque,
                &mut stats,
            );
        }

        for &(a, b) in &self.neighbours.pairs {
            let (a, b) = (a as usize, b as usize);
            let (ga, gb) = (&self.geoms[a], &self.geoms[b]);
            self.points.clear();
            contact_fibre_fibre(ga, gb, &mut self.points);
            if self.points.is_empty() {
                continue;
            }
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let (ma, mb) = (
                &materials[ba.material as usize],
                &materials[bb.material as usize],
            );
            let law = HertzLaw::fibre_fibre(
                ba.shape.diameter(),
                ma.young,
                ma.poisson,
                bb.shape.diameter(),
                mb.young,
                mb.poisson,
            );
            apply(
                &self.points,
                &law,
                (ga, a),
                Some((gb, b)),
                force,
                torque,
                &mut stats,
            );
        }
        self.stats = stats;
    }
}

/// Hertz force of each point on body A (and the reaction on B, if a body).
#[inline]
fn apply(
    points: &[ContactPoint],
    law: &HertzLaw,
    (ga, a): (&FibreGeom, usize),
    b: Option<(&FibreGeom, usize)>,
    force: &mut [DVec3],
    torque: &mut [DVec3],
    stats: &mut ContactStats,
) {
    if points.is_empty() {
        return;
    }
    stats.touching += 1;
    for c in points {
        let f = (c.weight * law.force(c.overlap)) * c.normal;
        let u = law.energy(c.overlap);
        stats.elastic += c.weight * u;
        // δ/D on each body (they may differ in diameter).
        stats.note_overlap(c.overlap / (2.0 * ga.radius), a);
        // Couple of an orientation-dependent weight (zero for walls).
        let couple = -u * c.weight_grad;
        force[a] += f;
        torque[a] += (c.point - ga.centre).cross(f) + couple;
        if let Some((gb, b)) = b {
            stats.note_overlap(c.overlap / (2.0 * gb.radius), b);
            force[b] -= f;
            torque[b] -= (c.point - gb.centre).cross(f) + couple;
        }
    }
}

impl ContactStats {
    #[inline]
    fn note_overlap(&mut self, ratio: f64, body: usize) {
        if ratio > self.max_overlap_ratio {
            self.max_overlap_ratio = ratio;
            self.max_overlap_body = body;
        }
    }
}

/// The first overlap found in a configuration: `(body, other body or None for a
/// wall, overlap)`. Used to reject scenes whose bodies overlap at the start.
pub fn first_overlap(
    bodies: &[Body],
    states: &[BodyState],
    _materials: &[Material],
    walls: Option<&Walls>,
) -> Option<(usize, Option<usize>, f64)> {
    let geoms: Vec<FibreGeom> = bodies.iter().zip(states).map(|(b, s)| geom(b, s)).collect();
    let mut pts = vec![];
    if let Some(w) = walls {
        for (i, g) in geoms.iter().enumerate() {
            for wall in box_walls(w) {
                pts.clear();
                contact_fibre_wall(g, &wall, &mut pts);
                if let Some(c) = pts.first() {
                    return Some((i, None, c.overlap));
                }
            }
        }
    }
    for i in 0..geoms.len() {
        for j in i + 1..geoms.len() {
            pts.clear();
            contact_fibre_fibre(&geoms[i], &geoms[j], &mut pts);
            if let Some(c) = pts.first() {
                return Some((i, Some(j), c.overlap));
            }
        }
    }
    None
}
