//! Validate a parsed [`ScenarioFile`] once into a ready-to-run [`Scene`]
//! (ripgrep's "raw args → checked objects"). Only what the scene declares is
//! built: no walls without `[box]`, no gravity without `world.gravity`, no
//! contact search for a single body without walls (docs/physics.md §7).

use super::bodies::{aabb, build_body, Materials};
use super::check::{self, Ctx};
use super::file::ScenarioFile;
use super::reference::build_reference;
use super::scene::{Prescribed, Scene, Walls};
use super::sim::{Guards, SimParams};
use crate::body::Shape;
use crate::error::{Error, Result};
use crate::fmt::{short, short3};
use crate::integrate::rotate::RotatorKind;
use std::path::Path;

/// Read and validate a scenario file.
pub fn load(path: &Path) -> Result<Scene> {
    load_with_warnings(path).map(|(scene, _)| scene)
}

/// [`load`], with the pre-check's warnings (values outside the range of
/// engineering practice, each naming the file, line, key and the unit it
/// may have been meant in) for the caller to print.
pub fn load_with_warnings(path: &Path) -> Result<(Scene, Vec<String>)> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        Error::bad(
            &file,
            "<SCENARIO>",
            format!("cannot read the scenario file: {e}; give the path of a scenario TOML file (examples in scenarios/)"),
        )
    })?;
    parse_with_warnings(&text, &file)
}

/// Parse and validate scenario text; `source` names it in error messages.
pub fn parse_str(text: &str, source: &str) -> Result<Scene> {
    parse_with_warnings(text, source).map(|(scene, _)| scene)
}

/// [`parse_str`], with the pre-check's warnings (see [`load_with_warnings`]).
pub fn parse_with_warnings(text: &str, source: &str) -> Result<(Scene, Vec<String>)> {
    // Every problem the key table can judge, in one message, before serde
    // (which stops at the first); its warnings join any error that follows,
    // since a value in the wrong unit is often the cause.
    let warnings = super::precheck::precheck(text, source)?;
    let built = toml::from_str::<ScenarioFile>(text)
        .map_err(|e| serde_error(&e, text, source))
        .and_then(|raw| build(raw, source).map_err(|e| e.located(source, text)));
    match built {
        Ok(mut scene) => {
            scene.text = text.to_string();
            Ok((scene, warnings.into_iter().map(|w| w.shown).collect()))
        }
        Err(e) => Err(super::precheck::with_warnings(e, &warnings)),
    }
}

/// What serde refuses after the pre-check passed it (a key in the serde
/// mirror the key table lacks), in the one style of bad-input messages.
fn serde_error(e: &toml::de::Error, text: &str, source: &str) -> Error {
    Error::BadInput {
        file: source.to_string(),
        line: e.span().map(|s| super::locate::line_col(text, s.start)),
        key: "TOML".into(),
        message: e.message().trim_end().replace('\n', "; "),
    }
}

