//! Every key a scenario file may hold, in one table: its kind, unit, whether
//! it is required (or its default), what it means, an example and, for
//! material and size values, the range a warning asks about.
//!
//! The pre-check ([`super::precheck`]) checks a file against this table
//! before serde, `fibresim keys` prints it, and docs/scenario.md carries it;
//! `tests/suite/scenario_reference.rs` keeps the table, the serde mirror
//! (`file.rs`) and the docs in step. A new key is one line in [`KEYS`] (and
//! its serde field).

use crate::fmt::short;
use crate::integrate::rotate::RotatorKind;

/// How a table appears in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Form {
    /// `[name]`, at most once.
    Single,
    /// `[[name]]`, one per item.
    Array,
    /// `[name.LABEL]`, one per label.
    Named,
}

/// A table of the scenario file.
#[derive(Debug, Clone, Copy)]
pub struct TableSpec {
    /// Its name (`simulation`, `body`, ...).
    pub name: &'static str,
    /// How it is written.
    pub form: Form,
    /// Whether a scene must have it.
    pub required: bool,
    /// What it declares, and what its absence means.
    pub meaning: &'static str,
}

/// Every table, in the order of the reference.
pub const TABLES: &[TableSpec] = &[
    TableSpec {
        name: "simulation",
        form: Form::Single,
        required: true,
        meaning: "time step, end time, rotator, output cadence",
    },
    TableSpec {
        name: "world",
        form: Form::Single,
        required: false,
        meaning: "gravity; without it, no gravity",
    },
    TableSpec {
        name: "box",
        form: Form::Single,
        required: false,
        meaning: "an axis-aligned box whose six faces are walls; without it, no walls",
    },
    TableSpec {
        name: "material",
        form: Form::Named,
        required: false,
        meaning: "a named material, used by `body.material = \"NAME\"`",
    },
    TableSpec {
        name: "body",
        form: Form::Array,
        required: false,
        meaning: "one rigid body (a scene has at least one `[[body]]` or a `[bodies]` file)",
    },
    TableSpec {
        name: "bodies",
        form: Form::Single,
        required: false,
        meaning: "bodies in bulk from a CSV body file (written by `fibresim generate` and `settle`); they join the `[[body]]` tables",
    },
    TableSpec {
        name: "output",
        form: Form::Single,
        required: false,
        meaning: "optional outputs and their cadences (`--vtk-every`, `--trajectory-every` override them); without it, none",
    },
    TableSpec {
        name: "contact",
        form: Form::Single,
        required: false,
        meaning: "normal contact damping set by a restitution coefficient, and Coulomb friction; without it, contacts are elastic and frictionless",
    },
    TableSpec {
        name: "reference",
        form: Form::Single,
        required: false,
        meaning: "a closed-form solution the scene declares (written to orientation.csv as ref_q*, err_rad)",
    },
    TableSpec {
        name: "guards",
        form: Form::Single,
        required: false,
        meaning: "limits that stop a run early with a named diagnosis",
    },
];

/// What a value must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A finite number > 0.
    Positive,
    /// A finite number.
    Finite,
    /// A finite number ≥ 0.
    NonNegative,
    /// A finite number other than 0.
    NonZero,
    /// Poisson's ratio, in (−1, 0.5).
    Poisson,
    /// An integer ≥ 1.
    Count,
    /// Three finite numbers.
    Vec3,
    /// Three finite numbers, not all zero (normalised by the loader).
    Direction,
    /// Four numbers `[w, x, y, z]` of norm 1 (to 1e-6).
    UnitQuaternion,
    /// Three numbers or expressions in `t`.
    Torque,
    /// One of the rotator names.
    Rotator,
    /// One of the shape names.
    Shape,
    /// One of the closed-form names.
    ClosedForm,
    /// Which bodies `orientation.csv` holds.
    OrientationBodies,
    /// Text.
    Text,
}

