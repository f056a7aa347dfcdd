//! The force stage on many threads, with the bits of one: every candidate
//! (pair or wall) is computed once, in parallel, into its block (a fixed
//! partition of the candidate list); the blocks' loads are then added to
//! the bodies in the order the serial stage sums them, and the scene
//! statistics are reduced in that order too. Forces, torques and energies
//! are therefore bit-identical to the serial stage, whatever the thread
//! count.
//!
//! The serial order of a body's sum is the candidate list's: its walls
//! (the list is body-major), then its pairs in sorted `(i, j)` order (its
//! side-B pairs `(i, b)`, `i < b`, all come before its own row). So the
//! blocks can be added one at a time in list order, each as soon as it and
//! those before it are computed: the pool's threads take the blocks in
//! order, compute each into a ring of [`RING`] slots, and whichever thread
//! finds the oldest computed block not yet added adds it. Only the ring's
//! blocks are held, not the whole list's (memory stays flat in N); a thread waits
//! only when the ring is full (the adding is behind) and at the list's end.

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
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// One contact point's loads on its two bodies, computed once with the
/// serial stage's expressions: the force on A (B gets minus it) and the
/// torques `(p − c) × F (+ couple)` about each body's own centre (A's
/// added, B's subtracted). With the torques made here, where the kernel
/// has both centres at hand, the gather only adds: it reads no geometry
/// (when it rebuilt them, from the point, its random reads of the centres
/// made it a noticeable share of a step on one thread).
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
/// sum); 256 candidates' kernels outweigh the pool's per-item cost by far,
/// and 10⁴ fibres still give ~400 blocks to balance the end-involved
/// pairs' uneven costs.
pub(super) const BLOCK: usize = 256;

/// Blocks in flight: block `n` is computed into slot `n % RING` once block
/// `n − RING` has been added. 16 blocks: 4096 candidates, ~0.25 MB in a
/// settled bed, as the two windows of 8 before them held; on two threads
/// no thread waited for a slot in any step of `bed_10k` or of the AR-10
/// bed of 10⁵ (counted in a temporary build). The bits do not depend on
/// it (nor on [`BLOCK`]).
const RING: usize = 16;

/// The touching candidates of one block of a candidate list, computed on one
/// thread: per hit (touching candidate) its index in the block and the
/// end of its points, all points in candidate order, the points' damping
/// loads (empty without damping), and the block's share of the statistics
/// (touching count and largest overlap; the elastic energy is summed over
/// the blocks in order afterwards), the kernels' counts, and which block
/// of the list it holds. A slot serves many blocks of a step; its buffers
/// are trimmed to the step's largest use with hysteresis ([`trim`]), so a
/// settled scene steps without allocating.
#[derive(Debug, Default)]
struct Block {
    hits: Vec<(u8, u16)>,
    points: Vec<PointLoad>,
    damp: Vec<Wrench>,
    stats: ContactStats,
    counters: KernelCounters,
    /// `n + 1` once block `n` of the list is computed here (0: none yet;
    /// set by [`compute_block`], reset per list by [`Sums::in_order`]).
    computed: usize,
    /// The largest lengths of `hits`, `points`, `damp` in this step's
    /// blocks (what [`Block::trim`] keeps).
    high: [usize; 3],
}

/// A ring of block slots (each locked by the thread computing or adding it).
type Ring = Vec<Mutex<Block>>;

/// The parallel stage's buffers, kept between steps: the rings of wall and
/// of pair candidates (holding every block of the list when the stage
/// keeps every hit for [`Slots::for_each_hit`]).
#[derive(Debug)]
pub(crate) struct Slots {
    wall_ring: Ring,
    pair_ring: Ring,
    /// Blocks in flight ([`RING`]; tests make it smaller).
    pub(super) ring: usize,
    /// The neighbour-list build whose order was last checked.
    checked: u64,
}

impl Default for Slots {
    fn default() -> Self {
        Slots {
            wall_ring: vec![],
            pair_ring: vec![],
            ring: RING,
            checked: 0,
        }
    }
}

/// A copy's slots start empty: they hold nothing between steps but
/// buffers (and, after an MPI rank's computation, its hits, which the
/// rank reads before anything is copied).
impl Clone for Slots {
    fn clone(&self) -> Self {
        Slots {
            ring: self.ring,
            ..Slots::default()
        }
    }
}