fn build(raw: ScenarioFile, src: &str) -> Result<Scene> {
    let cx = Ctx { src };
    let s = &raw.simulation;
    let rotator = match &s.rotator {
        None => RotatorKind::DEFAULT,
        Some(name) => RotatorKind::from_name(name)
            .ok_or_else(|| cx.err("simulation.rotator", check::unknown_rotator(name)))?,
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
                    format!(
                        "box.min {} must be below box.max {} on every axis",
                        short3(min),
                        short3(max)
                    ),
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

    let has_file = raw.bodies.is_some();
    if raw.body.is_empty() && !has_file {
        return Err(cx.err("body", check::NO_BODIES));
    }
    let needs_contacts = walls.is_some() || raw.body.len() > 1 || has_file;
    let mut bodies = crate::body::Bodies::new();
    let mut names = Vec::with_capacity(raw.body.len());
    let mut initial = Vec::with_capacity(raw.body.len());
    let mut torques = vec![];
    for (name, m) in &raw.material {
        if let Some(mu) = m.friction {
            cx.non_negative(&format!("material.{name}.friction"), mu)?;
        }
    }
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
    let mut ids: Vec<u64> = (0..bodies.len() as u64).collect();
    // Bodies of a body file follow the [[body]] ones; they carry no name
    // (`body{id}` in messages) and report errors at their file's line.
    let mut file_lines: Vec<u32> = vec![];
    let mut body_file = String::new();
    if let Some(f) = &raw.bodies {
        let path = body_file_path(src, &f.file);
        body_file = path.display().to_string();
        let read = super::body_file::read(
            &path,
            &body_file,
            &raw.material,
            &cx,
            ids.len() as u64,
            &mut materials,
        )?;
        if bodies.is_empty() {
            bodies = read.bodies;
        } else {
            bodies.extend(read.bodies.iter().copied());
        }
        initial.extend(read.initial);
        ids.extend(read.ids);
        file_lines = read.lines;
        if bodies.is_empty() {
            return Err(Error::BadInput {
                file: body_file,
                line: Some((read.header_line, 1)),
                key: "header".into(),
                message: "the body file has no rows after its header, and the scene no [[body]]; add a row per body".into(),
            });
        }
    }
    let toml_count = names.len();
    // Where body i was given: its [[body]] key, or its body file's row.
    let at = |i: usize, key: &str, col: usize, msg: String| -> Error {
        if i < toml_count {
            cx.err(&format!("body[{i}].{key}"), msg)
        } else {
            Error::BadInput {
                file: body_file.clone(),
                line: Some((file_lines[i - toml_count] as usize, col)),
                key: super::body_file::COLUMNS[col - 1].to_string(),
                message: msg,
            }
        }
    };
    let label = |i: usize| -> String {
        match names.get(i) {
            Some(n) => format!("body[{i}] `{n}`"),
            None => format!("body {}", ids[i]),
        }
    };

    let start_overlap = match raw.guards.start_overlap_ratio {
        Some(v) if v.is_finite() && v >= 0.0 => v,
        Some(v) => {
            return Err(cx.err(
                "guards.start_overlap_ratio",
                format!(
                    "must be a finite number >= 0, got {}; give e.g. 0.01",
                    short(v)
                ),
            ))
        }
        None => 0.0,
    };

    if let Some(w) = &walls {
        for (i, (b, st)) in bodies.iter().zip(&initial).enumerate() {
            // A box pokes past a wall by the fibre's depth into it: the
            // resting wall contacts a settled bed may keep (the overlap
            // check below bounds them exactly).
            let (lo, hi) = aabb(&b.shape, st);
            let allow = glam::DVec3::splat(start_overlap * b.shape.diameter());
            if lo.cmplt(w.min - allow).any() || hi.cmpgt(w.max + allow).any() {
                return Err(at(
                    i,
                    "position",
                    2,
                    format!(
                        "{} (bounds {} .. {}) does not fit inside the box {} .. {}; move it inside{}",
                        label(i),
                        short3(lo),
                        short3(hi),
                        short3(w.min),
                        short3(w.max),
                        size_hint(&b.shape)
                    ),
                ));
            }
        }
    }

    if needs_contacts {
        if let Some((i, other, overlap)) = crate::contact::overlap_check::first_overlap(
            &bodies,
            &initial,
            walls.as_ref(),
            start_overlap,
        ) {
            let with = match other {
                Some(j) => label(j),
                None => "a wall".to_string(),
            };
            let allowed = if start_overlap > 0.0 {
                format!(
                    " (more than guards.start_overlap_ratio = {} of the diameter)",
                    short(start_overlap)
                )
            } else {
                String::new()
            };
            return Err(at(
                i,
                "position",
                2,
                format!(
                    "{} overlaps {with} by {} m at the start{allowed}; move the bodies apart{}",
                    label(i),
                    short(overlap),
                    size_hint(&bodies[i].shape)
                ),
            ));
        }
    }

    let reference = match &raw.reference {
        Some(r) => Some(build_reference(
            &cx,
            r,
            &bodies,
            &mut initial,
            &mut torques,
            needs_contacts,
        )?),
        None => None,
    };

    let mut guards = Guards::default();
    if let Some(v) = raw.guards.energy_error_pct {
        guards.energy_error_pct = cx.positive("guards.energy_error_pct", v)?;
    }
    if let Some(v) = raw.guards.overlap_ratio {
        guards.overlap_ratio = cx.positive("guards.overlap_ratio", v)?;
    }

    let damping = match &raw.contact {
        Some(c) => restitution(&cx, c)?,
        None => None,
    };
    let friction = friction(&cx, raw.contact.as_ref(), &materials.table)?;

    bodies.shrink_to_fit();
    Ok(Scene {
        damping,
        friction,
        output: super::output::build_output(src, raw.output.as_ref())?,
        guards,
        source: src.to_string(),
        text: String::new(),
        sim,
        ids: ids.into(),
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

/// `, or check its size: ...` with the unit hint of a fibre whose diameter
/// or length lies outside the range of fibres (a size in mm makes a fibre
/// that fits no box); nothing for a plausible size.
fn size_hint(shape: &Shape) -> String {
    let Shape::Fibre { diameter, length } = *shape else {
        return String::new();
    };
    let hints: Vec<String> = [("diameter", diameter), ("length", length)]
        .into_iter()
        .filter_map(|(k, x)| {
            super::keys::key("body", k)?
                .unit_hint(x)
                .map(|h| format!("{k} {h}"))
        })
        .collect();
    if hints.is_empty() {
        String::new()
    } else {
        format!(", or check its size: {}", hints.join("; "))
    }
}

/// The body file `file` of the scenario `src`: relative to the scenario's
/// folder (to the working folder for a scenario without one).
fn body_file_path(src: &str, file: &str) -> std::path::PathBuf {
    let f = Path::new(file);
    match Path::new(src).parent() {
        Some(dir) if f.is_relative() && !src.starts_with('<') => dir.join(f),
        _ => f.to_path_buf(),
    }
}

/// The checked `[contact]` table; `None` when both coefficients are 1
/// (elastic), so such a scene runs exactly as one without the table.
fn restitution(
    cx: &Ctx,
    c: &super::file::ContactSection,
) -> Result<Option<crate::contact::damping::Restitution>> {
    let check = |key: &str, e: f64| -> Result<f64> {
        if e.is_finite() && e > 0.0 && e <= 1.0 {
            Ok(e)
        } else {
            Err(cx.err(
                key,
                format!("a coefficient of restitution must lie in (0, 1], got {}; give e.g. 0.3 (1 is elastic)", short(e)),
            ))
        }
    };
    let fibre = match c.restitution {
        Some(e) => check("contact.restitution", e)?,
        None => 1.0,
    };
    let wall = match c.wall_restitution {
        Some(e) => check("contact.wall_restitution", e)?,
        None => fibre,
    };
    Ok((fibre < 1.0 || wall < 1.0).then_some(crate::contact::damping::Restitution { fibre, wall }))
}

/// The checked Coulomb coefficients of `[contact]`, the defaults of the
/// `materials` the bodies use; `None` when they and every material's own
/// coefficient are 0 (frictionless), so such a scene runs exactly as one
/// without the keys.
fn friction(
    cx: &Ctx,
    c: Option<&super::file::ContactSection>,
    materials: &[crate::body::Material],
) -> Result<Option<crate::contact::tangential::Friction>> {
    let body = match c.and_then(|c| c.friction) {
        Some(mu) => cx.non_negative("contact.friction", mu)?,
        None => 0.0,
    };
    let wall = match c.and_then(|c| c.wall_friction) {
        Some(mu) => cx.non_negative("contact.wall_friction", mu)?,
        None => body,
    };
    let own = materials
        .iter()
        .any(|m| m.friction.is_some_and(|mu| mu > 0.0));
    Ok((body > 0.0 || wall > 0.0 || own)
        .then_some(crate::contact::tangential::Friction { body, wall }))
}
