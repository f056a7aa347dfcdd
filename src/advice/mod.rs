//! Time-step advice (docs/physics.md §8): Hertz contact time at the largest plausible
//! impact speed, Rayleigh time, and the recommended δt.
//!
//! **Impact-speed bound, per body.** A body can bring to a contact its own
//! energy `E_i`: its kinetic and rotational energy and its fall to the lowest
//! point of the box along g. (The whole scene's energy cannot go into one
//! contact of a bed: that bound grows with N, 125 → 2709 m/s from 10³ to
//! 10⁵ loose fibres, and refused every bed run. Collisions do pass energy
//! between bodies, so this is an estimate, not a proof; `--impact-speed`
//! replaces it for a user who knows the flow better.)
//!
//! **Effective mass.** An off-centre contact (a fibre's end) moves the normal
//! against the body's translation *and* rotation: along the normal `n` at the
//! contact point `r` (from the centre of mass) the body has the effective mass
//! `m_eff = 1/(1/m + (r×n)·I⁻¹(r×n))`, up to 4x smaller than `m` for a long
//! fibre. We use the smallest `m_eff` over every point of the surface and
//! every normal it can have ([`min_effective_mass`]). By Cauchy–Schwarz the
//! same `m_eff` bounds the normal speed of that point,
//! `v_n = n·v + (r×n)·ω ≤ √(2 E_i / m_eff)` (its spin at the lever arm
//! included), so `v_max,i = √(2 E_i / m_eff,i)`; a kind of body takes the
//! largest over its bodies.
//! A body meets a wall at `v_max,i` with `m* = m_eff,i`; two bodies approach
//! at most at `v_max,i + v_max,j` with `1/m* = 1/m_eff,i + 1/m_eff,j`. The
//! Hertz time `∝ m*^{2/5} v^{-1/5}` then scales as `√m_eff`: about half the
//! translational estimate for test case 1's fibre. Both bounds err on the
//! safe side.
//!
//! **Spheres.** Every normal of a sphere passes through its centre, so its
//! effective mass is its mass; each pair is timed with the Hertz law the
//! contact stage uses for its kinds (`contact/law/table.rs`: sphere–wall,
//! sphere–sphere, sphere–fibre), its Rayleigh time is that of its radius, and
//! it has no tilt mode; a fibre's face resting on a sphere rocks with the lever
//! `ρ = R_s`.
//!
//! **Bodies with a prescribed torque** other than zero have no energy bound
//! (the torque does work), so without `--impact-speed` their contacts are left out of the
//! pairs and the advice covers the contacts of the other bodies (and the
//! walls), with a warning naming how many bodies it leaves out; the torque
//! bodies' own rotation is limited by the rotator's accuracy only
//! ([`Advice::torque_bodies`]). One torque body does not switch the advice
//! off for the rest of the scene.
//!
//! **Face tilt.** A fibre whose end face is (nearly) flat on a wall or on
//! another fibre rocks on it: the face blend of the wall model and the domed
//! end faces of the fibre model make the depth rise as `ρ θ²/2` with the
//! tilt θ, so a normal force F gives the restoring torque `F (ρ − L/2) θ`
//! about the centre of mass (frictionless: the centre does not move
//! sideways), with `ρ = 4 r / s0` against a wall (`s0` =
//! [`FACE_BLEND_SIN`]) and `ρ = r / sin θc` on a fibre's domed face (θc =
//! [`END_FACE_DOME_SIN`]). The period `2π √(I_t / (F (ρ − L/2)))` at the
//! peak Hertz force of the worst impact is often shorter than the collision
//! itself, so it bounds δt too.
//!
//! **Tangential mode (friction).** A sticking contact holds the two
//! material points on a tangential spring `k_t = 8 G* a` (Mindlin, as the
//! law: `contact/tangential.rs`), `a = √(R* δ)`. Against its linearised
//! normal stiffness `S_n = dF/dδ = 2 E* a` that is `k_t/S_n = 4 G*/E*`,
//! `2(1−ν)/(2−ν)` for equal materials (0.79 at ν = 0.35). The spring
//! moves the point along a tangent `t` against the effective mass
//! `1/m_t = 1/m + (r×t)·I⁻¹(r×t)`, smaller than the normal one: a
//! tangential force at a fibre's end turns it about a transverse axis
//! (lever L/2, `I⊥ = m(3r² + L²)/12`) *and* spins it about its axis
//! (lever r, `I_ax = m r²/2`), which no normal force does
//! ([`min_tangential_mass`]). The sticking contact oscillates with the
//! half period `t_t = π √(m_t/k_t)`, taken at the deepest overlap of the
//! worst impact (where `k_t` is largest: the tangent stiffness, as the
//! face tilt takes the peak force), and `t_t` is held to the same
//! [`STEPS_PER_COLLISION`] and [`MIN_STEPS_PER_COLLISION`] as the Hertz
//! collision, which is itself about one half period of the normal
//! oscillation. Only pairs with μ > 0 have the mode: a frictionless scene's
//! advice is the one without it.

