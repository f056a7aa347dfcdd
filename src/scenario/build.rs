//! Validate a parsed [`ScenarioFile`] once into a ready-to-run [`Scene`]
//! (ripgrep's "raw args → checked objects"). Only what the scene declares is
//! built: no walls without `[box]`, no gravity without `world.gravity`, no
//! contact search for a single body without walls (SPEC §7).

use super::file::{BodySection, ReferenceSection, ScenarioFile, ShapeName};
use crate::body::{Body, BodyState, Material, MaterialId, RotState, Shape};
use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::torque::PrescribedTorque;
use glam::{DQuat, DVec3};
use std::path::Path;

/// Bodies (any point of them) must move slower than this, m/s.
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;

/// Numerical parameters of a run, checked: made only by [`SimParams::new`]
/// or [`SimParams::with_steps`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimParams {
    dt: f64,
    steps: u64,
    rotator: RotatorKind,
    every: Option<u64>,
}

impl SimParams {
    /// Check `dt`, `t_end` and `every`; `prefix` names where they came from in
    /// messages (`"simulation."` for the file, `"--"` for flags).
    pub fn new(
        dt: f64,
        t_end: f64,
        rotator: RotatorKind,
        every: Option<u64>,
        src: &str,
        prefix: &str,
    ) -> Result<Self> {
        let cx = Ctx { src };
        let dt = cx.positive(&format!("{prefix}dt"), dt)?;
        // Flags are spelled with a hyphen, file keys with an underscore.
        let key_t = if prefix == "--" {
            "--t-end".to_string()
        } else {
            format!("{prefix}t_end")
        };
        let t_end = cx.positive(&key_t, t_end)?;
        if dt > t_end {
            return Err(cx.err(
                &format!("{prefix}dt"),
                format!("dt = {dt:e} s is larger than t_end = {t_end:e} s; choose dt <= t_end"),
            ));
        }
        let ratio = t_end / dt;
        let steps = ratio.round();
        if (ratio - steps).abs() > 1e-6 * ratio.max(1.0) {
            return Err(cx.err(
                &key_t,
                format!("t_end = {t_end:e} s is not a whole number of steps of dt = {dt:e} s ({ratio} steps); adjust one of them"),
            ));
        }
        if steps > 1e12 {
            return Err(cx.err(
                &key_t,
                format!(
                    "{steps:e} steps is more than fibresim will run; increase dt or reduce t_end"
                ),
            ));
        }
        if every == Some(0) {
            return Err(cx.err(
                &format!("{prefix}every"),
                "must be >= 1 (one output row per `every` steps)",
            ));
        }
        Ok(SimParams {
            dt,
            steps: steps as u64,
            rotator,
            every,
        })
    }

    /// `steps` steps of `dt` (the studies' sweeps, which round a t_end up
    /// to whole steps themselves).
    pub fn with_steps(
        dt: f64,
        steps: u64,
        rotator: RotatorKind,
        every: Option<u64>,
    ) -> Result<Self> {
        if !(dt.is_finite() && dt > 0.0) || steps == 0 || every == Some(0) {
            return Err(Error::bad(
                "parameters",
                "dt",
                format!(
                    "need dt > 0, at least one step and every >= 1 (dt = {dt:e}, {steps} steps)"
                ),
            ));
        }
        Ok(SimParams {
            dt,
            steps,
            rotator,
            every,
        })
    }

    /// The same parameters with another rotator.
    pub fn with_rotator(&self, rotator: RotatorKind) -> Self {
        SimParams {
            rotator,
            ..self.clone()
        }
    }

    /// Time step δt, s.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Steps to run.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    pub fn rotator(&self) -> RotatorKind {
        self.rotator
    }

    /// Output cadence as given; `None` = the default.
    pub fn every(&self) -> Option<u64> {
        self.every
    }

    /// Output cadence: as given, else at most 2e4 rows
    /// ([`crate::output::default_every`]).
    pub fn every_or_default(&self) -> u64 {
        self.every
            .unwrap_or_else(|| crate::output::default_every(self.steps))
    }

    pub fn t_end(&self) -> f64 {
        self.steps as f64 * self.dt
    }
}

