//! Pair memories (`contact/fibre_fibre/coherence.rs`): a pair that answers
//! from its memory of its last end-involved scan answers what the scan
//! would. The reference is the scan itself (the feature-pair kernels,
//! checked against the brute-force oracle in `tests/suite/contact_oracle.rs`),
//! run on the same pair at the same pose: at every step of a settled bed
//! stepped at the settling δt (so that its contacts slide, open and
//! close), every remembered contact has the scan's points to within the
//! tolerance the scan itself allows between two answers for one minimum,
//! and a memory kept in its regime answers the whole dispatch's bits.

use crate::common;
use fibresim::contact::fibre_fibre::segment_closest_params;
use fibresim::contact::stage::{geom, motion_bound};
use fibresim::contact::{
    aabb, candidate_pairs, contact_fibre_fibre, contact_fibre_fibre_remembering, ContactPoint,
    FibreGeom, KernelCounters, PairMemory,
};
use fibresim::integrate::rotate::{Pcdm, RotatorKind};
use fibresim::integrate::step::World;
use fibresim::scenario::sim::SimParams;
use std::collections::HashMap;

/// A depth the memory may differ from the scan by: the scan certifies a
/// kernel's minimum when it is within `CERTIFY_TOL·(r_A + r_B)` (1e-14 m
/// here) of a cheap axis's value and keeps the lower of the two, and its
/// fallback (the iterative search, 0.07 % of the bed's scans) agrees with
/// the kernels to 5e-13 m (`tests/suite/contact_oracle.rs`); the memory keeps the
/// kernel's value.
const DEPTH_TOL: f64 = 1e-12;
/// The same for the normal (a unit vector): at a minimum the depth is flat
/// in the direction, so the kernels' iterations stop within ~1e-10 rad of
/// it (rim–side and rim–rim's step tolerances; rim–rim without the scan's
/// starting hints) and the search within its own.
const NORMAL_TOL: f64 = 1e-10;
/// Where the scan fell back, the search stops once the supports' offset
/// across the normal is below 1e-6 (r_A + r_B) (`search.rs`): a normal
/// within ~2e-6 rad.
const FALLBACK_NORMAL_TOL: f64 = 1e-5;
/// A face's point moves with the normal by the dome's radius
/// (`r/END_FACE_DOME_SIN` = 5 m here) times the normal's change.
const DOME_RADIUS: f64 = 5.0;

/// The same memory without its mark of a pair kept in its regime
/// (`coherence.rs`: a touching memory's kinds 9–15 are the kernels 1–7
/// marked; the apart ones set bit 0x40): what the whole dispatch answers from.
fn unmarked(m: PairMemory) -> PairMemory {
    let [code, left, cap] = m.to_raw();
    if code & 0x40 == 0 && code & 0x0f > 8 {
        PairMemory::from_raw([code - 8, left, cap]).expect("a touching memory")
    } else {
        m
    }
}

/// Whether the memory's contacts `m` are the scan's `s`, the scan having
/// fallen back to the iterative search or not.
fn agree(m: &[ContactPoint], s: &[ContactPoint], fell_back: bool) -> Result<(), String> {
    let normal_tol = if fell_back {
        FALLBACK_NORMAL_TOL
    } else {
        NORMAL_TOL
    };
    let point_tol = DOME_RADIUS * normal_tol;
    if m.len() != s.len() {
        return Err(format!(
            "{} points remembered, {} scanned",
            m.len(),
            s.len()
        ));
    }
    for (a, b) in m.iter().zip(s) {
        let dd = (a.overlap - b.overlap).abs();
        let dn = (a.normal - b.normal).length();
        let dp = (a.point - b.point).length();
        if dd > DEPTH_TOL || dn > normal_tol || dp > point_tol || a.weight != b.weight {
            return Err(format!(
                "depth {} vs {} ({dd:e}), normal off by {dn:e}, point by {dp:e}, weights {} {}",
                a.overlap, b.overlap, a.weight, b.weight
            ));
        }
    }
    Ok(())
}

