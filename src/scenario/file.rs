//! Serde mirror of the scenario TOML: the raw input, unchecked. Unknown keys are
//! errors (`deny_unknown_fields`). See `scenarios/*.toml` for commented examples.

use serde::Deserialize;
use std::collections::BTreeMap;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioFile {
    pub simulation: SimulationSection,
    #[serde(default)]
    pub world: WorldSection,
    /// Axis-aligned box whose six faces are walls.
    #[serde(rename = "box")]
    pub walls: Option<BoxSection>,
    #[serde(default)]
    pub material: BTreeMap<String, MaterialSection>,
    #[serde(default)]
    pub body: Vec<BodySection>,
    pub reference: Option<ReferenceSection>,
    #[serde(default)]
    pub guards: GuardsSection,
}

/// Limits that stop a run early with a diagnosis (defaults in `build::Guards`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GuardsSection {
    /// Largest full-budget energy error, percent.
    pub energy_error_pct: Option<f64>,
    /// Largest contact overlap as a fraction of the fibre diameter.
    pub overlap_ratio: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSection {
    /// Time step δt, s.
    pub dt: f64,
    /// End time, s.
    pub t_end: f64,
    /// Rotator name (default `pcdm`).
    pub rotator: Option<String>,
    /// Write one output row per `every` steps (default: at most ~1e5 rows).
    pub every: Option<u64>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldSection {
    /// Gravitational acceleration, m/s². Absent: no gravity.
    pub gravity: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxSection {
    pub min: [f64; 3],
    pub max: [f64; 3],
    pub young: f64,
    pub poisson: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    pub density: f64,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShapeName {
    Fibre,
    Sphere,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySection {
    pub name: Option<String>,
    pub shape: ShapeName,
    pub diameter: f64,
    /// Fibres only.
    pub length: Option<f64>,
    /// Either `material = "name"` or inline `density` (+ `young`, `poisson`).
    pub material: Option<String>,
    pub density: Option<f64>,
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub position: [f64; 3],
    /// Direction of body x (the fibre axis) in the world; or give `quaternion`.
    pub axis: Option<[f64; 3]>,
    /// Orientation `[w, x, y, z]`, body → world.
    pub quaternion: Option<[f64; 4]>,
    #[serde(default)]
    pub velocity: [f64; 3],
    /// World-frame angular velocity, rad/s.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    /// Prescribed world-frame torque, N·m: numbers or expressions in `t`.
    pub torque: Option<[TorqueComponent; 3]>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum TorqueComponent {
    Number(f64),
    Expr(String),
}

impl TorqueComponent {
    pub fn text(&self) -> String {
        match self {
            TorqueComponent::Number(x) => format!("{x:e}"),
            TorqueComponent::Expr(s) => s.clone(),
        }
    }
}

/// A closed-form reference solution the scene declares (test case 3).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSection {
    /// `"exp-torque-sphere"`: a sphere at rest under `τ = A e^{Ct} â` (world) turns
    /// about `â` by `θ(t) = A (e^{Ct} − 1 − Ct) / (I C²)`.
    pub closed_form: String,
    pub axis: [f64; 3],
    pub a: f64,
    pub c: f64,
}