impl Kind {
    /// The allowed values, as the reference states them.
    pub fn allowed(self) -> String {
        match self {
            Kind::Positive => "> 0".into(),
            Kind::Finite => "finite".into(),
            Kind::NonNegative => "≥ 0".into(),
            Kind::NonZero => "≠ 0".into(),
            Kind::Poisson => "in (−1, 0.5)".into(),
            Kind::Count => "integer ≥ 1".into(),
            Kind::Vec3 => "[x, y, z]".into(),
            Kind::Direction => "[x, y, z], not zero; any length".into(),
            Kind::UnitQuaternion => "[w, x, y, z], norm 1 (± 1e-6)".into(),
            Kind::Torque => "[x, y, z]: numbers or expressions in t".into(),
            Kind::Rotator => quoted(&rotator_names()),
            Kind::Shape => quoted(SHAPES),
            Kind::ClosedForm => quoted(CLOSED_FORMS),
            Kind::OrientationBodies => quoted(ORIENTATION_BODIES),
            Kind::Text => "text".into(),
        }
    }

    /// The names an enumerated kind allows; empty for the others.
    pub fn names(self) -> Vec<&'static str> {
        match self {
            Kind::Rotator => rotator_names(),
            Kind::Shape => SHAPES.to_vec(),
            Kind::ClosedForm => CLOSED_FORMS.to_vec(),
            Kind::OrientationBodies => ORIENTATION_BODIES.to_vec(),
            _ => vec![],
        }
    }
}

/// `a`, `b`, `c` as the reference writes them.
fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|s| format!("`{s}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The rotators a scenario may name.
fn rotator_names() -> Vec<&'static str> {
    RotatorKind::SELECTABLE.iter().map(|k| k.name()).collect()
}

/// The body shapes (`body.shape`).
pub const SHAPES: &[&str] = &["fibre", "sphere", "rigid"];

/// The closed forms a scene may declare (`reference.closed_form`).
pub const CLOSED_FORMS: &[&str] = &["exp-torque-sphere", "torque-free", "manufactured"];

/// Which bodies `orientation.csv` holds (`output.orientation`): those that
/// need it (a prescribed torque, a closed form), or every body.
pub const ORIENTATION_BODIES: &[&str] = &["needed", "all"];

/// What the pre-check knows about one table instance, for conditional keys.
#[derive(Debug, Clone, Default)]
pub struct Facts {
    /// `body.shape`, when it is text.
    pub shape: Option<String>,
    /// The body names a `material`.
    pub has_material: bool,
    /// Bodies can touch: a `[box]`, or more than one body.
    pub contacts: bool,
    /// A `[material.NAME]` that some body uses.
    pub used: bool,
    /// `reference.closed_form`, when it is text.
    pub closed_form: Option<String>,
}

/// Whether a scene must give a key.
#[derive(Debug, Clone, Copy)]
pub enum Need {
    /// Always.
    Required,
    /// Never; the text says what its absence means.
    Optional(&'static str),
    /// When `when` holds for the table; `text` says when, for the reference.
    When {
        /// The condition, in words ("for fibres").
        text: &'static str,
        /// The condition.
        when: fn(&Facts) -> bool,
    },
}

/// A range of values engineering practice knows, and units a value outside
/// it may have been meant in (the warning names them).
#[derive(Debug, Clone, Copy)]
pub struct Typical {
    /// Lowest typical value, SI.
    pub lo: f64,
    /// Highest typical value, SI.
    pub hi: f64,
    /// What the range spans, in words.
    pub what: &'static str,
    /// Other units a user may have typed the value in: name and its size
    /// in SI as a power of ten (`mm`: -3).
    pub units: &'static [(&'static str, i32)],
}

/// One key of one table.
#[derive(Debug, Clone, Copy)]
pub struct Key {
    /// The table's name ([`TABLES`]).
    pub table: &'static str,
    /// The key.
    pub name: &'static str,
    /// What its value must be.
    pub kind: Kind,
    /// SI unit, empty for none.
    pub unit: &'static str,
    /// Required, optional or conditional.
    pub need: Need,
    /// What it sets.
    pub meaning: &'static str,
    /// A value, as TOML.
    pub example: &'static str,
    /// Typical range (a warning outside it), for sizes and materials.
    pub typical: Option<Typical>,
}

