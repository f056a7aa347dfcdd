//! The force stage on many threads, with the bits of one: every candidate
//! (pair or wall) is computed once, in parallel, into a slot of its block
//! (a fixed partition of the candidate list, kept between steps); then
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
    /// δ, m (for an MPI rank's tally; the stage notes it at once).
    #[cfg(feature = "mpi")]
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

/// Candidates per block: the fixed partition of a candidate list into the
/// pool's work items. It does not depend on the thread count (nor does any
/// sum); 256 candidates are ~10⁵–10⁶ instructions of kernels, so a block
/// outweighs the pool's per-item cost and 10⁴ fibres give ~400 blocks to
/// balance the end-involved pairs' 10× cost spread.
pub(super) const BLOCK: usize = 256;

/// The touching candidates of one block of a candidate list, computed on one
/// thread and kept between steps (the buffers never shrink, so a settled
/// scene steps without allocating): per hit its candidate (index in the
/// block) and the end of its points, all points' wrenches in candidate
/// order, their damping loads (empty without damping), and the block's
/// share of the statistics (touching count and largest overlap; the elastic
/// energy is summed over the blocks in order afterwards).
#[derive(Debug, Clone, Default)]
struct Block {
    hits: Vec<(u32, u32)>,
    points: Vec<PointWrench>,
    damp: Vec<DampWrench>,
    stats: ContactStats,
}

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
    wall_blocks: Vec<Block>,
    pair_blocks: Vec<Block>,
    /// Candidate index → index of its hit in its block (`u32::MAX`: no contact).
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

impl Block {
    /// Append the wrench of each of `points` between body `a` (`ga`) and
    /// `b` (`gb`, absent for a wall) as the serial stage's `apply` computes
    /// it, as one hit of candidate `k`; with `damping` (the view, A's and
    /// B's indices) the damping force is added as `apply` adds it, and its
    /// loads are appended. The overlaps are noted in `apply`'s order.
    #[inline]
    fn push(
        &mut self,
        k: usize,
        points: &[ContactPoint],
        law: &HertzLaw,
        (ga, a): (&FibreGeom, usize),
        b: Option<(&FibreGeom, usize)>,
        damping: Option<&DampingView>,
    ) {
        let gb = b.map(|(gb, _)| gb);
        for c in points {
            let mut f_n = c.weight * law.force(c.overlap);
            if let Some(view) = damping {
                let other = b.map(|(gb, b)| (b, gb.centre));
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
                self.damp.push(DampWrench {
                    force: fv,
                    torque_a: (c.point - ga.centre).cross(fv),
                    torque_b: gb.map_or(DVec3::ZERO, |gb| (c.point - gb.centre).cross(fv)),
                });
            }
            let force = f_n * c.normal;
            let u = law.energy(c.overlap);
            let couple = -u * c.weight_grad;
            self.points.push(PointWrench {
                force,
                torque_a: (c.point - ga.centre).cross(force) + couple,
                torque_b: gb.map_or(DVec3::ZERO, |gb| {
                    (c.point - gb.centre).cross(force) + couple
                }),
                energy: c.weight * u,
                #[cfg(feature = "mpi")]
                overlap: c.overlap,
            });
            self.stats.note_overlap(c.overlap / (2.0 * ga.radius), a);
            if let Some((gb, b)) = b {
                self.stats.note_overlap(c.overlap / (2.0 * gb.radius), b);
            }
        }
        self.stats.touching += 1;
        self.hits.push((k as u32, self.points.len() as u32));
    }

    /// The points of hit `s` (an index in `hits`).
    #[inline]
    fn range(&self, s: u32) -> std::ops::Range<usize> {
        let s = s as usize;
        let start = if s == 0 {
            0
        } else {
            self.hits[s - 1].1 as usize
        };
        start..self.hits[s].1 as usize
    }
}

/// Compute every candidate of `candidates` into `blocks` (one per
/// [`BLOCK`] candidates, on the pool) and point `slot` at their hits;
/// returns the kernels' counts. `eval(k, candidate, buffer, counters,
/// block)` pushes candidate `k`'s hit to the block if it touches.
fn compute_blocks<T: Sync>(
    candidates: &[T],
    blocks: &mut Vec<Block>,
    slot: &mut Vec<u32>,
    eval: impl Fn(usize, &T, &mut Vec<ContactPoint>, &mut KernelCounters, &mut Block) + Sync,
) -> KernelCounters {
    blocks.resize_with(candidates.len().div_ceil(BLOCK), Block::default);
    // Every entry is written below, so a resize need not reset them.
    slot.resize(candidates.len(), NONE);
    blocks
        .par_iter_mut()
        .zip(slot.par_chunks_mut(BLOCK))
        .zip(candidates.par_chunks(BLOCK))
        .with_min_len(1)
        .map_init(Vec::new, |buf, ((block, slot), cands)| {
            let mut counters = KernelCounters::default();
            block.hits.clear();
            block.points.clear();
            block.damp.clear();
            block.stats = ContactStats::default();
            for (k, (c, s)) in cands.iter().zip(slot.iter_mut()).enumerate() {
                buf.clear();
                let before = block.hits.len();
                eval(k, c, buf, &mut counters, block);
                *s = if block.hits.len() > before {
                    before as u32
                } else {
                    NONE
                };
            }
            counters
        })
        .reduce(KernelCounters::default, |a, b| a + b)
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
    wall_blocks: &'a [Block],
    pair_blocks: &'a [Block],
}

