//! One VTK frame of a world: every fibre a `VTK_LINE` cell between its two
//! end-face centres, with its per-fibre cell data (docs/guide.md, "The VTK
//! time series", lists the arrays, their units and their order conventions).

use super::xml::{polydata, Array, Data, PolyPiece};
use crate::body::Shape;
use crate::integrate::step::World;
use crate::math::{body_x_axis, to_world};

/// The cell arrays of a frame, in file order: name, components, unit.
pub const CELL_ARRAYS: [(&str, usize, &str); 12] = [
    ("id", 1, ""),
    ("material", 1, ""),
    ("diameter", 1, "m"),
    ("length", 1, "m"),
    ("quaternion", 4, ""),
    ("axis", 3, ""),
    ("velocity", 3, "m/s"),
    ("omega", 3, "rad/s"),
    ("omega_body", 3, "rad/s"),
    ("speed", 1, "m/s"),
    ("kinetic_energy", 1, "J"),
    ("contacts", 1, ""),
];

/// Components of the `quaternion` array: scalar first, as in every
/// fibresim file (docs/physics.md §1) and as `vtkQuaternion` stores it.
pub const QUATERNION_COMPONENTS: [&str; 4] = ["w", "x", "y", "z"];

/// The `.vtp` bytes of `world`'s current state; `contacts` is each body's
/// live contact count (storage order).
pub(crate) fn frame_bytes(world: &World, contacts: &[u32]) -> Vec<u8> {
    let scene = world.scene;
    let n = world.states.len();
    let mut points = Vec::with_capacity(6 * n);
    let (mut id, mut material) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut diameter, mut length) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut quat = Vec::with_capacity(4 * n);
    let mut axis = Vec::with_capacity(3 * n);
    let mut vel = Vec::with_capacity(3 * n);
    let mut omega = Vec::with_capacity(3 * n);
    let mut omega_b = Vec::with_capacity(3 * n);
    let (mut speed, mut energy) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for (i, (s, b)) in world.states.iter().zip(&scene.bodies).enumerate() {
        let (d, l) = match b.shape {
            Shape::Fibre { diameter, length } => (diameter, length),
            // A sphere is a zero-length line at its centre (docs/guide.md).
            Shape::Sphere { diameter } => (diameter, 0.0),
            // A rigid body: its equivalent ellipsoid's long axis along body x
            // (VTK shows it as a line of that length).
            Shape::Rigid { semi_axes } => (2.0 * semi_axes.y.max(semi_axes.z), 2.0 * semi_axes.x),
        };
        let q = s.rot.q;
        let a = body_x_axis(q);
        let h = 0.5 * l * a;
        for p in [s.x - h, s.x + h] {
            points.extend(p.to_array().map(|c| c as f32));
        }
        id.push(scene.ids.get(i) as i64);
        material.push(b.material as i32);
        diameter.push(d as f32);
        length.push(l as f32);
        quat.extend([q.w, q.x, q.y, q.z].map(|c| c as f32));
        axis.extend(a.to_array().map(|c| c as f32));
        vel.extend(s.v.to_array().map(|c| c as f32));
        omega.extend(to_world(q, s.rot.omega_b).to_array().map(|c| c as f32));
        omega_b.extend(s.rot.omega_b.to_array().map(|c| c as f32));
        speed.push(s.v.length() as f32);
        let ke = 0.5 * b.mass * s.v.length_squared() + b.inertia.kinetic_energy(s.rot.omega_b);
        energy.push(ke as f32);
    }
    let counts: Vec<i32> = contacts.iter().map(|&c| c as i32).collect();
    let connectivity: Vec<i32> = (0..2 * n as i32).collect();
    let offsets: Vec<i32> = (1..=n as i32).map(|k| 2 * k).collect();
    let time = [world.time()];
    let step = [world.step as i64];
    let piece = PolyPiece {
        field: vec![
            Array::new("TimeValue", 1, Data::F64(&time)),
            Array::new("step", 1, Data::I64(&step)),
        ],
        points: Array::new("Points", 3, Data::F32(&points)),
        cells: vec![
            Array::new("id", 1, Data::I64(&id)),
            Array::new("material", 1, Data::I32(&material)),
            Array::new("diameter", 1, Data::F32(&diameter)),
            Array::new("length", 1, Data::F32(&length)),
            Array::new("quaternion", 4, Data::F32(&quat)).named(&QUATERNION_COMPONENTS),
            Array::new("axis", 3, Data::F32(&axis)),
            Array::new("velocity", 3, Data::F32(&vel)),
            Array::new("omega", 3, Data::F32(&omega)),
            Array::new("omega_body", 3, Data::F32(&omega_b)),
            Array::new("speed", 1, Data::F32(&speed)),
            Array::new("kinetic_energy", 1, Data::F32(&energy)),
            Array::new("contacts", 1, Data::I32(&counts)),
        ],
        lines: [
            Array::new("connectivity", 1, Data::I32(&connectivity)),
            Array::new("offsets", 1, Data::I32(&offsets)),
        ],
        n_points: 2 * n,
        n_lines: n,
    };
    polydata(&piece, &legend(world))
}

/// The XML comment of a frame: what `material` indexes.
fn legend(world: &World) -> String {
    let scene = world.scene;
    let materials: Vec<String> = scene
        .materials
        .iter()
        .enumerate()
        .map(|(k, m)| format!("{k}={}", m.name))
        .collect();
    format!(
        "fibresim frame: material {}; quaternion is [w, x, y, z] (scalar first), body to world",
        materials.join(", ")
    )
}