const YOUNG: Typical = Typical {
    lo: 1e5,
    hi: 1.2e12,
    what: "engineering materials, soft foams and rubbers to diamond",
    units: &[("kPa", 3), ("MPa", 6), ("GPa", 9)],
};
const DENSITY: Typical = Typical {
    lo: 10.0,
    hi: 23_000.0,
    what: "solids, from foams to osmium",
    units: &[("g/cm³", 3)],
};
const FIBRE_DIAMETER: Typical = Typical {
    lo: 1e-7,
    hi: 0.1,
    what: "fibres, from nanofibres to 10 cm rods",
    units: &[("mm", -3), ("µm", -6), ("cm", -2)],
};
const FIBRE_LENGTH: Typical = Typical {
    lo: 1e-7,
    hi: 2.0,
    what: "fibres",
    units: &[("mm", -3), ("µm", -6), ("cm", -2)],
};

fn fibre(f: &Facts) -> bool {
    f.shape.as_deref() == Some("fibre")
}
/// Fibres and spheres; also a body whose shape is missing or mistyped (it is
/// reported, and both known shapes need the key).
fn known_shape(f: &Facts) -> bool {
    f.shape
        .as_deref()
        .is_none_or(|s| s != "rigid" && SHAPES.contains(&s))
}
fn rigid(f: &Facts) -> bool {
    f.shape.as_deref() == Some("rigid")
}
fn inline(f: &Facts) -> bool {
    !f.has_material && !rigid(f)
}
fn inline_touching(f: &Facts) -> bool {
    inline(f) && f.contacts
}
fn manufactured(f: &Facts) -> bool {
    f.closed_form.as_deref() == Some("manufactured")
}
fn used_touching(f: &Facts) -> bool {
    f.used && f.contacts
}
fn exp_torque_sphere(f: &Facts) -> bool {
    f.closed_form.as_deref() == Some("exp-torque-sphere")
}

const REQUIRED: Need = Need::Required;

