//! Random sequential placement of non-overlapping fibres in a box region, on
//! a uniform cell grid of the fibres' centres (O(N) for a bounded density).
//!
//! A candidate (centre uniform where its bounds fit in the region, axis from
//! the orientation distribution) is accepted when the axis segments of every
//! placed fibre near it are farther apart than the two radii plus `gap`: the
//! capsule of a segment holds its cylinder, so accepted fibres never touch.
//! Grid cells are at least the longest fibre plus the thickest diameter plus
//! the gap wide, so every fibre that can touch a candidate has its centre in
//! the 27 cells around the candidate's.

use super::sample::{Orientation, Rng, Size};
use crate::contact::{fibre_fibre::segment_closest_params, FibreGeom};
use glam::{DQuat, DVec3};

/// One placed fibre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Centre, m.
    pub x: DVec3,
    /// Orientation, body → world.
    pub q: DQuat,
    /// D, m.
    pub diameter: f64,
    /// L, m.
    pub length: f64,
}

/// What to place.
#[derive(Debug, Clone)]
pub struct Placement {
    /// Number of fibres.
    pub n: usize,
    /// Region of the centres' bounds (lower, upper corner), m.
    pub region: (DVec3, DVec3),
    /// Diameter distribution.
    pub diameter: Size,
    /// Length distribution.
    pub length: Size,
    /// Axis distribution.
    pub orientation: Orientation,
    /// Smallest surface gap between two placed fibres, m.
    pub gap: f64,
    /// Candidates tried per fibre before giving up.
    pub max_attempts: u64,
}

/// The fibres placed, and the candidates drawn for them.
#[derive(Debug, Clone)]
pub struct Layout {
    /// In placement order.
    pub fibres: Vec<Placed>,
    /// Candidates drawn in all.
    pub attempts: u64,
}

/// Why placement stopped short.
#[derive(Debug, Clone, PartialEq)]
pub struct Jammed {
    /// Fibres placed before the one that found no room.
    pub placed: usize,
    /// Their volume fraction of the region.
    pub volume_fraction: f64,
}

/// Axis-aligned half extent of a fibre of axis `a`.
fn half_extent(a: DVec3, d: f64, l: f64) -> DVec3 {
    let disc = (DVec3::ONE - a * a).max(DVec3::ZERO);
    0.5 * l * a.abs() + 0.5 * d * DVec3::new(disc.x.sqrt(), disc.y.sqrt(), disc.z.sqrt())
}

/// Place `p.n` fibres drawn from `rng` (module docs).
pub fn place(p: &Placement, rng: &mut Rng) -> Result<Layout, Jammed> {
    let (lo, hi) = p.region;
    let cell = p.length.max() + p.diameter.max() + p.gap;
    let span = hi - lo;
    let dims = [0, 1, 2].map(|k| ((span[k] / cell).floor() as usize).max(1));
    let cells = dims[0] * dims[1] * dims[2];
    let cell_of = |x: DVec3| -> [usize; 3] {
        [0, 1, 2].map(|k| ((((x[k] - lo[k]) / span[k]) * dims[k] as f64) as usize).min(dims[k] - 1))
    };
    let index = |c: [usize; 3]| (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    // Linked lists per cell: `head[cell]`, `next[fibre]` (u32::MAX ends).
    let mut head = vec![u32::MAX; cells];
    let mut next: Vec<u32> = Vec::with_capacity(p.n);
    let mut fibres: Vec<Placed> = Vec::with_capacity(p.n);
    let mut geoms: Vec<FibreGeom> = Vec::with_capacity(p.n);
    let mut attempts = 0u64;
    let volume = span.x * span.y * span.z;
    let mut filled = 0.0;
    for _ in 0..p.n {
        let d = p.diameter.draw(rng);
        let l = p.length.draw(rng);
        let mut tries = 0;
        loop {
            if tries == p.max_attempts {
                return Err(Jammed {
                    placed: fibres.len(),
                    volume_fraction: filled / volume,
                });
            }
            tries += 1;
            attempts += 1;
            let q = p.orientation.draw(rng);
            let axis = crate::math::body_x_axis(q);
            let half = half_extent(axis, d, l);
            let room = span - 2.0 * half;
            let u = DVec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            if room.min_element() < 0.0 {
                continue; // this orientation does not fit: draw another
            }
            let x = lo + half + u * room;
            let g = FibreGeom {
                centre: x,
                axis,
                radius: 0.5 * d,
                half_length: 0.5 * l,
            };
            let c = cell_of(x);
            let mut free = true;
            'near: for k in c[2].saturating_sub(1)..=(c[2] + 1).min(dims[2] - 1) {
                for j in c[1].saturating_sub(1)..=(c[1] + 1).min(dims[1] - 1) {
                    for i in c[0].saturating_sub(1)..=(c[0] + 1).min(dims[0] - 1) {
                        let mut m = head[index([i, j, k])];
                        while m != u32::MAX {
                            if touches(&g, &geoms[m as usize], p.gap) {
                                free = false;
                                break 'near;
                            }
                            m = next[m as usize];
                        }
                    }
                }
            }
            if free {
                let cell = index(c);
                next.push(head[cell]);
                head[cell] = fibres.len() as u32;
                fibres.push(Placed {
                    x,
                    q,
                    diameter: d,
                    length: l,
                });
                geoms.push(g);
                filled += std::f64::consts::PI * 0.25 * d * d * l;
                break;
            }
        }
    }
    Ok(Layout { fibres, attempts })
}

/// Whether the capsules of `a` and `b`, grown by `gap`, meet.
fn touches(a: &FibreGeom, b: &FibreGeom, gap: f64) -> bool {
    let reach = a.radius + b.radius + gap;
    let far = a.half_length + b.half_length + reach;
    if a.centre.distance_squared(b.centre) > far * far {
        return false;
    }
    let (s, t) = segment_closest_params(a, b);
    (a.centre + s * a.axis).distance_squared(b.centre + t * b.axis) < reach * reach
}