/// Run `work` on `threads` threads of the pool (a tree of `rayon::join`s:
/// unlike a scope's spawns, no allocation). A `work` not taken by another
/// thread runs after the first, when the list is taken (or abandoned).
fn on_threads(threads: usize, work: &(impl Fn() + Sync)) {
    if threads <= 1 {
        work();
    } else {
        let half = threads / 2;
        rayon::join(
            || on_threads(half, work),
            || on_threads(threads - half, work),
        );
    }
}

/// Sets its flag if dropped by a panicking thread.
struct OnPanic<'a>(&'a AtomicBool);

impl Drop for OnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.store(true, Ordering::Relaxed);
        }
    }
}

/// The slot behind `m`. A thread that panicked while holding it (a bug in
/// a kernel) has already taken the step down with it: the pool's join
/// re-raises the panic, and the slot is cleared (and its poison) before a
/// stage caught and reused computes again ([`Slots::compute`]).
#[inline]
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
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
        self.hits.push((candidate(k), point(self.points.len())));
    }

    /// Ready for the next block (its use noted for [`Block::trim`]).
    fn clear(&mut self) {
        let lens = [self.hits.len(), self.points.len(), self.damp.len()];
        for (h, l) in self.high.iter_mut().zip(lens) {
            *h = (*h).max(l);
        }
        self.hits.clear();
        self.points.clear();
        self.damp.clear();
        self.stats = ContactStats::default();
        self.counters = KernelCounters::default();
    }

    /// At the end of a step: release what the step's blocks did not use.
    fn trim(&mut self) {
        self.clear();
        let [h, p, d] = std::mem::take(&mut self.high);
        trim(&mut self.hits, h);
        trim(&mut self.points, p);
        trim(&mut self.damp, d);
    }

    /// Each hit's candidate (index in the block) and the range of its
    /// points, in order.
    #[inline]
    fn hits(&self) -> impl Iterator<Item = (usize, std::ops::Range<usize>)> + '_ {
        let mut start = 0;
        self.hits.iter().map(move |&(k, end)| {
            let points = start..usize::from(end);
            start = usize::from(end);
            (usize::from(k), points)
        })
    }
}

/// A candidate's index in its block, one byte ([`BLOCK`] is 256 at most).
#[inline]
fn candidate(k: usize) -> u8 {
    const { assert!(BLOCK <= 256) };
    k as u8
}

/// A point's index in its block (a block's 256 candidates have a few
/// points each, far below 2¹⁶).
#[inline]
fn point(i: usize) -> u16 {
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

/// Compute block `n` of a candidate list (its `candidates` with their
/// `memory`, one each) into `block`: `eval(k, candidate, memory, buffer,
/// counters, block)` pushes candidate `k`'s hit to the block if it
/// touches.
fn compute_block<T, M>(
    n: usize,
    candidates: &[T],
    memory: &mut [M],
    block: &mut Block,
    eval: &impl Eval<T, M>,
) {
    block.clear();
    let mut counters = KernelCounters::default();
    BUF.with_borrow_mut(|buf| {
        for (k, (c, m)) in candidates.iter().zip(memory).enumerate() {
            buf.clear();
            eval(k, c, m, buf, &mut counters, block);
        }
    });
    block.counters = counters;
    block.computed = n + 1;
}

/// Which loads of a block's points a gather adds.
trait Load {
    /// A block's record of each point, in point order.
    type Record;
    fn records(block: &Block) -> &[Self::Record];
    fn wrench(record: &Self::Record) -> &Wrench;
}

/// The Hertz force with its damping part (`PointLoad::wrench`).
struct Total;

impl Load for Total {
    type Record = PointLoad;
    #[inline]
    fn records(block: &Block) -> &[PointLoad] {
        &block.points
    }
    #[inline]
    fn wrench(record: &PointLoad) -> &Wrench {
        &record.wrench
    }
}

/// The damping part alone, for the ledger (`Damping::account`).
struct DampingPart;

impl Load for DampingPart {
    type Record = Wrench;
    #[inline]
    fn records(block: &Block) -> &[Wrench] {
        &block.damp
    }
    #[inline]
    fn wrench(record: &Wrench) -> &Wrench {
        record
    }
}

/// Add the loads `L` of a computed `block` to the bodies' sums, point by
/// point in candidate order as the serial stage does: side A `+F`, `+τ_A`,
/// side B `−F`, `−τ_B`. `bodies(candidate)` are its body A and body B
/// (none for a wall); `cands` are the block's.
#[inline]
fn add_block<L: Load, T>(
    block: &Block,
    cands: &[T],
    bodies: &impl Fn(&T) -> (usize, Option<usize>),
    force: &mut [DVec3],
    torque: &mut [DVec3],
) {
    let records = L::records(block);
    for (k, points) in block.hits() {
        let (a, b) = bodies(&cands[k]);
        for w in records[points].iter().map(L::wrench) {
            force[a] += w.force;
            torque[a] += w.torque_a;
            if let Some(b) = b {
                force[b] -= w.force;
                torque[b] -= w.torque_b;
            }
        }
    }
}

/// Where the blocks' loads go: each body's forces and torques, its damping
/// loads (damped scenes), the statistics and the kernels' counts.
struct Sums<'a> {
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    damping: Option<(&'a mut [DVec3], &'a mut [DVec3])>,
    stats: ContactStats,
    counters: KernelCounters,
}

