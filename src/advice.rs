//! Time-step advice (SPEC §8): Hertz contact time at the largest plausible
//! impact speed, Rayleigh time, and the recommended δt.
//!
//! **Impact-speed bound.** Nothing dissipates energy, so no body can ever move
//! faster than if the whole initial energy (kinetic + rotational + the potential
//! energy above the box floor) went into its translation:
//! `v_max,i = √(2 E_avail / m_i)`. Two bodies approach at most at
//! `v_max,i + v_max,j`; a body meets a wall at most at `v_max,i`. Hertz contact
//! times fall as `v^{-1/5}`, so this bound errs on the safe side. Scenes with a
//! prescribed torque have no energy bound and get no contact advice.

use crate::body::{Body, Shape};
use crate::contact::HertzLaw;
use crate::scenario::Scene;

/// Steps per Hertz collision at the recommended δt.
pub const STEPS_PER_COLLISION: f64 = 50.0;
/// Fraction of the Rayleigh time at the recommended δt.
pub const RAYLEIGH_FRACTION: f64 = 0.2;
/// Fewer steps per collision than this is refused as bad input (the collision is
/// not resolved at all), unless the user insists (`--allow-large-dt`).
pub const MIN_STEPS_PER_COLLISION: f64 = 5.0;

#[derive(Debug, Clone, serde::Serialize)]
pub struct PairAdvice {
    /// e.g. `fibre0–wall`, `fibre0–fibre3` (first body of each distinct kind).
    pub pair: String,
    pub reduced_mass: f64,
    pub v_max: f64,
    pub contact_time: f64,
    pub rayleigh_time: f64,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Advice {
    /// Energy available for impacts, J (see the module docs).
    pub available_energy: f64,
    pub pairs: Vec<PairAdvice>,
    /// Recommended δt, s (None: no contacts, accuracy is the only limit).
    pub recommended_dt: Option<f64>,
    /// Above this δt a collision spans fewer than 5 steps.
    pub hard_limit_dt: Option<f64>,
    pub warnings: Vec<String>,
}

/// Rayleigh time of a fibre's material: `π r √(ρ/G) / (0.1631 ν + 0.8766)`.
pub fn rayleigh_time(b: &Body) -> f64 {
    let r = 0.5 * diameter(b);
    let g = b.young / (2.0 * (1.0 + b.poisson));
    std::f64::consts::PI * r * (b.density / g).sqrt() / (0.1631 * b.poisson + 0.8766)
}

fn diameter(b: &Body) -> f64 {
    match b.shape {
        Shape::Fibre { diameter, .. } | Shape::Sphere { diameter } => diameter,
    }
}

/// Bodies that are the same kind for contact purposes.
fn same_kind(a: &Body, b: &Body) -> bool {
    a.shape == b.shape && a.density == b.density && a.young == b.young && a.poisson == b.poisson
}

pub fn advise(scene: &Scene) -> Advice {
    let mut warnings = vec![];
    let mut e = 0.0;
    for (b, s) in scene.bodies.iter().zip(&scene.initial) {
        e += 0.5 * b.mass * s.v.length_squared() + b.inertia.kinetic_energy(s.rot.omega_b);
        if let (Some(g), Some(w)) = (scene.gravity, &scene.walls) {
            // Potential energy above the lowest point of the box along g.
            let lowest = if g.x > 0.0 { w.max.x } else { w.min.x } * g.x
                + if g.y > 0.0 { w.max.y } else { w.min.y } * g.y
                + if g.z > 0.0 { w.max.z } else { w.min.z } * g.z;
            e += b.mass * (lowest - g.dot(s.x)).max(0.0);
        }
    }
    let no_advice = |warnings| Advice {
        available_energy: e,
        pairs: vec![],
        recommended_dt: None,
        hard_limit_dt: None,
        warnings,
    };
    if !scene.needs_contacts() {
        return no_advice(warnings);
    }
    if scene.has_prescribed_torque() {
        warnings.push(
            "prescribed torques do work: impact speeds cannot be bounded, no contact advice".into(),
        );
        return no_advice(warnings);
    }
    let mut pairs = vec![];
    if e <= 0.0 {
        warnings.push(
            "the scene starts at rest with no energy to release: nothing will collide".into(),
        );
    }
    let v_max = |b: &Body| (2.0 * e / b.mass).sqrt().max(1e-12);
    // One representative body per kind.
    let mut kinds: Vec<usize> = vec![];
    for (i, b) in scene.bodies.iter().enumerate() {
        if !kinds.iter().any(|&k| same_kind(&scene.bodies[k], b)) {
            kinds.push(i);
        }
    }
    let name = |i: usize| scene.bodies[i].name.clone();
    if let Some(w) = &scene.walls {
        for &i in &kinds {
            let b = &scene.bodies[i];
            let law = HertzLaw::fibre_wall(diameter(b), b.young, b.poisson, w.young, w.poisson);
            pairs.push(PairAdvice {
                pair: format!("{}–wall", name(i)),
                reduced_mass: b.mass,
                v_max: v_max(b),
                contact_time: law.contact_time(b.mass, v_max(b)),
                rayleigh_time: rayleigh_time(b),
            });
        }
    }
    if scene.bodies.len() > 1 {
        for (x, &i) in kinds.iter().enumerate() {
            for &j in &kinds[x..] {
                // A kind meets itself only if it has at least two bodies.
                if i == j
                    && scene
                        .bodies
                        .iter()
                        .filter(|b| same_kind(b, &scene.bodies[i]))
                        .count()
                        < 2
                {
                    continue;
                }
                let (a, b) = (&scene.bodies[i], &scene.bodies[j]);
                let law = HertzLaw::fibre_fibre(
                    diameter(a),
                    a.young,
                    a.poisson,
                    diameter(b),
                    b.young,
                    b.poisson,
                );
                let m = a.mass * b.mass / (a.mass + b.mass);
                let v = v_max(a) + v_max(b);
                pairs.push(PairAdvice {
                    pair: format!(
                        "{}–{}",
                        name(i),
                        if i == j { "same kind".into() } else { name(j) }
                    ),
                    reduced_mass: m,
                    v_max: v,
                    contact_time: law.contact_time(m, v),
                    rayleigh_time: rayleigh_time(a).min(rayleigh_time(b)),
                });
            }
        }
    }
    let t_c = pairs
        .iter()
        .map(|p| p.contact_time)
        .fold(f64::INFINITY, f64::min);
    let t_r = pairs
        .iter()
        .map(|p| p.rayleigh_time)
        .fold(f64::INFINITY, f64::min);
    let recommended = (t_c / STEPS_PER_COLLISION).min(RAYLEIGH_FRACTION * t_r);
    let dt = scene.sim.dt;
    if dt > recommended {
        warnings.push(format!(
            "dt = {dt:e} s is above the recommended {recommended:.3e} s (the shortest Hertz collision, {t_c:.3e} s, gets {:.1} steps; 0.2 x Rayleigh time = {:.3e} s)",
            t_c / dt,
            RAYLEIGH_FRACTION * t_r
        ));
    }
    Advice {
        available_energy: e,
        pairs,
        recommended_dt: recommended.is_finite().then_some(recommended),
        hard_limit_dt: t_c.is_finite().then_some(t_c / MIN_STEPS_PER_COLLISION),
        warnings,
    }
}
