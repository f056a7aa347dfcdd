//! The force stage on many threads, with the bits of one: every candidate
//! (pair or wall) is computed once, in parallel, into its own slot; then
//! each body gathers its slots in the order the serial stage sums them
//! (its walls, then its pairs in sorted order, each pair's points in
//! order), and the scene statistics are reduced in that order too. Forces,
//! torques and energies are therefore bit-identical to the serial stage,
//! whatever the thread count.

use super::broad::NeighbourList;
use super::damping::{Damping, DampingView};
use super::laws::LawTable;
use super::stage::ContactStats;
use super::{contacts, Collider, ContactPoint, FibreGeom, HertzLaw, KernelCounters, Wall};
use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

/// One contact point's share of a candidate's wrench, computed once: the
/// force on A, the torques on A and B about their centres, and what the
/// statistics need.
#[derive(Debug, Clone, Copy)]
struct PointWrench {
    force: DVec3,
    torque_a: DVec3,
    torque_b: DVec3,
    /// `weight · U(δ)`, J.
    energy: f64,
    overlap: f64,
}

/// One contact point's damping load, for the ledger (`Damping::account`):
/// the damping part of the force on A and its torques on A and B.
#[derive(Debug, Clone, Copy)]
struct DampWrench {
    force: DVec3,
    torque_a: DVec3,
    torque_b: DVec3,
}

/// A candidate that touches: its index in the neighbour list, its points,
/// and their damping loads (empty, never allocated, without damping).
#[derive(Debug, Clone)]
struct Hit {
    candidate: u32,
    points: SmallVec<[PointWrench; 1]>,
    damp: Vec<DampWrench>,
}

/// What a candidate's evaluation gives: its points' wrenches and damping loads.
type Wrenches = (SmallVec<[PointWrench; 1]>, Vec<DampWrench>);

/// For each body, its pair candidates in the serial stage's order, with the
/// side it is on (CSR, rebuilt with the neighbour list).
#[derive(Debug, Clone, Default)]
struct Incidence {
    /// Per body, the range of its entries in `pairs` (`start[b]..start[b+1]`).
    start: Vec<u32>,
    /// The candidate, with [`SIDE_B`] set when the body is its side B.
    pairs: Vec<u32>,
    /// Per body, the range of its wall candidates (body-major in the list).
    walls: Vec<u32>,
    /// The neighbour-list build this was made for.
    build: u64,
}

/// The parallel stage's buffers, kept between steps.
#[derive(Debug, Clone, Default)]
pub(crate) struct Slots {
    incidence: Incidence,
    wall_hits: Vec<Hit>,
    pair_hits: Vec<Hit>,
    /// Candidate index → index in the hits (`u32::MAX`: no contact).
    wall_slot: Vec<u32>,
    pair_slot: Vec<u32>,
}

const NONE: u32 = u32::MAX;

/// The flag of an incidence entry whose body is the pair's side B (pair
/// indices stay below 2³¹: ten pairs per fibre for 2×10⁸ fibres).
const SIDE_B: u32 = 1 << 31;

impl Incidence {
    fn rebuild(&mut self, n: usize, list: &NeighbourList) {
        // Pairs are sorted `(i, j)`, so pushing each pair to both bodies in
        // list order gives each body its pairs in the serial order.
        let mut count = vec![0u32; n + 1];
        for &(i, j) in &list.pairs {
            count[i as usize + 1] += 1;
            count[j as usize + 1] += 1;
        }
        for b in 0..n {
            count[b + 1] += count[b];
        }
        let mut fill = count.clone();
        self.pairs.clear();
        assert!(
            list.pairs.len() < SIDE_B as usize,
            "fewer than 2^31 candidate pairs"
        );
        self.pairs.resize(list.pairs.len() * 2, 0);
        for (k, &(i, j)) in list.pairs.iter().enumerate() {
            for (b, side) in [(i, 0), (j, SIDE_B)] {
                let at = &mut fill[b as usize];
                self.pairs[*at as usize] = k as u32 | side;
                *at += 1;
            }
        }
        self.start = count;
        self.walls.clear();
        self.walls.resize(n + 1, 0);
        for &(i, _) in &list.walls {
            self.walls[i as usize + 1] += 1;
        }
        for b in 0..n {
            self.walls[b + 1] += self.walls[b];
        }
        self.build = list.builds;
    }
}

