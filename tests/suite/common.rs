//! Shared helpers for the integration tests.
#![allow(dead_code)]

use fibresim::body::BodyState;
use fibresim::contact::FibreGeom;
use fibresim::integrate::rotate::RotatorKind;
use fibresim::math::geodesic_angle;
use fibresim::scenario::{self, Scene};
use glam::DVec3;
use std::process::{Command, Output};

/// Run the `fibresim` binary from the crate root.
pub fn fibresim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fibresim"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("binary runs")
}

/// Require a successful run (its stderr in the failure message); its stdout.
pub fn ok(o: Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A file's bytes; a missing file fails the test naming it.
pub fn read_bytes(p: &std::path::Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The states file that `dir/checkpoint.json` names (`checkpoint.<step>.states`).
pub fn states_file(dir: &std::path::Path) -> std::path::PathBuf {
    let c: serde_json::Value =
        serde_json::from_slice(&read_bytes(&dir.join("checkpoint.json"))).unwrap();
    dir.join(c["states_file"].as_str().expect("a states file"))
}

/// `fibresim run --resume CHECKPOINT --t-end T -q [EXTRA…]`, required to succeed.
pub fn resume_to(checkpoint: &std::path::Path, t_end: &str, extra: &[&str]) {
    let mut a = vec![
        "run",
        "--resume",
        checkpoint.to_str().unwrap(),
        "--t-end",
        t_end,
        "-q",
    ];
    a.extend(extra);
    ok(fibresim(&a));
}

pub fn scene_file(name: &str) -> Scene {
    let path = format!("{}/scenarios/{name}", env!("CARGO_MANIFEST_DIR"));
    scenario::load(std::path::Path::new(&path)).expect("shipped scenario loads")
}

pub fn scene_str(text: &str) -> Scene {
    scenario::parse_str(text, "<test>").expect("test scenario is valid")
}

pub fn final_state(scene: &Scene, kind: RotatorKind, dt: f64) -> BodyState {
    fibresim::run::integrate(scene, kind, dt).expect("run completes")[0]
}

/// Least-squares slope of log(err) against log(dt), by the library's
/// [`fit_order`](fibresim::study::fit::fit_order). Every point must count:
/// a zero or non-finite error fails the test instead of being skipped.
pub fn fitted_order(dts: &[f64], errs: &[f64]) -> f64 {
    let fit = fibresim::study::fit::fit_order(dts, errs)
        .unwrap_or_else(|| panic!("no order fits dt {dts:?}, errors {errs:?}"));
    assert_eq!(fit.points, dts.len(), "errors {errs:?}");
    fit.order
}

/// Orientation error at the end time: geodesic angle to a reference state.
pub fn angle_error(a: &BodyState, b: &BodyState) -> f64 {
    geodesic_angle(a.rot.q, b.rot.q)
}

/// Test case 1's fibre (docs/physics.md §6): D = 0.01 m, L = 0.025 m, radius and half length.
pub const R: f64 = 0.005;
pub const H: f64 = 0.0125;

/// Test case 1's fibre at `centre` along `axis` (normalised), as the kernels see it.
pub fn fib(centre: DVec3, axis: DVec3) -> FibreGeom {
    FibreGeom {
        centre,
        axis: axis.normalize(),
        radius: R,
        half_length: H,
    }
}

/// Test case 1's fibre material and shape, as scenario keys (docs/physics.md §6).
pub const FIBRE: &str = r#"
shape = "fibre"
diameter = 0.01
length = 0.025
density = 1100.0
young = 5e7
poisson = 0.35
"#;

/// A tiny deterministic generator (xorshift64*), for reproducible poses.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> DVec3 {
        let z = 2.0 * self.next() - 1.0;
        let phi = std::f64::consts::TAU * self.next();
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// The fibre–fibre kernel's contacts of `a` with `b`, with the kernel's
/// counts for this one call (its own counters: no other test can add to them).
pub fn ff_contacts_counted(
    a: &FibreGeom,
    b: &FibreGeom,
) -> (
    Vec<fibresim::contact::ContactPoint>,
    fibresim::contact::KernelCounters,
) {
    let (mut out, mut counters) = (vec![], fibresim::contact::KernelCounters::default());
    fibresim::contact::contact_fibre_fibre(a, b, &mut out, &mut counters);
    (out, counters)
}

/// The fibre–fibre kernel's contacts of `a` with `b`.
pub fn ff_contacts(a: &FibreGeom, b: &FibreGeom) -> Vec<fibresim::contact::ContactPoint> {
    ff_contacts_counted(a, b).0
}

/// Force and torque (about `x`) on body A of the contact points `c` under
/// `law`, as the contact stage applies them (with the couple `−U·weight_grad`
/// of orientation-dependent weights), and their potential `Σ w U(δ)`.
pub fn hertz_wrench(
    law: &fibresim::contact::HertzLaw,
    c: &[fibresim::contact::ContactPoint],
    x: DVec3,
) -> (DVec3, DVec3, f64) {
    c.iter()
        .fold((DVec3::ZERO, DVec3::ZERO, 0.0), |(fo, to, u), p| {
            let f = p.weight * law.force(p.overlap) * p.normal;
            let couple = -law.energy(p.overlap) * p.weight_grad;
            (
                fo + f,
                to + (p.point - x).cross(f) + couple,
                u + p.weight * law.energy(p.overlap),
            )
        })
}

/// The scenario text of a packed block of nearly parallel fibres (along x), 0.1 mm apart and
/// tilted by up to 2 mrad, moving at up to 0.5 m/s: within a few hundred
/// steps most fibres touch several neighbours at once (side–side and
/// end–end), so the order in which a body's contributions are summed
/// matters to the bits.
pub fn packed_scene(nx: usize, ny: usize, nz: usize, t_end: f64) -> String {
    packed(nx, ny, nz, t_end, false)
}

/// [`packed_scene`] with every third cell (in lattice order) holding a
/// sphere of the fibres' diameter at its centre instead of a fibre: a dense
/// mixed bed whose fibre–fibre, sphere–fibre, sphere–sphere and both wall
/// contacts are live within a few hundred steps.
pub fn packed_mixed_scene(nx: usize, ny: usize, nz: usize, t_end: f64) -> String {
    packed(nx, ny, nz, t_end, true)
}

fn packed(nx: usize, ny: usize, nz: usize, t_end: f64, spheres: bool) -> String {
    let mut rng = Rng(0x51ed_270b_67d3_a1c5);
    let (d, l, gap) = (0.01, 0.025, 1e-4);
    let (px, py) = (l + gap, d + gap);
    let max = [
        px * nx as f64 + 0.01,
        py * ny as f64 + 0.01,
        py * nz as f64 + 0.01,
    ];
    let mut text = format!(
        "[simulation]\ndt = 1e-6\nt_end = {t_end}\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [{}, {}, {}]\nyoung = 5e7\npoisson = 0.23\n",
        max[0], max[1], max[2]
    );
    let mut n = 0;
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                let mut r = || 2.0 * rng.next() - 1.0;
                let shape = if spheres && n % 3 == 2 {
                    format!("shape = \"sphere\"\ndiameter = {d}")
                } else {
                    format!("shape = \"fibre\"\ndiameter = {d}\nlength = {l}")
                };
                n += 1;
                text += &format!(
                    "[[body]]\n{shape}\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [{}, {}, {}]\naxis = [1.0, {}, {}]\nvelocity = [{}, {}, {}]\n",
                    0.005 + px * (i as f64 + 0.5),
                    0.005 + py * (j as f64 + 0.5),
                    0.005 + py * (k as f64 + 0.5),
                    1e-3 * r(), 1e-3 * r(),
                    0.3 * r(), 0.3 * r(), 0.3 * r(),
                );
            }
        }
    }
    text
}
