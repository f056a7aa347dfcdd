//! The report of `fibresim check`: the scene, what will run, and the
//! time-step advice, as text.

use super::Advice;
use crate::scenario::Scene;
use std::fmt;

/// `fibresim check`'s report of `scene` with its `advice`.
pub struct CheckReport<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Its advice.
    pub advice: &'a Advice,
}

impl fmt::Display for CheckReport<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (scene, a) = (self.scene, self.advice);
        writeln!(
            f,
            "scenario {}: {} bodies, dt = {:e} s, {} steps, rotator {}",
            scene.source,
            scene.bodies.len(),
            scene.sim.dt(),
            scene.sim.steps(),
            scene.sim.rotator()
        )?;
        writeln!(
            f,
            "\nbodies (mass kg; principal inertia kg m^2, body x y z):"
        )?;
        // A bed lists its first bodies only.
        const LISTED: usize = 20;
        for (i, b) in scene.bodies.iter().enumerate().take(LISTED) {
            let p = b.inertia.principal;
            writeln!(
                f,
                "  [{i}] {:<10} {:?}  m = {:.4e}  I = ({:.4e}, {:.4e}, {:.4e})",
                scene.name(i),
                b.shape,
                b.mass,
                p.x,
                p.y,
                p.z
            )?;
        }
        if scene.bodies.len() > LISTED {
            writeln!(f, "  ... and {} more", scene.bodies.len() - LISTED)?;
        }
        let search = match scene.bodies.len() {
            _ if !scene.needs_contacts() => "off".to_string(),
            1 => "walls only".into(),
            n if n <= 32 => format!("{n} bodies, all pairs"),
            n => format!("{n} bodies, sort-and-sweep"),
        };
        writeln!(f, "\ncomponents: gravity {}, walls {}, contact search {}, prescribed torques on {} bodies, closed-form reference {}",
            if scene.gravity.is_some() { "on" } else { "off" },
            if scene.walls.is_some() { "6 half-spaces" } else { "none" },
            search,
            scene.torques.len(),
            if scene.reference.is_some() { "yes" } else { "no" })?;
        if !a.pairs.is_empty() {
            match a.impact_speed {
                Some(v) => writeln!(f, "\nimpact speed given: v_max = {v:e} m/s for every pair (--impact-speed)")?,
                None => writeln!(f, "\nimpact speeds bounded per body: E_i = its kinetic + rotational energy + its fall to the box floor; largest E_avail = {:.4e} J", a.available_energy)?,
            }
            if a.grouped_by_material {
                writeln!(f, "  (more than 16 fibre sizes: grouped by material, each group as its lightest fibre at its fastest speed)")?;
            }
            writeln!(f, "m* = effective mass at the worst contact point: 1/m_eff = 1/m + |r x n|^2 / I_transverse, lever arm")?;
            writeln!(f, "  |r x n| = max(D/2, L/2) (a fibre's end hit along its side normal); a pair sums 1/m_eff of its bodies")?;
            writeln!(f, "  and their bounds v_max = sqrt(2 E_i / m_eff) (largest of the kind); m_trans = the translational mass alone;")?;
            writeln!(f, "  t_tilt = period of an end face rocking on the contact under the peak force of that impact")?;
            writeln!(
                f,
                "  {:<24} {:>11} {:>12} {:>11} {:>13} {:>13} {:>14}",
                "pair",
                "m* (kg)",
                "m_trans (kg)",
                "v_max (m/s)",
                "t_Hertz (s)",
                "t_tilt (s)",
                "t_Rayleigh (s)"
            )?;
            for p in &a.pairs {
                writeln!(
                    f,
                    "  {:<24} {:>11.4e} {:>12.4e} {:>11.4e} {:>13.4e} {:>13.4e} {:>14.4e}",
                    p.pair,
                    p.reduced_mass,
                    p.translational_mass,
                    p.v_max,
                    p.contact_time,
                    p.tilt_period,
                    p.rayleigh_time
                )?;
            }
        }
        match a.recommended_dt {
            Some(r) => writeln!(f, "\nrecommended dt <= {r:.3e} s (shortest collision / 50, fastest face tilt / 50, and 0.2 x Rayleigh time); chosen dt = {:e} s, margin {:.3}x", scene.sim.dt(), r / scene.sim.dt())?,
            None => writeln!(f, "\nno contacts to resolve: dt is limited by accuracy only (see `fibresim rotators` for orders)")?,
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
                    " That is first order in dt: its energy error per collision falls only like dt (README, test case 1; `fibresim stress` for stiff impacts)"
                }
            )?;
        }
        for w in &a.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}
