//! `fibresim generate`: a scenario with non-overlapping fibres, spheres or
//! a mix of both in a box, and its body file (random sequential placement on a cell grid, O(N);
//! [`place`]). Same options and seed, same bytes.

pub mod order;
pub mod place;
pub mod replicate;
pub mod sample;

use crate::body::{Body, BodyState, Material, RotState, Shape};
use crate::contact::damping::Restitution;
use crate::contact::Walls;
use crate::error::{Error, Result};
use crate::scenario::write::BedScenario;
use crate::scenario::Ids;
use glam::DVec3;
use place::Placement;
use sample::Rng;
use std::path::PathBuf;

/// `guards.start_overlap_ratio` of a settled bed's scenario: the largest
/// overlap ratio the settling run saw (an upper bound of the resting ones;
/// the bottom of the 10⁴-fibre bed rests at ~1 % of D under the pile's
/// weight), rounded up to 3 decimals, and at least 0.01.
pub fn settled_start_overlap(max_overlap_ratio: f64) -> f64 {
    ((max_overlap_ratio * 1000.0).ceil() / 1000.0).max(0.01)
}

/// Initial velocities of the bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Velocity {
    /// All the same, m/s.
    Fixed(DVec3),
    /// This speed in a direction uniform on the sphere, m/s.
    Random(f64),
}

/// What `fibresim generate` makes (checked by the CLI's plan).
#[derive(Debug, Clone)]
pub struct GenerateOptions {
    /// Fibres and spheres, sizes, orientations, region.
    pub placement: Placement,
    /// The box (its walls).
    pub walls: Walls,
    /// Gravity, m/s².
    pub gravity: Option<DVec3>,
    /// The bodies' material (named in the body file).
    pub material: Material,
    /// Initial velocities.
    pub velocity: Velocity,
    /// Angular speed about a random axis normal to each body's x, rad/s.
    pub spin: f64,
    /// Seed of the random draws.
    pub seed: u64,
    /// The scenario's time step and end time, s.
    pub dt: f64,
    /// (See `dt`.)
    pub t_end: f64,
    /// Declared normal restitution (`None`: elastic).
    pub restitution: Option<Restitution>,
    /// Declared Coulomb friction (`None`: frictionless).
    pub friction: Option<crate::contact::tangential::Friction>,
    /// The scenario file to write; the body file is `<stem>_bodies.csv` beside it.
    pub out: PathBuf,
    /// The command line, for the scenario's header.
    pub command: String,
}

/// What `fibresim generate` did.
#[derive(Debug, Clone)]
pub struct GenerateReport {
    /// Bodies placed.
    pub placed: usize,
    /// Of those, spheres.
    pub spheres: usize,
    /// Candidates drawn.
    pub attempts: u64,
    /// Volume fraction of the bodies in the placement region.
    pub volume_fraction: f64,
    /// Volume fraction in the whole box.
    pub box_fraction: f64,
    /// The scenario written.
    pub scenario: PathBuf,
    /// Its body file.
    pub body_file: PathBuf,
}

/// `N fibres`, `M spheres` or `N fibres and M spheres`.
pub fn counted(fibres: usize, spheres: usize) -> String {
    match (fibres, spheres) {
        (f, 0) => format!("{f} fibres"),
        (0, s) => format!("{s} spheres"),
        (f, s) => format!("{f} fibres and {s} spheres"),
    }
}

/// The body file beside scenario `toml`: `<stem>_bodies.csv`.
pub fn body_file_of(toml: &std::path::Path) -> PathBuf {
    let stem = toml
        .file_stem()
        .map_or("bed".into(), |s| s.to_string_lossy().into_owned());
    toml.with_file_name(format!("{stem}_bodies.csv"))
}

/// Place the fibres and write the scenario and its body file.
pub fn generate(o: &GenerateOptions) -> Result<GenerateReport> {
    let mut rng = Rng::new(o.seed);
    let layout = place::place(&o.placement, &mut rng).map_err(|j| {
        Error::bad(
            "command line",
            "--n",
            format!(
                "no room for body {} after {} candidates: the region is jammed at volume fraction {:.4}; enlarge the region (--region, --box), place fewer bodies or allow more attempts (--max-attempts)",
                j.placed, o.placement.max_attempts, j.volume_fraction
            ),
        )
    })?;
    let mut bodies = crate::body::Bodies::new();
    let mut states = Vec::with_capacity(layout.bodies.len());
    let mut volume = 0.0;
    for p in &layout.bodies {
        let shape = p.shape;
        volume += shape.volume();
        bodies.push(Body::new(shape, 0, o.material.density));
        let v = match o.velocity {
            Velocity::Fixed(v) => v,
            Velocity::Random(s) => s * rng.unit_vector(),
        };
        let omega_b = if o.spin > 0.0 {
            // Normal to the axis (body x): axial spin does not change under
            // frictionless contacts (docs/physics.md §9).
            let phi = 2.0 * std::f64::consts::PI * rng.uniform();
            o.spin * DVec3::new(0.0, phi.cos(), phi.sin())
        } else {
            DVec3::ZERO
        };
        states.push(BodyState {
            x: p.x,
            v,
            rot: RotState { q: p.q, omega_b },
        });
    }
    crate::output::create_parent_dir(&o.out, "--out")?;
    let body_file = body_file_of(&o.out);
    let ids = Ids::Sequential(bodies.len());
    crate::scenario::body_file::write(
        &body_file,
        &ids,
        &bodies,
        &states,
        std::slice::from_ref(&o.material.name),
    )?;
    let (lo, hi) = o.placement.region;
    let region = (hi - lo).x * (hi - lo).y * (hi - lo).z;
    let span = o.walls.max - o.walls.min;
    let spheres = bodies
        .iter()
        .filter(|b| matches!(b.shape, Shape::Sphere { .. }))
        .count();
    let report = GenerateReport {
        placed: bodies.len(),
        spheres,
        attempts: layout.attempts,
        volume_fraction: volume / region,
        box_fraction: volume / (span.x * span.y * span.z),
        scenario: o.out.clone(),
        body_file: body_file.clone(),
    };
    let text = BedScenario {
        comment: vec![
            format!("Generated by: {}", o.command),
            format!(
                "{}, volume fraction {:.4} of the region, {:.4} of the box; {} placement attempts (seed {}).",
                counted(report.placed - spheres, spheres),
                report.volume_fraction,
                report.box_fraction,
                report.attempts,
                o.seed
            ),
        ],
        dt: o.dt,
        t_end: o.t_end,
        gravity: o.gravity,
        walls: Some(&o.walls),
        materials: std::slice::from_ref(&o.material),
        restitution: o.restitution,
        friction: o.friction,
        start_overlap_ratio: None,
        body_file: &body_file
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().into_owned()),
    }
    .to_string();
    std::fs::write(&o.out, text).map_err(|e| Error::io(&o.out, e))?;
    Ok(report)
}