/// Limits that stop a run early with a named diagnosis (SPEC §8).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Guards {
    /// Largest full-budget energy error (Eq. 65 with the elastic term), percent.
    /// Default 10 %: far above any trustworthy run (the paper's worst is ~2 %),
    /// low enough to stop a blow-up within a few steps of its start.
    pub energy_error_pct: f64,
    /// Largest overlap as a fraction of the fibre diameter. Default 0.2: Hertz
    /// theory assumes small strains; beyond δ = D/5 the contact model is fiction.
    pub overlap_ratio: f64,
}

impl Default for Guards {
    fn default() -> Self {
        Guards {
            energy_error_pct: 10.0,
            overlap_ratio: 0.2,
        }
    }
}

/// The six walls of an axis-aligned box (defined with the contacts).
pub use crate::contact::Walls;

/// A closed-form orientation the scene declares (see `file::ReferenceSection`).
#[derive(Debug, Clone, PartialEq)]
pub enum ClosedForm {
    /// Sphere of inertia `i` at rest under `τ = A e^{Ct} â`.
    ExpTorqueSphere {
        axis: DVec3,
        a: f64,
        c: f64,
        inertia: f64,
    },
}

impl ClosedForm {
    /// Reference orientation at time `t` (body 0).
    pub fn orientation(&self, t: f64, q0: DQuat) -> DQuat {
        match *self {
            ClosedForm::ExpTorqueSphere {
                axis,
                a,
                c,
                inertia,
            } => {
                let theta = a * ((c * t).exp() - 1.0 - c * t) / (inertia * c * c);
                DQuat::from_axis_angle(axis, theta) * q0
            }
        }
    }
}

/// A prescribed world torque on one body.
#[derive(Debug, Clone)]
pub struct Prescribed {
    /// Storage index of the body.
    pub body: usize,
    pub torque: PrescribedTorque,
}

/// A checked scene, ready to run.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Where it came from (a path, or `<built-in>`), for messages.
    pub source: String,
    /// The scenario text as read (embedded in checkpoints).
    pub text: String,
    pub sim: SimParams,
    /// Per-body constants, by storage index.
    pub bodies: Vec<Body>,
    /// Stable global id of each body (the `body` column of the outputs,
    /// diagnoses, checkpoints), by storage index.
    pub ids: Vec<u64>,
    /// Each body's `name`, by storage index.
    pub names: Vec<String>,
    pub materials: Vec<Material>,
    pub initial: Vec<BodyState>,
    /// Prescribed torques, sparse, in storage order of their bodies.
    pub torques: Vec<Prescribed>,
    pub gravity: Option<DVec3>,
    pub walls: Option<Walls>,
    pub reference: Option<ClosedForm>,
    pub guards: Guards,
}

impl Scene {
    /// Contacts are needed when bodies can touch something: walls or each other.
    pub fn needs_contacts(&self) -> bool {
        self.walls.is_some() || self.bodies.len() > 1
    }

    pub fn has_prescribed_torque(&self) -> bool {
        !self.torques.is_empty()
    }

    /// The material of body `i`.
    pub fn material(&self, i: usize) -> &Material {
        &self.materials[self.bodies[i].material as usize]
    }
}

/// Read and validate a scenario file.
pub fn load(path: &Path) -> Result<Scene> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        Error::bad(
            &file,
            "<SCENARIO>",
            format!("cannot read the scenario file: {e}; give the path of a scenario TOML file (examples in scenarios/)"),
        )
    })?;
    parse_str(&text, &file)
}

/// Parse and validate scenario text; `source` names it in error messages.
pub fn parse_str(text: &str, source: &str) -> Result<Scene> {
    let raw: ScenarioFile = toml::from_str(text).map_err(|e| {
        // toml's message carries the line, column and offending key.
        let msg = e.to_string();
        let msg = msg.trim_end().replace('\n', "\n  ");
        Error::bad(source, "TOML", msg)
    })?;
    let mut scene = build(raw, source).map_err(|e| e.located(text))?;
    scene.text = text.to_string();
    Ok(scene)
}

struct Ctx<'a> {
    src: &'a str,
}

impl Ctx<'_> {
    fn err(&self, key: &str, msg: impl Into<String>) -> Error {
        Error::bad(self.src, key, msg)
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("must be a finite number > 0, got {v}; give a positive value"),
            ))
        }
    }

    fn finite3(&self, key: &str, v: [f64; 3]) -> Result<DVec3> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(DVec3::from_array(v))
        } else {
            Err(self.err(
                key,
                format!(
                    "must be three finite numbers, got {v:?}; give [x, y, z] with finite entries"
                ),
            ))
        }
    }

    fn poisson(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > -1.0 && v < 0.5 {
            Ok(v)
        } else {
            Err(self.err(
                key,
                format!("Poisson's ratio must lie in (-1, 0.5), got {v}; give e.g. 0.3"),
            ))
        }
    }
}