mod report;
pub use report::CheckReport;

use crate::body::{Body, Material, Shape};
use crate::contact::fibre_fibre::END_FACE_DOME_SIN;
use crate::contact::fibre_wall::FACE_BLEND_SIN;
use crate::contact::law::{body_law, body_wall_law};
use crate::contact::tangential::Tangential;
use crate::contact::HertzLaw;
use crate::scenario::Scene;

/// Steps per Hertz collision at the recommended δt.
pub const STEPS_PER_COLLISION: f64 = 50.0;
/// Fraction of the Rayleigh time at the recommended δt.
pub const RAYLEIGH_FRACTION: f64 = 0.2;
/// Steps per face-tilt period at the recommended δt.
pub const STEPS_PER_TILT_PERIOD: f64 = 50.0;
/// Fewer steps per collision (or per face-tilt period) than this is refused
/// as bad input (the motion is not resolved at all), unless the user insists
/// (`--allow-large-dt`).
pub const MIN_STEPS_PER_COLLISION: f64 = 5.0;

#[derive(Debug, Clone, serde::Serialize)]
/// The advice for one pair type (a body kind with a wall, or two kinds).
pub struct PairAdvice {
    /// e.g. `fibre0–wall`, `fibre0–fibre3` (first body of each distinct kind).
    pub pair: String,
    /// Effective mass of the pair at its worst contact points (module docs).
    pub reduced_mass: f64,
    /// The translational reduced mass alone (`m`, or `m_i m_j/(m_i + m_j)`).
    pub translational_mass: f64,
    /// Bound on the approach speed at the contact point, m/s.
    pub v_max: f64,
    /// Hertz collision time at `v_max`, s.
    pub contact_time: f64,
    /// Rayleigh time of the softer material, s.
    pub rayleigh_time: f64,
    /// Period of a face rocking on the contact at the peak force (module docs).
    pub tilt_period: f64,
    /// Half period of the sticking tangential oscillation at the deepest
    /// overlap (module docs), s; `None` for a frictionless pair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_time: Option<f64>,
}

#[derive(Debug, Clone, serde::Serialize)]
/// The time-step advice of a scene.
pub struct Advice {
    /// The largest energy one body can bring to a contact, J (module docs).
    pub available_energy: f64,
    /// The impact speed given instead of the bound (`--impact-speed`), m/s.
    pub impact_speed: Option<f64>,
    /// Whether the kinds were grouped by material and shape (more than 16
    /// sizes).
    pub grouped_by_material: bool,
    /// One entry per pair type that can touch.
    pub pairs: Vec<PairAdvice>,
    /// Recommended δt, s (None: no contacts, accuracy is the only limit).
    pub recommended_dt: Option<f64>,
    /// Bodies with a prescribed torque other than zero: their rotation is
    /// limited by the rotator's accuracy only, and without `--impact-speed`
    /// their contacts are left out of the pairs (no energy bound).
    pub torque_bodies: usize,
    /// Above this δt a collision spans fewer than 5 steps.
    pub hard_limit_dt: Option<f64>,
    /// What `run` and `check` print as warnings.
    pub warnings: Vec<String>,
}

impl Advice {
    /// What [`Advice::hard_limit_dt`] resolves, for the refusal of a larger δt.
    pub fn limited_by(&self) -> &'static str {
        match self.pairs.iter().any(|p| p.tangential_time.is_some()) {
            true => "the shortest Hertz collision, face-tilt period or sticking tangential (friction) half period",
            false => "the shortest Hertz collision or face-tilt period",
        }
    }
}