/// The loads `of` candidate `c`'s hit, if it has one.
#[inline]
fn hit_of<'a, L>(
    blocks: &'a [Block],
    slot: &[u32],
    c: usize,
    of: &impl Fn(&Block) -> &[L],
) -> Option<&'a [L]> {
    let s = slot[c];
    (s != NONE).then(|| {
        let block = &blocks[c / BLOCK];
        &of(block)[block.range(s)]
    })
}

impl Gather<'_> {
    /// Each body's sum of the loads `of` its hits, in the serial order:
    /// its walls, then its pairs in sorted order, each hit's points in order.
    fn sum<L: Load>(
        &self,
        force: &mut [DVec3],
        torque: &mut [DVec3],
        of: impl Fn(&Block) -> &[L] + Sync,
    ) {
        let inc = self.inc;
        force
            .par_iter_mut()
            .zip(torque.par_iter_mut())
            .enumerate()
            .for_each(|(b, (f, t))| {
                let (mut fb, mut tb) = (DVec3::ZERO, DVec3::ZERO);
                for w in inc.walls[b]..inc.walls[b + 1] {
                    let hit = hit_of(self.wall_blocks, self.wall_slot, w as usize, &of);
                    for p in hit.into_iter().flatten() {
                        let (pf, pa, _) = p.parts();
                        fb += pf;
                        tb += pa;
                    }
                }
                let range = inc.start[b] as usize..inc.start[b + 1] as usize;
                for &entry in &inc.pairs[range] {
                    let (c, a_side) = (entry & !SIDE_B, entry & SIDE_B == 0);
                    let Some(hit) = hit_of(self.pair_blocks, self.pair_slot, c as usize, &of)
                    else {
                        continue;
                    };
                    for p in hit {
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
        let (view, loads) = match damping {
            Some((d, bodies, states)) => {
                let view = d.view(bodies, states);
                (Some(view), Some(d.loads()))
            }
            None => (None, None),
        };
        let view = view.as_ref();
        // Walls and pairs in one fork: the walls' few blocks need not wait
        // for a pool of their own.
        let (wall_counts, pair_counts) = rayon::join(
            || {
                compute_blocks(
                    &list.walls,
                    &mut self.wall_blocks,
                    &mut self.wall_slot,
                    |k, &(i, w), buf, c, out| {
                        let (g, i) = (&geoms[i as usize], i as usize);
                        contacts(
                            Collider::Fibre(g),
                            Collider::Wall(&walls[w as usize]),
                            buf,
                            c,
                        );
                        if !buf.is_empty() {
                            out.push(k, buf, laws.fibre_wall(i), (g, i), None, view);
                        }
                    },
                )
            },
            || {
                compute_blocks(
                    &list.pairs,
                    &mut self.pair_blocks,
                    &mut self.pair_slot,
                    |k, &(a, b), buf, c, out| {
                        let (a, b) = (a as usize, b as usize);
                        let (ga, gb) = (&geoms[a], &geoms[b]);
                        contacts(Collider::Fibre(ga), Collider::Fibre(gb), buf, c);
                        if !buf.is_empty() {
                            let law = &laws.fibre_fibre(a, b);
                            out.push(k, buf, law, (ga, a), Some((gb, b)), view);
                        }
                    },
                )
            },
        );
        *counters = *counters + wall_counts + pair_counts;

        // Gather: each body sums its slots in the serial order (and so its
        // damping loads, for the ledger).
        let gather = Gather {
            inc: &self.incidence,
            wall_slot: &self.wall_slot,
            pair_slot: &self.pair_slot,
            wall_blocks: &self.wall_blocks,
            pair_blocks: &self.pair_blocks,
        };
        gather.sum(force, torque, |b| &b.points);
        if let Some((df, dt)) = loads {
            gather.sum(df, dt, |b| &b.damp);
        }

        // The statistics in the serial order (walls, then pairs): the
        // blocks' counts and first largest overlaps, then the energy summed
        // point by point (a sum of partial sums would round differently).
        let mut stats = ContactStats::default();
        let blocks = self.wall_blocks.iter().chain(&self.pair_blocks);
        for part in blocks.clone().map(|b| &b.stats) {
            stats.touching += part.touching;
            stats.note_overlap(part.max_overlap_ratio, part.max_overlap_body);
        }
        for p in blocks.flat_map(|b| &b.points) {
            stats.elastic += p.energy;
        }
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
        for (n, block) in self.wall_blocks.iter().enumerate() {
            for (s, &(k, _)) in block.hits.iter().enumerate() {
                let candidate = (n * BLOCK) as u32 + k;
                let a = list.walls[candidate as usize].0 as usize;
                let ra = 2.0 * geoms[a].radius;
                f(
                    true,
                    candidate,
                    &mut block.points[block.range(s as u32)]
                        .iter()
                        .map(|p| [p.energy, p.overlap / ra, 0.0]),
                );
            }
        }
        for (n, block) in self.pair_blocks.iter().enumerate() {
            for (s, &(k, _)) in block.hits.iter().enumerate() {
                let candidate = (n * BLOCK) as u32 + k;
                let (a, b) = list.pairs[candidate as usize];
                let (ra, rb) = (
                    2.0 * geoms[a as usize].radius,
                    2.0 * geoms[b as usize].radius,
                );
                f(
                    false,
                    candidate,
                    &mut block.points[block.range(s as u32)]
                        .iter()
                        .map(|p| [p.energy, p.overlap / ra, p.overlap / rb]),
                );
            }
        }
    }
}
