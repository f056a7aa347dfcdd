//! Ties of two local minima of the end-involved depth (regimes 1 and 3,
//! `fibre_fibre::END_TIE_BAND`): test case 2's two events, as isolated
//! two-fibre replays and as pose families through the tie.
//!
//! References: a conservative system integrated by leap-frog keeps its
//! energy to O(dt²) of the curvature of the potential, so a pair whose
//! potential is C² through the tie keeps the error it has away from it;
//! a kink (the plain minimum) shows a step of ~ΔF·v·dt. Forces are checked
//! against central finite differences of the potential, and the force
//! along a family through the tie must change by small steps (C¹).

use crate::common;
use common::*;
use fibresim::contact::{FibreGeom, HertzLaw};
use fibresim::integrate::step::World;

use glam::{DQuat, DVec3};

/// A body's state, as the scenario file gives it.
struct Start {
    position: [f64; 3],
    quaternion: [f64; 4],
    velocity: [f64; 3],
    angular_velocity: [f64; 3],
}

/// Test case 2, `leapfrog`, fibres 1 and 3 at step 7 559 200 (t = 0.75592 s,
/// 47 steps before B's face cap and A's side circle tie).
const EVENT_1: [Start; 2] = [
    Start {
        position: [
            0.44427239633308613,
            0.26534974521811894,
            0.19587087374929218,
        ],
        quaternion: [
            0.995136526964773,
            4.2309925275355064e-8,
            0.09850529275367702,
            2.0742770440328362e-8,
        ],
        velocity: [-1.3138920896376811, 1.000000765272536, -1.4522817822563663],
        angular_velocity: [
            0.00016206792941983846,
            -246.91830570028765,
            0.0007469708248685215,
        ],
    },
    Start {
        position: [0.4226002199481432, 0.26534974890749896, 0.21081350421933726],
        quaternion: [
            0.13456884353439874,
            4.7567595010031057e-7,
            -0.9909042468115791,
            -6.046369383035388e-7,
        ],
        velocity: [-1.97051051541955, 0.9999991787042437, -1.389944156156212],
        angular_velocity: [
            -6.2832453117941e-5,
            -219.50790834718768,
            -0.0011377927334478147,
        ],
    },
];

/// Test case 2, `leapfrog`, fibres 1 and 2 at step 9 760 150 (t = 0.976015 s,
/// crossed at 53°, 65 steps before A's and B's face caps tie).
const EVENT_2: [Start; 2] = [
    Start {
        position: [0.15300901582645826, 0.4854448211079445, 0.17473780182567375],
        quaternion: [
            0.8615069402701556,
            6.656352580536334e-7,
            -0.5077457945329183,
            2.161138970499969e-7,
        ],
        velocity: [-1.0817612545250062, 1.0000003503485957, 0.6209613849036014],
        angular_velocity: [
            -0.0013491235015648017,
            343.5848791251652,
            0.0008664680351150658,
        ],
    },
    Start {
        position: [0.13119782510387404, 0.4854447551108911, 0.15994881225829372],
        quaternion: [
            0.9979032190581218,
            -6.048691290067161e-9,
            -0.06472376220089537,
            6.293239096442994e-9,
        ],
        velocity: [1.3821551887306471, 0.9999999946493878, -1.0373836017785873],
        angular_velocity: [
            -3.585929179229217e-5,
            -85.9960513998181,
            0.0002840265793839344,
        ],
    },
];

/// The pair alone (no gravity, no walls), leap-frog at dt = 1e-7 s for
/// `steps`. The loader refuses overlapping bodies, so B is loaded 1 m away
/// and put back.
fn replay(starts: &[Start; 2], steps: u64) -> Replay {
    let mut t = format!(
        "[simulation]\ndt = 1e-7\nt_end = {}\nrotator = \"leapfrog\"\n[world]\ngravity = [0.0, 0.0, 0.0]\n",
        steps as f64 * 1e-7
    );
    let away = DVec3::new(0.0, 1.0, 0.0);
    for (i, s) in starts.iter().enumerate() {
        let x = DVec3::from(s.position) + if i == 1 { away } else { DVec3::ZERO };
        t += &format!(
            "[[body]]\n{FIBRE}position = {:?}\nquaternion = {:?}\nvelocity = {:?}\nangular_velocity = {:?}\n",
            x.to_array(),
            s.quaternion,
            s.velocity,
            s.angular_velocity
        );
    }
    let scene = scene_str(&t);
    let mut w = World::new(&scene);
    let mut states = w.states.clone();
    states[1].x -= away;
    w.restore(states, vec![], 0, vec![]);
    let e0 = w.ledger.total_full();
    // (The energy guard's reference: the pair as put back.)
    w.e0_full = e0;
    let geom = |w: &World, i: usize| FibreGeom {
        centre: w.states[i].x,
        axis: w.states[i].rot.q * DVec3::X,
        radius: 0.005,
        half_length: 0.0125,
    };
    let mut r = Replay {
        worst: 0.0,
        worst_step: 0.0,
        band: vec![],
        poses: vec![],
    };
    let mut prev = 0.0;
    while w.step < steps {
        w.step_kind(fibresim::integrate::rotate::RotatorKind::Leapfrog)
            .expect("step");
        let e = (w.ledger.total_full() - e0) / e0;
        r.worst = r.worst.max(e.abs());
        r.worst_step = r.worst_step.max((e - prev).abs());
        prev = e;
        let (a, b) = (geom(&w, 0), geom(&w, 1));
        if ff_contacts(&a, &b).len() == 2 {
            r.band.push(r.poses.len());
        }
        r.poses.push((a, b));
    }
    r
}

