//! The contact stage's neighbour list finds every contact a full search finds:
//! forces, torques and elastic energy are bit-identical to evaluating every
//! pair and every wall with the same kernels in the same order, at every step
//! of a dense, colliding scene. Both remember each
//! pair's last end-involved scan the same way (the search by pair, the
//! stage along its list, carried across its rebuilds).

use crate::common;
use common::scene_str;
use fibresim::body::BodyState;
use fibresim::contact::shape::{geom, ColliderKind, ColliderPose, ColliderShape};
use fibresim::contact::stage::motion_bound;
use fibresim::contact::{
    box_walls, contacts, contacts_remembering, Collider, FibreGeom, HertzLaw, KernelCounters,
    PairMemory,
};
use std::collections::HashMap;

/// Every pair's memory and every fibre's pose at the last search.
#[derive(Default)]
struct Memories {
    pairs: HashMap<(usize, usize), PairMemory>,
    last: Vec<FibreGeom>,
}
use fibresim::integrate::rotate::Pcdm;
use fibresim::integrate::step::World;
use fibresim::scenario::Scene;
use glam::DVec3;

/// Forces, torques and elastic energy from every wall of every body, then
/// every pair `i < j`: the order the stage sums in, so the bits must agree.
/// The kernels' counts are added to `counters`.
fn full_search(
    scene: &Scene,
    states: &[BodyState],
    counters: &mut KernelCounters,
    memories: &mut Memories,
) -> (Vec<DVec3>, Vec<DVec3>, f64) {
    let n = states.len();
    let (mut force, mut torque, mut elastic) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n], 0.0);
    let geom = |i: usize| geom(&scene.bodies[i], &states[i]);
    let kind = |i: usize| ColliderKind::of(&scene.bodies[i].shape).unwrap();
    let collider = |i: usize| {
        let shape = ColliderShape::of(&scene.bodies[i]);
        shape.collider(&ColliderPose::of(shape.kind, &states[i]))
    };
    let walls = box_walls(scene.walls.as_ref().unwrap());
    let w = scene.walls.as_ref().unwrap();
    let mut pts = vec![];
    let mut add = |pts: &[fibresim::contact::ContactPoint],
                   law: HertzLaw,
                   (ga, a): (FibreGeom, usize),
                   b: Option<(FibreGeom, usize)>| {
        for c in pts {
            let f = (c.weight * law.force(c.overlap)) * c.normal;
            let u = law.energy(c.overlap);
            elastic += c.weight * u;
            let couple = -u * c.weight_grad;
            force[a] += f;
            torque[a] += (c.point - ga.centre).cross(f) + couple;
            if let Some((gb, b)) = b {
                force[b] -= f;
                torque[b] -= (c.point - gb.centre).cross(f) + couple;
            }
        }
    };
    for i in 0..n {
        let b = scene.material(i);
        let law = match kind(i) {
            ColliderKind::Fibre => HertzLaw::fibre_wall,
            ColliderKind::Sphere => HertzLaw::sphere_wall,
        }(2.0 * geom(i).radius, b.young, b.poisson, w.young, w.poisson);
        for wall in &walls {
            pts.clear();
            contacts(collider(i), Collider::Wall(wall), &mut pts, counters);
            add(&pts, law, (geom(i), i), None);
        }
    }
    memories.last.resize(n, FibreGeom::default());
    let motion: Vec<f64> = (0..n)
        .map(|i| f64::from(motion_bound(&memories.last[i], &geom(i))))
        .collect();
    for i in 0..n {
        for j in i + 1..n {
            pts.clear();
            let memory = memories.pairs.entry((i, j)).or_default();
            let m = Some((memory, motion[i] + motion[j]));
            let (ci, cj) = (collider(i), collider(j));
            contacts_remembering(ci, cj, &mut pts, counters, m);
            // The law of the two kinds (a sphere–fibre law takes the sphere
            // first; hertz_spheres.rs).
            use ColliderKind::*;
            let (a, b) = match (kind(i), kind(j)) {
                (Fibre, Sphere) => (j, i),
                _ => (i, j),
            };
            let law = match (kind(i), kind(j)) {
                (Fibre, Fibre) => HertzLaw::fibre_fibre,
                (Sphere, Sphere) => HertzLaw::sphere_sphere,
                _ => HertzLaw::sphere_fibre,
            }(
                2.0 * geom(a).radius,
                scene.material(a).young,
                scene.material(a).poisson,
                2.0 * geom(b).radius,
                scene.material(b).young,
                scene.material(b).poisson,
            );
            add(&pts, law, (geom(i), i), Some((geom(j), j)));
        }
    }
    for (i, g) in memories.last.iter_mut().enumerate() {
        *g = geom(i);
    }
    (force, torque, elastic)
}

