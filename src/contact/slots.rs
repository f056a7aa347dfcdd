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
/// force on A (elastic plus damping) and where it acts, and what the
/// statistics need. The torques are rebuilt in the gather with the serial
/// stage's expression, `(p − c) × F (+ couple)`, from the body's own centre:
/// 56 bytes a point instead of the 80 of force and both torques.
#[derive(Debug, Clone, Copy)]
struct PointLoad {
    force: DVec3,
    point: DVec3,
    /// `weight · U(δ)`, J.
    energy: f64,
    /// δ, m (for an MPI rank's tally; the stage notes it at once).
    #[cfg(feature = "mpi")]
    overlap: f64,
}

/// Candidates per block: the fixed partition of a candidate list into the
/// pool's work items. It does not depend on the thread count (nor does any
/// sum); 256 candidates are ~10⁵–10⁶ instructions of kernels, so a block
/// outweighs the pool's per-item cost and 10⁴ fibres give ~400 blocks to
/// balance the end-involved pairs' 10× cost spread.
pub(super) const BLOCK: usize = 256;

/// The touching candidates of one block of a candidate list, computed on one
/// thread and kept between steps: which candidates touch (a bit each; a
/// hit's index is the count of set bits before it), per hit the end of its
/// points, all points in candidate order, the couples of the few points
/// whose weight has a gradient (by point index; the others' couple is zero,
/// and `x + (±0)` adds nothing to a sum that starts at +0), the points'
/// damping forces (empty without damping), and the block's share of the
/// statistics (touching count and largest overlap; the elastic energy is
/// summed over the blocks in order afterwards). The buffers are trimmed
/// with hysteresis ([`trim`]), so a settled scene steps without allocating.
#[derive(Debug, Clone, Default)]
struct Block {
    touched: [u64; BLOCK / 64],
    ends: Vec<u16>,
    points: Vec<PointLoad>,
    couples: Vec<(u16, DVec3)>,
    damp: Vec<DVec3>,
    stats: ContactStats,
}

/// For each body, its candidates in the serial stage's order (rebuilt with
/// the neighbour list): its walls (the list is body-major), the pairs it is
/// side B of (sorted by side A), then its own row of pairs (the list is
/// sorted `(i, j)`, so a body's side-A pairs are contiguous).
#[derive(Debug, Clone, Default)]
struct Incidence {
    /// Per body, the range of its wall candidates (`walls[b]..walls[b+1]`).
    walls: Vec<u32>,
    /// Per body, the range of its row (side A) in the pair list.
    rows: Vec<u32>,
    /// Per body, the range of its entries in `side_b`.
    b_start: Vec<u32>,
    /// The pairs each body is side B of, ascending.
    side_b: Vec<u32>,
    /// The neighbour-list build this was made for.
    build: u64,
}

/// The parallel stage's buffers, kept between steps.
#[derive(Debug, Clone, Default)]
pub(crate) struct Slots {
    incidence: Incidence,
    wall_blocks: Vec<Block>,
    pair_blocks: Vec<Block>,
}

/// Per body `0..n`, the start of its entries among `keys` (ascending),
/// and the end: `n + 1` offsets (CSR).
fn offsets(n: usize, keys: impl Iterator<Item = u32>, out: &mut Vec<u32>) {
    out.clear();
    out.resize(n + 1, 0);
    for k in keys {
        out[k as usize + 1] += 1;
    }
    for b in 0..n {
        out[b + 1] += out[b];
    }
}

impl Incidence {
    fn rebuild(&mut self, n: usize, list: &NeighbourList) {
        assert!(
            list.pairs.len() <= u32::MAX as usize,
            "fewer than 2^32 candidate pairs"
        );
        // The serial order the gather reproduces rests on these.
        assert!(
            list.pairs.iter().all(|&(i, j)| i < j) && list.pairs.is_sorted(),
            "pairs (i < j), sorted"
        );
        assert!(
            list.walls.is_sorted_by_key(|w| w.0),
            "wall candidates body-major"
        );
        offsets(n, list.walls.iter().map(|w| w.0), &mut self.walls);
        offsets(n, list.pairs.iter().map(|p| p.0), &mut self.rows);
        offsets(n, list.pairs.iter().map(|p| p.1), &mut self.b_start);
        // Pushing each pair to its side B in list order gives each body
        // its side-B pairs in the serial order (ascending side A).
        self.side_b.clear();
        self.side_b.resize(list.pairs.len(), 0);
        let mut fill = self.b_start.clone();
        for (k, &(_, j)) in list.pairs.iter().enumerate() {
            let at = &mut fill[j as usize];
            self.side_b[*at as usize] = k as u32;
            *at += 1;
        }
        // Exact sizes: rebuilt only with the list, kept in between.
        self.side_b.shrink_to_fit();
        self.build = list.builds;
    }
}

