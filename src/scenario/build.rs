//! Validate a parsed [`ScenarioFile`] once into a ready-to-run [`Scene`]
//! (ripgrep's "raw args → checked objects"). Only what the scene declares is
//! built: no walls without `[box]`, no gravity without `world.gravity`, no
//! contact search for a single body without walls (docs/physics.md §7).

use super::bodies::{aabb, build_body, Materials};
use super::check::Ctx;
use super::file::ScenarioFile;
use super::reference::build_reference;
use super::scene::{Prescribed, Scene, Walls};
use super::sim::{Guards, SimParams};
use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use std::path::Path;

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
        if let Some((i, other, overlap)) =
            crate::contact::stage::first_overlap(&bodies, &initial, walls.as_ref())
        {
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
        output: super::output::build_output(src, raw.output.as_ref())?,
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
