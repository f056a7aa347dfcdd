//! Random sequential placement of non-overlapping fibres and spheres in a
//! box region, on a uniform cell grid of the bodies' centres (O(N) for a
//! bounded density): the fibres first, then the spheres in the room left.
//!
//! A candidate (centre uniform where its bounds fit in the region, a fibre's
//! axis from the orientation distribution) is accepted when the axis
//! segments of every placed body near it are farther apart than the two
//! radii plus `gap`: the capsule of a segment holds its cylinder, and a
//! sphere is the capsule of zero length, so accepted bodies never touch.
//! Grid cells are at least the longest body plus the thickest diameter plus
//! the gap wide, so every body that can touch a candidate has its centre in
//! the 27 cells around the candidate's.

use super::sample::{Orientation, Rng, Size};
use crate::body::Shape;
use crate::contact::{fibre_fibre::segment_closest_params, FibreGeom};
use glam::{DQuat, DVec3};

/// One placed body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Centre, m.
    pub x: DVec3,
    /// Orientation, body → world (a sphere's: the identity).
    pub q: DQuat,
    /// Its shape and size.
    pub shape: Shape,
}

/// The fibres to place.
#[derive(Debug, Clone)]
pub struct Fibres {
    /// How many.
    pub n: usize,
    /// Diameter distribution.
    pub diameter: Size,
    /// Length distribution.
    pub length: Size,
    /// Axis distribution.
    pub orientation: Orientation,
}

/// The spheres to place.
#[derive(Debug, Clone)]
pub struct Spheres {
    /// How many.
    pub n: usize,
    /// Diameter distribution.
    pub diameter: Size,
}

/// What to place.
#[derive(Debug, Clone)]
pub struct Placement {
    /// The fibres, if any.
    pub fibres: Option<Fibres>,
    /// The spheres, if any (placed after the fibres).
    pub spheres: Option<Spheres>,
    /// Region of the centres' bounds (lower, upper corner), m.
    pub region: (DVec3, DVec3),
    /// Smallest surface gap between two placed bodies, m.
    pub gap: f64,
    /// Candidates tried per body before giving up.
    pub max_attempts: u64,
}

impl Placement {
    /// The number of bodies to place.
    pub fn n(&self) -> usize {
        self.fibres.as_ref().map_or(0, |f| f.n) + self.spheres.as_ref().map_or(0, |s| s.n)
    }

    /// The thickest diameter that can be drawn.
    pub fn max_diameter(&self) -> f64 {
        let f = self.fibres.as_ref().map_or(0.0, |f| f.diameter.max());
        f.max(self.spheres.as_ref().map_or(0.0, |s| s.diameter.max()))
    }

    /// The longest body that can be drawn (a sphere's length is its
    /// diameter).
    fn max_extent(&self) -> f64 {
        let f = self.fibres.as_ref().map_or(0.0, |f| f.length.max());
        f.max(self.spheres.as_ref().map_or(0.0, |s| s.diameter.max()))
    }
}

/// The bodies placed, and the candidates drawn for them.
#[derive(Debug, Clone)]
pub struct Layout {
    /// In placement order: the fibres, then the spheres.
    pub bodies: Vec<Placed>,
    /// Candidates drawn in all.
    pub attempts: u64,
}

/// Why placement stopped short.
#[derive(Debug, Clone, PartialEq)]
pub struct Jammed {
    /// Bodies placed before the one that found no room.
    pub placed: usize,
    /// Their volume fraction of the region.
    pub volume_fraction: f64,
}

/// Axis-aligned half extent of a fibre of axis `a`.
fn half_extent(a: DVec3, d: f64, l: f64) -> DVec3 {
    let disc = (DVec3::ONE - a * a).max(DVec3::ZERO);
    0.5 * l * a.abs() + 0.5 * d * DVec3::new(disc.x.sqrt(), disc.y.sqrt(), disc.z.sqrt())
}

/// Place the fibres, then the spheres, of `p` drawn from `rng` (module
/// docs).
pub fn place(p: &Placement, rng: &mut Rng) -> Result<Layout, Jammed> {
    let (lo, hi) = p.region;
    let cell = p.max_extent() + p.max_diameter() + p.gap;
    let span = hi - lo;
    let dims = [0, 1, 2].map(|k| ((span[k] / cell).floor() as usize).max(1));
    let cells = dims[0] * dims[1] * dims[2];
    let cell_of = |x: DVec3| -> [usize; 3] {
        [0, 1, 2].map(|k| ((((x[k] - lo[k]) / span[k]) * dims[k] as f64) as usize).min(dims[k] - 1))
    };
    let index = |c: [usize; 3]| (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    // Linked lists per cell: `head[cell]`, `next[body]` (u32::MAX ends).
    let mut head = vec![u32::MAX; cells];
    let n = p.n();
    let mut next: Vec<u32> = Vec::with_capacity(n);
    let mut bodies: Vec<Placed> = Vec::with_capacity(n);
    let mut geoms: Vec<FibreGeom> = Vec::with_capacity(n);
    let mut attempts = 0u64;
    let volume = span.x * span.y * span.z;
    let mut filled = 0.0;
    // What each body draws: its size once, then per candidate its
    // orientation (a fibre's) and its centre.
    let fibres = p.fibres.iter().flat_map(|f| (0..f.n).map(move |_| Ok(f)));
    let spheres = p.spheres.iter().flat_map(|s| (0..s.n).map(move |_| Err(s)));
    for kind in fibres.chain(spheres) {
        let (shape, orientation) = match kind {
            Ok(f) => {
                let diameter = f.diameter.draw(rng);
                let length = f.length.draw(rng);
                (Shape::Fibre { diameter, length }, Some(f.orientation))
            }
            Err(s) => {
                let diameter = s.diameter.draw(rng);
                (Shape::Sphere { diameter }, None)
            }
        };
        let (d, l) = match shape {
            Shape::Fibre { diameter, length } => (diameter, length),
            _ => (shape.diameter(), 0.0),
        };
        let mut tries = 0;
        loop {
            if tries == p.max_attempts {
                return Err(Jammed {
                    placed: bodies.len(),
                    volume_fraction: filled / volume,
                });
            }
            tries += 1;
            attempts += 1;
            let q = orientation.map_or(DQuat::IDENTITY, |o| o.draw(rng));
            // A sphere is the capsule of zero length (its axis unused).
            let axis = crate::math::body_x_axis(q);
            let half = match orientation {
                Some(_) => half_extent(axis, d, l),
                None => DVec3::splat(0.5 * d),
            };
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
                head[cell] = bodies.len() as u32;
                bodies.push(Placed { x, q, shape });
                geoms.push(g);
                filled += shape.volume();
                break;
            }
        }
    }
    Ok(Layout { bodies, attempts })
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