fn build(raw: ScenarioFile, src: &str) -> Result<Scene> {
    let cx = Ctx { src };
    let s = &raw.simulation;
    let rotator = match &s.rotator {
        None => RotatorKind::Pcdm,
        Some(name) => RotatorKind::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = RotatorKind::ALL.iter().map(|k| k.name()).collect();
            cx.err(
                "simulation.rotator",
                format!(
                    "unknown rotator `{name}`; choose one of {}",
                    names.join(", ")
                ),
            )
        })?,
    };
    let sim = SimParams::new(s.dt, s.t_end, rotator, s.every, src, "simulation.")?;
    let gravity = match raw.world.gravity {
        Some(g) => Some(cx.finite3("world.gravity", g)?),
        None => None,
    };
    let walls = match &raw.walls {
        Some(b) => {
            let min = cx.finite3("box.min", b.min)?;
            let max = cx.finite3("box.max", b.max)?;
            if !(min.cmplt(max).all()) {
                return Err(cx.err(
                    "box",
                    format!("box.min {min} must be below box.max {max} on every axis"),
                ));
            }
            Some(Walls {
                min,
                max,
                young: cx.positive("box.young", b.young)?,
                poisson: cx.poisson("box.poisson", b.poisson)?,
            })
        }
        None => None,
    };

    if raw.body.is_empty() {
        return Err(cx.err(
            "body",
            "the scene has no bodies; add at least one [[body]] table",
        ));
    }
    let needs_contacts = walls.is_some() || raw.body.len() > 1;
    let mut bodies = Vec::with_capacity(raw.body.len());
    let mut names = Vec::with_capacity(raw.body.len());
    let mut initial = Vec::with_capacity(raw.body.len());
    let mut torques = vec![];
    let mut materials = Materials::default();
    for (i, b) in raw.body.iter().enumerate() {
        let (body, state, torque) = build_body(&cx, &raw, i, b, needs_contacts, &mut materials)?;
        bodies.push(body);
        names.push(b.name.clone().unwrap_or_else(|| format!("body{i}")));
        initial.push(state);
        if let Some(torque) = torque {
            torques.push(Prescribed { body: i, torque });
        }
    }

    if let Some(w) = &walls {
        for (i, (b, st)) in bodies.iter().zip(&initial).enumerate() {
            let (lo, hi) = aabb(&b.shape, st);
            if lo.cmplt(w.min).any() || hi.cmpgt(w.max).any() {
                return Err(cx.err(
                    &format!("body[{i}].position"),
                    format!(
                        "body `{}` (bounds {lo} .. {hi}) does not fit inside the box {} .. {}; move it inside",
                        names[i], w.min, w.max
                    ),
                ));
            }
        }
    }

    if needs_contacts {
        if let Some((i, other, overlap)) = crate::contact::stage::first_overlap(
            &bodies,
            &initial,
            &materials.table,
            walls.as_ref(),
        ) {
            let with = match other {
                Some(j) => format!("body[{j}] `{}`", names[j]),
                None => "a wall".to_string(),
            };
            return Err(cx.err(
                &format!("body[{i}].position"),
                format!(
                    "body `{}` overlaps {with} by {overlap:e} m at the start; move the bodies apart",
                    names[i]
                ),
            ));
        }
    }

    let reference = match &raw.reference {
        Some(r) => Some(build_reference(&cx, r, &bodies, &initial, &torques)?),
        None => None,
    };

    let mut guards = Guards::default();
    if let Some(v) = raw.guards.energy_error_pct {
        guards.energy_error_pct = cx.positive("guards.energy_error_pct", v)?;
    }
    if let Some(v) = raw.guards.overlap_ratio {
        guards.overlap_ratio = cx.positive("guards.overlap_ratio", v)?;
    }

    Ok(Scene {
        guards,
        source: src.to_string(),
        text: String::new(),
        sim,
        ids: (0..bodies.len() as u64).collect(),
        bodies,
        names,
        materials: materials.table,
        initial,
        torques,
        gravity,
        walls,
        reference,
    })
}