#[test]
#[ignore = "slow tier: a settling bed's remembered contacts against a scan at every step"]
fn a_remembered_contact_is_the_scanned_contact() {
    let mut scene = common::scene_file("bed_1k.toml");
    // The settling step: 20× the bed's, so that in 600 steps its contacts
    // move as in 12 000 of its own.
    scene.sim = SimParams::new(2e-5, 0.012, RotatorKind::Pcdm, None, "<test>", "--").unwrap();
    let mut w = World::new(&scene);
    let n = scene.bodies.len();
    let mut memories: HashMap<(u32, u32), PairMemory> = HashMap::new();
    let mut last: Vec<FibreGeom> = vec![FibreGeom::default(); n];
    let (mut remembered, mut scanned, mut touching_memories, mut fell_back, mut passed_over) =
        (0u64, 0u64, 0u64, 0u64, 0u64);
    let (mut worst, mut boxes, mut pairs, mut kept) = ([0.0f64; 3], vec![], vec![], 0u64);
    for _ in 0..scene.sim.steps() {
        w.step::<Pcdm>().expect("the bed stays stable");
        let g: Vec<FibreGeom> = (0..n)
            .map(|i| geom(&scene.bodies[i], &w.states[i]))
            .collect();
        let motion: Vec<f64> = (0..n)
            .map(|i| f64::from(motion_bound(&last[i], &g[i])))
            .collect();
        boxes.clear();
        boxes.extend((0..n).map(|i| aabb(&scene.bodies[i].shape, g[i].centre, g[i].axis)));
        candidate_pairs(&boxes, &mut pairs);
        for &(i, j) in &pairs {
            let (a, b) = (&g[i as usize], &g[j as usize]);
            let memory = memories.entry((i, j)).or_default();
            let before = *memory;
            let (mut m, mut s) = (vec![], vec![]);
            let mut k = KernelCounters::default();
            let spent = motion[i as usize] + motion[j as usize];
            contact_fibre_fibre_remembering(a, b, &mut m, &mut k, Some((memory, spent)));
            if unmarked(before) != before {
                // Kept in its regime: the whole dispatch from the same
                // memory unmarked gives the same bits, counts and memory.
                kept += 1;
                let mut whole = unmarked(before);
                let (mut mw, mut kw) = (vec![], KernelCounters::default());
                contact_fibre_fibre_remembering(a, b, &mut mw, &mut kw, Some((&mut whole, spent)));
                assert_eq!(m, mw, "pair ({i}, {j}) kept at step {}", w.step);
                assert_eq!(format!("{k:?}"), format!("{kw:?}"), "pair ({i}, {j})");
                assert_eq!(unmarked(*memory), unmarked(whole), "pair ({i}, {j})");
            }
            let mut ks = KernelCounters::default();
            contact_fibre_fibre(a, b, &mut s, &mut ks);
            if k.remembered == 1 {
                remembered += 1;
                fell_back += ks.fallbacks;
                touching_memories += u64::from(before.is_touching() && !m.is_empty());
                if let Err(e) = agree(&m, &s, ks.fallbacks > 0) {
                    panic!("pair ({i}, {j}) at step {}: {e}", w.step);
                }
                for (x, y) in m.iter().zip(&s).filter(|_| ks.fallbacks == 0) {
                    worst[0] = worst[0].max((x.overlap - y.overlap).abs());
                    worst[1] = worst[1].max((x.normal - y.normal).length());
                    worst[2] = worst[2].max((x.point - y.point).length());
                }
            } else {
                scanned += k.end_scans;
                passed_over += k.passed_over;
                // A scan is a scan, and a pair passed over (apart in every
                // regime) is apart: the same answer, bit for bit.
                assert_eq!(m, s, "pair ({i}, {j}) scanned at step {}", w.step);
            }
        }
        // A pair whose boxes parted is not asked (it cannot touch), so its
        // memory would not be spent: it forgets (as the stage's list does).
        memories.retain(|p, _| pairs.binary_search(p).is_ok());
        last = g;
    }
    println!(
        "{remembered} remembered ({touching_memories} touching, {kept} kept in their regime; the scan fell back on {fell_back}), {scanned} scanned, {passed_over} passed over (apart in every regime); worst differences where it did not: depth {:e} m, normal {:e}, point {:e} m",
        worst[0], worst[1], worst[2]
    );
    assert!(kept > 300_000, "{kept} kept in their regime");
    // The memories do the work even at 20× the bed's step: 90 % of the
    // end-involved answers, most of them touching.
    assert!(remembered > 5 * scanned, "{remembered} vs {scanned}");
    assert!(touching_memories > 500_000, "{touching_memories}");
    assert!(passed_over > 100_000, "{passed_over}");
}

