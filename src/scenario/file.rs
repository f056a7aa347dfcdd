//! Serde mirror of the scenario TOML: the raw input, unchecked. Unknown keys are
//! errors (`deny_unknown_fields`). See `scenarios/*.toml` for commented examples.

use serde::Deserialize;
use std::collections::BTreeMap;

/// A whole scenario file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    /// `[simulation]`: time step, end time, rotator, output cadence.
    pub simulation: SimulationSection,
    /// `[world]`: gravity.
    #[serde(default)]
    pub world: WorldSection,
    /// Axis-aligned box whose six faces are walls.
    #[serde(rename = "box")]
    pub walls: Option<BoxSection>,
    /// `[material.NAME]` tables, referred to by `body.material`.
    #[serde(default)]
    pub material: BTreeMap<String, MaterialSection>,
    /// `[[body]]` tables.
    #[serde(default)]
    pub body: Vec<BodySection>,
    /// `[bodies]`: more bodies, from a body file (after the `[[body]]` ones).
    pub bodies: Option<BodiesSection>,
    /// `[contact]`: a declared normal dissipation (absent: elastic).
    pub contact: Option<ContactSection>,
    /// `[reference]`: a closed-form solution the scene declares.
    pub reference: Option<ReferenceSection>,
    /// `[guards]`: limits that stop a run early.
    #[serde(default)]
    pub guards: GuardsSection,
    /// `[output]`: optional outputs (VTK series, trajectories).
    pub output: Option<OutputSection>,
}

/// `[output]`: optional outputs and their cadences, in steps.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// A VTK frame every this many steps.
    pub vtk_every: Option<u64>,
    /// A `trajectory.csv` row per body every this many steps.
    pub trajectory_every: Option<u64>,
    /// Which bodies `orientation.csv` holds: `needed` or `all`.
    pub orientation: Option<String>,
}

/// Limits that stop a run early with a diagnosis (defaults in `build::Guards`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuardsSection {
    /// Largest full-budget energy error, percent.
    pub energy_error_pct: Option<f64>,
    /// Largest contact overlap as a fraction of the fibre diameter.
    pub overlap_ratio: Option<f64>,
    /// Largest overlap (fraction of the thinner diameter) accepted at step 0,
    /// e.g. the resting contacts of a settled bed (default 0: none).
    pub start_overlap_ratio: Option<f64>,
}

/// `[bodies]`: bodies in bulk from a body file (CSV, see
/// [`crate::scenario::body_file`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodiesSection {
    /// Path of the body file, relative to the scenario file's folder.
    pub file: String,
}

/// `[contact]`: normal dissipation set by a coefficient of restitution
/// (docs/physics.md §3; [`crate::contact::damping`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// Normal restitution of fibre–fibre contacts, in (0, 1]; 1 is elastic.
    pub restitution: Option<f64>,
    /// Normal restitution of fibre–wall contacts (default: `restitution`).
    pub wall_restitution: Option<f64>,
    /// Coulomb coefficient of body–body contacts (default 0: frictionless).
    pub friction: Option<f64>,
    /// Coulomb coefficient of body–wall contacts (default: `friction`).
    pub wall_friction: Option<f64>,
}

/// `[simulation]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSection {
    /// Time step δt, s.
    pub dt: f64,
    /// End time, s.
    pub t_end: f64,
    /// Rotator name (default [`crate::integrate::rotate::RotatorKind::DEFAULT`]).
    pub rotator: Option<String>,
    /// Write one output row per `every` steps (default: at most ~1e5 rows).
    pub every: Option<u64>,
}

/// `[world]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSection {
    /// Gravitational acceleration, m/s². Absent: no gravity.
    pub gravity: Option<[f64; 3]>,
}

/// `[box]`: an axis-aligned box whose six faces are walls.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSection {
    /// Lower corner, m.
    pub min: [f64; 3],
    /// Upper corner, m.
    pub max: [f64; 3],
    /// Young's modulus of the walls, Pa.
    pub young: f64,
    /// Poisson ratio of the walls.
    pub poisson: f64,
}