/// What a replay saw.
struct Replay {
    /// Largest |E − E0|/E0.
    worst: f64,
    /// Largest one-step change of (E − E0)/E0.
    worst_step: f64,
    /// Steps (indices into `poses`) with two contact points: in the band.
    band: Vec<usize>,
    /// The pair after each step.
    poses: Vec<(FibreGeom, FibreGeom)>,
}

#[test]
fn tie_replays_conserve_energy_through_the_band() {
    // Measured with the plain minimum (the force turned by 86° resp. at the
    // cap-to-cap switch in one step): one-step changes of 2.54e-4 and
    // 2.59e-4 of the pair's energy. With the smooth minimum: 3.0e-7 and
    // 1.8e-7, max 2.4e-6 and 1.8e-6 (the leap-frog error of the band's
    // curvature, ~1/ε, gone after it).
    for (name, starts) in [("cap vs side", &EVENT_1), ("cap vs cap", &EVENT_2)] {
        let r = replay(starts, 400);
        println!(
            "{name}: max |ΔE|/E0 {:.2e}, largest one-step change {:.2e}, {} steps in the band",
            r.worst,
            r.worst_step,
            r.band.len()
        );
        assert!(r.band.len() >= 10, "{name}: the replay must cross the band");
        assert!(r.worst < 2e-5, "{name}: {}", r.worst);
        assert!(r.worst_step < 2e-6, "{name}: {}", r.worst_step);
    }
}

/// Worst relative mismatch of (F, τ) on A against central differences of
/// U (steps `hx`, `hx/L`), scaled by |F| and |F|·L.
fn gradient_error(law: &HertzLaw, a: &FibreGeom, b: &FibreGeom, hx: f64) -> f64 {
    let (force, torque, _) = hertz_wrench(law, &ff_contacts(a, b), a.centre);
    let u = |g: &FibreGeom| hertz_wrench(law, &ff_contacts(g, b), g.centre).2;
    let (fscale, lscale) = (force.length(), a.half_length + a.radius);
    let hr = hx / lscale;
    let mut worst = 0.0f64;
    for e in DVec3::AXES {
        let shift = |s: f64| FibreGeom {
            centre: a.centre + s * e,
            ..*a
        };
        let turn = |s: f64| FibreGeom {
            axis: DQuat::from_axis_angle(e, s) * a.axis,
            ..*a
        };
        let g = -(u(&shift(hx)) - u(&shift(-hx))) / (2.0 * hx);
        worst = worst.max((g - force.dot(e)).abs() / fscale);
        let g = -(u(&turn(hr)) - u(&turn(-hr))) / (2.0 * hr);
        worst = worst.max((g - torque.dot(e)).abs() / (fscale * lscale));
    }
    worst
}

#[test]
fn tie_families_are_c1_with_exact_gradient() {
    // A straight family of poses through each replay's band (centres
    // interpolated, axes normalised-interpolated), from 3 steps before it
    // to 3 steps after. C¹: the force changes by small steps along it
    // (the plain minimum: a step of ~1.4 |F| at the tie); exact gradient:
    // central differences of U inside the band, where the two contacts'
    // weights vary; the depth is at most 3ε/16 below the plain minimum's.
    let law = HertzLaw::fibre_fibre(0.01, 5e7, 0.35, 0.01, 5e7, 0.35);
    for (name, starts) in [("cap vs side", &EVENT_1), ("cap vs cap", &EVENT_2)] {
        let r = replay(starts, 400);
        let (i0, i1) = (r.band[0] - 3, r.band[r.band.len() - 1] + 3);
        let (p0, p1) = (r.poses[i0], r.poses[i1]);
        let at = |x: f64| {
            let mix = |f: &FibreGeom, g: &FibreGeom| FibreGeom {
                centre: f.centre.lerp(g.centre, x),
                axis: f.axis.lerp(g.axis, x).normalize(),
                ..*f
            };
            (mix(&p0.0, &p1.0), mix(&p0.1, &p1.1))
        };
        let n = 4000;
        let (mut worst_df, mut fmax, mut worst_fd, mut two) = (0.0f64, 0.0f64, 0.0f64, 0);
        let mut prev: Option<DVec3> = None;
        for k in 0..=n {
            let (a, b) = at(k as f64 / n as f64);
            let c = ff_contacts(&a, &b);
            let (f, _, _) = hertz_wrench(&law, &c, a.centre);
            fmax = fmax.max(f.length());
            if let Some(p) = prev {
                worst_df = worst_df.max((f - p).length());
            }
            prev = Some(f);
            if c.len() == 2 {
                two += 1;
                assert!((c[0].weight + c[1].weight - 1.0).abs() < 1e-12, "{c:?}");
                assert_eq!(c[0].overlap, c[1].overlap);
                assert!(c[0].normal.dot(c[1].normal) < 0.995, "{c:?}");
                if two % 100 == 1 {
                    worst_fd = worst_fd.max(gradient_error(&law, &a, &b, 1e-9));
                }
            }
        }
        println!(
            "{name}: {two}/{n} samples blended, largest force step {:.1e} of max |F|, worst gradient mismatch {worst_fd:.1e}",
            worst_df / fmax
        );
        assert!(two > n / 2, "{name}: {two}");
        assert!(worst_df / fmax < 3e-3, "{name}: {}", worst_df / fmax);
        assert!(worst_fd < 1e-5, "{name}: {worst_fd}");
    }
}