/// The wrench of each of `points` between A (`ga`) and B (`gb`, absent for
/// a wall), as the serial stage's `apply` computes it; with `damping`
/// (the view, A's and B's indices) the damping force is added as `apply`
/// adds it, and its loads are returned.
#[inline]
fn wrenches(
    points: &[ContactPoint],
    law: &HertzLaw,
    ga: &FibreGeom,
    gb: Option<&FibreGeom>,
    damping: Option<(&DampingView, usize, Option<usize>)>,
) -> Wrenches {
    let mut damp = Vec::new();
    let wrenches = points
        .iter()
        .map(|c| {
            let mut f_n = c.weight * law.force(c.overlap);
            if let Some((view, a, b)) = damping {
                let other = b.zip(gb).map(|(b, gb)| (b, gb.centre));
                let d = view.force(
                    (a, ga.centre),
                    other,
                    law.stiffness(),
                    c.weight,
                    c.point,
                    c.normal,
                    c.overlap,
                );
                f_n += d;
                let fv = d * c.normal;
                damp.push(DampWrench {
                    force: fv,
                    torque_a: (c.point - ga.centre).cross(fv),
                    torque_b: gb.map_or(DVec3::ZERO, |gb| (c.point - gb.centre).cross(fv)),
                });
            }
            let force = f_n * c.normal;
            let u = law.energy(c.overlap);
            let couple = -u * c.weight_grad;
            PointWrench {
                force,
                torque_a: (c.point - ga.centre).cross(force) + couple,
                torque_b: gb.map_or(DVec3::ZERO, |gb| {
                    (c.point - gb.centre).cross(force) + couple
                }),
                energy: c.weight * u,
                overlap: c.overlap,
            }
        })
        .collect();
    (wrenches, damp)
}

/// Compute every candidate of `list` in parallel into `hits` (in candidate
/// order), and their kernel counts.
fn compute_hits<T: Sync>(
    candidates: &[T],
    hits: &mut Vec<Hit>,
    eval: impl Fn(&T, &mut Vec<ContactPoint>, &mut KernelCounters) -> Option<Wrenches> + Sync,
) -> KernelCounters {
    let (list, counters) = candidates
        .par_iter()
        .enumerate()
        .fold(
            || (Vec::new(), Vec::new(), KernelCounters::default()),
            |(mut out, mut buf, mut counters): (Vec<Hit>, Vec<ContactPoint>, KernelCounters),
             (k, c)| {
                buf.clear();
                if let Some((points, damp)) = eval(c, &mut buf, &mut counters) {
                    out.push(Hit {
                        candidate: k as u32,
                        points,
                        damp,
                    });
                }
                (out, buf, counters)
            },
        )
        .map(|(out, _, counters)| (vec![out], counters))
        .reduce(
            || (Vec::new(), KernelCounters::default()),
            |(mut a, ca), (b, cb)| {
                a.extend(b);
                (a, ca + cb)
            },
        );
    hits.clear();
    for part in list {
        hits.extend(part);
    }
    counters
}

/// Point `slot` at the hits (resetting the previous step's).
fn index_hits(slot: &mut Vec<u32>, len: usize, previous: &[Hit], hits: &[Hit]) {
    if slot.len() != len {
        slot.clear();
        slot.resize(len, NONE);
    } else {
        for h in previous {
            slot[h.candidate as usize] = NONE;
        }
    }
    for (k, h) in hits.iter().enumerate() {
        slot[h.candidate as usize] = k as u32;
    }
}

