//! Live contacts per body, recounted when a frame is written (VTK cell data,
//! `fibresim render --color contacts`), so a run that writes no frame pays
//! nothing: the contact stage keeps no per-body counts.
//!
//! The recount asks the same kernels ([`crate::contact::contacts`]) the same
//! questions the force stage asked at these states: fibre geometry formed as
//! the stage forms it, candidates from capsule boxes (a flat-ended cylinder
//! lies inside the capsule of its axis segment, so no touching pair is
//! missed). A body's count is the number of bodies and walls it touches, so
//! the counts sum to `2 × fibre–fibre + fibre–wall` touching pairs.

use crate::body::{Body, BodyState, Shape};
use crate::contact::{box_walls, candidate_pairs, contacts, Collider, FibreGeom, KernelCounters};
use crate::math::body_x_axis;
use crate::scenario::Walls;
use glam::DVec3;
use rayon::prelude::*;

/// Touching bodies and walls per body at `states`, in storage order. Zero for
/// every body of a scene without contacts (`walls` none and one body) or
/// with spheres.
pub fn contacts_per_body(bodies: &[Body], states: &[BodyState], walls: Option<&Walls>) -> Vec<u32> {
    let n = bodies.len();
    let mut count = vec![0u32; n];
    let fibres = bodies
        .iter()
        .all(|b| matches!(b.shape, Shape::Fibre { .. }));
    if !fibres || (walls.is_none() && n < 2) {
        return count;
    }
    let geoms: Vec<FibreGeom> = bodies
        .iter()
        .zip(states)
        .map(|(b, s)| FibreGeom {
            centre: s.x,
            axis: body_x_axis(s.rot.q),
            radius: 0.5 * b.shape.diameter(),
            half_length: match b.shape {
                Shape::Fibre { length, .. } => 0.5 * length,
                Shape::Sphere { .. } => 0.0,
            },
        })
        .collect();
    let boxes: Vec<(DVec3, DVec3)> = geoms
        .iter()
        .map(|g| {
            let (a, b) = (
                g.centre - g.half_length * g.axis,
                g.centre + g.half_length * g.axis,
            );
            // The capsule's box, grown by 0.1 D as the stage's half skin is:
            // a few more candidates to reject, never a contact missed.
            let r = DVec3::splat(1.2 * g.radius);
            (a.min(b) - r, a.max(b) + r)
        })
        .collect();
    let touch = |a: Collider, b: Collider| {
        let mut pts = Vec::new();
        contacts(a, b, &mut pts, &mut KernelCounters::default());
        !pts.is_empty()
    };
    if let Some(w) = walls {
        let walls = box_walls(w);
        let on_walls: Vec<u32> = geoms
            .par_iter()
            .zip(&boxes)
            .map(|(g, (lo, hi))| {
                let reaches = |wall: &&crate::contact::Wall| {
                    let corner = if wall.normal.max_element() > 0.0 {
                        *lo
                    } else {
                        *hi
                    };
                    wall.normal.dot(corner) <= wall.offset
                };
                walls
                    .iter()
                    .filter(reaches)
                    .filter(|wall| touch(Collider::Fibre(g), Collider::Wall(wall)))
                    .count() as u32
            })
            .collect();
        for (c, k) in count.iter_mut().zip(on_walls) {
            *c += k;
        }
    }
    let mut pairs = Vec::new();
    candidate_pairs(&boxes, &mut pairs);
    let touching: Vec<bool> = pairs
        .par_iter()
        .map(|&(i, j)| {
            touch(
                Collider::Fibre(&geoms[i as usize]),
                Collider::Fibre(&geoms[j as usize]),
            )
        })
        .collect();
    for (&(i, j), t) in pairs.iter().zip(touching) {
        if t {
            count[i as usize] += 1;
            count[j as usize] += 1;
        }
    }
    count
}