/// Euclidean norm without overflow for huge components (1e300).
fn norm(v: DVec3) -> f64 {
    let s = v.abs().max_element();
    if s > 0.0 && s.is_finite() {
        s * (v / s).length()
    } else {
        s
    }
}

/// Exact axis-aligned bounds of a body ([`crate::contact::aabb`]).
pub fn aabb(shape: &Shape, st: &BodyState) -> (DVec3, DVec3) {
    crate::contact::aabb(shape, st.x, st.rot.q * DVec3::X)
}

fn build_body(
    cx: &Ctx,
    raw: &ScenarioFile,
    i: usize,
    b: &BodySection,
    needs_contacts: bool,
    materials: &mut Materials,
) -> Result<(Body, BodyState, Option<PrescribedTorque>)> {
    let key = |k: &str| format!("body[{i}].{k}");
    let diameter = cx.positive(&key("diameter"), b.diameter)?;
    let shape = match (b.shape, b.length) {
        (ShapeName::Fibre, Some(l)) => Shape::Fibre {
            diameter,
            length: cx.positive(&key("length"), l)?,
        },
        (ShapeName::Fibre, None) => {
            return Err(cx.err(&key("length"), "a fibre needs `length` (m)"))
        }
        (ShapeName::Sphere, None) => Shape::Sphere { diameter },
        (ShapeName::Sphere, Some(_)) => {
            return Err(cx.err(
                &key("length"),
                "a sphere has no `length`; remove it or use shape = \"fibre\"",
            ))
        }
    };
    if needs_contacts && matches!(shape, Shape::Sphere { .. }) {
        return Err(cx.err(
            &key("shape"),
            "spheres are supported only in contact-free scenes (one body, no [box]); use fibres",
        ));
    }

    // Material: a named table or inline values, not both. Messages name
    // where the value was given.
    let mkey = |k: &str| match &b.material {
        Some(m) => format!("material.{m}.{k}"),
        None => key(k),
    };
    let (density, young, poisson) = match &b.material {
        Some(m) => {
            if b.density.is_some() || b.young.is_some() || b.poisson.is_some() {
                return Err(cx.err(
                    &key("material"),
                    "give either `material` or inline density/young/poisson, not both",
                ));
            }
            let mat = raw.material.get(m).ok_or_else(|| {
                let known: Vec<&String> = raw.material.keys().collect();
                cx.err(
                    &key("material"),
                    format!("unknown material `{m}`; defined: {known:?}"),
                )
            })?;
            (mat.density, mat.young, mat.poisson)
        }
        None => (
            b.density
                .ok_or_else(|| cx.err(&key("density"), "give `density` (kg/m^3) or `material`"))?,
            b.young,
            b.poisson,
        ),
    };
    let density = cx.positive(&mkey("density"), density)?;
    let (young, poisson) = if needs_contacts {
        let e = young.ok_or_else(|| {
            cx.err(
                &mkey("young"),
                "bodies that can touch need Young's modulus `young` (Pa)",
            )
        })?;
        let nu = poisson.ok_or_else(|| {
            cx.err(
                &mkey("poisson"),
                "bodies that can touch need Poisson's ratio `poisson`",
            )
        })?;
        (
            cx.positive(&mkey("young"), e)?,
            cx.poisson(&mkey("poisson"), nu)?,
        )
    } else {
        (young.unwrap_or(f64::NAN), poisson.unwrap_or(f64::NAN))
    };

    let q = match (b.axis, b.quaternion) {
        (Some(_), Some(_)) => {
            return Err(cx.err(&key("axis"), "give either `axis` or `quaternion`, not both"))
        }
        (Some(a), None) => {
            let a = cx.finite3(&key("axis"), a)?;
            if a.length() < 1e-12 {
                return Err(cx.err(&key("axis"), "the axis direction must be non-zero"));
            }
            DQuat::from_rotation_arc(DVec3::X, a.normalize())
        }
        (None, Some(c)) => {
            let q = crate::math::quat_wxyz(c);
            let n = q.length();
            if !n.is_finite() || (n - 1.0).abs() > 1e-6 {
                return Err(cx.err(
                    &key("quaternion"),
                    format!("must be a unit quaternion [w, x, y, z] (norm {n}); normalise it"),
                ));
            }
            // Only input rounding (< 1e-6) is removed here.
            q.normalize()
        }
        (None, None) => DQuat::IDENTITY,
    };
    let x = cx.finite3(&key("position"), b.position)?;
    let v = cx.finite3(&key("velocity"), b.velocity)?;
    let omega_w = cx.finite3(&key("angular_velocity"), b.angular_velocity)?;
    // Newtonian mechanics: a point of the body at or above the speed of light
    // is not physical (and its energy may overflow, defeating the dt advice).
    let rim = norm(omega_w) * shape.bounding_radius();
    for (k, speed, what) in [
        ("velocity", norm(v), "speed"),
        (
            "angular_velocity",
            rim,
            "rim speed |omega| x bounding radius",
        ),
    ] {
        if speed >= SPEED_OF_LIGHT {
            return Err(cx.err(
                &key(k),
                format!("{what} {speed:e} m/s is not physical (at or above the speed of light, 3e8 m/s; fibresim is Newtonian); give a speed far below it"),
            ));
        }
    }
    let torque = match &b.torque {
        Some(t) => {
            let texts = [t[0].text(), t[1].text(), t[2].text()];
            Some(
                PrescribedTorque::parse(&texts)
                    .map_err(|(c, msg)| cx.err(&key(&format!("torque[{c}]")), msg))?,
            )
        }
        None => None,
    };
    let material = materials.intern(b.material.as_deref(), density, young, poisson);
    let body = Body::new(shape, material, density);
    let state = BodyState {
        x,
        v,
        rot: RotState {
            q,
            omega_b: q.conjugate() * omega_w,
        },
    };
    Ok((body, state, torque))
}

