//! The force stage on many threads, with the bits of one: every candidate
//! (pair or wall) is computed once, in parallel, into a slot of its block
//! (a fixed partition of the candidate list); then each body adds its slots
//! in the order the serial stage sums them, and the scene statistics are
//! reduced in that order too. Forces, torques and energies are therefore
//! bit-identical to the serial stage, whatever the thread count.
//!
//! The serial order of a body's sum is the candidate list's: its walls
//! (the list is body-major), then its pairs in sorted `(i, j)` order (its
//! side-B pairs `(i, b)`, `i < b`, all come before its own row). So the
//! list can be computed a window of blocks at a time, each window's loads
//! added before the next window's: only two windows' slots are held (one
//! being added while the next is computed), not the whole list's (issue 10
//! item 7).

use super::broad::NeighbourList;
use super::damping::{Damping, DampingView};
use super::fibre_fibre::PairMemory;
use super::laws::LawTable;
use super::stage::ContactStats;
use super::{
    contacts, contacts_remembering, Collider, ContactPoint, FibreGeom, HertzLaw, KernelCounters,
    Wall,
};
use glam::DVec3;
use rayon::prelude::*;

/// One contact point's loads on its two bodies, computed once with the
/// serial stage's expressions: the force on A (B gets minus it) and the
/// torques `(p − c) × F (+ couple)` about each body's own centre (A's
/// added, B's subtracted). With the torques made here, where the kernel
/// has both centres at hand, the gather only adds: it reads no geometry
/// (when it rebuilt them, from the point, it took 13 % of a step on one
/// thread, its random reads of the centres mostly).
#[derive(Debug, Clone, Copy)]
struct Wrench {
    force: DVec3,
    torque_a: DVec3,
    /// Zero for a wall.
    torque_b: DVec3,
}

impl Wrench {
    /// The wrench of the force `f` at `p` between A (centre `ca`) and B
    /// (centre `cb`, none for a wall), with the weight's `couple` if any
    /// (the damping force has none), each torque as the serial stage makes it.
    #[inline(always)]
    fn new(f: DVec3, p: DVec3, couple: Option<DVec3>, ca: DVec3, cb: Option<DVec3>) -> Self {
        let torque = |c: DVec3| {
            let t = (p - c).cross(f);
            couple.map_or(t, |couple| t + couple)
        };
        Wrench {
            force: f,
            torque_a: torque(ca),
            torque_b: cb.map_or(DVec3::ZERO, torque),
        }
    }
}

