//! The scenario text of a bed whose bodies are in a body file (what
//! `fibresim generate` and `fibresim settle` write): simulation, gravity,
//! box, named materials, restitution, the start-overlap tolerance and the
//! body file, in the layout of `scenarios/*.toml`.

use crate::body::Material;
use crate::contact::damping::Restitution;
use crate::contact::Walls;
use glam::DVec3;
use std::fmt::{self, Write};

/// A bed scenario to write.
#[derive(Debug, Clone)]
pub struct BedScenario<'a> {
    /// Comment lines at the top (how the bed was made).
    pub comment: Vec<String>,
    /// Time step, s.
    pub dt: f64,
    /// End time, s.
    pub t_end: f64,
    /// Gravity, m/s².
    pub gravity: Option<DVec3>,
    /// The box.
    pub walls: Option<&'a Walls>,
    /// The materials the body file names.
    pub materials: &'a [Material],
    /// Normal restitution (`None`: elastic).
    pub restitution: Option<Restitution>,
    /// Coulomb friction (`None`: frictionless): a property of the bodies,
    /// kept by every bed written from a frictional scene.
    pub friction: Option<crate::contact::tangential::Friction>,
    /// `guards.start_overlap_ratio`, if any.
    pub start_overlap_ratio: Option<f64>,
    /// The body file, relative to the scenario's folder.
    pub body_file: &'a str,
}

/// A float in shortest round-trip form (always with a `.` or an exponent,
/// so TOML reads a float).
fn num(x: f64) -> String {
    ryu::Buffer::new().format(x).to_string()
}

fn vec3(v: DVec3) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

/// A TOML key: bare when it can be, quoted otherwise.
fn key(name: &str) -> String {
    let bare = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if bare {
        name.to_string()
    } else {
        format!("{name:?}")
    }
}

impl fmt::Display for BedScenario<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = String::new();
        for c in &self.comment {
            writeln!(s, "# {c}")?;
        }
        writeln!(
            s,
            "\n[simulation]\ndt = {}\nt_end = {}",
            num(self.dt),
            num(self.t_end)
        )?;
        if let Some(g) = self.gravity {
            writeln!(s, "\n[world]\ngravity = {}", vec3(g))?;
        }
        if let Some(w) = self.walls {
            writeln!(
                s,
                "\n[box]\nmin = {}\nmax = {}\nyoung = {}\npoisson = {}",
                vec3(w.min),
                vec3(w.max),
                num(w.young),
                num(w.poisson)
            )?;
        }
        for m in self.materials {
            writeln!(
                s,
                "\n[material.{}]\ndensity = {}\nyoung = {}\npoisson = {}",
                key(&m.name),
                num(m.density),
                num(m.young),
                num(m.poisson)
            )?;
            if let Some(mu) = m.friction {
                writeln!(s, "friction = {}", num(mu))?;
            }
        }
        if self.restitution.is_some() || self.friction.is_some() {
            writeln!(s, "\n[contact]")?;
        }
        if let Some(e) = self.restitution {
            writeln!(
                s,
                "restitution = {}\nwall_restitution = {}",
                num(e.fibre),
                num(e.wall)
            )?;
        }
        if let Some(f) = self.friction {
            writeln!(
                s,
                "friction = {}\nwall_friction = {}",
                num(f.body),
                num(f.wall)
            )?;
        }
        if let Some(r) = self.start_overlap_ratio {
            writeln!(s, "\n[guards]\nstart_overlap_ratio = {}", num(r))?;
        }
        writeln!(s, "\n[bodies]\nfile = {:?}", self.body_file)?;
        f.write_str(&s)
    }
}