/// Release what `v` holds beyond its length with hysteresis: keep up to
/// 1/8 (+8) spare, else cut back to 1/16 (+4) spare. A block's count moves
/// by a few per step in a settled scene, which the spare absorbs, so such
/// a scene steps without allocating; a block that grows past it
/// reallocates once (Vec's doubling, then this trim).
fn trim<T>(v: &mut Vec<T>) {
    let len = v.len();
    if v.capacity() > len + len / 8 + 8 {
        v.shrink_to(len + len / 16 + 4);
    }
}

impl Block {
    /// Append the loads of each of `points` between body `a` (`ga`) and
    /// `b` (`gb`, absent for a wall) as the serial stage's `apply` computes
    /// them, as the hit of candidate `k` (the block's next); with `damping`
    /// (the view, A's and B's indices) the damping force is added as
    /// `apply` adds it, and kept apart for the ledger. The overlaps are
    /// noted in `apply`'s order.
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
                self.damp.push(d * c.normal);
            }
            let u = law.energy(c.overlap);
            let couple = -u * c.weight_grad;
            if couple != DVec3::ZERO {
                self.couples.push((index(self.points.len()), couple));
            }
            self.points.push(PointLoad {
                force: f_n * c.normal,
                point: c.point,
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
        self.touched[k / 64] |= 1 << (k % 64);
        self.ends.push(index(self.points.len()));
    }

    /// The points of candidate `k` (index in the block), if it touches.
    #[inline]
    fn hit(&self, k: usize) -> Option<std::ops::Range<usize>> {
        let (word, bit) = (k / 64, k % 64);
        if self.touched[word] & (1 << bit) == 0 {
            return None;
        }
        let below = self.touched[..word]
            .iter()
            .map(|w| w.count_ones())
            .sum::<u32>()
            + (self.touched[word] & ((1 << bit) - 1)).count_ones();
        Some(self.range(below as usize))
    }

    /// The points of hit `s` (in block order).
    #[inline]
    fn range(&self, s: usize) -> std::ops::Range<usize> {
        let start = if s == 0 { 0 } else { self.ends[s - 1] as usize };
        start..self.ends[s] as usize
    }

    fn clear(&mut self) {
        self.touched = [0; BLOCK / 64];
        self.ends.clear();
        self.points.clear();
        self.couples.clear();
        self.damp.clear();
        self.stats = ContactStats::default();
    }

    fn trim(&mut self) {
        trim(&mut self.ends);
        trim(&mut self.points);
        trim(&mut self.couples);
        trim(&mut self.damp);
    }
}

/// A point's index in its block (a block's 256 candidates have a few
/// points each, far below 2¹⁶).
#[inline]
fn index(i: usize) -> u16 {
    u16::try_from(i).expect("fewer than 2^16 contact points in a block")
}