/// Rayleigh time of a fibre or a sphere of material `m`, `r` its radius:
/// `π r √(ρ/G) / (0.1631 ν + 0.8766)`.
pub fn rayleigh_time(b: &Body, m: &Material) -> f64 {
    let r = 0.5 * b.shape.diameter();
    let g = m.young / (2.0 * (1.0 + m.poisson));
    std::f64::consts::PI * r * (m.density / g).sqrt() / (0.1631 * m.poisson + 0.8766)
}

/// Smallest effective mass `1/(1/m + (r×n)·I⁻¹(r×n))` of a body over its
/// surface points `r` and their normals `n`, and the lever arm `|r×n|` that
/// gives it.
///
/// Fibre (axis body x): every normal of a cylinder is parallel to the axis
/// (end faces) or meets it (side), and so is every normal of the rim's cone,
/// so `r×n` is perpendicular to the axis (frictionless contacts never spin a
/// fibre about it) and only `I_transverse` enters. Face point, face normal:
/// `|r×n| ≤ D/2`; side point at axial position `x`, side normal: `|r×n| = |x|
/// ≤ L/2`; rim, normal at angle `α` from the axis: `|(L/2) sin α − (D/2) cos α|
/// ≤ max(D/2, L/2)`. So the lever arm is `max(D/2, L/2)`: for `L > D` the end
/// of the side hit along the side normal (a fibre landing nearly flat on one
/// end, or a T-junction at a fibre's end).
/// Sphere: every normal passes through the centre, `m_eff = m`.
pub fn min_effective_mass(b: &Body) -> (f64, f64) {
    match b.shape {
        Shape::Fibre { diameter, length } => {
            let arm = (0.5 * diameter).max(0.5 * length);
            let i_t = b.inertia.principal.y;
            (1.0 / (1.0 / b.mass + arm * arm / i_t), arm)
        }
        Shape::Sphere { .. } => (b.mass, 0.0),
        // Contact-free only (the scenario refuses it elsewhere): never asked.
        Shape::Rigid { semi_axes } => (b.mass, semi_axes.max_element()),
    }
}

/// Smallest effective mass `1/(1/m + (r×t)·I⁻¹(r×t))` of a body against a
/// tangential force at a surface point `r` along a tangent `t` (module docs,
/// "Tangential mode").
///
/// Fibre (axis body x, `I⊥` about y and z, `I_ax` about x): write `r×t`
/// as its axial part `a` and its transverse part `b`. A surface point
/// lies at most `D/2` from the axis, so `|a| ≤ D/2`, and `|a|² + |b|² =
/// |r×t|² ≤ |r|² ≤ (L/2)² + (D/2)²`. `a²/I_ax + b²/I⊥` is linear in `a²`
/// on that range, so its largest value is at an end:
/// `((L/2)² + (D/2)²)/I⊥` (`a = 0`) or `(L/2)²/I⊥ + (D/2)²/I_ax`
/// (`|a| = D/2`: the end of the side, pushed along the tangent normal to
/// the axis; the larger one for `L > √3 D/2`, where `I⊥ > I_ax`).
/// Sphere: `|r×t| ≤ R`, `I = (2/5) m R²`, so `m_t = 2m/7`.
pub fn min_tangential_mass(b: &Body) -> f64 {
    match b.shape {
        Shape::Fibre { diameter, length } => {
            let (h, r) = (0.5 * length, 0.5 * diameter);
            let (i_ax, i_t) = (b.inertia.principal.x, b.inertia.principal.y);
            let turn = ((h * h + r * r) / i_t).max(h * h / i_t + r * r / i_ax);
            1.0 / (1.0 / b.mass + turn)
        }
        Shape::Sphere { diameter } => {
            let r = 0.5 * diameter;
            1.0 / (1.0 / b.mass + r * r / b.inertia.principal.x)
        }
        // Contact-free only: never asked.
        Shape::Rigid { .. } => b.mass,
    }
}

