//! The walls a scene can have: the six inward-facing half-spaces of an
//! axis-aligned box.

use glam::DVec3;

/// The six walls of an axis-aligned box, with their elastic constants (a
/// scene's `[box]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Walls {
    /// Lower corner (m).
    pub min: DVec3,
    /// Upper corner (m).
    pub max: DVec3,
    /// Young's modulus of the walls (Pa).
    pub young: f64,
    /// Poisson ratio of the walls.
    pub poisson: f64,
}

/// Half-space wall of an axis-aligned box: plane `normal·x = offset`, the
/// box interior is `normal·x >= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// Unit normal pointing into the box.
    pub normal: DVec3,
    /// Plane offset (m).
    pub offset: f64,
}

/// The six inward-facing half-spaces of the box `w`: `−x, +x, −y, +y, −z,
/// +z` faces in this order (the order the stage sums wall forces in).
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