thread_local! {
    /// Each pool thread's kernel output buffer, kept for the thread's life
    /// (a per-job buffer would allocate on every step).
    static BUF: std::cell::RefCell<Vec<ContactPoint>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Compute every candidate of `candidates` into `blocks` (one per
/// [`BLOCK`] candidates, on the pool); returns the kernels' counts.
/// `eval(k, candidate, buffer, counters, block)` pushes candidate `k`'s hit
/// to the block if it touches.
fn compute_blocks<T: Sync>(
    candidates: &[T],
    blocks: &mut Vec<Block>,
    eval: impl Fn(usize, &T, &mut Vec<ContactPoint>, &mut KernelCounters, &mut Block) + Sync,
) -> KernelCounters {
    blocks.resize_with(candidates.len().div_ceil(BLOCK), Block::default);
    blocks
        .par_iter_mut()
        .zip(candidates.par_chunks(BLOCK))
        .with_min_len(1)
        .map(|(block, cands)| {
            let mut counters = KernelCounters::default();
            block.clear();
            BUF.with_borrow_mut(|buf| {
                for (k, c) in cands.iter().enumerate() {
                    buf.clear();
                    eval(k, c, buf, &mut counters, block);
                }
            });
            block.trim();
            counters
        })
        .reduce(KernelCounters::default, |a, b| a + b)
}

/// The loads of one kind a contact point puts on its two bodies: a force
/// on A acting at the point (B gets minus it), with or without the
/// weight's couple.
trait Load {
    /// Whether the point's torque carries the weight's couple.
    const COUPLES: bool;
    fn force(block: &Block, i: usize) -> DVec3;
}

/// The Hertz force with its damping part (`PointLoad::force`).
struct Total;

impl Load for Total {
    const COUPLES: bool = true;
    #[inline]
    fn force(block: &Block, i: usize) -> DVec3 {
        block.points[i].force
    }
}

/// The damping part alone, for the ledger (`Damping::account`).
struct DampingPart;

impl Load for DampingPart {
    const COUPLES: bool = false;
    #[inline]
    fn force(block: &Block, i: usize) -> DVec3 {
        block.damp[i]
    }
}

/// The hits of one computation, indexed per body.
struct Gather<'a> {
    inc: &'a Incidence,
    geoms: &'a [FibreGeom],
    wall_blocks: &'a [Block],
    pair_blocks: &'a [Block],
}

/// Add to `(f, t)` the loads `L` of candidate `c`'s hit, if it has one, on
/// a body centred at `centre` (side A: `sign` +1, side B: −1), point by
/// point as the serial stage does: `F`, then `(p − c) × F (+ couple)`.
#[inline]
fn add<L: Load>(
    blocks: &[Block],
    c: usize,
    centre: DVec3,
    side_a: bool,
    f: &mut DVec3,
    t: &mut DVec3,
) {
    let block = &blocks[c / BLOCK];
    let Some(range) = block.hit(c % BLOCK) else {
        return;
    };
    let mut next = if L::COUPLES && !block.couples.is_empty() {
        block
            .couples
            .partition_point(|e| (e.0 as usize) < range.start)
    } else {
        block.couples.len()
    };
    for i in range {
        let force = L::force(block, i);
        let mut torque = (block.points[i].point - centre).cross(force);
        if L::COUPLES {
            if let Some(&(j, couple)) = block.couples.get(next) {
                if j as usize == i {
                    torque += couple;
                    next += 1;
                }
            }
        }
        if side_a {
            *f += force;
            *t += torque;
        } else {
            *f -= force;
            *t -= torque;
        }
    }
}

impl Gather<'_> {
    /// Each body's sum of its loads `L`, in the serial order: its walls,
    /// then its pairs in sorted order (side B of pairs `(i, b)`, then its
    /// own row `(b, j)`), each hit's points in order.
    fn sum<L: Load>(&self, force: &mut [DVec3], torque: &mut [DVec3]) {
        let inc = self.inc;
        force
            .par_iter_mut()
            .zip(torque.par_iter_mut())
            .enumerate()
            .for_each(|(b, (f, t))| {
                let centre = self.geoms[b].centre;
                let (mut fb, mut tb) = (DVec3::ZERO, DVec3::ZERO);
                for w in inc.walls[b]..inc.walls[b + 1] {
                    add::<L>(self.wall_blocks, w as usize, centre, true, &mut fb, &mut tb);
                }
                let side_b = inc.b_start[b] as usize..inc.b_start[b + 1] as usize;
                for &c in &inc.side_b[side_b] {
                    add::<L>(
                        self.pair_blocks,
                        c as usize,
                        centre,
                        false,
                        &mut fb,
                        &mut tb,
                    );
                }
                for c in inc.rows[b]..inc.rows[b + 1] {
                    add::<L>(self.pair_blocks, c as usize, centre, true, &mut fb, &mut tb);
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
        if self.incidence.build != list.builds || self.incidence.rows.len() != n + 1 {
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

        // Gather: each body sums its hits in the serial order (and so its
        // damping loads, for the ledger).
        let gather = Gather {
            inc: &self.incidence,
            geoms,
            wall_blocks: &self.wall_blocks,
            pair_blocks: &self.pair_blocks,
        };
        gather.sum::<Total>(force, torque);
        if let Some((df, dt)) = loads {
            gather.sum::<DampingPart>(df, dt);
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
impl Block {
    /// Each hit's candidate (index in the block) and its points, in order.
    fn hits(&self) -> impl Iterator<Item = (usize, &[PointLoad])> {
        let touched = (0..BLOCK).filter(|k| self.touched[k / 64] & (1 << (k % 64)) != 0);
        touched
            .enumerate()
            .map(|(s, k)| (k, &self.points[self.range(s)]))
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
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let a = list.walls[candidate as usize].0 as usize;
                let ra = 2.0 * geoms[a].radius;
                f(
                    true,
                    candidate,
                    &mut points.iter().map(|p| [p.energy, p.overlap / ra, 0.0]),
                );
            }
        }
        for (n, block) in self.pair_blocks.iter().enumerate() {
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let (a, b) = list.pairs[candidate as usize];
                let (ra, rb) = (
                    2.0 * geoms[a as usize].radius,
                    2.0 * geoms[b as usize].radius,
                );
                f(
                    false,
                    candidate,
                    &mut points
                        .iter()
                        .map(|p| [p.energy, p.overlap / ra, p.overlap / rb]),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::trim;

    /// The hysteresis of [`trim`]: a buffer whose length moves by a few
    /// per step around 1000 keeps its allocation (the steady state makes
    /// none), and one whose length halves is cut back to within 1/8 + 8
    /// of it (the heap follows the contacts down).
    #[test]
    fn trim_keeps_a_steady_buffer_and_releases_a_shrunk_one() {
        // As a block's buffer after its first fill: grown past its length.
        let mut v: Vec<u64> = Vec::with_capacity(2000);
        v.extend(0..1000);
        trim(&mut v);
        let (ptr, cap) = (v.as_ptr(), v.capacity());
        assert!((1062..=1133).contains(&cap), "spare kept: {cap}");
        for len in [1003, 998, 1040, 990, 1010, 1000] {
            v.resize(len, 0);
            trim(&mut v);
            assert_eq!((v.as_ptr(), v.capacity()), (ptr, cap), "length {len}");
        }
        v.truncate(500);
        trim(&mut v);
        assert!(v.capacity() <= 500 + 500 / 8 + 8, "{}", v.capacity());
    }
}