/// `n` fibres on a grid 0.04 m apart in a box of that pitch, fast random motions, no
/// gravity: many fibre–fibre and wall contacts within 0.02 s.
fn dense_scene(n: usize) -> Scene {
    dense_scene_at(n, 0.04, false)
}

/// [`dense_scene`] with grid pitch `pitch` (≥ 0.027 m, the fibres' bounding
/// diameter, so nothing overlaps at the start); with `spheres`, every third
/// body a sphere of diameter 0.02 m.
fn dense_scene_at(n: usize, pitch: f64, spheres: bool) -> Scene {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let side = (n as f64).cbrt().ceil() as usize;
    let edge = pitch * side as f64;
    let mut text = format!(
        "[simulation]\ndt = 1e-6\nt_end = 0.02\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [{edge}, {edge}, {edge}]\nyoung = 5e7\npoisson = 0.23\n",
    );
    for k in 0..n {
        let (i, j, l) = (k % side, (k / side) % side, k / (side * side));
        let c = |g: usize| 0.5 * pitch + pitch * g as f64;
        let shape = match spheres && k % 3 == 2 {
            true => "shape = \"sphere\"\ndiameter = 0.02",
            false => "shape = \"fibre\"\ndiameter = 0.01\nlength = 0.025",
        };
        text += &format!(
            "[[body]]\n{shape}\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [{}, {}, {}]\naxis = [{}, {}, {}]\nvelocity = [{}, {}, {}]\nangular_velocity = [{}, {}, {}]\n",
            c(i), c(j), c(l),
            rnd() + 0.7, rnd(), rnd(),
            4.0 * rnd(), 4.0 * rnd(), 4.0 * rnd(),
            100.0 * rnd(), 100.0 * rnd(), 100.0 * rnd(),
        );
    }
    scene_str(&text)
}

fn check(n: usize) {
    check_scene(dense_scene(n), true);
}

/// [`check`] of `scene`; `remembering`: its fibre pairs answer mostly from
/// their memories (a bed of fibres; with spheres the end-involved fibre
/// pairs are too few to say).
fn check_scene(scene: Scene, remembering: bool) {
    let n = scene.bodies.len();
    let mut w = World::new(&scene);
    let (mut touching_steps, mut rebuilds_seen) = (0u64, 0u64);
    // The stage's counts since it was built (its first computation is in
    // World::new): a pair the list leaves out has no capsule overlap and
    // never reaches the end-involved kernel, so both ask it the same pairs.
    // (Which of those it scans, rather than remembers apart, differs: a
    // pair back in the list after a rebuild has forgotten it was apart.)
    let mut counters = KernelCounters::default();
    let mut memories = Memories::default();
    full_search(&scene, &w.states, &mut counters, &mut memories);
    let asked = |k: KernelCounters| k.end_scans + k.remembered;
    while w.step < scene.sim.steps() {
        w.step::<Pcdm>().expect("the dense scene stays stable");
        let (f, t, e) = full_search(&scene, &w.states, &mut counters, &mut memories);
        assert_eq!(f, w.force, "forces at step {}", w.step);
        assert_eq!(t, w.torque, "torques at step {}", w.step);
        assert_eq!(
            e.to_bits(),
            w.elastic().to_bits(),
            "energy at step {}",
            w.step
        );
        touching_steps += u64::from(w.contact_stats().unwrap().touching > 0);
        let stage = w.contacts.as_ref().unwrap();
        rebuilds_seen = stage.neighbour_builds();
        assert_eq!(
            asked(stage.kernel_counters()),
            asked(counters),
            "end-involved pairs at step {}",
            w.step
        );
    }
    // The scene must exercise the list: contacts most of the time, and far
    // fewer builds than steps.
    println!(
        "{n} bodies: {touching_steps} of {} steps with contacts, {rebuilds_seen} list builds, {counters:?}",
        scene.sim.steps(),
    );
    assert!(
        !remembering || counters.remembered > counters.end_scans,
        "the memories are used: {counters:?}"
    );
    assert!(touching_steps > scene.sim.steps() / 2, "{touching_steps}");
    assert!(
        rebuilds_seen > 10 && rebuilds_seen < scene.sim.steps() / 10,
        "{rebuilds_seen}"
    );
}