/// A load one contact point puts on its two bodies: the force on A and the
/// torques on A and B (B gets minus the force).
trait Load {
    fn parts(&self) -> (DVec3, DVec3, DVec3);
}

impl Load for PointWrench {
    #[inline]
    fn parts(&self) -> (DVec3, DVec3, DVec3) {
        (self.force, self.torque_a, self.torque_b)
    }
}

impl Load for DampWrench {
    #[inline]
    fn parts(&self) -> (DVec3, DVec3, DVec3) {
        (self.force, self.torque_a, self.torque_b)
    }
}

/// The hits of one computation, indexed per body.
struct Gather<'a> {
    inc: &'a Incidence,
    wall_slot: &'a [u32],
    pair_slot: &'a [u32],
    wall_hits: &'a [Hit],
    pair_hits: &'a [Hit],
}

impl Gather<'_> {
    /// Each body's sum of the loads `of` its hits, in the serial order:
    /// its walls, then its pairs in sorted order, each hit's points in order.
    fn sum<L: Load>(
        &self,
        force: &mut [DVec3],
        torque: &mut [DVec3],
        of: impl Fn(&Hit) -> &[L] + Sync,
    ) {
        let inc = self.inc;
        force
            .par_iter_mut()
            .zip(torque.par_iter_mut())
            .enumerate()
            .for_each(|(b, (f, t))| {
                let (mut fb, mut tb) = (DVec3::ZERO, DVec3::ZERO);
                for w in inc.walls[b]..inc.walls[b + 1] {
                    let s = self.wall_slot[w as usize];
                    if s != NONE {
                        for p in of(&self.wall_hits[s as usize]) {
                            let (pf, pa, _) = p.parts();
                            fb += pf;
                            tb += pa;
                        }
                    }
                }
                let range = inc.start[b] as usize..inc.start[b + 1] as usize;
                for &entry in &inc.pairs[range] {
                    let (c, a_side) = (entry & !SIDE_B, entry & SIDE_B == 0);
                    let s = self.pair_slot[c as usize];
                    if s == NONE {
                        continue;
                    }
                    for p in of(&self.pair_hits[s as usize]) {
                        let (pf, pa, pb) = p.parts();
                        if a_side {
                            fb += pf;
                            tb += pa;
                        } else {
                            fb -= pf;
                            tb -= pb;
                        }
                    }
                }
                *f = fb;
                *t = tb;
            });
    }
}