impl Sums<'_> {
    /// Add a computed `block` (its candidates `cands`) to the sums, and
    /// its statistics, in the serial order: the counts and the first
    /// largest overlap, then the energy point by point (a sum of partial
    /// sums would round differently).
    fn add<T>(
        &mut self,
        block: &Block,
        cands: &[T],
        bodies: &impl Fn(&T) -> (usize, Option<usize>),
    ) {
        self.counters = self.counters + block.counters;
        add_block::<Total, T>(block, cands, bodies, self.force, self.torque);
        if let Some((df, dt)) = &mut self.damping {
            add_block::<DampingPart, T>(block, cands, bodies, df, dt);
        }
        self.stats.touching += block.stats.touching;
        let (ratio, body) = (block.stats.max_overlap_ratio, block.stats.max_overlap_body);
        self.stats.note_overlap(ratio, body);
        for p in &block.points {
            self.stats.elastic += p.energy;
        }
    }

    /// Compute `candidates` (with their `memory`, one each; `eval` as in
    /// [`compute_block`]) on every thread of the pool, into the `size`
    /// slots of `ring` (made if missing), and add each block's loads in
    /// list order; `bodies(candidate)` are its body A and body B (none for
    /// a wall). The threads take the blocks in order; after each, a thread
    /// adds every block that is next in order and computed, unless another
    /// thread is adding; a thread whose next block's slot still holds a
    /// block not added adds or waits. So the adding (serial: it reads any
    /// body) overlaps the computing, and the threads meet once, at the
    /// list's end, not at every window of blocks.
    fn in_order<T: Sync, M: Send>(
        &mut self,
        candidates: &[T],
        memory: &mut [M],
        ring: &mut Ring,
        size: usize,
        eval: impl Eval<T, M>,
        bodies: impl Fn(&T) -> (usize, Option<usize>) + Sync,
    ) {
        let total = candidates.len().div_ceil(BLOCK);
        let size = size.min(total).max(1);
        if ring.len() < size {
            ring.resize_with(size, Mutex::default);
        }
        // No slot holds a block of this list yet (a slot's `computed`
        // marks a block of the last call too, whose number may recur).
        for slot in &mut ring[..size] {
            slot.get_mut()
                .unwrap_or_else(PoisonError::into_inner)
                .computed = 0;
        }
        let ring = &ring[..size];
        // The blocks not yet taken, in order.
        let next = Mutex::new(
            candidates
                .chunks(BLOCK)
                .zip(memory.chunks_mut(BLOCK))
                .enumerate(),
        );
        // Blocks added so far (the sums' lock orders its updates).
        let added = AtomicUsize::new(0);
        let sums = Mutex::new(self);
        // Add the computed blocks that are next in order, unless another
        // thread holds the sums (it adds them); whether any was added.
        let add_ready = || {
            let mut any = false;
            while let Ok(mut sums) = sums.try_lock() {
                let mut n = added.load(Ordering::Relaxed);
                while n < total {
                    // A slot locked is being computed (or read): not ready.
                    let Ok(block) = ring[n % size].try_lock() else {
                        break;
                    };
                    if block.computed != n + 1 {
                        break;
                    }
                    sums.add(&block, &candidates[n * BLOCK..], &bodies);
                    drop(block);
                    n += 1;
                    added.store(n, Ordering::Release);
                    any = true;
                }
                drop(sums);
                // A block finished while the sums were held may have found
                // them taken and left its adding to this thread: look again
                // now rather than at the next thread's block (the final
                // loop below would add it anyway).
                let ready =
                    n < total && ring[n % size].try_lock().is_ok_and(|b| b.computed == n + 1);
                if !ready {
                    break;
                }
            }
            any
        };
        // Set by a thread that panics (a kernel's bug): the others take no
        // more blocks and stop waiting for its block, and the join
        // re-raises the panic.
        let abandoned = AtomicBool::new(false);
        // (`eval` must not use the pool: a thread waiting in a kernel for
        // rayon work could take a second `work` that waits for its block.)
        let work = || {
            let _panic = OnPanic(&abandoned);
            while !abandoned.load(Ordering::Relaxed) {
                // (A statement of its own: the lock is released at its end.)
                let taken = lock(&next).next();
                let Some((n, (cands, memory))) = taken else {
                    return;
                };
                // Slot `n % size` is free once block `n − size` is added.
                while n >= added.load(Ordering::Acquire) + size {
                    if abandoned.load(Ordering::Relaxed) {
                        return;
                    }
                    if !add_ready() {
                        std::thread::yield_now();
                    }
                }
                compute_block(n, cands, memory, &mut lock(&ring[n % size]), &eval);
                add_ready();
            }
        };
        on_threads(rayon::current_num_threads(), &work);
        // Every block is computed; what the threads left is added here.
        let sums = sums.into_inner().unwrap_or_else(PoisonError::into_inner);
        for n in added.into_inner()..total {
            let block = lock(&ring[n % size]);
            assert_eq!(
                block.computed,
                n + 1,
                "block {n} computed before its adding"
            );
            sums.add(&block, &candidates[n * BLOCK..], &bodies);
        }
    }
}