/// Half period `π √(m_t/k_t)` of the sticking tangential oscillation
/// (module docs) of a contact with Hertz law `law` and shear law `tan`,
/// hit by an impact of normal reduced mass `m` at speed `v`, the bodies'
/// tangential effective mass `m_t`. `None` when μ = 0.
fn tangential_time(
    law: &HertzLaw,
    tan: &crate::contact::tangential::Tangential,
    m: f64,
    v: f64,
    m_t: f64,
) -> Option<f64> {
    if tan.mu <= 0.0 {
        return None;
    }
    // Deepest overlap of the impact, as in `tilt_period`.
    let depth = (1.25 * m * v * v / law.stiffness()).powf(0.4);
    let k_t = tan.stiffness(law.r_star, depth);
    Some(std::f64::consts::PI * (m_t / k_t).sqrt())
}

/// Period of the face-tilt mode of fibre `b` (module docs) under the peak
/// Hertz force of an impact of reduced mass `m` at speed `v`, on a face of
/// curvature lever `rho`. Infinite for a sphere or when the mode is unstable.
fn tilt_period(b: &Body, law: &HertzLaw, m: f64, v: f64, rho: f64) -> f64 {
    let Shape::Fibre { length, .. } = b.shape else {
        return f64::INFINITY;
    };
    // Energy balance ½ m v² = (2/5) k δ^{5/2} gives the deepest overlap.
    let k = law.stiffness();
    let depth = (1.25 * m * v * v / k).powf(0.4);
    let force = k * depth * depth.sqrt();
    let stiffness = force * (rho - 0.5 * length);
    if stiffness > 0.0 {
        2.0 * std::f64::consts::PI * (b.inertia.principal.y / stiffness).sqrt()
    } else {
        f64::INFINITY
    }
}

/// Above this many distinct (material, D, L) kinds, the advice groups the
/// bodies by material and shape only (a polydisperse bed), each group
/// represented by its lightest body at the group's fastest speed.
const MAX_KINDS: usize = 16;

/// Kinds of bodies for the advice: a representative body, how many bodies
/// the kind has, and the largest impact-speed bound among them. O(N).
/// Bodies whose `v_max` is NaN (a speed that cannot be bounded) are left out.
fn kinds(scene: &Scene, v_max: &[f64]) -> (Vec<(usize, usize, f64)>, bool) {
    use std::collections::HashMap;
    let group = |by_size: bool| {
        let mut index: HashMap<(u32, u64, u64), usize> = HashMap::new();
        let mut out: Vec<(usize, usize, f64)> = vec![];
        for (i, b) in scene.bodies.iter().enumerate() {
            if v_max[i].is_nan() {
                continue;
            }
            let (d, l, shape) = match b.shape {
                Shape::Fibre { diameter, length } => (diameter, length, 0),
                Shape::Sphere { diameter } => (diameter, -1.0, 1),
                // Rigid bodies are contact-free: never in a pair; a kind of their own.
                Shape::Rigid { semi_axes } => (semi_axes.max_element(), -2.0, 2),
            };
            let key = match by_size {
                true => (b.material, d.to_bits(), l.to_bits()),
                // Fibres, spheres and rigid bodies stay apart.
                false => (b.material, shape, 0),
            };
            let k = *index.entry(key).or_insert_with(|| {
                out.push((i, 0, 0.0));
                out.len() - 1
            });
            let (rep, count, v) = &mut out[k];
            *count += 1;
            *v = v.max(v_max[i]);
            if min_effective_mass(b).0 < min_effective_mass(&scene.bodies[*rep]).0 {
                *rep = i;
            }
        }
        out
    };
    let by_size = group(true);
    if by_size.len() <= MAX_KINDS {
        (by_size, false)
    } else {
        (group(false), true)
    }
}

/// The energy body `b` at state `s` can bring to a contact: its kinetic and
/// rotational energy and its fall to the lowest point of the box along g.
fn body_energy(scene: &Scene, b: &Body, s: &crate::body::BodyState) -> f64 {
    let mut e = 0.5 * b.mass * s.v.length_squared() + b.inertia.kinetic_energy(s.rot.omega_b);
    if let (Some(g), Some(w)) = (scene.gravity, &scene.walls) {
        let lowest = if g.x > 0.0 { w.max.x } else { w.min.x } * g.x
            + if g.y > 0.0 { w.max.y } else { w.min.y } * g.y
            + if g.z > 0.0 { w.max.z } else { w.min.z } * g.z;
        e += b.mass * (lowest - g.dot(s.x)).max(0.0);
    }
    e
}

