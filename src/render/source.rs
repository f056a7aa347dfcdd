//! The inputs `render` reads, each turned into [`Frame`]s: a VTK frame or
//! collection, a trajectory (with its scenario for the fibre sizes), a
//! checkpoint (which embeds its scenario) or a scenario's start.

use super::frame::{Fibre, Frame};
use crate::error::{Error, Result};
use crate::output::vtk::read::{read_pvd, read_vtp, Vtp};
use crate::output::Checkpoint;
use crate::scenario::{self, Scene};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// Where the frames come from; frames are read one at a time.
pub enum Source {
    /// VTK frames (one file, or a `.pvd`'s list), with the box outline.
    Vtk {
        /// Each frame's file.
        frames: Vec<PathBuf>,
        /// The box, from `box.vtp` beside the collection.
        walls: Option<(DVec3, DVec3)>,
    },
    /// Frames already in memory (trajectory, checkpoint, scenario).
    Memory(Vec<Frame>),
}

fn bad(path: &Path, msg: impl Into<String>) -> Error {
    Error::bad(path.display().to_string(), "<INPUT>", msg)
}

impl Source {
    /// Open `input` (by its extension); `scenario` gives a trajectory's
    /// fibre sizes; `step` picks one step of a series (for a still).
    pub fn open(input: &Path, scenario: Option<&Path>) -> Result<Source> {
        let ext = input.extension().and_then(|e| e.to_str()).unwrap_or("");
        let name = input.file_name().and_then(|e| e.to_str()).unwrap_or("");
        match ext {
            "pvd" => {
                let frames: Vec<PathBuf> = read_pvd(input)?.into_iter().map(|(_, f)| f).collect();
                if frames.is_empty() {
                    return Err(bad(input, "the collection lists no frame yet; run longer or with a smaller --vtk-every"));
                }
                let dir = input.parent().unwrap_or(Path::new("."));
                Ok(Source::Vtk {
                    frames,
                    walls: box_beside(dir)?,
                })
            }
            "vtp" => {
                // A frame in <out>/vtk/: the box is in <out>/.
                let dir = input.parent().and_then(Path::parent).unwrap_or(Path::new("."));
                Ok(Source::Vtk {
                    frames: vec![input.to_path_buf()],
                    walls: box_beside(dir)?,
                })
            }
            "csv" => Ok(Source::Memory(trajectory(input, scenario)?)),
            "toml" => {
                let s = scenario::load(input)?;
                Ok(Source::Memory(vec![Frame::of_states(&s, &s.initial, 0, 0.0)]))
            }
            "json" if name.contains("checkpoint") => Ok(Source::Memory(vec![checkpoint(input)?])),
            _ => Err(bad(
                input,
                "cannot tell what this is; give a fibres.pvd, a vtk/fibres_<step>.vtp, a trajectory.csv, a checkpoint.json or a scenario .toml",
            )),
        }
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        match self {
            Source::Vtk { frames, .. } => frames.len(),
            Source::Memory(f) => f.len(),
        }
    }

    /// Whether there is no frame.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Frame `k`.
    pub fn frame(&self, k: usize) -> Result<Frame> {
        match self {
            Source::Vtk { frames, walls } => vtk_frame(&frames[k], *walls),
            Source::Memory(f) => Ok(f[k].clone()),
        }
    }
}