/// Reference: the scan at each pose. A pair of `bed_10k` over 90 steps
/// whose end-involved depth grows a second local minimum within the tie
/// band of the least (where the scan starts to blend two contacts): its
/// memory, made by an earlier scan, must have run out by then. (A memory
/// whose room counted only the local minima the scan had met, not the
/// other stationary points, answered one contact here for 12 steps.)
#[test]
fn a_minimum_born_near_the_least_ends_the_memory() {
    let text = include_str!("../data/memory_birth_pair.txt");
    let poses: Vec<[FibreGeom; 2]> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            let f = |k: usize| FibreGeom {
                centre: glam::DVec3::new(v[k], v[k + 1], v[k + 2]),
                axis: glam::DVec3::new(v[k + 3], v[k + 4], v[k + 5]),
                radius: 0.005,
                half_length: 0.015,
            };
            [f(0), f(6)]
        })
        .collect();
    assert_eq!(poses.len(), 90);
    let mut memory = PairMemory::default();
    let (mut remembered, mut blended) = (0, 0);
    let mut last = [FibreGeom::default(); 2];
    for (step, [a, b]) in poses.iter().enumerate() {
        let spent = f64::from(motion_bound(&last[0], a)) + f64::from(motion_bound(&last[1], b));
        let (mut m, mut s) = (vec![], vec![]);
        let mut k = KernelCounters::default();
        contact_fibre_fibre_remembering(a, b, &mut m, &mut k, Some((&mut memory, spent)));
        let mut ks = KernelCounters::default();
        contact_fibre_fibre(a, b, &mut s, &mut ks);
        remembered += k.remembered;
        blended += usize::from(s.len() == 2);
        if let Err(e) = agree(&m, &s, ks.fallbacks > 0) {
            panic!("step {step}: {e}");
        }
        last = [*a, *b];
    }
    // The pair is remembered before the birth, and the scan blends after.
    println!("{remembered} remembered, {blended} blended");
    assert!(
        remembered > 30 && blended > 5,
        "{remembered} remembered, {blended} blended"
    );
}

/// The premise of passing over a pair whose cylinders are apart before the
/// regime dispatch (`room_beyond_parallel` in `contact/fibre_fibre/mod.rs`):
/// with its axes out of the parallel band (|a×b| ≥ `PARALLEL_SIN`) no
/// regime touches such a pair (the side–side regime claims only interior
/// closest points there, a true overlap). Inside the band its end model is
/// capsule-like near the other's end, so the pass-over stops before the
/// axes can turn into it. Reference: parry's distance between the flat
/// cylinders, less both domes' sags (the domed cylinders are then apart
/// too). Poses: near-parallel pairs end to end with their ends overlapping
/// sideways (|sin| 0.035–0.06), and pairs at any angle out of the band
/// with B's centre anywhere its capsule can reach A's.
#[test]
fn out_of_the_parallel_band_no_regime_touches_apart_cylinders() {
    use common::{fib, Rng, H, R};
    use fibresim::contact::fibre_fibre::{dome_sag, PARALLEL_SIN};
    use glam::{DQuat, DVec3};
    use parry3d_f64::{math::Pose, query, shape::Cylinder};
    let mut rng = Rng(0x9a1a_11e1_2026_1203);
    let cylinder = Cylinder::new(H, R);
    let pose =
        |f: &FibreGeom| Pose::from_parts(f.centre, DQuat::from_rotation_arc(DVec3::Y, f.axis));
    let mut apart = [0; 2];
    for case in 0..200_000 {
        let a = fib(DVec3::ZERO, DVec3::X);
        let b = if case % 2 == 0 {
            let side = DVec3::new(0.0, rng.next() - 0.5, rng.next() - 0.5).normalize();
            let turn = DVec3::X.cross(rng.unit()).normalize();
            let sin: f64 = PARALLEL_SIN + 0.025 * rng.next();
            let centre = DVec3::new(2.0 * H - 2e-3 * rng.next(), 0.0, 0.0)
                + (1.2 + 0.8 * rng.next()) * R * side;
            fib(centre, DQuat::from_axis_angle(turn, sin.asin()) * DVec3::X)
        } else {
            let reach = 2.0 * (H + R);
            let centre = reach * (2.0 * DVec3::new(rng.next(), rng.next(), rng.next()) - 1.0);
            fib(centre, rng.unit())
        };
        if a.axis.cross(b.axis).length() < PARALLEL_SIN {
            continue;
        }
        let gap = query::distance(&pose(&a), &cylinder, &pose(&b), &cylinder)
            .unwrap()
            .distance;
        let (s, t) = segment_closest_params(&a, &b);
        let capsules = 2.0 * R - (a.centre + s * a.axis - b.centre - t * b.axis).length();
        if gap <= 2.0 * dome_sag(R) + 1e-9 || capsules <= 0.0 {
            continue;
        }
        apart[case % 2] += 1;
        let mut c = vec![];
        contact_fibre_fibre(&a, &b, &mut c, &mut KernelCounters::default());
        assert!(c.is_empty(), "apart by {gap:e} m: {a:?} {b:?} {c:?}");
    }
    println!(
        "apart cylinders, capsules overlapping: {apart:?} (end to end, any angle); none touch"
    );
    assert!(apart[0] > 1000 && apart[1] > 1000, "{apart:?}");
}