impl Slots {
    /// The contact forces and torques of every body, and the scene
    /// statistics, bit for bit as the serial stage computes them; with
    /// `damping` (and the velocities in `states`), the damping forces and
    /// their per-body loads too.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn compute(
        &mut self,
        list: &NeighbourList,
        geoms: &[FibreGeom],
        walls: &[Wall],
        laws: &LawTable,
        force: &mut [DVec3],
        torque: &mut [DVec3],
        counters: &mut KernelCounters,
        damping: Option<(
            &mut Damping,
            &[crate::body::Body],
            &[crate::body::BodyState],
        )>,
    ) -> ContactStats {
        let n = geoms.len();
        if self.incidence.build != list.builds || self.incidence.start.len() != n + 1 {
            self.incidence.rebuild(n, list);
        }
        let previous_walls = std::mem::take(&mut self.wall_hits);
        let previous_pairs = std::mem::take(&mut self.pair_hits);
        let mut wall_hits = Vec::new();
        let mut pair_hits = Vec::new();
        let (view, loads) = match damping {
            Some((d, bodies, states)) => {
                let view = d.view(bodies, states);
                (Some(view), Some(d.loads()))
            }
            None => (None, None),
        };
        let view = view.as_ref();
        *counters = *counters
            + compute_hits(&list.walls, &mut wall_hits, |&(i, k), buf, c| {
                let g = &geoms[i as usize];
                contacts(
                    Collider::Fibre(g),
                    Collider::Wall(&walls[k as usize]),
                    buf,
                    c,
                );
                let damping = view.map(|v| (v, i as usize, None));
                (!buf.is_empty())
                    .then(|| wrenches(buf, laws.fibre_wall(i as usize), g, None, damping))
            });
        *counters = *counters
            + compute_hits(&list.pairs, &mut pair_hits, |&(a, b), buf, c| {
                let (ga, gb) = (&geoms[a as usize], &geoms[b as usize]);
                contacts(Collider::Fibre(ga), Collider::Fibre(gb), buf, c);
                let damping = view.map(|v| (v, a as usize, Some(b as usize)));
                (!buf.is_empty()).then(|| {
                    let law = &laws.fibre_fibre(a as usize, b as usize);
                    wrenches(buf, law, ga, Some(gb), damping)
                })
            });
        index_hits(
            &mut self.wall_slot,
            list.walls.len(),
            &previous_walls,
            &wall_hits,
        );
        index_hits(
            &mut self.pair_slot,
            list.pairs.len(),
            &previous_pairs,
            &pair_hits,
        );

        // Gather: each body sums its slots in the serial order (and so its
        // damping loads, for the ledger).
        let gather = Gather {
            inc: &self.incidence,
            wall_slot: &self.wall_slot,
            pair_slot: &self.pair_slot,
            wall_hits: &wall_hits,
            pair_hits: &pair_hits,
        };
        gather.sum(force, torque, |h| &h.points);
        if let Some((df, dt)) = loads {
            gather.sum(df, dt, |h| &h.damp);
        }

        // The statistics, reduced in the serial order (walls, then pairs).
        let mut stats = ContactStats::default();
        for h in &wall_hits {
            let a = list.walls[h.candidate as usize].0 as usize;
            stats.touching += 1;
            for p in &h.points {
                stats.elastic += p.energy;
                stats.note_overlap(p.overlap / (2.0 * geoms[a].radius), a);
            }
        }
        for h in &pair_hits {
            let (a, b) = list.pairs[h.candidate as usize];
            let (a, b) = (a as usize, b as usize);
            stats.touching += 1;
            for p in &h.points {
                stats.elastic += p.energy;
                stats.note_overlap(p.overlap / (2.0 * geoms[a].radius), a);
                stats.note_overlap(p.overlap / (2.0 * geoms[b].radius), b);
            }
        }
        self.wall_hits = wall_hits;
        self.pair_hits = pair_hits;
        stats
    }
}

#[cfg(feature = "mpi")]
impl Slots {
    /// Each hit of the last [`Slots::compute`], walls first, in candidate
    /// order: `(wall, candidate, points)`, each point `[weight·U, δ/D on A,
    /// δ/D on B]` as the statistics of [`Slots::compute`] note them (an MPI
    /// rank's share of the scene statistics, `src/ranks/tally.rs`).
    pub(crate) fn for_each_hit(
        &self,
        list: &NeighbourList,
        geoms: &[FibreGeom],
        mut f: impl FnMut(bool, u32, &mut dyn Iterator<Item = [f64; 3]>),
    ) {
        for h in &self.wall_hits {
            let a = list.walls[h.candidate as usize].0 as usize;
            let ra = 2.0 * geoms[a].radius;
            f(
                true,
                h.candidate,
                &mut h.points.iter().map(|p| [p.energy, p.overlap / ra, 0.0]),
            );
        }
        for h in &self.pair_hits {
            let (a, b) = list.pairs[h.candidate as usize];
            let (ra, rb) = (
                2.0 * geoms[a as usize].radius,
                2.0 * geoms[b as usize].radius,
            );
            f(
                false,
                h.candidate,
                &mut h
                    .points
                    .iter()
                    .map(|p| [p.energy, p.overlap / ra, p.overlap / rb]),
            );
        }
    }
}
