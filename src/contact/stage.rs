//! The force stage of a contact scene (Yade's chain: geometry → physical
//! parameters → force law). Built only when the scene can have contacts.
//!
//! Per step: fibre poses → broad phase → kernels → Hertz force per contact point
//! → force `w F(δ) n` at `p` and torque `(p − x) × F` on each body (the opposite
//! on body B). Deterministic: fixed loop order, sorted pairs.

use super::{
    candidate_pairs_with, contact_fibre_fibre, contact_fibre_wall, fibre_aabb, ContactPoint,
    FibreGeom, HertzLaw, Wall,
};
use crate::body::{Body, BodyState, Shape};
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
    aabbs: Vec<(DVec3, DVec3)>,
    pairs: Vec<(u32, u32)>,
    /// Scratch for the sort-and-sweep broad phase (no per-step allocation).
    sweep_order: Vec<u32>,
    points: Vec<ContactPoint>,
    pub stats: ContactStats,
}

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
        axis: s.rot.q * DVec3::X,
        radius: 0.5 * diameter,
        half_length: 0.5 * length,
    }
}

impl ContactStage {
    pub fn new(bodies: &[Body], walls: Option<&Walls>) -> Self {
        let (walls, wall_law) = match walls {
            Some(w) => (
                box_walls(w),
                bodies
                    .iter()
                    .map(|b| {
                        HertzLaw::fibre_wall(diameter(b), b.young, b.poisson, w.young, w.poisson)
                    })
                    .collect(),
            ),
            None => (vec![], vec![]),
        };
        ContactStage {
            walls,
            wall_law,
            geoms: Vec::with_capacity(bodies.len()),
            aabbs: Vec::with_capacity(bodies.len()),
            pairs: vec![],
            sweep_order: vec![],
            points: vec![],
            stats: ContactStats::default(),
        }
    }

    /// Contact forces and torques (world) at `states`, written into `force` and
    /// `torque` (overwritten).
    pub fn compute(
        &mut self,
        bodies: &[Body],
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
    ) {
        force.fill(DVec3::ZERO);
        torque.fill(DVec3::ZERO);
        let mut stats = ContactStats::default();
        self.geoms.clear();
        self.geoms
            .extend(bodies.iter().zip(states).map(|(b, s)| geom(b, s)));
        self.aabbs.clear();
        self.aabbs.extend(self.geoms.iter().map(fibre_aabb));

        for (i, g) in self.geoms.iter().enumerate() {
            let (lo, hi) = self.aabbs[i];
            for w in &self.walls {
                // Cheap reject: the box of the fibre does not reach the plane.
                let reach = w
                    .normal
                    .dot(if w.normal.max_element() > 0.0 { lo } else { hi });
                if reach > w.offset {
                    continue;
                }
                self.points.clear();
                contact_fibre_wall(g, w, &mut self.points);
                apply(
                    &self.points,
                    &self.wall_law[i],
                    g,
                    None,
                    force,
                    torque,
                    i,
                    0,
                    &mut stats,
                );
            }
        }

        if self.geoms.len() > 1 {
            candidate_pairs_with(&self.aabbs, &mut self.sweep_order, &mut self.pairs);
            for &(a, b) in &self.pairs {
                let (a, b) = (a as usize, b as usize);
                let (ga, gb) = (&self.geoms[a], &self.geoms[b]);
                self.points.clear();
                contact_fibre_fibre(ga, gb, &mut self.points);
                if self.points.is_empty() {
                    continue;
                }
                let (ba, bb) = (&bodies[a], &bodies[b]);
                let law = HertzLaw::fibre_fibre(
                    diameter(ba),
                    ba.young,
                    ba.poisson,
                    diameter(bb),
                    bb.young,
                    bb.poisson,
                );
                apply(
                    &self.points,
                    &law,
                    ga,
                    Some(gb),
                    force,
                    torque,
                    a,
                    b,
                    &mut stats,
                );
            }
        }
        self.stats = stats;
    }
}

fn diameter(b: &Body) -> f64 {
    match b.shape {
        Shape::Fibre { diameter, .. } | Shape::Sphere { diameter } => diameter,
    }
}

/// Hertz force of each point on A (and the reaction on B, if a body).
#[allow(clippy::too_many_arguments)]
#[inline]
fn apply(
    points: &[ContactPoint],
    law: &HertzLaw,
    ga: &FibreGeom,
    gb: Option<&FibreGeom>,
    force: &mut [DVec3],
    torque: &mut [DVec3],
    a: usize,
    b: usize,
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
        let ratio_a = c.overlap / (2.0 * ga.radius);
        if ratio_a > stats.max_overlap_ratio {
            stats.max_overlap_ratio = ratio_a;
            stats.max_overlap_body = a;
        }
        // Couple of an orientation-dependent weight (zero for walls).
        let couple = -u * c.weight_grad;
        force[a] += f;
        torque[a] += (c.point - ga.centre).cross(f) + couple;
        if let Some(gb) = gb {
            force[b] -= f;
            torque[b] -= (c.point - gb.centre).cross(f) + couple;
        }
    }
}

/// The first overlap found in a configuration: `(body, other body or None for a
/// wall, overlap)`. Used to reject scenes whose bodies overlap at the start.
pub fn first_overlap(
    bodies: &[Body],
    states: &[BodyState],
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