/// The advice for `scene` with the per-body impact-speed bound (module docs).
pub fn advise(scene: &Scene) -> Advice {
    advise_with(scene, None)
}

/// The advice for `scene`; `impact_speed` (m/s), when given, replaces the
/// per-body bound for every pair (a user who knows the flow better).
pub fn advise_with(scene: &Scene, impact_speed: Option<f64>) -> Advice {
    let mut warnings = vec![];
    // A prescribed torque other than zero does work: its body's energy
    // bounds nothing (NaN) unless the impact speed is given.
    let working = |i: usize| {
        crate::scenario::scene::prescribed_on(&scene.torques, i).is_some_and(|t| !t.is_zero())
    };
    let torque_bodies = (0..scene.bodies.len()).filter(|&i| working(i)).count();
    let energies: Vec<f64> = scene
        .bodies
        .iter()
        .zip(&scene.initial)
        .enumerate()
        .map(|(i, (b, s))| match impact_speed.is_none() && working(i) {
            true => f64::NAN,
            false => body_energy(scene, b, s),
        })
        .collect();
    let unbounded = energies.iter().filter(|e| e.is_nan()).count();
    let bounded = || energies.iter().copied().filter(|e| !e.is_nan());
    let e = bounded().fold(0.0, f64::max);
    let e = if bounded().any(|x| !x.is_finite()) {
        f64::INFINITY
    } else {
        e
    };
    let no_advice = |warnings| Advice {
        available_energy: e,
        impact_speed,
        grouped_by_material: false,
        pairs: vec![],
        recommended_dt: None,
        torque_bodies,
        hard_limit_dt: None,
        warnings,
    };
    if !scene.needs_contacts() {
        return no_advice(warnings);
    }
    if !e.is_finite() && impact_speed.is_none() {
        warnings.push(format!(
            "the initial energy is not finite ({e:e} J): impact speeds cannot be bounded, no contact advice; check the masses and speeds"
        ));
        return no_advice(warnings);
    }
    if unbounded > 0 {
        let (n, its) = match unbounded {
            1 => ("1 body".to_string(), "its"),
            n => (format!("{n} bodies"), "their"),
        };
        warnings.push(format!(
            "{n} with a prescribed torque: the torque does work, so {its} impact speed cannot be bounded and {its} contacts are left out of the advice (which covers the other bodies' contacts); give --impact-speed V to include them"
        ));
        if unbounded == scene.bodies.len() {
            return no_advice(warnings);
        }
    }
    let mut pairs = vec![];
    if e <= 0.0 && impact_speed.is_none() {
        warnings.push(
            "the scene starts at rest with no energy to release: nothing will collide".into(),
        );
    }
    let m_eff = |b: &Body| min_effective_mass(b).0;
    let v_body: Vec<f64> = scene
        .bodies
        .iter()
        .zip(&energies)
        .map(|(b, &e)| match e.is_nan() {
            true => f64::NAN,
            false => impact_speed.unwrap_or_else(|| (2.0 * e / m_eff(b)).sqrt().max(1e-12)),
        })
        .collect();
    let (kinds, grouped) = kinds(scene, &v_body);
    let name = |i: usize| scene.name(i);
    let mat = |i: usize| scene.material(i);
    if let Some(w) = &scene.walls {
        for &(i, _, v) in &kinds {
            let (b, m) = (&scene.bodies[i], mat(i));
            let d = b.shape.diameter();
            let law = body_wall_law(b, m, w);
            let rho = 4.0 * 0.5 * d / FACE_BLEND_SIN;
            let tangential = scene.friction.and_then(|f| {
                let mu = f.against_wall(m.friction);
                let tan = Tangential::new(mu, m.young, m.poisson, w.young, w.poisson);
                tangential_time(&law, &tan, m_eff(b), v, min_tangential_mass(b))
            });
            pairs.push(PairAdvice {
                pair: format!("{}–wall", name(i)),
                reduced_mass: m_eff(b),
                translational_mass: b.mass,
                v_max: v,
                contact_time: law.contact_time(m_eff(b), v),
                rayleigh_time: rayleigh_time(b, m),
                tilt_period: tilt_period(b, &law, m_eff(b), v, rho),
                tangential_time: tangential,
            });
        }
    }
    if scene.bodies.len() > 1 {
        for (x, &(i, count, vi)) in kinds.iter().enumerate() {
            for &(j, _, vj) in &kinds[x..] {
                // A kind meets itself only if it has at least two bodies.
                if i == j && count < 2 {
                    continue;
                }
                let (a, b) = (&scene.bodies[i], &scene.bodies[j]);
                let (ma, mb) = (mat(i), mat(j));
                let law = body_law(a, ma, b, mb);
                let m = 1.0 / (1.0 / m_eff(a) + 1.0 / m_eff(b));
                // A given impact speed is the approach speed itself.
                let v = match impact_speed {
                    Some(v) => v,
                    None => vi + vj,
                };
                let tangential = scene.friction.and_then(|f| {
                    let mu = f.pair(ma.friction, mb.friction);
                    let tan = Tangential::new(mu, ma.young, ma.poisson, mb.young, mb.poisson);
                    let m_t = 1.0 / (1.0 / min_tangential_mass(a) + 1.0 / min_tangential_mass(b));
                    tangential_time(&law, &tan, m, v, m_t)
                });
                pairs.push(PairAdvice {
                    pair: format!(
                        "{}–{}",
                        name(i),
                        if i == j { "same kind".into() } else { name(j) }
                    ),
                    reduced_mass: m,
                    translational_mass: a.mass * b.mass / (a.mass + b.mass),
                    v_max: v,
                    contact_time: law.contact_time(m, v),
                    rayleigh_time: rayleigh_time(a, ma).min(rayleigh_time(b, mb)),
                    // Either fibre's face may rest on the other: on a
                    // fibre's domed face, or on a sphere (its radius is
                    // the face's lever).
                    tilt_period: [(a, b), (b, a)]
                        .map(|(f, other)| {
                            let rho = match other.shape {
                                Shape::Sphere { diameter } => 0.5 * diameter,
                                _ => 0.5 * f.shape.diameter() / END_FACE_DOME_SIN,
                            };
                            tilt_period(f, &law, m, v, rho)
                        })
                        .into_iter()
                        .fold(f64::INFINITY, f64::min),
                    tangential_time: tangential,
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
    let t_tilt = pairs
        .iter()
        .map(|p| p.tilt_period)
        .fold(f64::INFINITY, f64::min);
    let t_t = pairs
        .iter()
        .filter_map(|p| p.tangential_time)
        .fold(f64::INFINITY, f64::min);
    let recommended = (t_c / STEPS_PER_COLLISION)
        .min(RAYLEIGH_FRACTION * t_r)
        .min(t_tilt / STEPS_PER_TILT_PERIOD)
        .min(t_t / STEPS_PER_COLLISION);
    let dt = scene.sim.dt();
    if dt > recommended {
        // A frictionless scene has no tangential term (t_t infinite).
        let tangential = match t_t.is_finite() {
            true => format!(
                "; the fastest sticking tangential oscillation (friction), half period {t_t:.3e} s, {:.1}",
                t_t / dt
            ),
            false => String::new(),
        };
        // A scene of spheres has no face to tilt (t_tilt infinite).
        let tilt = match t_tilt.is_finite() {
            true => format!(
                "; the fastest face tilt, {t_tilt:.3e} s, {:.1}",
                t_tilt / dt
            ),
            false => String::new(),
        };
        warnings.push(format!(
            "dt = {dt:e} s is above the recommended {recommended:.3e} s (the shortest Hertz collision, {t_c:.3e} s, gets {:.1} steps{tilt}{tangential}; 0.2 x Rayleigh time = {:.3e} s)",
            t_c / dt,
            RAYLEIGH_FRACTION * t_r
        ));
    }
    let unresolved = t_c.min(t_tilt).min(t_t);
    Advice {
        available_energy: e,
        impact_speed,
        grouped_by_material: grouped,
        pairs,
        recommended_dt: recommended.is_finite().then_some(recommended),
        torque_bodies,
        hard_limit_dt: unresolved
            .is_finite()
            .then_some(unresolved / MIN_STEPS_PER_COLLISION),
        warnings,
    }
}