/// One contact point's share of a candidate's loads and what the
/// statistics need.
#[derive(Debug, Clone, Copy)]
struct PointLoad {
    /// Elastic plus damping.
    wrench: Wrench,
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

/// Blocks per window: the candidates computed before their loads are
/// added (2048). Two windows' slots are held (one being added while the
/// next is computed), ~0.25 MB in a settled bed: at 16 blocks `bed_10k`'s
/// copy of 10⁵ fibres held 514 B per fibre on 2 threads, at 8 506 B, at the
/// same speed (the pipeline hides the windows' ends). The bits do not
/// depend on it (nor on [`BLOCK`]).
const WINDOW: usize = 8;

/// The touching candidates of one block of a candidate list, computed on one
/// thread: which candidates touch (a bit each; a hit's index is the count
/// of set bits before it), per hit the end of its points, all points in
/// candidate order, the points' damping loads
/// (empty without damping), and the block's share of the statistics
/// (touching count and largest overlap; the elastic energy is summed over
/// the blocks in order afterwards). A block serves every window of a step;
/// its buffers are trimmed to the step's largest use with hysteresis
/// ([`trim`]), so a settled scene steps without allocating.
#[derive(Debug, Clone, Default)]
struct Block {
    touched: [u64; BLOCK / 64],
    ends: Vec<u16>,
    points: Vec<PointLoad>,
    damp: Vec<Wrench>,
    stats: ContactStats,
    /// The largest lengths of `ends`, `points`, `damp` in this step's
    /// windows (what [`Block::trim`] keeps).
    high: [usize; 3],
}

/// The parallel stage's buffers, kept between steps: two windows' blocks
/// of wall and of pair candidates (the first set all of them when the
/// stage keeps every hit for [`Slots::for_each_hit`]).
#[derive(Debug, Clone)]
pub(crate) struct Slots {
    /// Two sets, one being added while the next window is computed into
    /// the other ([`Sums::windows`]).
    wall_blocks: [Vec<Block>; 2],
    pair_blocks: [Vec<Block>; 2],
    /// Blocks per window ([`WINDOW`]; tests make it smaller).
    pub(super) window: usize,
    /// The neighbour-list build whose order was last checked.
    checked: u64,
}

impl Default for Slots {
    fn default() -> Self {
        Slots {
            wall_blocks: [vec![], vec![]],
            pair_blocks: [vec![], vec![]],
            window: WINDOW,
            checked: 0,
        }
    }
}

/// Release what `v` holds beyond a use of `len` with hysteresis: keep up
/// to 1/8 (+8) spare, else cut back to 1/16 (+4) spare. A block's count
/// moves by a few per step in a settled scene, which the spare absorbs, so
/// such a scene steps without allocating; a block that grows past it
/// reallocates once (Vec's doubling, then this trim).
fn trim<T>(v: &mut Vec<T>, len: usize) {
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
    /// noted in `apply`'s order. (Inlined, as `apply` is.)
    #[inline(always)]
    fn push(
        &mut self,
        k: usize,
        points: &[ContactPoint],
        law: &HertzLaw,
        (ga, a): (&FibreGeom, usize),
        b: Option<(&FibreGeom, usize)>,
        damping: Option<&DampingView>,
    ) {
        let cb = b.map(|(gb, _)| gb.centre);
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
                let fd = d * c.normal;
                self.damp
                    .push(Wrench::new(fd, c.point, None, ga.centre, cb));
            }
            let u = law.energy(c.overlap);
            let couple = -u * c.weight_grad;
            self.points.push(PointLoad {
                wrench: Wrench::new(f_n * c.normal, c.point, Some(couple), ga.centre, cb),
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

    /// The points of hit `s` (in block order).
    #[inline]
    fn range(&self, s: usize) -> std::ops::Range<usize> {
        let start = if s == 0 { 0 } else { self.ends[s - 1] as usize };
        start..self.ends[s] as usize
    }

    /// Ready for the next window (its use noted for [`Block::trim`]).
    fn clear(&mut self) {
        let lens = [self.ends.len(), self.points.len(), self.damp.len()];
        for (h, l) in self.high.iter_mut().zip(lens) {
            *h = (*h).max(l);
        }
        self.touched = [0; BLOCK / 64];
        self.ends.clear();
        self.points.clear();
        self.damp.clear();
        self.stats = ContactStats::default();
    }

    /// At the end of a step: release what the step's windows did not use.
    fn trim(&mut self) {
        self.clear();
        let [e, p, d] = std::mem::take(&mut self.high);
        trim(&mut self.ends, e);
        trim(&mut self.points, p);
        trim(&mut self.damp, d);
    }

    /// Each hit's candidate (index in the block), in order.
    #[inline]
    fn hits(&self) -> impl Iterator<Item = usize> + '_ {
        self.touched.iter().enumerate().flat_map(|(w, &word)| {
            let mut bits = word;
            std::iter::from_fn(move || {
                (bits != 0).then(|| {
                    let k = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    64 * w + k
                })
            })
        })
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

/// What the stage computes a candidate with: the candidate, its memory
/// (pairs; `()` for walls), the kernels' output buffer, counters, and the
/// block its hit goes to.
trait Eval<T, M>:
    Fn(usize, &T, &mut M, &mut Vec<ContactPoint>, &mut KernelCounters, &mut Block) + Sync
{
}

impl<T, M, F> Eval<T, M> for F where
    F: Fn(usize, &T, &mut M, &mut Vec<ContactPoint>, &mut KernelCounters, &mut Block) + Sync
{
}

/// Compute every candidate of `candidates` (with its entry of `memory`)
/// into the first of `blocks` (one per [`BLOCK`] candidates, on the pool;
/// more are made if needed); returns how many blocks it used and the
/// kernels' counts. `eval(k, candidate, memory, buffer, counters, block)`
/// pushes candidate `k`'s hit to the block if it touches.
fn compute_blocks<T: Sync, M: Send>(
    candidates: &[T],
    memory: &mut [M],
    blocks: &mut Vec<Block>,
    eval: &impl Eval<T, M>,
) -> (usize, KernelCounters) {
    let used = candidates.len().div_ceil(BLOCK);
    if blocks.len() < used {
        blocks.resize_with(used, Block::default);
    }
    let counters = blocks[..used]
        .par_iter_mut()
        .zip(candidates.par_chunks(BLOCK))
        .zip(memory.par_chunks_mut(BLOCK))
        .with_min_len(1)
        .map(|((block, cands), memory)| {
            let mut counters = KernelCounters::default();
            block.clear();
            BUF.with_borrow_mut(|buf| {
                for (k, (c, m)) in cands.iter().zip(memory).enumerate() {
                    buf.clear();
                    eval(k, c, m, buf, &mut counters, block);
                }
            });
            counters
        })
        .reduce(KernelCounters::default, |a, b| a + b);
    (used, counters)
}

/// Which loads of a block's points a gather adds.
trait Load {
    fn wrench(block: &Block, i: usize) -> &Wrench;
}

/// The Hertz force with its damping part (`PointLoad::wrench`).
struct Total;

impl Load for Total {
    #[inline]
    fn wrench(block: &Block, i: usize) -> &Wrench {
        &block.points[i].wrench
    }
}

/// The damping part alone, for the ledger (`Damping::account`).
struct DampingPart;

impl Load for DampingPart {
    #[inline]
    fn wrench(block: &Block, i: usize) -> &Wrench {
        &block.damp[i]
    }
}

/// Add the loads `L` of a window's `blocks` to the bodies' sums, point by
/// point in candidate order as the serial stage does: side A `+F`, `+τ_A`,
/// side B `−F`, `−τ_B`. `bodies(candidate)` are its body A and body B
/// (none for a wall); `cands` are the window's.
#[inline]
fn add_window<L: Load, T>(
    blocks: &[Block],
    cands: &[T],
    bodies: &impl Fn(&T) -> (usize, Option<usize>),
    force: &mut [DVec3],
    torque: &mut [DVec3],
) {
    for (n, block) in blocks.iter().enumerate() {
        for (s, k) in block.hits().enumerate() {
            let (a, b) = bodies(&cands[n * BLOCK + k]);
            for i in block.range(s) {
                let w = L::wrench(block, i);
                force[a] += w.force;
                torque[a] += w.torque_a;
                if let Some(b) = b {
                    force[b] -= w.force;
                    torque[b] -= w.torque_b;
                }
            }
        }
    }
}

/// Add a window's statistics to `stats` in the serial order: the blocks'
/// counts and first largest overlaps, then the energy point by point (a
/// sum of partial sums would round differently).
fn reduce(blocks: &[Block], stats: &mut ContactStats) {
    for part in blocks.iter().map(|b| &b.stats) {
        stats.touching += part.touching;
        stats.note_overlap(part.max_overlap_ratio, part.max_overlap_body);
    }
    for p in blocks.iter().flat_map(|b| &b.points) {
        stats.elastic += p.energy;
    }
}

/// Where a window's loads go: each body's forces and torques, its damping
/// loads (damped scenes), the statistics and the kernels' counts.
struct Sums<'a> {
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    damping: Option<(&'a mut [DVec3], &'a mut [DVec3])>,
    stats: ContactStats,
    counters: KernelCounters,
}

impl Sums<'_> {
    /// Compute `candidates` (with their `memory`, one each) a `window` at a
    /// time (`eval` as in [`compute_blocks`]) and add each window's loads
    /// and statistics in the serial order before the next's; `bodies(candidate)`
    /// are its body A and body B (none for a wall). Pipelined: while one
    /// thread adds a window's loads, the others compute the next window
    /// (into `blocks[0]` and `blocks[1]` in turn), then join it. The adding reads
    /// the whole window whatever body range it covers, so split over the
    /// threads it did not run faster; overlapped, it costs its share of a
    /// thread's time.
    fn windows<T: Sync, M: Send>(
        &mut self,
        candidates: &[T],
        memory: &mut [M],
        window: usize,
        blocks: &mut [Vec<Block>; 2],
        eval: impl Eval<T, M>,
        bodies: impl Fn(&T) -> (usize, Option<usize>) + Sync,
    ) {
        let mut chunks = candidates.chunks(window).zip(memory.chunks_mut(window));
        let Some((first, first_memory)) = chunks.next() else {
            return;
        };
        let [mut front, mut back] = blocks.each_mut();
        // The window computed into `front` and not yet added.
        let (mut ready, mut done) = (first, compute_blocks(first, first_memory, front, &eval));
        for (cands, memory) in chunks {
            let ((), next) = rayon::join(
                || self.add(&front[..done.0], ready, done.1, &bodies),
                || compute_blocks(cands, memory, back, &eval),
            );
            std::mem::swap(&mut front, &mut back);
            (ready, done) = (cands, next);
        }
        self.add(&front[..done.0], ready, done.1, &bodies);
    }

    /// Add a computed window (its `blocks`, candidates `cands` and kernel
    /// `counts`) to the sums, in the serial order.
    fn add<T>(
        &mut self,
        blocks: &[Block],
        cands: &[T],
        counts: KernelCounters,
        bodies: &impl Fn(&T) -> (usize, Option<usize>),
    ) {
        self.counters = self.counters + counts;
        add_window::<Total, T>(blocks, cands, bodies, self.force, self.torque);
        if let Some((df, dt)) = &mut self.damping {
            add_window::<DampingPart, T>(blocks, cands, bodies, df, dt);
        }
        reduce(blocks, &mut self.stats);
    }
}

impl Slots {
    /// The contact forces and torques of every body (overwritten), and the
    /// scene statistics, bit for bit as the serial stage computes them;
    /// with `damping` (and the velocities in `states`), the damping forces
    /// and their per-body loads too. With `keep_hits` the whole list is
    /// one window, whose hits stay for [`Slots::for_each_hit`].
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn compute(
        &mut self,
        list: &mut NeighbourList,
        geoms: &[FibreGeom],
        motion: &[f32],
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
        keep_hits: bool,
    ) -> ContactStats {
        // The last step's hits (kept for `for_each_hit`) go; what its
        // windows did not use is released.
        let sets = self.wall_blocks.iter_mut().chain(&mut self.pair_blocks);
        sets.flatten().for_each(Block::trim);
        force.fill(DVec3::ZERO);
        torque.fill(DVec3::ZERO);
        let (view, loads) = match damping {
            Some((d, bodies, states)) => {
                let view = d.view(bodies, states);
                (Some(view), Some(d.loads()))
            }
            None => (None, None),
        };
        let view = view.as_ref();
        let window = if keep_hits {
            usize::MAX
        } else {
            self.window * BLOCK
        };
        if self.checked != list.builds {
            // The serial order the windows reproduce rests on these.
            assert!(
                list.pairs.iter().all(|&(i, j)| i < j) && list.pairs.is_sorted(),
                "pairs (i < j), sorted"
            );
            assert!(
                list.walls.is_sorted_by_key(|w| w.0),
                "wall candidates body-major"
            );
            self.checked = list.builds;
        }
        let mut sums = Sums {
            force,
            torque,
            damping: loads,
            stats: ContactStats::default(),
            counters: *counters,
        };
        // Walls first, then pairs: each body's serial order. (Walls
        // remember nothing: a zero-sized entry each, no allocation.)
        sums.windows(
            &list.walls,
            &mut vec![(); list.walls.len()],
            window,
            &mut self.wall_blocks,
            |k, &(i, w), _: &mut (), buf, c, out| {
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
            |&(i, _)| (i as usize, None),
        );
        sums.windows(
            &list.pairs,
            &mut list.memory,
            window,
            &mut self.pair_blocks,
            |k, &(a, b), memory: &mut PairMemory, buf, c, out| {
                let (a, b) = (a as usize, b as usize);
                let (ga, gb) = (&geoms[a], &geoms[b]);
                let motion = f64::from(motion[a]) + f64::from(motion[b]);
                let m = Some((memory, motion));
                contacts_remembering(Collider::Fibre(ga), Collider::Fibre(gb), buf, c, m);
                if !buf.is_empty() {
                    let law = &laws.fibre_fibre(a, b);
                    out.push(k, buf, law, (ga, a), Some((gb, b)), view);
                }
            },
            |&(a, b)| (a as usize, Some(b as usize)),
        );
        *counters = sums.counters;
        sums.stats
    }
}

#[cfg(feature = "mpi")]
impl Slots {
    /// Each hit of the last [`Slots::compute`] (with `keep_hits`), walls
    /// first, in candidate order: `(wall, candidate, points)`, each point
    /// `[weight·U, δ/D on A, δ/D on B]` as the statistics of
    /// [`Slots::compute`] note them (an MPI rank's share of the scene
    /// statistics, `src/ranks/tally.rs`).
    pub(crate) fn for_each_hit(
        &self,
        list: &NeighbourList,
        geoms: &[FibreGeom],
        mut f: impl FnMut(bool, u32, &mut dyn Iterator<Item = [f64; 3]>),
    ) {
        // With `keep_hits` the first blocks hold the whole list.
        let (walls, pairs) = (list.walls.len(), list.pairs.len());
        for (n, block) in self.wall_blocks[0][..walls.div_ceil(BLOCK)]
            .iter()
            .enumerate()
        {
            for (s, k) in block.hits().enumerate() {
                let candidate = (n * BLOCK + k) as u32;
                let a = list.walls[candidate as usize].0 as usize;
                let ra = 2.0 * geoms[a].radius;
                let points = &block.points[block.range(s)];
                f(
                    true,
                    candidate,
                    &mut points.iter().map(|p| [p.energy, p.overlap / ra, 0.0]),
                );
            }
        }
        for (n, block) in self.pair_blocks[0][..pairs.div_ceil(BLOCK)]
            .iter()
            .enumerate()
        {
            for (s, k) in block.hits().enumerate() {
                let candidate = (n * BLOCK + k) as u32;
                let (a, b) = list.pairs[candidate as usize];
                let (ra, rb) = (
                    2.0 * geoms[a as usize].radius,
                    2.0 * geoms[b as usize].radius,
                );
                let points = &block.points[block.range(s)];
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
        trim(&mut v, 1000);
        let (ptr, cap) = (v.as_ptr(), v.capacity());
        assert!((1062..=1133).contains(&cap), "spare kept: {cap}");
        for len in [1003, 998, 1040, 990, 1010, 1000] {
            v.resize(len, 0);
            trim(&mut v, len);
            assert_eq!((v.as_ptr(), v.capacity()), (ptr, cap), "length {len}");
        }
        v.truncate(500);
        trim(&mut v, 500);
        assert!(v.capacity() <= 500 + 500 / 8 + 8, "{}", v.capacity());
    }
}