/// Every key, table by table in the order of [`TABLES`]: one line each.
#[rustfmt::skip]
pub const KEYS: &[Key] = &[
    // [simulation]
    Key { table: "simulation", name: "dt", kind: Kind::Positive, unit: "s", need: REQUIRED, meaning: "time step δt", example: "1e-6", typical: None },
    Key { table: "simulation", name: "t_end", kind: Kind::Positive, unit: "s", need: REQUIRED, meaning: "end time: a whole number of steps of dt (t_n = n·δt)", example: "0.1", typical: None },
    Key { table: "simulation", name: "rotator", kind: Kind::Rotator, unit: "", need: Need::Optional("`omelyan`, the most accurate per unit of run time on contact scenes"), meaning: "rotation integrator (`fibresim rotators` describes each); `--rotator` overrides it", example: "\"pcdm\"", typical: None },
    Key { table: "simulation", name: "every", kind: Kind::Count, unit: "steps", need: Need::Optional("at most 2·10⁴ rows"), meaning: "one output row per `every` steps; `--every` overrides it", example: "1000", typical: None },
    // [world]
    Key { table: "world", name: "gravity", kind: Kind::Vec3, unit: "m/s²", need: Need::Optional("no gravity"), meaning: "gravitational acceleration; potential energy is measured from z = 0 along it", example: "[0.0, 0.0, -9.81]", typical: None },
    // [box]
    Key { table: "box", name: "min", kind: Kind::Vec3, unit: "m", need: REQUIRED, meaning: "lower corner", example: "[0.0, 0.0, 0.0]", typical: None },
    Key { table: "box", name: "max", kind: Kind::Vec3, unit: "m", need: REQUIRED, meaning: "upper corner, above `min` on every axis", example: "[1.0, 1.0, 1.0]", typical: None },
    Key { table: "box", name: "young", kind: Kind::Positive, unit: "Pa", need: REQUIRED, meaning: "Young's modulus of the walls", example: "5e7", typical: Some(YOUNG) },
    Key { table: "box", name: "poisson", kind: Kind::Poisson, unit: "", need: REQUIRED, meaning: "Poisson's ratio of the walls", example: "0.23", typical: None },
    // [material.NAME]
    Key { table: "material", name: "density", kind: Kind::Positive, unit: "kg/m³", need: REQUIRED, meaning: "density", example: "1100.0", typical: Some(DENSITY) },
    Key { table: "material", name: "young", kind: Kind::Positive, unit: "Pa", need: Need::When { text: "when a body using it can touch something", when: used_touching }, meaning: "Young's modulus", example: "5e7", typical: Some(YOUNG) },
    Key { table: "material", name: "poisson", kind: Kind::Poisson, unit: "", need: Need::When { text: "when a body using it can touch something", when: used_touching }, meaning: "Poisson's ratio", example: "0.35", typical: None },
    Key { table: "material", name: "friction", kind: Kind::NonNegative, unit: "–", need: Need::Optional("`[contact] friction` (body–body), `wall_friction` (body–wall)"), meaning: "the material's own Coulomb coefficient μ: two bodies use the smaller of their materials' μ, a body and a wall the smaller of its material's μ and `wall_friction` (docs/contacts.md, \"Friction\")", example: "0.4", typical: None },
    // [[body]]
    Key { table: "body", name: "name", kind: Kind::Text, unit: "", need: Need::Optional("`body<index>`"), meaning: "label in messages and in `fibresim check`", example: "\"fibre0\"", typical: None },
    Key { table: "body", name: "shape", kind: Kind::Shape, unit: "", need: REQUIRED, meaning: "`fibre`: solid flat-ended cylinder, axis = body x; `sphere`: solid sphere (touches fibres, spheres and walls); `rigid`: a general rigid body given by `mass` and `inertia`, contact-free scenes only", example: "\"fibre\"", typical: None },
    Key { table: "body", name: "diameter", kind: Kind::Positive, unit: "m", need: Need::When { text: "for fibres and spheres", when: known_shape }, meaning: "diameter D", example: "0.01", typical: Some(FIBRE_DIAMETER) },
    Key { table: "body", name: "length", kind: Kind::Positive, unit: "m", need: Need::When { text: "for fibres (a sphere has none)", when: fibre }, meaning: "length L of a fibre", example: "0.025", typical: Some(FIBRE_LENGTH) },
    Key { table: "body", name: "mass", kind: Kind::Positive, unit: "kg", need: Need::When { text: "for rigid bodies (only)", when: rigid }, meaning: "mass of a `rigid` body", example: "2.0", typical: None },
    Key { table: "body", name: "inertia", kind: Kind::Vec3, unit: "kg m²", need: Need::When { text: "for rigid bodies (only)", when: rigid }, meaning: "principal moments `[I1, I2, I3]` about body x, y, z of a `rigid` body: each > 0, and each at most the sum of the other two", example: "[1.0, 2.0, 3.0]", typical: None },
    Key { table: "body", name: "material", kind: Kind::Text, unit: "", need: Need::Optional("the inline density, young, poisson"), meaning: "name of a `[material.NAME]` table, instead of inline values", example: "\"fibre\"", typical: None },
    Key { table: "body", name: "density", kind: Kind::Positive, unit: "kg/m³", need: Need::When { text: "without `material`", when: inline }, meaning: "density", example: "1100.0", typical: Some(DENSITY) },
    Key { table: "body", name: "young", kind: Kind::Positive, unit: "Pa", need: Need::When { text: "without `material`, when bodies can touch (a box, or two bodies)", when: inline_touching }, meaning: "Young's modulus", example: "5e7", typical: Some(YOUNG) },
    Key { table: "body", name: "poisson", kind: Kind::Poisson, unit: "", need: Need::When { text: "without `material`, when bodies can touch (a box, or two bodies)", when: inline_touching }, meaning: "Poisson's ratio", example: "0.35", typical: None },
    Key { table: "body", name: "position", kind: Kind::Vec3, unit: "m", need: REQUIRED, meaning: "centre of mass, world frame", example: "[0.5, 0.5, 0.5]", typical: None },
    Key { table: "body", name: "axis", kind: Kind::Direction, unit: "", need: Need::Optional("[1, 0, 0]"), meaning: "direction of body x (a fibre's axis) in the world; or give `quaternion`", example: "[0.8660254037844387, 0.0, 0.5]", typical: None },
    Key { table: "body", name: "quaternion", kind: Kind::UnitQuaternion, unit: "", need: Need::Optional("the identity"), meaning: "orientation, body → world, scalar first; instead of `axis`", example: "[1.0, 0.0, 0.0, 0.0]", typical: None },
    Key { table: "body", name: "velocity", kind: Kind::Vec3, unit: "m/s", need: Need::Optional("[0, 0, 0]"), meaning: "velocity of the centre of mass, world frame", example: "[1.0, -1.0, 0.0]", typical: None },
    Key { table: "body", name: "angular_velocity", kind: Kind::Vec3, unit: "rad/s", need: Need::Optional("[0, 0, 0]"), meaning: "angular velocity, world frame", example: "[0.0, 0.0, 10.0]", typical: None },
    Key { table: "body", name: "torque", kind: Kind::Torque, unit: "N·m", need: Need::Optional("none"), meaning: "prescribed torque, world frame: numbers or expressions in t (`+ - * / ^`, `pi`, `e`, `sin cos tan exp ln sqrt abs sinh cosh tanh`)", example: "[\"5e-4*sin(200*pi*t)\", 0.0, 0.0]", typical: None },
    // [reference]
    Key { table: "reference", name: "closed_form", kind: Kind::ClosedForm, unit: "", need: REQUIRED, meaning: "`exp-torque-sphere`: one sphere at rest under τ = A e^{Ct} â turns about â by θ(t) = A (e^{Ct} − 1 − Ct)/(I C²); `torque-free`: the exact torque-free motion of the one body from its start (regular precession, or Jacobi's elliptic functions); `manufactured`: q(t) = exp(φ u/2) q₀ exp(ψ v/2), driven by the torque it implies (the body gives no `torque` and no `angular_velocity`)", example: "\"exp-torque-sphere\"", typical: None },
    Key { table: "reference", name: "axis", kind: Kind::Direction, unit: "", need: Need::When { text: "for exp-torque-sphere", when: exp_torque_sphere }, meaning: "the torque's direction â, world frame", example: "[0.0, 1.0, 0.0]", typical: None },
    Key { table: "reference", name: "a", kind: Kind::Finite, unit: "N·m", need: Need::When { text: "for exp-torque-sphere", when: exp_torque_sphere }, meaning: "A", example: "1e5", typical: None },
    Key { table: "reference", name: "c", kind: Kind::NonZero, unit: "1/s", need: Need::When { text: "for exp-torque-sphere", when: exp_torque_sphere }, meaning: "C", example: "1.0", typical: None },
    Key { table: "reference", name: "precession_axis", kind: Kind::Direction, unit: "", need: Need::When { text: "for manufactured", when: manufactured }, meaning: "the world axis u of φ", example: "[0.0, 0.0, 1.0]", typical: None },
    Key { table: "reference", name: "spin_axis", kind: Kind::Direction, unit: "", need: Need::When { text: "for manufactured", when: manufactured }, meaning: "the body axis v of ψ", example: "[1.0, 0.0, 0.0]", typical: None },
    Key { table: "reference", name: "precession", kind: Kind::Vec3, unit: "", need: Need::When { text: "for manufactured", when: manufactured }, meaning: "`[a, b, c]` of φ(t) = a t + b sin(c t) (rad/s, rad, rad/s)", example: "[2.0, 0.3, 5.0]", typical: None },
    Key { table: "reference", name: "spin", kind: Kind::Vec3, unit: "", need: Need::When { text: "for manufactured", when: manufactured }, meaning: "`[a, b, c]` of ψ(t) = a t + b (1 − cos(c t)) (rad/s, rad, rad/s)", example: "[10.0, 0.5, 3.0]", typical: None },
    // [bodies]
    Key { table: "bodies", name: "file", kind: Kind::Text, unit: "", need: REQUIRED, meaning: "CSV body file, relative to the scenario's folder: `id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material` (SI units, ω in the body frame, floats in shortest round-trip form, `material` a `[material.NAME]`), every row a fibre; with an 18th column `shape` (`fibre` or `sphere`, a sphere's `length` empty) it holds spheres too", example: "\"bed_10k.bodies.csv\"", typical: None },
    // [output]
    Key { table: "output", name: "vtk_every", kind: Kind::Count, unit: "steps", need: Need::Optional("no VTK frames"), meaning: "a VTK frame every N steps: `vtk/fibres_<step>.vtp`, listed with its time in `fibres.pvd` (ParaView), and the box in `box.vtp`", example: "2000", typical: None },
    Key { table: "output", name: "trajectory_every", kind: Kind::Count, unit: "steps", need: Need::Optional("no trajectory"), meaning: "a `trajectory.csv` row per body every N steps: position, quaternion (w, x, y, z), velocity, world angular velocity", example: "1000", typical: None },
    Key { table: "output", name: "orientation", kind: Kind::OrientationBodies, unit: "", need: Need::Optional("`needed`"), meaning: "which bodies `orientation.csv` holds: `needed`, those with a prescribed torque or a closed-form reference (none: no file), or `all`, every body at every output row", example: "\"all\"", typical: None },
    // [contact]
    Key { table: "contact", name: "restitution", kind: Kind::Positive, unit: "–", need: Need::Optional("1 (elastic)"), meaning: "normal restitution e of body–body contacts, in (0, 1]: Tsuji-type Hertzian damping (docs/physics.md), e independent of the impact speed", example: "0.3", typical: None },
    Key { table: "contact", name: "wall_restitution", kind: Kind::Positive, unit: "–", need: Need::Optional("`restitution`"), meaning: "normal restitution of body–wall contacts, in (0, 1]", example: "0.3", typical: None },
    Key { table: "contact", name: "friction", kind: Kind::NonNegative, unit: "–", need: Need::Optional("0 (frictionless)"), meaning: "Coulomb coefficient μ of body–body contacts: a tangential spring (Mindlin's stiffness) capped at μ times the normal force (docs/contacts.md, \"Friction\")", example: "0.3", typical: None },
    Key { table: "contact", name: "wall_friction", kind: Kind::NonNegative, unit: "–", need: Need::Optional("`friction`"), meaning: "Coulomb coefficient μ of body–wall contacts", example: "0.3", typical: None },
    // [guards]
    Key { table: "guards", name: "energy_error_pct", kind: Kind::Positive, unit: "%", need: Need::Optional("10"), meaning: "stop when the full-budget energy error (Eq. 65 with elastic energy) exceeds this; scenes without a prescribed torque", example: "10.0", typical: None },
    Key { table: "guards", name: "overlap_ratio", kind: Kind::Positive, unit: "–", need: Need::Optional("0.2"), meaning: "stop when a contact overlap exceeds this fraction of the smaller diameter of the pair", example: "0.2", typical: None },
    Key { table: "guards", name: "start_overlap_ratio", kind: Kind::Finite, unit: "–", need: Need::Optional("0: no overlap at step 0"), meaning: "largest overlap, as a fraction of the thinner diameter, accepted at step 0 (the resting contacts of a settled bed)", example: "0.01", typical: None },
];