/// The box of a `box.vtp` in `dir`, if there is one.
fn box_beside(dir: &Path) -> Result<Option<(DVec3, DVec3)>> {
    let p = dir.join(crate::output::vtk::BOX_FILE);
    if !p.exists() {
        return Ok(None);
    }
    let v = read_vtp(&p)?;
    let pts = v.points.to_f64();
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for c in pts.chunks_exact(3) {
        let p = DVec3::new(c[0], c[1], c[2]);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    Ok((lo.x <= hi.x).then_some((lo, hi)))
}

fn vtk_frame(path: &Path, walls: Option<(DVec3, DVec3)>) -> Result<Frame> {
    let v = read_vtp(path)?;
    let need = |name: &str, comps: usize| -> Result<Vec<f64>> {
        let a = v.cell(name).ok_or_else(|| {
            bad(
                path,
                format!("has no cell array `{name}`: not a fibresim frame"),
            )
        })?;
        let vals = a.to_f64();
        if a.components != comps || vals.len() != comps * v.n_lines {
            return Err(bad(path, format!("cell array `{name}` has the wrong size")));
        }
        Ok(vals)
    };
    let pts = v.points.to_f64();
    if pts.len() != 6 * v.n_lines {
        return Err(bad(path, "expected two points per line"));
    }
    let (axis, d, l) = (need("axis", 3)?, need("diameter", 1)?, need("length", 1)?);
    let (vel, om, ke) = (
        need("velocity", 3)?,
        need("omega", 3)?,
        need("kinetic_energy", 1)?,
    );
    let (cnt, mat, id) = (need("contacts", 1)?, need("material", 1)?, need("id", 1)?);
    let v3 = |a: &[f64], i: usize| DVec3::new(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
    let fibres = (0..v.n_lines)
        .map(|i| {
            let (p, q) = (
                DVec3::new(pts[6 * i], pts[6 * i + 1], pts[6 * i + 2]),
                DVec3::new(pts[6 * i + 3], pts[6 * i + 4], pts[6 * i + 5]),
            );
            Fibre {
                centre: 0.5 * (p + q),
                axis: v3(&axis, i).normalize_or(DVec3::X),
                diameter: d[i],
                length: l[i],
                velocity: v3(&vel, i),
                omega: v3(&om, i),
                kinetic_energy: ke[i],
                contacts: cnt[i] as u32,
                material: mat[i] as u32,
                id: id[i] as u64,
            }
        })
        .collect();
    let field = |n: &str| v.field(n).and_then(|a| a.to_f64().first().copied());
    Ok(Frame {
        step: field("step").unwrap_or(0.0) as u64,
        t: field("TimeValue").unwrap_or(0.0),
        fibres,
        walls,
        materials: materials_of(&v),
    })
}

/// Material names are not in a frame: number them.
fn materials_of(v: &Vtp) -> Vec<String> {
    let n = v
        .cell("material")
        .map(|a| a.to_f64().iter().fold(0.0f64, |m, &x| m.max(x)) as usize + 1)
        .unwrap_or(0);
    (0..n).map(|k| format!("material {k}")).collect()
}

fn checkpoint(path: &Path) -> Result<Frame> {
    let c = Checkpoint::read(path)?;
    let scene = crate::run::scene_from_checkpoint(&c, None)?;
    let states = &c.states;
    if states.len() != scene.bodies.len() || c.ids != scene.ids {
        return Err(bad(path, "its states do not match its own scenario"));
    }
    Ok(Frame::of_states(
        &scene,
        states,
        c.step,
        c.step as f64 * scene.sim.dt(),
    ))
}

/// The scenario of a trajectory: `--scenario`, else the summary beside it.
fn trajectory_scene(input: &Path, scenario: Option<&Path>) -> Result<Scene> {
    if let Some(p) = scenario {
        return scenario::load(p);
    }
    let summary = input.with_file_name("summary.json");
    let fix = "give the scenario with --scenario PATH";
    let text = std::fs::read_to_string(&summary).map_err(|e| {
        bad(
            input,
            format!(
                "the fibre sizes are in its scenario, and {} cannot be read ({e}); {fix}",
                summary.display()
            ),
        )
    })?;
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| bad(&summary, format!("not JSON ({e}); {fix}")))?;
    let source = v["scenario"].as_str().unwrap_or("");
    if source.starts_with("<built-in") {
        let (name, text) = scenario::DEFAULT_SCENE;
        return scenario::parse_str(text, name);
    }
    scenario::load(Path::new(source)).map_err(|_| {
        bad(
            input,
            format!(
                "its scenario `{source}` (from {}) cannot be loaded from here; {fix}",
                summary.display()
            ),
        )
    })
}

fn trajectory(input: &Path, scenario: Option<&Path>) -> Result<Vec<Frame>> {
    let scene = trajectory_scene(input, scenario)?;
    let mut r =
        csv::Reader::from_path(input).map_err(|e| bad(input, format!("cannot read: {e}")))?;
    let header: Vec<String> = r
        .headers()
        .map_err(|e| bad(input, e.to_string()))?
        .iter()
        .map(str::to_string)
        .collect();
    if header != crate::output::trajectory::TRAJECTORY_COLUMNS {
        return Err(bad(
            input,
            "not a trajectory.csv (its columns differ); give one written by --trajectory-every N",
        ));
    }
    let index: std::collections::HashMap<u64, usize> = scene
        .ids
        .iter()
        .enumerate()
        .map(|(i, id)| (id, i))
        .collect();
    let mut frames = vec![];
    let mut states = scene.initial.clone();
    let mut seen = 0usize;
    let mut current: Option<(u64, f64)> = None;
    for (line, rec) in r.records().enumerate() {
        let rec = rec.map_err(|e| bad(input, e.to_string()))?;
        let num = |k: usize| -> Result<f64> {
            rec.get(k)
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| {
                    bad(
                        input,
                        format!("line {}: column {} is not a number", line + 2, header[k]),
                    )
                })
        };
        let (step, t, id) = (num(0)? as u64, num(1)?, num(2)? as u64);
        if let Some((s, ts)) = current {
            if s != step {
                if seen != states.len() {
                    return Err(bad(input, format!("step {s} lists {seen} bodies, the scenario has {}; give its own scenario with --scenario", states.len())));
                }
                frames.push(Frame::of_states(&scene, &states, s, ts));
                seen = 0;
            }
        }
        current = Some((step, t));
        let i = *index
            .get(&id)
            .ok_or_else(|| bad(input, format!("line {}: body {id} is not in the scenario; give its own scenario with --scenario", line + 2)))?;
        let st = &mut states[i];
        st.x = DVec3::new(num(3)?, num(4)?, num(5)?);
        st.rot.q = crate::math::quat_wxyz([num(6)?, num(7)?, num(8)?, num(9)?]);
        st.v = DVec3::new(num(10)?, num(11)?, num(12)?);
        let omega = DVec3::new(num(13)?, num(14)?, num(15)?);
        st.rot.omega_b = crate::math::to_body(st.rot.q, omega);
        seen += 1;
    }
    if let Some((s, ts)) = current {
        frames.push(Frame::of_states(&scene, &states, s, ts));
    }
    if frames.is_empty() {
        return Err(bad(input, "has no rows"));
    }
    Ok(frames)
}