impl Slots {
    /// The contact forces and torques of every body (overwritten), and the
    /// scene statistics, bit for bit as the serial stage computes them;
    /// with `damping` (and the velocities in `states`), the damping forces
    /// and their per-body loads too. With `keep_hits` the rings hold the
    /// whole list, whose hits stay for [`Slots::for_each_hit`].
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
        // blocks did not use is released.
        let slots = self.wall_ring.iter_mut().chain(&mut self.pair_ring);
        slots.for_each(|b| {
            // (A slot poisoned by a panic caught above: `try_lock` would
            // call it busy forever.)
            b.clear_poison();
            b.get_mut().unwrap_or_else(PoisonError::into_inner).trim();
        });
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
        let size = if keep_hits { usize::MAX } else { self.ring };
        if self.checked != list.builds {
            // The serial order the blocks are added in rests on these.
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
        sums.in_order(
            &list.walls,
            &mut vec![(); list.walls.len()],
            &mut self.wall_ring,
            size,
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
        sums.in_order(
            &list.pairs,
            &mut list.memory,
            &mut self.pair_ring,
            size,
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
        // With `keep_hits` the rings hold the whole list.
        let (walls, pairs) = (list.walls.len(), list.pairs.len());
        for (n, block) in self.wall_ring[..walls.div_ceil(BLOCK)]
            .iter()
            .map(lock)
            .enumerate()
        {
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let a = list.walls[candidate as usize].0 as usize;
                let ra = 2.0 * geoms[a].radius;
                let points = &block.points[points];
                f(
                    true,
                    candidate,
                    &mut points.iter().map(|p| [p.energy, p.overlap / ra, 0.0]),
                );
            }
        }
        for (n, block) in self.pair_ring[..pairs.div_ceil(BLOCK)]
            .iter()
            .map(lock)
            .enumerate()
        {
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let (a, b) = list.pairs[candidate as usize];
                let (ra, rb) = (
                    2.0 * geoms[a as usize].radius,
                    2.0 * geoms[b as usize].radius,
                );
                let points = &block.points[points];
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
    use super::*;

    /// A candidate's pseudo-random load (a hash of its index, in [−1, 1);
    /// not a stream like `fibre_fibre/uniform.rs`: the blocks are computed
    /// in any order, and each candidate's load must not depend on it).
    fn load(c: u32, salt: u64) -> f64 {
        let mut x = u64::from(c)
            .wrapping_add(salt)
            .wrapping_mul(0x9e37_79b9_7f4a_7c15);
        x ^= x >> 29;
        x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x ^= x >> 32;
        2.0 * ((x >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }

    /// Candidate `c`'s wrench and energy, if it touches (two in three do).
    fn hit(c: u32, salt: u64) -> Option<(Wrench, f64)> {
        let f = DVec3::new(load(c, salt), load(c, salt + 7), 1.0);
        let p = DVec3::new(load(c, salt + 1), 0.5, load(c, salt + 2));
        let wrench = Wrench::new(f, p, None, DVec3::ZERO, Some(DVec3::X));
        (!c.is_multiple_of(3)).then_some((wrench, load(c, salt + 3)))
    }

    /// A candidate's two bodies (of 12).
    fn bodies(c: &u32) -> (usize, Option<usize>) {
        ((c % 7) as usize, Some((7 + c % 5) as usize))
    }

    /// The bits of [`ordered`] by a plain loop over the candidates in order.
    fn serial(n: usize) -> Vec<u64> {
        let (mut force, mut torque) = (vec![DVec3::ZERO; 12], vec![DVec3::ZERO; 12]);
        let mut elastic = vec![];
        for salt in [1, 2] {
            force.fill(DVec3::ZERO);
            torque.fill(DVec3::ZERO);
            let mut e = 0.0;
            for c in 0..n as u32 {
                if let Some((w, energy)) = hit(c, salt) {
                    let (a, b) = bodies(&c);
                    let b = b.unwrap();
                    force[a] += w.force;
                    torque[a] += w.torque_a;
                    force[b] -= w.force;
                    torque[b] -= w.torque_b;
                    e += energy;
                }
            }
            elastic.push(e);
        }
        (force.iter().chain(&torque))
            .flat_map(|v| v.to_array())
            .chain(elastic)
            .map(f64::to_bits)
            .collect()
    }

    /// Forces, torques and energy of `n` synthetic candidates added by
    /// [`Sums::in_order`] (`threads`, a ring of `size`, twice on one ring),
    /// and how many times each candidate was computed.
    fn ordered(n: usize, threads: usize, size: usize) -> (Vec<u64>, Vec<u32>) {
        let candidates: Vec<u32> = (0..n as u32).collect();
        let mut computed = vec![0u32; n];
        let mut ring: Ring = vec![];
        let (mut force, mut torque) = (vec![DVec3::ZERO; 12], vec![DVec3::ZERO; 12]);
        let mut elastic = vec![];
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for salt in [1, 2] {
            force.fill(DVec3::ZERO);
            torque.fill(DVec3::ZERO);
            let mut sums = Sums {
                force: &mut force,
                torque: &mut torque,
                damping: None,
                stats: ContactStats::default(),
                counters: KernelCounters::default(),
            };
            pool.install(|| {
                sums.in_order(
                    &candidates,
                    &mut computed,
                    &mut ring,
                    size,
                    |k, &c, times: &mut u32, _, _, block: &mut Block| {
                        *times += 1;
                        // Blocks of uneven cost, so that they finish out of order.
                        let spin = (load(c / BLOCK as u32, salt) + 1.0) * 2e4;
                        (0..spin as u32).for_each(|i| {
                            std::hint::black_box(i);
                        });
                        if let Some((wrench, energy)) = hit(c, salt) {
                            block.points.push(PointLoad {
                                wrench,
                                energy,
                                #[cfg(feature = "mpi")]
                                overlap: 0.0,
                            });
                            block.hits.push((candidate(k), point(block.points.len())));
                        }
                    },
                    bodies,
                );
            });
            elastic.push(sums.stats.elastic);
        }
        let bits = (force.iter().chain(&torque))
            .flat_map(|v| v.to_array())
            .chain(elastic)
            .map(f64::to_bits)
            .collect();
        (bits, computed)
    }

    /// [`Sums::in_order`] adds every block once, in list order, with the
    /// bits of a plain loop over the candidates, on 1 to 8 threads, rings
    /// of 1 to 3 slots or the whole list, lists of 0 to 17 blocks (the
    /// last one partial), reusing its ring for a second list. Run on a
    /// watchdog: a hang (a wait that never ends) fails the test.
    #[test]
    fn blocks_are_added_once_each_in_list_order() {
        let (done, wait) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for blocks in [0, 1, 2, 3, 5, 17] {
                let n = (blocks * BLOCK).saturating_sub(BLOCK / 3);
                let reference = serial(n);
                for threads in [1, 2, 3, 8] {
                    for size in [1, 2, 3, usize::MAX] {
                        let (bits, computed) = ordered(n, threads, size);
                        assert!(
                            computed.iter().all(|&t| t == 2),
                            "{blocks} blocks, {threads} threads, ring {size}: each candidate computed once a list"
                        );
                        assert!(
                            bits == reference,
                            "{blocks} blocks, {threads} threads, ring {size}: the bits of one thread"
                        );
                    }
                }
            }
            done.send(()).unwrap();
        });
        // A few seconds of work at most; a minute means a thread waits forever.
        match wait.recv_timeout(std::time::Duration::from_secs(60)) {
            Ok(()) => {}
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("in_order hangs"),
            Err(e) => panic!("the test's thread failed: {e}"),
        }
    }

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