/// The scene's material table: named `[material.NAME]` tables in the order
/// bodies first use them, and inline values, one entry per distinct set.
#[derive(Default)]
struct Materials {
    table: Vec<Material>,
}

impl Materials {
    fn intern(&mut self, name: Option<&str>, density: f64, young: f64, poisson: f64) -> MaterialId {
        let same = |m: &Material| match name {
            Some(n) => m.name == n,
            None => {
                m.name.starts_with("inline-")
                    && [m.density, m.young, m.poisson].map(f64::to_bits)
                        == [density, young, poisson].map(f64::to_bits)
            }
        };
        if let Some(k) = self.table.iter().position(same) {
            return k as MaterialId;
        }
        let inline = self
            .table
            .iter()
            .filter(|m| m.name.starts_with("inline-"))
            .count();
        self.table.push(Material {
            name: name.map_or_else(|| format!("inline-{inline}"), str::to_string),
            density,
            young,
            poisson,
        });
        (self.table.len() - 1) as MaterialId
    }
}

fn build_reference(
    cx: &Ctx,
    r: &ReferenceSection,
    bodies: &[Body],
    initial: &[BodyState],
    torques: &[Prescribed],
) -> Result<ClosedForm> {
    if r.closed_form != "exp-torque-sphere" {
        return Err(cx.err(
            "reference.closed_form",
            format!(
                "unknown closed form `{}`; known: exp-torque-sphere",
                r.closed_form
            ),
        ));
    }
    let axis = cx.finite3("reference.axis", r.axis)?;
    if axis.length() < 1e-12 || !r.a.is_finite() || !r.c.is_finite() || r.c == 0.0 {
        return Err(cx.err(
            "reference",
            "needs a non-zero axis, finite a and a non-zero finite c",
        ));
    }
    let axis = axis.normalize();
    let ok_body = bodies.len() == 1
        && matches!(bodies[0].shape, Shape::Sphere { .. })
        && initial[0].rot.omega_b == DVec3::ZERO;
    if !ok_body {
        return Err(cx.err(
            "reference",
            "exp-torque-sphere needs exactly one sphere, initially at rest",
        ));
    }
    // The declared closed form must describe the declared torque: check it.
    let torque = torques.first().map(|p| &p.torque).ok_or_else(|| {
        cx.err(
            "reference",
            "exp-torque-sphere needs a prescribed torque on the sphere",
        )
    })?;
    for t in [0.0, 0.37, 1.0] {
        let want = r.a * (r.c * t).exp() * axis;
        let got = torque.at(t);
        if (got - want).length() > 1e-9 * want.length().max(1e-300) {
            return Err(cx.err(
                "reference",
                format!(
                    "the body's torque at t = {t} is {got}, but the closed form assumes {want}"
                ),
            ));
        }
    }
    Ok(ClosedForm::ExpTorqueSphere {
        axis,
        a: r.a,
        c: r.c,
        inertia: bodies[0].inertia.principal.x,
    })
}
