//! The poses of `benches/kernels.rs` (and of `examples/kernel_profile.rs`,
//! which runs them under callgrind): test case 1's fibre (D = 10 mm,
//! L = 25 mm), live overlaps 10 µm, placed in closed form.

use fibresim::contact::FibreGeom;
use glam::{DQuat, DVec3};

const R: f64 = 0.005;
const H: f64 = 0.0125;
/// Live overlap of the touching poses (m).
const DELTA: f64 = 1e-5;

fn fib(centre: DVec3, axis: DVec3) -> FibreGeom {
    FibreGeom {
        centre,
        axis: axis.normalize(),
        radius: R,
        half_length: H,
    }
}

/// The lowest point of `f`'s lower end rim (axis tilted from +z).
fn lowest_rim_point(f: &FibreGeom) -> DVec3 {
    let e = f.centre - H * f.axis;
    let down = -(DVec3::Z - DVec3::Z.dot(f.axis) * f.axis).normalize();
    e + R * down
}

/// (name, A, B): side–side first, then end-involved live pairs, then near
/// misses that pass the capsule bound.
pub fn poses() -> Vec<(&'static str, FibreGeom, FibreGeom)> {
    let x = DVec3::X;
    let z = DVec3::Z;
    let a_x = fib(DVec3::ZERO, x);
    let a_z = fib(DVec3::ZERO, z);
    let deg = |d: f64| d.to_radians();
    let tilted = |t: f64, azimuth: f64| {
        DVec3::new(t.sin() * azimuth.cos(), t.sin() * azimuth.sin(), t.cos())
    };
    let mut v = vec![
        // Side–side: crossings and a parallel line contact.
        (
            "side_side/crossing_90",
            a_x,
            fib(DVec3::new(0.002, 0.003, 2.0 * R - DELTA), DVec3::Y),
        ),
        (
            "side_side/crossing_30",
            a_x,
            fib(
                DVec3::new(0.0, 0.0, 2.0 * R - DELTA),
                DVec3::new(deg(30.0).cos(), deg(30.0).sin(), 0.0),
            ),
        ),
        (
            "side_side/parallel",
            a_x,
            fib(DVec3::new(0.005, 2.0 * R - DELTA, 0.0), x),
        ),
        // End involved. T-junction: A's top face flat under B's side.
        (
            "end/face_on_side",
            a_z,
            fib(DVec3::new(0.001, 0.0, H + R - DELTA), x),
        ),
    ];
    // A tilted by 30°, its top rim under B's side (B along y over A's
    // highest rim point).
    let t = deg(30.0);
    let a_t = fib(DVec3::ZERO, DVec3::new(t.sin(), 0.0, t.cos()));
    let top = DVec3::new(H * t.sin() - R * t.cos(), 0.0, H * t.cos() + R * t.sin());
    v.push((
        "end/rim_on_side",
        a_t,
        fib(top + DVec3::new(0.0, 0.0, R - DELTA), DVec3::Y),
    ));
    // B tilted by 30°, its lowest rim point 1 mm off A's axis on A's top face.
    let b = fib(DVec3::ZERO, tilted(t, 0.0));
    let low = lowest_rim_point(&b);
    v.push((
        "end/rim_on_face",
        a_z,
        fib(DVec3::new(0.001, 0.0, H - DELTA) - low, b.axis),
    ));
    // L corner: B tilted by 40° at 45° azimuth, its lowest rim point just
    // outside A's top rim edge (the rims cross).
    let b = fib(DVec3::ZERO, tilted(deg(40.0), deg(45.0)));
    let low = lowest_rim_point(&b);
    v.push((
        "end/rim_on_rim",
        a_z,
        fib(DVec3::new(R + 2e-5, 0.0, H - DELTA) - low, b.axis),
    ));
    // End to end: coaxial faces (laterally offset) and tilted by 0.5°.
    v.push((
        "end/face_on_face",
        a_x,
        fib(DVec3::new(2.0 * H - DELTA, 0.002, 0.0), x),
    ));
    let tilt = DQuat::from_rotation_z(deg(0.5));
    v.push((
        "end/near_coaxial",
        a_x,
        fib(DVec3::new(2.0 * H - DELTA, 0.001, 0.0), tilt * x),
    ));
    // Near misses inside the capsule bound.
    v.push((
        "miss/coaxial_gap_1mm",
        a_x,
        fib(DVec3::new(2.0 * H + 1e-3, 0.0, 0.0), x),
    ));
    v.push((
        "miss/t_junction_gap_0.5mm",
        a_z,
        fib(DVec3::new(0.001, 0.0, H + R + 5e-4), x),
    ));
    v.push((
        "miss/l_corner_gap_0.2mm",
        a_z,
        fib(
            DVec3::new(R + 2e-4, 0.0, H + 2e-4) - lowest_rim_point(&b),
            b.axis,
        ),
    ));
    v
}