/// `[material.NAME]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    /// kg/m³.
    pub density: f64,
    /// Young's modulus, Pa (needed where bodies can touch).
    pub young: Option<f64>,
    /// Poisson ratio (needed where bodies can touch).
    pub poisson: Option<f64>,
    /// Coulomb coefficient of the material (default: `[contact]`'s).
    pub friction: Option<f64>,
}

/// `body.shape`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeName {
    /// Flat-ended solid cylinder.
    Fibre,
    /// Solid sphere.
    Sphere,
    /// A general rigid body given by `mass` and principal `inertia`
    /// (contact-free scenes only).
    Rigid,
}

/// `[[body]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySection {
    /// A label for messages and outputs (default `body<index>`).
    pub name: Option<String>,
    /// `fibre`, `sphere` or `rigid`.
    pub shape: ShapeName,
    /// m (fibres and spheres).
    pub diameter: Option<f64>,
    /// Fibres only.
    pub length: Option<f64>,
    /// Mass, kg (rigid bodies only).
    pub mass: Option<f64>,
    /// Principal moments of inertia `[I1, I2, I3]` about body x, y, z,
    /// kg m² (rigid bodies only).
    pub inertia: Option<[f64; 3]>,
    /// Either `material = "name"` or inline `density` (+ `young`, `poisson`).
    pub material: Option<String>,
    /// Inline density, kg/m³.
    pub density: Option<f64>,
    /// Inline Young's modulus, Pa.
    pub young: Option<f64>,
    /// Inline Poisson ratio.
    pub poisson: Option<f64>,
    /// Centre of mass, m (world).
    pub position: [f64; 3],
    /// Direction of body x (the fibre axis) in the world; or give `quaternion`.
    pub axis: Option<[f64; 3]>,
    /// Orientation `[w, x, y, z]`, body → world.
    pub quaternion: Option<[f64; 4]>,
    /// Velocity of the centre of mass, m/s (world).
    #[serde(default)]
    pub velocity: [f64; 3],
    /// World-frame angular velocity, rad/s.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Prescribed world-frame torque, N·m: numbers or expressions in `t`.
    pub torque: Option<[TorqueComponent; 3]>,
}

/// One component of a prescribed torque.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum TorqueComponent {
    /// A constant, N·m.
    Number(f64),
    /// An expression in `t` (docs/guide.md, "Scenario files").
    Expr(String),
}

impl TorqueComponent {
    /// The component as expression text.
    pub fn text(&self) -> String {
        match self {
            TorqueComponent::Number(x) => format!("{x:e}"),
            TorqueComponent::Expr(s) => s.clone(),
        }
    }
}

/// A closed-form reference solution the scene declares.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSection {
    /// `"exp-torque-sphere"` (test case 3): a sphere at rest under
    /// `τ = A e^{Ct} â` (world) turns about `â` by `θ(t) = A (e^{Ct} − 1 − Ct) / (I C²)`.
    /// `"torque-free"`: the exact torque-free motion of the body from its
    /// start (regular precession, or Jacobi's elliptic functions).
    /// `"manufactured"`: `q(t) = exp(φ u/2) q₀ exp(ψ v/2)`, driven by the torque
    /// it implies (the body gives no `torque` and no `angular_velocity`).
    pub closed_form: String,
    /// exp-torque-sphere: the torque's direction `â` (world).
    pub axis: Option<[f64; 3]>,
    /// exp-torque-sphere: `A`, N·m.
    pub a: Option<f64>,
    /// exp-torque-sphere: `C`, 1/s.
    pub c: Option<f64>,
    /// manufactured: the world axis `u` of `φ`.
    pub precession_axis: Option<[f64; 3]>,
    /// manufactured: the body axis `v` of `ψ`.
    pub spin_axis: Option<[f64; 3]>,
    /// manufactured: `[a, b, c]` of `φ(t) = a t + b sin(c t)` (rad/s, rad, rad/s).
    pub precession: Option<[f64; 3]>,
    /// manufactured: `[a, b, c]` of `ψ(t) = a t + b (1 − cos(c t))`.
    pub spin: Option<[f64; 3]>,
}