/// All pairs below 33 bodies.
#[test]
fn neighbour_list_matches_a_full_search_all_pairs() {
    check(27);
}

/// The grid above 32 bodies.
#[test]
fn neighbour_list_matches_a_full_search_grid() {
    check(40);
}

/// Fibres and spheres (every third body a sphere of twice the fibres'
/// diameter): a sphere's capsule of zero length in the list, its skin test
/// and its boxes, on all pairs and on the grid.
#[test]
fn neighbour_list_matches_a_full_search_with_spheres() {
    check_scene(dense_scene_at(27, 0.04, true), false);
    check_scene(dense_scene_at(40, 0.035, true), false);
}

/// The grid finds exactly the box pairs the sweep finds (itself checked
/// against brute force in `tests/suite/contact_geometry.rs`), on dense, sparse,
/// elongated and degenerate sets of boxes.
#[test]
fn grid_pairs_equal_sweep_pairs() {
    use fibresim::contact::broad::{grid_pairs, GridScratch};
    use fibresim::contact::candidate_pairs;
    let mut rng = common::Rng(0x2545_f491_4f6c_dd1d);
    let mut scratch = GridScratch::default();
    let cases: [(usize, DVec3, f64); 5] = [
        (2000, DVec3::splat(0.3), 0.03),          // a filled box
        (2000, DVec3::new(0.3, 0.3, 30.0), 0.03), // a tall, sparse column
        (500, DVec3::splat(0.1), 0.1),            // boxes as wide as the region
        (300, DVec3::new(5.0, 0.01, 0.01), 0.05), // along a line
        (50, DVec3::ZERO, 0.02),                  // all at one point
    ];
    for (n, region, size) in cases {
        let boxes: Vec<(DVec3, DVec3)> = (0..n)
            .map(|_| {
                let lo = DVec3::new(rng.next(), rng.next(), rng.next()) * region;
                let ext = DVec3::new(rng.next(), rng.next(), rng.next()) * size;
                (lo, lo + ext)
            })
            .collect();
        let (mut sweep, mut grid) = (vec![], vec![]);
        candidate_pairs(&boxes, &mut sweep);
        grid_pairs(&boxes, &mut scratch, &mut grid);
        assert_eq!(grid, sweep, "{n} boxes in {region}, size {size}");
        assert!(!sweep.is_empty() || n < 2, "the case has pairs");
    }
}

/// The parallel force stage (pair slots gathered per body in the serial
/// order) gives the bits of the serial one: the same scene stepped on pools
/// of 1 (serial path), 2 and 4 threads ends in the same states, forces and
/// energies, and the forces equal a full search at every checked step.
#[test]
fn thread_count_changes_no_bit() {
    let scene = scene_str(&common::packed_scene(6, 8, 8, 1e-3));
    assert!(scene.bodies.len() >= fibresim::contact::stage::PARALLEL_MIN_BODIES);
    let steps = 600;
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = World::new(&scene);
            let mut touching = 0;
            let mut counters = KernelCounters::default();
            // (The search remembers what the stage does: every step.)
            let mut memories = Memories::default();
            if threads == 2 {
                full_search(&scene, &w.states, &mut counters, &mut memories);
            }
            for k in 0..steps {
                w.step::<Pcdm>().expect("stable");
                touching += w.contact_stats().unwrap().touching;
                if threads == 2 {
                    let (f, t, e) = full_search(&scene, &w.states, &mut counters, &mut memories);
                    if k % 300 == 299 {
                        assert!(f == w.force && t == w.torque, "forces at step {}", w.step);
                        assert_eq!(e.to_bits(), w.elastic().to_bits());
                    }
                }
            }
            (w.states.clone(), w.force.clone(), w.ledger, touching)
        })
    };
    let one = run(1);
    assert!(
        one.3 > 100 * steps / 10,
        "the scene has live contacts: {}",
        one.3
    );
    for threads in [2, 4] {
        let other = run(threads);
        assert!(one.0 == other.0, "states with {threads} threads");
        assert!(one.1 == other.1, "forces with {threads} threads");
        assert_eq!(one.2, other.2, "ledger with {threads} threads");
    }
}