impl Key {
    /// The unit hint for a value `x` of this key outside its typical range:
    /// the range, and, where a common unit would put `x` inside it, how to
    /// write that in SI (`10` m for a fibre's diameter: "if you meant 10 mm
    /// or 10 µm or 10 cm, write 1e-2 or 1e-5 or 1e-1"). `None` inside the
    /// range, and for keys without one.
    pub fn unit_hint(&self, x: f64) -> Option<String> {
        let r = self.typical?;
        if (r.lo..=r.hi).contains(&x) {
            return None;
        }
        let shown = short(x);
        let side = if x < r.lo { "below" } else { "above" };
        let meant: Vec<(&str, f64)> = r
            .units
            .iter()
            // Shifted in decimal, so 10 µm is 1e-5 exactly as typed.
            .map(|&(u, p)| (u, format!("{shown}e{p}").parse::<f64>().unwrap_or(f64::NAN)))
            .filter(|(_, si)| (r.lo..=r.hi).contains(si))
            .collect();
        let fix = if meant.is_empty() {
            format!("check the value; it is read in {}", self.unit)
        } else {
            let said: Vec<String> = meant.iter().map(|(u, _)| format!("{shown} {u}")).collect();
            // Written as a user would type it in the file.
            let write: Vec<String> = meant.iter().map(|(_, si)| format!("{si:e}")).collect();
            format!(
                "if you meant {}, write {} (values are read in {})",
                said.join(" or "),
                write.join(" or "),
                self.unit
            )
        };
        Some(format!(
            "{shown} {unit} is {side} the range of {} ({} to {} {unit}); {fix}",
            r.what,
            short(r.lo),
            short(r.hi),
            unit = self.unit,
        ))
    }
}

