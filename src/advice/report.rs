//! The report of `fibresim check`: the scene, what will run, and the
//! time-step advice, as text.
//!
//! Tables have a header row with the unit of every column and are aligned;
//! cells never hold two spaces in a row, so a script splits a row on runs
//! of two or more spaces (pandas: `read_csv(..., sep=r"\s{2,}")`).

use super::Advice;
use crate::body::Shape;
use crate::scenario::Scene;
use std::fmt;

/// `fibresim check`'s report of `scene` with its `advice`.
pub struct CheckReport<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its advice.
    pub advice: &'a Advice,
    /// The scenario's own warnings (values outside engineering practice).
    pub scene_warnings: &'a [String],
}

/// `1 body`, `9 bodies`.
fn count(n: u64, one: &str, many: &str) -> String {
    if n == 1 {
        format!("1 {one}")
    } else {
        format!("{n} {many}")
    }
}

/// Rows of cells under a header, each column as wide as its widest cell,
/// two spaces apart; numbers right-aligned, text left-aligned.
fn table(f: &mut fmt::Formatter<'_>, header: &[&str], rows: &[Vec<String>]) -> fmt::Result {
    let width: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|r| r[c].chars().count())
                .chain([header[c].chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let numeric: Vec<bool> = (0..header.len())
        .map(|c| {
            rows.iter()
                .all(|r| r[c].parse::<f64>().is_ok() || r[c] == "–")
        })
        .collect();
    let line = |cells: Vec<&str>| -> String {
        let parts: Vec<String> = cells
            .iter()
            .enumerate()
            .map(|(c, s)| {
                let pad = width[c] - s.chars().count();
                if numeric[c] {
                    format!("{}{s}", " ".repeat(pad))
                } else {
                    format!("{s}{}", " ".repeat(pad))
                }
            })
            .collect();
        format!("  {}", parts.join("  ").trim_end())
    };
    writeln!(f, "{}", line(header.to_vec()))?;
    for r in rows {
        writeln!(f, "{}", line(r.iter().map(String::as_str).collect()))?;
    }
    Ok(())
}

/// A body's shape and its dimensions, m.
fn shape_cells(s: &Shape) -> [String; 3] {
    match *s {
        Shape::Fibre { diameter, length } => {
            ["fibre".into(), format!("{diameter}"), format!("{length}")]
        }
        Shape::Sphere { diameter } => ["sphere".into(), format!("{diameter}"), "–".into()],
        Shape::Rigid { .. } => ["rigid".into(), "–".into(), "–".into()],
    }
}

/// The advice's pair label (`A–wall`, `A–same kind`, `A–B`) as the report
/// writes it: `A – wall`, `A – A (same kind)`, `A – B`.
fn pair_label(pair: &str) -> String {
    if let Some(a) = pair.strip_suffix("–same kind") {
        format!("{a} – {a} (same kind)")
    } else {
        pair.replacen('–', " – ", 1)
    }
}

impl fmt::Display for CheckReport<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (scene, a) = (self.scene, self.advice);
        writeln!(
            f,
            "scenario {}: {}, dt = {:e} s, {} (t_end = {} s), rotator {}",
            scene.source,
            count(scene.bodies.len() as u64, "body", "bodies"),
            scene.sim.dt(),
            count(scene.sim.steps(), "step", "steps"),
            scene.sim.t_end(),
            scene.sim.rotator()
        )?;
        writeln!(
            f,
            "\nbodies (principal moments of inertia about body x, y, z):"
        )?;
        // A bed lists its first bodies only.
        const LISTED: usize = 20;
        let rows: Vec<Vec<String>> = scene
            .bodies
            .iter()
            .enumerate()
            .take(LISTED)
            .map(|(i, b)| {
                let [shape, d, l] = shape_cells(&b.shape);
                let p = b.inertia.principal;
                vec![
                    i.to_string(),
                    scene.name(i).replace("  ", " "),
                    shape,
                    d,
                    l,
                    scene.material(i).name.clone(),
                    format!("{:.4e}", b.mass),
                    format!("{:.4e}", p.x),
                    format!("{:.4e}", p.y),
                    format!("{:.4e}", p.z),
                ]
            })
            .collect();
        table(
            f,
            &[
                "#",
                "name",
                "shape",
                "D (m)",
                "L (m)",
                "material",
                "mass (kg)",
                "I_x (kg m^2)",
                "I_y (kg m^2)",
                "I_z (kg m^2)",
            ],
            &rows,
        )?;
        if scene.bodies.len() > LISTED {
            writeln!(f, "  ... and {} more", scene.bodies.len() - LISTED)?;
        }
        if !scene.materials.is_empty() {
            writeln!(f, "\nmaterials:")?;
            let rows: Vec<Vec<String>> = scene
                .materials
                .iter()
                .map(|m| {
                    let or_dash = |x: f64| {
                        if x.is_finite() {
                            format!("{x:e}")
                        } else {
                            "–".into()
                        }
                    };
                    vec![
                        m.name.clone(),
                        format!("{}", m.density),
                        or_dash(m.young),
                        if m.poisson.is_finite() {
                            format!("{}", m.poisson)
                        } else {
                            "–".into()
                        },
                    ]
                })
                .collect();
            table(
                f,
                &["material", "density (kg/m^3)", "young (Pa)", "poisson (-)"],
                &rows,
            )?;
        }
        let search = match scene.bodies.len() {
            _ if !scene.needs_contacts() => "off".to_string(),
            1 => "walls only".into(),
            n if n <= 32 => format!("{n} bodies, all pairs"),
            n => format!("{n} bodies, cell grid"),
        };
        writeln!(
            f,
            "\nwhat will run: gravity {}; walls {}; contact search {}; prescribed torques on {}; closed-form reference {}",
            if scene.gravity.is_some() { "on" } else { "off" },
            if scene.walls.is_some() { "6 half-spaces" } else { "none" },
            search,
            count(scene.torques.len() as u64, "body", "bodies"),
            if scene.reference.is_some() { "yes" } else { "no" }
        )?;
        if !a.pairs.is_empty() {
            writeln!(f, "\ncontact pairs (one row per kind of pair: bodies of the same shape and material are one kind, named by its first body):")?;
            // The tangential column only where friction declares the mode.
            let frictional = a.pairs.iter().any(|p| p.tangential_time.is_some());
            let rows: Vec<Vec<String>> = a
                .pairs
                .iter()
                .map(|p| {
                    let mut row = vec![
                        pair_label(&p.pair),
                        format!("{:.4e}", p.reduced_mass),
                        format!("{:.4e}", p.translational_mass),
                        format!("{:.4e}", p.v_max),
                        format!("{:.4e}", p.contact_time),
                        format!("{:.4e}", p.tilt_period),
                    ];
                    if frictional {
                        row.push(p.tangential_time.map_or("–".into(), |t| format!("{t:.4e}")));
                    }
                    row.push(format!("{:.4e}", p.rayleigh_time));
                    row
                })
                .collect();
            let mut header = vec![
                "pair",
                "m* (kg)",
                "m_trans (kg)",
                "v_max (m/s)",
                "t_Hertz (s)",
                "t_tilt (s)",
            ];
            if frictional {
                header.push("t_tangential (s)");
            }
            header.push("t_Rayleigh (s)");
            table(f, &header, &rows)?;
            match a.impact_speed {
                Some(v) => writeln!(f, "  impact speed given: v_max = {v:e} m/s for every pair (--impact-speed)")?,
                None => writeln!(f, "  impact speeds bounded per body: E_i = its kinetic + rotational energy + its fall to the box floor; largest E_avail = {:.4e} J", a.available_energy)?,
            }
            if a.grouped_by_material {
                writeln!(f, "  (more than 16 body sizes: grouped by material and shape, each group as its lightest body at its fastest speed)")?;
            }
            writeln!(f, "  m* = effective mass at the worst contact point: 1/m_eff = 1/m + |r x n|^2 / I_transverse, lever arm")?;
            writeln!(f, "  |r x n| = max(D/2, L/2) (a fibre's end hit along its side normal); a pair sums 1/m_eff of its bodies")?;
            writeln!(f, "  and their bounds v_max = sqrt(2 E_i / m_eff) (largest of the kind); m_trans = the translational mass alone;")?;
            writeln!(f, "  t_tilt = period of an end face rocking on the contact under the peak force of that impact")?;
            if frictional {
                writeln!(f, "  t_tangential = half period pi sqrt(m_t / k_t) of a sticking friction contact: Mindlin's k_t = 8 G* a at the deepest")?;
                writeln!(f, "  overlap of that impact, m_t the effective mass against a tangential force (a fibre's end turns and spins)")?;
            }
        }
        let frictional = a.pairs.iter().any(|p| p.tangential_time.is_some());
        match a.recommended_dt {
            Some(r) if frictional => writeln!(f, "\nrecommended dt <= {r:.3e} s (shortest collision / 50, fastest face tilt / 50, shortest tangential half period / 50, and 0.2 x Rayleigh time); chosen dt = {:e} s, margin {:.3}x", scene.sim.dt(), r / scene.sim.dt())?,
            Some(r) => writeln!(f, "\nrecommended dt <= {r:.3e} s (shortest collision / 50, fastest face tilt / 50, and 0.2 x Rayleigh time); chosen dt = {:e} s, margin {:.3}x", scene.sim.dt(), r / scene.sim.dt())?,
            None if scene.needs_contacts() && a.torque_bodies > 0 && a.impact_speed.is_none() => writeln!(f, "\nno contact advice: every body that can touch has a prescribed torque, so no impact speed can be bounded; give --impact-speed V")?,
            None => writeln!(f, "\nno contacts to resolve: dt is limited by accuracy only (see `fibresim rotators` for orders)")?,
        }
        if a.torque_bodies > 0 {
            writeln!(
                f,
                "prescribed torques on {}: {} rotation is limited by the rotator's accuracy only (`fibresim rotators` for the orders, `fibresim converge` to measure it)",
                count(a.torque_bodies as u64, "body", "bodies"),
                if a.torque_bodies == 1 { "its" } else { "their" },
            )?;
        }
        if a.recommended_dt.is_some() {
            let i = scene.sim.rotator().info();
            writeln!(
                f,
                "note: the advice resolves the contact mechanics; the rotator's own error on contact torques comes on top. {}: {}.{}",
                i.name,
                i.contact_contract,
                if i.closing_kick {
                    ""
                } else {
                    " That is first order in dt: its energy error per collision falls only like dt (docs/validation.md, test case 1; `fibresim stress` for stiff impacts)"
                }
            )?;
        }
        for w in self.scene_warnings.iter().chain(&a.warnings) {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}
