//! `fibresim replicate`: a bed copied `nx × ny × nz` times side by side in a
//! box as many times larger (LAMMPS's `replicate`), written as a scenario
//! and its body file. The copies keep every state bit for bit except the
//! position, which moves by whole box sides. Each copy's walls between copies
//! are gone, so the fibres that leaned on them now lean on the next copy's
//! fibres: the seams overlap (measured, and allowed by the written
//! `guards.start_overlap_ratio`) and are not at rest.

use crate::body::{BodyState, Shape};
use crate::error::{Error, Result};
use crate::integrate::step::World;
use crate::scenario::write::BedScenario;
use crate::scenario::{Ids, Scene, Walls};
use glam::DVec3;
use std::path::PathBuf;

/// What to replicate, checked by the CLI's plan.
#[derive(Debug, Clone)]
pub struct ReplicateOptions {
    /// Copies along x, y and z (each ≥ 1).
    pub times: [usize; 3],
    /// The scenario to write; the body file is `<stem>_bodies.csv` beside it.
    pub out: PathBuf,
    /// The command line, for the scenario's header.
    pub command: String,
}

/// What `fibresim replicate` made.
#[derive(Debug, Clone)]
pub struct ReplicateReport {
    /// What was written (copies × the source's): "20000 fibres", "…
    /// fibres and … spheres".
    pub written: String,
    /// The new box.
    pub walls: Walls,
    /// Touching contacts of the source, and of the replicated bed.
    pub touching: (usize, usize),
    /// Largest overlap ratio δ/D of the replicated bed at its start.
    pub max_overlap_ratio: f64,
    /// The `guards.start_overlap_ratio` written.
    pub start_overlap_ratio: f64,
    /// The scenario written.
    pub scenario: PathBuf,
    /// Its body file.
    pub body_file: PathBuf,
}

/// The bed of `scene` copied `times` over: the box grows to `times` × its
/// sides from its lower corner, copy `(i, j, k)` is moved by `(i, j, k)` box
/// sides, and the bodies of all copies are numbered along the box's
/// space-filling curve ([`super::order`]).
pub fn replicated(scene: &Scene, times: [usize; 3]) -> Result<Scene> {
    let Some(walls) = scene.walls.clone() else {
        return Err(Error::bad(
            &scene.source,
            "box",
            "replicate copies the bed's box side by side; give the scenario a [box]",
        ));
    };
    if scene.has_prescribed_torque() || scene.reference.is_some() {
        return Err(Error::bad(
            &scene.source,
            "body.torque",
            "replicate copies beds; a scene with prescribed torques or a closed-form reference cannot be copied (remove them)",
        ));
    }
    if let Some(i) = scene
        .bodies
        .iter()
        .position(|b| matches!(b.shape, Shape::Rigid { .. }))
    {
        return Err(Error::bad(
            &scene.source,
            "body.shape",
            format!(
                "{} is a rigid body; body files (what replicate writes) hold fibres and spheres only",
                scene.name(i)
            ),
        ));
    }
    let span = walls.max - walls.min;
    let copies = times.iter().product::<usize>();
    let n = scene.bodies.len();
    let mut out = scene.clone();
    out.walls = Some(Walls {
        max: walls.min + span * DVec3::new(times[0] as f64, times[1] as f64, times[2] as f64),
        ..walls.clone()
    });
    out.bodies = scene.bodies.repeat(copies);
    out.initial = Vec::with_capacity(copies * n);
    out.names = vec![];
    for k in 0..times[2] {
        for j in 0..times[1] {
            for i in 0..times[0] {
                let shift = span * DVec3::new(i as f64, j as f64, k as f64);
                out.initial.extend(scene.initial.iter().map(|s| BodyState {
                    x: s.x + shift,
                    ..*s
                }));
            }
        }
    }
    let big = out.walls.as_ref().expect("set above");
    let order = super::order::space_filling_order(&out.initial, big.min, big.max);
    out.bodies = order.iter().map(|&i| out.bodies[i]).collect();
    out.initial = order.iter().map(|&i| out.initial[i]).collect();
    out.ids = Ids::Sequential(out.bodies.len());
    Ok(out)
}

/// Replicate `scene`, measure the seams' overlaps, and write the scenario and
/// its body file.
pub fn replicate(scene: &Scene, o: &ReplicateOptions) -> Result<ReplicateReport> {
    let big = replicated(scene, o.times)?;
    let stats = |s: &Scene| {
        World::new(s)
            .contacts
            .map(|c| (c.stats.touching, c.stats.max_overlap_ratio))
            .unwrap_or((0, 0.0))
    };
    let (touching_source, _) = stats(scene);
    let (touching, max_overlap_ratio) = stats(&big);
    // The loader refuses an overlap deeper than this × D: above every overlap
    // measured here (the copies' own resting contacts, walls included, and
    // the seams'), as `settle` sets it.
    let start_overlap_ratio = if max_overlap_ratio > 0.0 {
        super::settled_start_overlap(max_overlap_ratio)
    } else {
        0.0
    };
    crate::output::create_parent_dir(&o.out, "--out")?;
    let body_file = super::body_file_of(&o.out);
    let material_names: Vec<String> = big.materials.iter().map(|m| m.name.clone()).collect();
    crate::scenario::body_file::write(
        &body_file,
        &big.ids,
        &big.bodies,
        &big.initial,
        &material_names,
    )?;
    let walls = big.walls.expect("replicated beds have a box");
    let [nx, ny, nz] = o.times;
    let census = |bodies: &crate::body::Bodies| {
        let spheres = bodies
            .iter()
            .filter(|b| matches!(b.shape, crate::body::Shape::Sphere { .. }))
            .count();
        crate::fmt::census(bodies.len() - spheres, spheres)
    };
    let copies = nx * ny * nz;
    let (source, result) = (census(&scene.bodies), census(&big.bodies));
    let text = BedScenario {
        comment: vec![
            format!("Replicated by: {}", o.command),
            format!(
                "{copies} copies ({nx} x {ny} x {nz}) of {} ({source}): {result}; touching contacts {} (the source: {} each); largest overlap ratio at the start {:.4}.",
                scene.source,
                touching,
                touching_source,
                max_overlap_ratio
            ),
            "The copies' shared walls are gone: the seams overlap and are not at rest.".into(),
        ],
        dt: scene.sim.dt(),
        t_end: scene.sim.t_end(),
        gravity: scene.gravity,
        walls: Some(&walls),
        materials: &big.materials,
        restitution: scene.damping,
        friction: scene.friction,
        start_overlap_ratio: (start_overlap_ratio > 0.0).then_some(start_overlap_ratio),
        body_file: &body_file
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().into_owned()),
    }
    .to_string();
    std::fs::write(&o.out, text).map_err(|e| Error::io(&o.out, e))?;
    Ok(ReplicateReport {
        written: result,
        walls,
        touching: (touching_source, touching),
        max_overlap_ratio,
        start_overlap_ratio,
        scenario: o.out.clone(),
        body_file,
    })
}