/// The keys of table `table`.
pub fn keys_of(table: &str) -> impl Iterator<Item = &'static Key> + '_ {
    KEYS.iter().filter(move |k| k.table == table)
}

/// The key `name` of table `table`.
pub fn key(table: &str, name: &str) -> Option<&'static Key> {
    keys_of(table).find(|k| k.name == name)
}

impl TableSpec {
    /// The table as it is written: `[box]`, `[[body]]`, `[material.NAME]`.
    pub fn header(&self) -> String {
        match self.form {
            Form::Single => format!("[{}]", self.name),
            Form::Array => format!("[[{}]]", self.name),
            Form::Named => format!("[{}.NAME]", self.name),
        }
    }
}

impl Need {
    /// The "required / default" cell of the reference.
    pub fn text(&self) -> String {
        match self {
            Need::Required => "required".into(),
            Need::Optional(d) => format!("default: {d}"),
            Need::When { text, .. } => format!("required {text}"),
        }
    }
}

/// The reference as markdown: one table per scenario table (docs/scenario.md
/// carries it between `<!-- BEGIN keys -->` and `<!-- END keys -->`).
pub fn keys_markdown() -> String {
    let mut s = String::new();
    for t in TABLES {
        s += &format!(
            "\n#### `{}`{}\n\n{}.\n\n",
            t.header(),
            if t.required { " (required)" } else { "" },
            capitalise(t.meaning)
        );
        s += "| key | unit | required / default | allowed | meaning | example |\n";
        s += "|---|---|---|---|---|---|\n";
        for k in keys_of(t.name) {
            let allowed = match k.typical {
                Some(r) => format!(
                    "{}; warns outside {:e} – {:e} ({})",
                    k.kind.allowed(),
                    r.lo,
                    r.hi,
                    r.what
                ),
                None => k.kind.allowed(),
            };
            s += &format!(
                "| `{}` | {} | {} | {} | {} | `{} = {}` |\n",
                k.name,
                if k.unit.is_empty() { "–" } else { k.unit },
                k.need.text(),
                allowed,
                k.meaning,
                k.name,
                k.example
            );
        }
    }
    s
}

/// The reference as plain text, for `fibresim keys`.
pub fn keys_text() -> String {
    let mut s = String::new();
    for t in TABLES {
        s += &format!(
            "{}{}: {}\n",
            t.header(),
            if t.required { " (required)" } else { "" },
            t.meaning
        );
        for k in keys_of(t.name) {
            let unit = if k.unit.is_empty() {
                String::new()
            } else {
                format!(" ({})", k.unit)
            };
            s += &format!(
                "  {:<17} {}{unit}; {}; {}. e.g. {} = {}\n",
                k.name,
                k.meaning,
                k.need.text(),
                k.kind.allowed(),
                k.name,
                k.example
            );
        }
        s += "\n";
    }
    s += "Full reference with examples: docs/scenario.md\n";
    s
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or(String::new(), |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}
