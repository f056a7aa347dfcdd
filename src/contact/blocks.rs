//! The one loop over a candidate list (pairs or walls), on one thread or
//! many, with the same bits: the list is cut into fixed blocks of
//! [`BLOCK`] candidates; a worker computes a block (each candidate through
//! the kernels, each touching one's points through the contact law,
//! `contact/law/`) into a buffer of per-point loads; the blocks are then
//! added to the bodies' sums in list order, and the scene statistics are
//! reduced in that order too. Neither the blocks nor the order of adding
//! depend on the number of workers, so forces, torques and energies are
//! bit-identical whatever the thread count.
//!
//! A body's sum runs in list order: its walls (the list is body-major),
//! then its pairs in sorted `(i, j)` order (its side-B pairs `(i, b)`,
//! `i < b`, all come before its own row). One worker computes a block and
//! adds it, block after block, with no lock and no atomic. On the pool,
//! the blocks can be added one at a time in list order, each as soon as it
//! and those before it are computed: the pool's threads take the blocks in
//! order, compute each into a ring of [`RING`] slots, and whichever thread
//! finds the oldest computed block not yet added adds it. Only the ring's
//! blocks are held, not the whole list's; a thread waits only when the ring
//! is full (the adding is behind) and at the list's end.
//!
//! How a fibre pair's points are obtained is the loop's type parameter
//! ([`PairKernel`]): computed by the kernels, or replayed by a measuring
//! build (`contact/replay.rs`). Whether the law keeps a record per contact
//! is another ([`Keeping`]): a frictionless scene's loop is compiled
//! without the history's lookups and writes.

use super::broad::NeighbourList;
use super::dispatch::sphere_pair;
use super::fibre_fibre::PairMemory;
use super::history::{
    pair_records, recall, recall_by_place, recall_one_by_place, sorted, ContactKey, Entry, History,
    Recalled,
};
use super::law::{CandidateLaw, Keeping, Laws, PointLoad, Record, Side, Wrench};
use super::shape::{ColliderKind, ColliderPose, Shapes};
use super::stage::ContactStats;
use super::{contacts, Collider, ContactPoint, KernelCounters, SphereGeom, Wall};
use glam::DVec3;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// One contact point's loads as a block keeps them for the adding.
#[derive(Debug, Clone, Copy)]
struct Point {
    /// Everything the bodies feel (the law's total).
    wrench: Wrench,
    /// Elastic energy, `w U(δ)`, J.
    energy: f64,
    /// δ, m (for an MPI rank's tally; the block notes it at once).
    #[cfg(feature = "mpi")]
    overlap: f64,
}

/// How the loop obtains a body pair's contact points: [`Computed`] by
/// the kernels; a measuring build may replay recorded answers instead
/// (`contact/replay.rs`).
pub(crate) trait PairKernel: Sync {
    /// Whether the loop must run on one thread (a replay reads its
    /// recorded answers in list order).
    const ONE_THREAD: bool = false;

    /// A computation of a (non-empty) pair list starts.
    fn computation(&self) {}

    /// The contacts of bodies `a` and `b` appended to `out`, with the
    /// pair's `memory` and the sum of both bodies' motion bounds since
    /// its last computation (fibre pairs, `fibre_fibre/coherence.rs`).
    fn contacts(
        &self,
        a: Collider,
        b: Collider,
        out: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
        memory: &mut PairMemory,
        motion: f64,
    );
}

/// The kernels themselves ([`super::dispatch`]).
pub(crate) struct Computed;

impl PairKernel for Computed {
    #[inline(always)]
    fn contacts(
        &self,
        a: Collider,
        b: Collider,
        out: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
        memory: &mut PairMemory,
        motion: f64,
    ) {
        super::contacts_remembering(a, b, out, counters, Some((memory, motion)));
    }
}

/// Which collider kinds the loop meets, chosen once per computation (as
/// [`Keeping`] is): [`AnyKinds`] reads each body's kind and lets the
/// dispatch find the pair's kernel; [`Spheres`], a scene of spheres only,
/// sends every pair to the sphere–sphere kernel, and every contact of such
/// a scene is central (the law's normal loads have no moment), so its
/// loop is compiled without the kind lookups and the normal torques.
pub(crate) trait Kinds: Copy + Send + Sync + 'static {
    /// Every body is a sphere.
    const SPHERES: bool;
}

/// Any mix of collider kinds.
#[derive(Clone, Copy)]
pub(crate) struct AnyKinds;

impl Kinds for AnyKinds {
    const SPHERES: bool = false;
}

/// Spheres only.
#[derive(Clone, Copy)]
pub(crate) struct Spheres;

impl Kinds for Spheres {
    const SPHERES: bool = true;
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

/// The touching candidates of one block of a candidate list, computed on
/// one worker: per hit (touching candidate) its index in the block and the
/// end of its points, all points' loads in candidate order, their
/// non-conservative parts (empty for an elastic law), the block's share of
/// the statistics (touching count and largest overlap; the elastic energy
/// is summed over the blocks in order afterwards), the kernels' counts,
/// and which block of the list it holds. A slot serves many blocks of a
/// step; its buffers are trimmed to the step's largest use with hysteresis
/// ([`trim`]), so a settled scene steps without allocating.
#[derive(Debug, Default)]
struct Block {
    hits: Vec<(u8, u16)>,
    points: Vec<Point>,
    dissipative: Vec<Wrench>,
    /// The touching contacts' records (a law that keeps them), in order,
    /// and the energy of each one's spring.
    records: Vec<Entry>,
    springs: Vec<f64>,
    stats: ContactStats,
    counters: KernelCounters,
    /// `n + 1` once block `n` of the list is computed here (0: none yet;
    /// set by [`compute_block`], reset per list by [`Sums::in_order`]).
    computed: usize,
    /// The largest lengths of `hits`, `points`, `dissipative`, `records`
    /// in this step's blocks (what [`Block::trim`] keeps).
    high: [usize; 4],
}

/// A ring of block slots (each locked by the thread computing or adding
/// it; one worker reaches them without locking).
type Ring = Vec<Mutex<Block>>;

/// The loop's buffers, kept between steps: the rings of wall and of pair
/// candidates (holding every block of the list when the stage keeps every
/// hit for [`Blocks::for_each_hit`]) and one worker's kernel output.
#[derive(Debug)]
pub(crate) struct Blocks {
    wall_ring: Ring,
    pair_ring: Ring,
    /// Blocks in flight on the pool ([`RING`]; tests make it smaller).
    pub(super) ring: usize,
    /// The neighbour-list build whose order was last checked.
    checked: u64,
    /// The kernels' output on one worker (the pool's threads keep their
    /// own, [`BUF`]).
    buf: Vec<ContactPoint>,
    /// The history store before the last one, emptied: the next
    /// computation writes its records there, so a settled frictional
    /// scene keeps its records without allocating.
    spare: History,
}

impl Default for Blocks {
    fn default() -> Self {
        Blocks {
            wall_ring: vec![],
            pair_ring: vec![],
            ring: RING,
            checked: 0,
            buf: vec![],
            spare: History::default(),
        }
    }
}

/// A copy's blocks start empty: they hold nothing between steps but
/// buffers (and, after an MPI rank's computation, its hits, which the
/// rank reads before anything is copied).
impl Clone for Blocks {
    fn clone(&self) -> Self {
        Blocks {
            ring: self.ring,
            ..Blocks::default()
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
/// stage caught and reused computes again ([`Blocks::compute`]).
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

/// Where the loop puts the loads of each touching candidate's points: a
/// block's buffer (to be added in list order later), or, on one worker,
/// the bodies' sums themselves (the same additions in the same order).
trait Sink {
    /// The loads `load` of a point of overlap `overlap` between body A
    /// (`(index, diameter)`) and body B (none for a wall); its torques
    /// too, unless `torques` is false ([`torques`]).
    fn point(
        &mut self,
        load: &PointLoad,
        overlap: f64,
        a: (usize, f64),
        b: Option<(usize, f64)>,
        torques: bool,
    );
    /// Candidate `k` of the block touched: its points are in.
    fn touched(&mut self, k: usize);
    /// A touching contact's record after its computation, and the energy
    /// of its spring.
    fn keep(&mut self, entry: Entry, spring: f64);
}

impl Sink for Block {
    /// The point's loads appended; its overlaps δ/D noted on A, then on B.
    #[inline(always)]
    fn point(
        &mut self,
        load: &PointLoad,
        overlap: f64,
        (a, d_a): (usize, f64),
        b: Option<(usize, f64)>,
        torques: bool,
    ) {
        // (Torques not added are not kept: zeros, as the law's are not
        // worked out.)
        let kept = |w: Wrench| {
            if torques {
                w
            } else {
                Wrench {
                    force: w.force,
                    ..Wrench::default()
                }
            }
        };
        if let Some(w) = load.dissipative {
            self.dissipative.push(kept(w));
        }
        self.points.push(Point {
            wrench: kept(load.total),
            energy: load.elastic,
            #[cfg(feature = "mpi")]
            overlap,
        });
        self.stats.note_contact_overlap(overlap, (a, d_a), b);
    }

    #[inline(always)]
    fn touched(&mut self, k: usize) {
        self.stats.touching += 1;
        self.hits.push((candidate(k), point(self.points.len())));
    }

    #[inline(always)]
    fn keep(&mut self, entry: Entry, spring: f64) {
        self.records.push(entry);
        self.springs.push(spring);
    }
}

impl Block {
    /// Ready for the next block (its use noted for [`Block::trim`]).
    fn clear(&mut self) {
        let lens = [
            self.hits.len(),
            self.points.len(),
            self.dissipative.len(),
            self.records.len(),
        ];
        for (h, l) in self.high.iter_mut().zip(lens) {
            *h = (*h).max(l);
        }
        self.hits.clear();
        self.points.clear();
        self.dissipative.clear();
        self.records.clear();
        self.springs.clear();
        self.stats = ContactStats::default();
        self.counters = KernelCounters::default();
    }

    /// At the end of a step: release what the step's blocks did not use.
    fn trim(&mut self) {
        self.clear();
        let [h, p, d, r] = std::mem::take(&mut self.high);
        trim(&mut self.hits, h);
        trim(&mut self.points, p);
        trim(&mut self.dissipative, d);
        trim(&mut self.records, r);
        trim(&mut self.springs, r);
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

/// A touching candidate as its evaluation leaves it (its points in the
/// kernels' buffer): its law, and its body A and body B (none for a wall),
/// each as `(index, diameter)`.
pub(crate) struct Touching<'l, F: Keeping> {
    law: CandidateLaw<'l, F>,
    a: (usize, f64),
    b: Option<(usize, f64)>,
}

/// A kind of candidate list (walls, fibre pairs): how one of its
/// candidates is evaluated and whose sums its loads go to.
trait Candidates<'l>: Sync {
    /// A candidate: `(body, wall)` or `(i, j)`.
    type Candidate: Sync;
    /// What the list keeps per candidate between computations.
    type Memory: Send;
    /// Whether its laws keep a record per contact.
    type Keeping: Keeping;
    /// Whether every contact of the list is central: its normal lines
    /// pass through both centres ([`torques`]).
    const CENTRAL: bool;

    /// Whether every candidate of the list has at most one point, given by
    /// [`Candidates::eval_one`] (no memory, no counts, no buffer).
    const ONE_POINT: bool = false;

    /// Candidate `c` with its memory `m` through the kernels into `buf`
    /// (counted in `counters`): it touches if `buf` is not empty.
    fn eval(
        &self,
        c: &Self::Candidate,
        m: &mut Self::Memory,
        buf: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
    );

    /// Candidate `c`'s one point, if it touches (a list that is
    /// [`Candidates::ONE_POINT`]; [`Candidates::eval`] gives the same).
    #[inline(always)]
    fn eval_one(&self, _c: &Self::Candidate) -> Option<ContactPoint> {
        unreachable!("only a list that is ONE_POINT is asked for its one point")
    }

    /// Touching candidate `c`'s law and bodies.
    fn touching(&self, c: &Self::Candidate) -> Touching<'l, Self::Keeping>;

    /// Candidate `c`'s body A and body B (none for a wall).
    fn bodies(&self, c: &Self::Candidate) -> (usize, Option<usize>);

    /// The identity of point `p`, the `s`-th of touching candidate `c`
    /// (`contact/history.rs`).
    fn key(&self, c: &Self::Candidate, s: usize, p: &ContactPoint) -> ContactKey;

    /// The records of the last computation of this list (sorted by key).
    fn recorded(&self) -> &[Entry];

    /// The records touching candidate `c`'s `points` start from, in their
    /// order, into `out` (`cursor` as for `history::recall`): by key.
    #[inline(always)]
    fn recall(
        &self,
        c: &Self::Candidate,
        points: &[ContactPoint],
        cursor: &mut usize,
        out: &mut Recalled,
    ) {
        for (s, p) in points.iter().enumerate() {
            out.push(recall(self.recorded(), cursor, &self.key(c, s, p)));
        }
    }

    /// [`Candidates::recall`] of a candidate with one point `p`.
    #[inline(always)]
    fn recall_one(&self, c: &Self::Candidate, p: &ContactPoint, cursor: &mut usize) -> Record {
        recall(self.recorded(), cursor, &self.key(c, 0, p))
    }
}

/// What both lists read: the bodies' collider poses and shapes (all
/// spheres if `S` says so), and the laws.
#[derive(Clone, Copy)]
struct Scene<'a, 'l, F, S> {
    poses: &'a [ColliderPose],
    shapes: Shapes<'a>,
    laws: &'a Laws<'l, F>,
    kinds: std::marker::PhantomData<S>,
}

impl<'l, F: Keeping, S: Kinds> Scene<'_, 'l, F, S> {
    /// Body `i`'s collider: its shape at its pose.
    #[inline(always)]
    fn collider(&self, i: usize) -> Collider<'static> {
        if S::SPHERES {
            Collider::Sphere(self.sphere(i))
        } else {
            self.shapes.collider(i, &self.poses[i])
        }
    }

    /// Body `i` as a sphere (`S::SPHERES`).
    #[inline(always)]
    fn sphere(&self, i: usize) -> SphereGeom {
        SphereGeom {
            centre: self.poses[i].centre,
            radius: self.shapes.get(i).radius,
        }
    }

    /// Body `i` as a side of a candidate.
    #[inline(always)]
    fn side(&self, i: usize) -> Side {
        Side {
            index: i,
            centre: self.poses[i].centre,
        }
    }

    /// Body `i` as `(index, diameter)`.
    #[inline(always)]
    fn body(&self, i: usize) -> (usize, f64) {
        (i, 2.0 * self.shapes.get(i).radius)
    }
}

/// The wall candidates `(body, wall)` of a box, and their contacts'
/// records of the last computation.
struct WallList<'a, 'l, F, S> {
    scene: Scene<'a, 'l, F, S>,
    walls: &'a [Wall],
    recorded: &'a [Entry],
}

impl<'l, F: Keeping, S: Kinds> Candidates<'l> for WallList<'_, 'l, F, S> {
    type Candidate = (u32, u32);
    /// Walls remember nothing (a zero-sized entry each).
    type Memory = ();
    type Keeping = F;
    /// A sphere's wall contact is central.
    const CENTRAL: bool = S::SPHERES;

    #[inline(always)]
    fn eval(
        &self,
        &(i, w): &(u32, u32),
        _: &mut (),
        buf: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
    ) {
        let wall = Collider::Wall(&self.walls[w as usize]);
        contacts(self.scene.collider(i as usize), wall, buf, counters);
    }

    #[inline(always)]
    fn touching(&self, &(i, _): &(u32, u32)) -> Touching<'l, F> {
        let i = i as usize;
        Touching {
            law: self.scene.laws.wall(self.scene.side(i)),
            a: self.scene.body(i),
            b: None,
        }
    }

    #[inline(always)]
    fn bodies(&self, &(i, _): &(u32, u32)) -> (usize, Option<usize>) {
        (i as usize, None)
    }

    /// A fibre's end (0: the one at `−axis`, 1: at `+axis`), a sphere's 0.
    #[inline(always)]
    fn key(&self, &(i, w): &(u32, u32), _: usize, p: &ContactPoint) -> ContactKey {
        let g = &self.scene.poses[i as usize];
        let kind = if S::SPHERES {
            ColliderKind::Sphere
        } else {
            self.scene.shapes.get(i as usize).kind
        };
        let end = match kind {
            ColliderKind::Fibre => u8::from((p.point - g.centre).dot(g.axis) > 0.0),
            ColliderKind::Sphere => 0,
        };
        ContactKey {
            a: i,
            b: w,
            slot: end,
        }
    }

    fn recorded(&self) -> &[Entry] {
        self.recorded
    }
}

/// The body pair candidates `(i, j)`, with their memories, whose
/// contacts `kernel` gives.
struct PairList<'a, 'l, K, F, S> {
    scene: Scene<'a, 'l, F, S>,
    /// Each body's motion bound since the last computation.
    motion: &'a [f32],
    kernel: &'a K,
    /// The contacts' records of the last computation.
    recorded: &'a [Entry],
}

impl<'l, K: PairKernel, F: Keeping, S: Kinds> Candidates<'l> for PairList<'_, 'l, K, F, S> {
    type Candidate = (u32, u32);
    type Memory = PairMemory;
    type Keeping = F;
    /// Sphere pairs' contacts are central.
    const CENTRAL: bool = S::SPHERES;
    /// Sphere pairs: the dispatch's sphere–sphere arm, decided for the
    /// whole list (a replay still answers every pair itself).
    const ONE_POINT: bool = S::SPHERES && !K::ONE_THREAD;

    #[inline(always)]
    fn eval(
        &self,
        c: &(u32, u32),
        memory: &mut PairMemory,
        buf: &mut Vec<ContactPoint>,
        counters: &mut KernelCounters,
    ) {
        if Self::ONE_POINT {
            buf.extend(self.eval_one(c));
            return;
        }
        let (a, b) = (c.0 as usize, c.1 as usize);
        let motion = f64::from(self.motion[a]) + f64::from(self.motion[b]);
        let (ca, cb) = (self.scene.collider(a), self.scene.collider(b));
        self.kernel.contacts(ca, cb, buf, counters, memory, motion);
    }

    #[inline(always)]
    fn eval_one(&self, &(a, b): &(u32, u32)) -> Option<ContactPoint> {
        let (a, b) = (a as usize, b as usize);
        sphere_pair(&self.scene.sphere(a), &self.scene.sphere(b))
    }

    #[inline(always)]
    fn touching(&self, &(a, b): &(u32, u32)) -> Touching<'l, F> {
        let (a, b) = (a as usize, b as usize);
        Touching {
            law: self.scene.laws.pair(self.scene.side(a), self.scene.side(b)),
            a: self.scene.body(a),
            b: Some(self.scene.body(b)),
        }
    }

    #[inline(always)]
    fn bodies(&self, &(a, b): &(u32, u32)) -> (usize, Option<usize>) {
        (a as usize, Some(b as usize))
    }

    /// The point's rank in the kernel's output (the key keeps the store
    /// sorted and unique; a point finds its record by place, [`recall`]).
    ///
    /// [`recall`]: Candidates::recall
    #[inline(always)]
    fn key(&self, &(a, b): &(u32, u32), s: usize, _: &ContactPoint) -> ContactKey {
        ContactKey {
            a,
            b,
            slot: s as u8,
        }
    }

    fn recorded(&self) -> &[Entry] {
        self.recorded
    }

    /// By place (`history::recall_by_place`), within [`PairList::reach`].
    #[inline(always)]
    fn recall(
        &self,
        &(a, b): &(u32, u32),
        points: &[ContactPoint],
        cursor: &mut usize,
        out: &mut Recalled,
    ) {
        let old = pair_records(self.recorded, cursor, (a, b));
        let (centre, reach) = self.reach(a, b);
        let places = points.iter().map(|p| (p.point - centre, p.weight));
        recall_by_place(old, places, reach, out);
    }

    #[inline(always)]
    fn recall_one(&self, &(a, b): &(u32, u32), p: &ContactPoint, cursor: &mut usize) -> Record {
        let old = pair_records(self.recorded, cursor, (a, b));
        let (centre, reach) = self.reach(a, b);
        recall_one_by_place(old, (p.point - centre, p.weight), reach)
    }
}

impl<K, F, S> PairList<'_, '_, K, F, S> {
    /// Body A's centre (places are taken from it) and the reach of the
    /// pair's records: 1.5 times the smaller radius (docs/contacts.md,
    /// "Identity and history": beyond a split wrench's lever, within two).
    #[inline(always)]
    fn reach(&self, a: u32, b: u32) -> (DVec3, f64) {
        let shapes = self.scene.shapes;
        let (ra, rb) = (shapes.get(a as usize).radius, shapes.get(b as usize).radius);
        (self.scene.poses[a as usize].centre, 1.5 * ra.min(rb))
    }
}

/// The one loop over candidates: each of `candidates` (with its
/// `memory`) evaluated into the kernel output buffer `buf`, and each point
/// of a touching one through its law, the one place a contact's loads are
/// made, into `sink`; the kernels count into `counters`.
#[inline(always)]
fn each_candidate<'l, C: Candidates<'l>>(
    list: &C,
    candidates: &[C::Candidate],
    memory: &mut [C::Memory],
    buf: &mut Vec<ContactPoint>,
    counters: &mut KernelCounters,
    sink: &mut impl Sink,
) {
    // Where the last record was found (`history::recall`), and the records
    // a candidate's points start from.
    let mut cursor = 0;
    let mut records = Recalled::new();
    for (k, (c, m)) in candidates.iter().zip(memory).enumerate() {
        if C::ONE_POINT {
            // The point by value, never through the buffer.
            if let Some(p) = list.eval_one(c) {
                one_point(list, c, &list.touching(c), &p, &mut cursor, sink);
                sink.touched(k);
            }
            continue;
        }
        buf.clear();
        list.eval(c, m, buf, counters);
        if !buf.is_empty() {
            let t = list.touching(c);
            if let [p] = &buf[..] {
                // One point (most contacts): its record without gathering.
                one_point(list, c, &t, p, &mut cursor, sink);
            } else if t.law.keeps_history() {
                records.clear();
                list.recall(c, buf, &mut cursor, &mut records);
                for (s, (p, record)) in buf.iter().zip(&mut records).enumerate() {
                    let load = t.law.load(p, record);
                    sink.point(&load, p.overlap, t.a, t.b, true);
                    sink.keep((list.key(c, s, p), *record), load.spring);
                }
            } else {
                for p in buf.iter() {
                    let load = t.law.load(p, &mut Record::default());
                    sink.point(&load, p.overlap, t.a, t.b, torques::<C>());
                }
            }
            sink.touched(k);
        }
    }
}

/// The loads of touching candidate `c`'s one point `p` (its law and
/// bodies `t`) into `sink`, with its record (a law that keeps them: found
/// from `cursor` without gathering, and kept).
#[inline(always)]
fn one_point<'l, C: Candidates<'l>>(
    list: &C,
    c: &C::Candidate,
    t: &Touching<'l, C::Keeping>,
    p: &ContactPoint,
    cursor: &mut usize,
    sink: &mut impl Sink,
) {
    if t.law.keeps_history() {
        let mut record = list.recall_one(c, p, cursor);
        let load = t.law.load(p, &mut record);
        sink.point(&load, p.overlap, t.a, t.b, true);
        sink.keep((list.key(c, 0, p), record), load.spring);
    } else {
        let load = t.law.load(p, &mut Record::default());
        sink.point(&load, p.overlap, t.a, t.b, torques::<C>());
    }
}

/// Whether the loads of `C`'s list have torques: not when its contacts are
/// central and frictionless (a sphere scene's without friction), whose
/// normal loads have no moment about either centre (the force's line
/// passes through both centres): the law's torques there are rounding
/// only, and are not added (the sums start at zero and stay so).
#[inline(always)]
fn torques<'l, C: Candidates<'l>>() -> bool {
    !C::CENTRAL || <C::Keeping as Keeping>::RECORDS
}

/// Compute block `n` of a candidate list (its `candidates` with their
/// `memory`, one each) into `block`, with the kernel output buffer `buf`.
#[inline]
fn compute_block<'l, C: Candidates<'l>>(
    list: &C,
    n: usize,
    candidates: &[C::Candidate],
    memory: &mut [C::Memory],
    block: &mut Block,
    buf: &mut Vec<ContactPoint>,
) {
    block.clear();
    let mut counters = KernelCounters::default();
    each_candidate(list, candidates, memory, buf, &mut counters, block);
    block.counters = counters;
    block.computed = n + 1;
}

/// Add the loads `records` (a computed `block`'s, one per point in point
/// order: its totals or its non-conservative parts) to the bodies' sums,
/// point by point in candidate order: side A `+F`, `+τ_A`, side B `−F`,
/// `−τ_B`; `cands` are the block's (of `list`).
#[inline]
fn add_block<'l, R, C: Candidates<'l>>(
    list: &C,
    block: &Block,
    records: &[R],
    wrench: fn(&R) -> &Wrench,
    cands: &[C::Candidate],
    force: &mut [DVec3],
    torque: &mut [DVec3],
) {
    let torques = torques::<C>();
    for (k, points) in block.hits() {
        let (a, b) = list.bodies(&cands[k]);
        for w in records[points].iter().map(wrench) {
            force[a] += w.force;
            if torques {
                torque[a] += w.torque_a;
            }
            if let Some(b) = b {
                force[b] -= w.force;
                if torques {
                    torque[b] -= w.torque_b;
                }
            }
        }
    }
}

/// Where the blocks' loads go: each body's forces and torques, its
/// non-conservative loads (a law that has them), the statistics and the
/// kernels' counts.
struct Sums<'a> {
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    dissipative: Option<(&'a mut [DVec3], &'a mut [DVec3])>,
    stats: ContactStats,
    counters: &'a mut KernelCounters,
    /// The contacts' records, in list order (a law that keeps them).
    kept: Vec<Entry>,
    /// The energy stored in their springs, summed in list order, J.
    spring: f64,
}

/// One worker's sink: each point's loads added to the bodies at once, its
/// energy summed and its overlaps noted, in list order (as the blocks'
/// adding does).
impl Sink for Sums<'_> {
    #[inline(always)]
    fn point(
        &mut self,
        load: &PointLoad,
        overlap: f64,
        (a, d_a): (usize, f64),
        b: Option<(usize, f64)>,
        torques: bool,
    ) {
        let w = &load.total;
        self.force[a] += w.force;
        if torques {
            self.torque[a] += w.torque_a;
        }
        if let Some((b, _)) = b {
            self.force[b] -= w.force;
            if torques {
                self.torque[b] -= w.torque_b;
            }
        }
        if let (Some((df, dt)), Some(w)) = (&mut self.dissipative, &load.dissipative) {
            df[a] += w.force;
            if torques {
                dt[a] += w.torque_a;
            }
            if let Some((b, _)) = b {
                df[b] -= w.force;
                if torques {
                    dt[b] -= w.torque_b;
                }
            }
        }
        self.stats.elastic += load.elastic;
        self.stats.note_contact_overlap(overlap, (a, d_a), b);
    }

    #[inline(always)]
    fn touched(&mut self, _: usize) {
        self.stats.touching += 1;
    }

    #[inline(always)]
    fn keep(&mut self, entry: Entry, spring: f64) {
        self.kept.push(entry);
        self.spring += spring;
    }
}

impl Sums<'_> {
    /// Compute `candidates` (with their `memory`, one each) on this thread,
    /// each touching one's loads added as they are made (no block), with
    /// the kernel output buffer `buf`.
    fn direct<'l, C: Candidates<'l>>(
        &mut self,
        list: &C,
        candidates: &[C::Candidate],
        memory: &mut [C::Memory],
        buf: &mut Vec<ContactPoint>,
    ) {
        let mut counters = KernelCounters::default();
        each_candidate(list, candidates, memory, buf, &mut counters, self);
        *self.counters = *self.counters + counters;
    }

    /// Add a computed `block` (its candidates `cands`) to the sums, and
    /// its statistics, in list order: the counts and the first largest
    /// overlap, then the energy point by point (a sum of partial sums
    /// would round differently).
    #[inline]
    fn add<'l, C: Candidates<'l>>(&mut self, list: &C, block: &Block, cands: &[C::Candidate]) {
        *self.counters = *self.counters + block.counters;
        fn total(p: &Point) -> &Wrench {
            &p.wrench
        }
        fn itself(w: &Wrench) -> &Wrench {
            w
        }
        let (force, torque) = (&mut *self.force, &mut *self.torque);
        add_block(list, block, &block.points, total, cands, force, torque);
        if let Some((df, dt)) = &mut self.dissipative {
            add_block(list, block, &block.dissipative, itself, cands, df, dt);
        }
        self.stats.touching += block.stats.touching;
        let (ratio, body) = (block.stats.max_overlap_ratio, block.stats.max_overlap_body);
        self.stats.note_overlap(ratio, body);
        for p in &block.points {
            self.stats.elastic += p.energy;
        }
        self.kept.extend_from_slice(&block.records);
        for s in &block.springs {
            self.spring += s;
        }
    }

    /// Compute `candidates` of `list` (with their `memory`, one each) on
    /// `workers` threads, into the `size` slots of `ring` (made if
    /// missing), and add each block's loads in list order.
    ///
    /// One worker computes a block into the ring's slot and adds it, block
    /// after block, with the kernel output buffer `buf`. On the pool the
    /// threads take the blocks in order; after each, a thread adds every
    /// block that is next in order and computed, unless another thread is
    /// adding; a thread whose next block's slot still holds a block not
    /// added adds or waits. So the adding (serial: it reads any body)
    /// overlaps the computing, and the threads meet once, at the list's
    /// end.
    #[allow(clippy::too_many_arguments)]
    fn in_order<'l, C: Candidates<'l>>(
        &mut self,
        list: &C,
        candidates: &[C::Candidate],
        memory: &mut [C::Memory],
        ring: &mut Ring,
        size: usize,
        workers: usize,
        buf: &mut Vec<ContactPoint>,
    ) {
        let total = candidates.len().div_ceil(BLOCK);
        let size = size.min(total).max(1);
        if ring.len() < size {
            ring.resize_with(size, Mutex::default);
        }
        if workers <= 1 {
            let blocks = candidates.chunks(BLOCK).zip(memory.chunks_mut(BLOCK));
            for (n, (cands, memory)) in blocks.enumerate() {
                let slot = ring[n % size]
                    .get_mut()
                    .unwrap_or_else(PoisonError::into_inner);
                compute_block(list, n, cands, memory, slot, buf);
                self.add(list, slot, cands);
            }
            return;
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
                    sums.add(list, &block, &candidates[n * BLOCK..]);
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
        // (`list.eval` must not use the pool: a thread waiting in a kernel for
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
                BUF.with_borrow_mut(|buf| {
                    compute_block(list, n, cands, memory, &mut lock(&ring[n % size]), buf)
                });
                add_ready();
            }
        };
        on_threads(workers, &work);
        // Every block is computed; what the threads left is added here.
        let sums = sums.into_inner().unwrap_or_else(PoisonError::into_inner);
        for n in added.into_inner()..total {
            let block = lock(&ring[n % size]);
            assert_eq!(
                block.computed,
                n + 1,
                "block {n} computed before its adding"
            );
            sums.add(list, &block, &candidates[n * BLOCK..]);
        }
    }
}

/// The non-conservative loads per body that a computation fills (zeroed
/// by it): force and torque.
pub(crate) type Dissipative<'a> = (&'a mut [DVec3], &'a mut [DVec3]);

impl Blocks {
    /// The contact forces and torques of every body (overwritten), and the
    /// scene statistics, from the candidates of `list` at the bodies'
    /// collider `poses` of collider `shapes` (all spheres if `spheres`;
    /// their pairs' memories spending the bodies' `motion` bounds), the `walls` and the `laws`, on `workers` threads (the
    /// same bits for any number); with `dissipative`, the laws'
    /// non-conservative loads per body too; with `history` (a law that
    /// keeps records), each contact's record read from it and the new
    /// ones put in its place. With `keep_hits` the rings hold the whole
    /// list, whose hits stay for [`Blocks::for_each_hit`].
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn compute<K: PairKernel, F: Keeping>(
        &mut self,
        kernel: &K,
        list: &mut NeighbourList,
        (poses, shapes, spheres, motion, walls): (&[ColliderPose], Shapes, bool, &[f32], &[Wall]),
        laws: &Laws<F>,
        (force, torque): (&mut [DVec3], &mut [DVec3]),
        counters: &mut KernelCounters,
        dissipative: Option<Dissipative>,
        history: Option<&mut History>,
        keep_hits: bool,
        workers: usize,
    ) -> (ContactStats, f64) {
        // The last computation's records; the touching contacts' new ones
        // replace them (a contact not touching now loses its record).
        let recorded = history.filter(|_| F::RECORDS).map(|h| {
            let old = std::mem::take(h);
            (h, old)
        });
        force.fill(DVec3::ZERO);
        torque.fill(DVec3::ZERO);
        let dissipative = dissipative.map(|(f, t)| {
            f.fill(DVec3::ZERO);
            t.fill(DVec3::ZERO);
            (f, t)
        });
        if list.walls.is_empty() && list.pairs.is_empty() {
            // Bodies far apart: no block to compute (the rings keep their
            // buffers for the next contacts).
            return (ContactStats::default(), 0.0);
        }
        // The last step's hits (kept for `for_each_hit`) go; what its
        // blocks did not use is released.
        let slots = self.wall_ring.iter_mut().chain(&mut self.pair_ring);
        slots.for_each(|b| {
            // (A slot poisoned by a panic caught above: `try_lock` would
            // call it busy forever.)
            b.clear_poison();
            b.get_mut().unwrap_or_else(PoisonError::into_inner).trim();
        });
        let workers = if K::ONE_THREAD { 1 } else { workers };
        let size = match (keep_hits, workers) {
            (true, _) => usize::MAX,
            (false, 1) => 1,
            (false, _) => self.ring,
        };
        if self.checked != list.builds {
            // The order the blocks are added in rests on these.
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
            dissipative,
            stats: ContactStats::default(),
            counters,
            kept: std::mem::take(&mut self.spare.walls),
            spring: 0.0,
        };
        let (old_walls, old_pairs) = match &recorded {
            Some((_, old)) => (&old.walls[..], &old.pairs[..]),
            None => (&[][..], &[][..]),
        };
        // One worker adds each point's loads as it makes them; blocks are
        // made for the pool, and to keep the hits.
        let direct = workers == 1 && !keep_hits;
        let lists = Lists {
            kernel,
            list,
            old: (old_walls, old_pairs),
            motion,
            walls,
            size,
            workers,
            direct,
        };
        // A scene of spheres only is looped as such (`Kinds`).
        debug_assert!(
            !spheres || (0..poses.len()).all(|i| shapes.get(i).kind == ColliderKind::Sphere)
        );
        let kept_walls = if spheres {
            self.lists::<K, F, Spheres>(lists, poses, shapes, laws, &mut sums)
        } else {
            self.lists::<K, F, AnyKinds>(lists, poses, shapes, laws, &mut sums)
        };
        if let Some((h, mut old)) = recorded {
            h.walls = sorted(kept_walls);
            // The pairs' records come in key order already: the list is
            // sorted (checked at each build, above) and a pair's slots are
            // its points' ranks, in order.
            debug_assert!(
                sums.kept.is_sorted_by_key(|e| e.0),
                "pair records in key order"
            );
            h.pairs = sums.kept;
            old.walls.clear();
            old.pairs.clear();
            self.spare = old;
        }
        (sums.stats, sums.spring)
    }

    /// The wall candidates, then the pair candidates, of `l.list` into
    /// `sums`, with the scene's bodies all of the kinds `S` admits; the
    /// wall contacts' records kept (a law that keeps them).
    #[inline(never)]
    fn lists<K: PairKernel, F: Keeping, S: Kinds>(
        &mut self,
        l: Lists<'_, K>,
        poses: &[ColliderPose],
        shapes: Shapes,
        laws: &Laws<F>,
        sums: &mut Sums,
    ) -> Vec<Entry> {
        let Lists {
            kernel,
            list,
            old: (old_walls, old_pairs),
            motion,
            walls,
            size,
            workers,
            direct,
        } = l;
        let scene = Scene::<F, S> {
            poses,
            shapes,
            laws,
            kinds: std::marker::PhantomData,
        };
        // Walls first, then pairs: each body's order.
        if !list.walls.is_empty() {
            let walls = WallList {
                scene,
                walls,
                recorded: old_walls,
            };
            let memory = &mut vec![(); list.walls.len()];
            let buf = &mut self.buf;
            if direct {
                sums.direct(&walls, &list.walls, memory, buf);
            } else {
                let ring = &mut self.wall_ring;
                sums.in_order(&walls, &list.walls, memory, ring, size, workers, buf);
            }
        }
        let kept_walls = std::mem::replace(&mut sums.kept, std::mem::take(&mut self.spare.pairs));
        if !list.pairs.is_empty() {
            kernel.computation();
            let pairs = PairList {
                scene,
                motion,
                kernel,
                recorded: old_pairs,
            };
            let (memory, buf) = (&mut list.memory, &mut self.buf);
            if direct {
                sums.direct(&pairs, &list.pairs, memory, buf);
            } else {
                let ring = &mut self.pair_ring;
                sums.in_order(&pairs, &list.pairs, memory, ring, size, workers, buf);
            }
        }
        kept_walls
    }
}

/// What [`Blocks::lists`] loops over: the kernel, the list with its
/// records of the last computation (walls', pairs'), the bodies' motion
/// bounds, the walls, the ring's size, the workers, and whether one
/// worker adds the loads as it makes them.
struct Lists<'a, K> {
    kernel: &'a K,
    list: &'a mut NeighbourList,
    old: (&'a [Entry], &'a [Entry]),
    motion: &'a [f32],
    walls: &'a [Wall],
    size: usize,
    workers: usize,
    direct: bool,
}

#[cfg(feature = "mpi")]
impl Blocks {
    /// Each hit of the last [`Blocks::compute`] (with `keep_hits`), walls
    /// first, in candidate order: `(wall, candidate, points, springs)`,
    /// each point `[w U(δ), δ/D on A, δ/D on B]` as the blocks hold and
    /// note them, and the energies of its points' springs (one per point;
    /// none for a law that keeps no records) as the blocks sum them (an
    /// MPI rank's share of the scene statistics, `src/ranks/tally.rs`).
    pub(crate) fn for_each_hit(
        &self,
        list: &NeighbourList,
        shapes: Shapes,
        mut f: impl FnMut(bool, u32, &mut dyn Iterator<Item = [f64; 3]>, &[f64]),
    ) {
        // With `keep_hits` the rings hold the whole list.
        let (walls, pairs) = (list.walls.len(), list.pairs.len());
        let diameter = |i: u32| 2.0 * shapes.get(i as usize).radius;
        for (n, block) in self.wall_ring[..walls.div_ceil(BLOCK)]
            .iter()
            .map(lock)
            .enumerate()
        {
            let mut kept = KeptSprings::default();
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let (a, w) = list.walls[candidate as usize];
                let springs = kept.of(&block, (a, w), points.len());
                let da = diameter(a);
                let points = &block.points[points];
                f(
                    true,
                    candidate,
                    &mut points.iter().map(|p| [p.energy, p.overlap / da, 0.0]),
                    springs,
                );
            }
        }
        for (n, block) in self.pair_ring[..pairs.div_ceil(BLOCK)]
            .iter()
            .map(lock)
            .enumerate()
        {
            let mut kept = KeptSprings::default();
            for (k, points) in block.hits() {
                let candidate = (n * BLOCK + k) as u32;
                let (a, b) = list.pairs[candidate as usize];
                let springs = kept.of(&block, (a, b), points.len());
                let (da, db) = (diameter(a), diameter(b));
                let points = &block.points[points];
                f(
                    false,
                    candidate,
                    &mut points
                        .iter()
                        .map(|p| [p.energy, p.overlap / da, p.overlap / db]),
                    springs,
                );
            }
        }
    }
}

/// A cursor over a block's records while its hits are read in order: a
/// hit whose law keeps records has one per point, in order (the loop's
/// `keep`); one whose law keeps none (a frictionless wall, say) has none.
#[cfg(feature = "mpi")]
#[derive(Default)]
struct KeptSprings {
    next: usize,
}

#[cfg(feature = "mpi")]
impl KeptSprings {
    /// The springs' energies of the hit `(a, b)` of `points` points.
    fn of<'b>(&mut self, block: &'b Block, (a, b): (u32, u32), points: usize) -> &'b [f64] {
        match block.records.get(self.next) {
            Some((key, _)) if (key.a, key.b) == (a, b) => {
                let springs = &block.springs[self.next..self.next + points];
                self.next += points;
                springs
            }
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::law::{Frictionless, LawTable};

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

    /// Twelve fibres of two kinds, for a table of elastic laws; their
    /// centres.
    fn fibres() -> (LawTable, Vec<DVec3>) {
        let material = crate::body::Material {
            name: String::new(),
            density: 1100.0,
            young: 5e7,
            poisson: 0.35,
            friction: None,
        };
        let bodies: crate::body::Bodies = (0..12)
            .map(|i| {
                let shape = crate::body::Shape::Fibre {
                    diameter: if i % 2 == 0 { 0.01 } else { 0.007 },
                    length: 0.025,
                };
                crate::body::Body::new(shape, 0, 1100.0)
            })
            .collect();
        let centres = (0..12)
            .map(|i| DVec3::new(i as f64, load(i, 9), load(i, 11)))
            .collect();
        (LawTable::new(&bodies, &[material], None), centres)
    }

    /// Candidate `c`'s points (one or two), if it touches (two in three do).
    fn points(c: u32, salt: u64, out: &mut Vec<ContactPoint>) {
        if c.is_multiple_of(3) {
            return;
        }
        for j in 0..1 + (c % 2) as u64 {
            let s = salt + 16 * j;
            out.push(ContactPoint {
                point: DVec3::new(load(c, s + 1), 0.5, load(c, s + 2)),
                normal: DVec3::new(load(c, s), load(c, s + 7), 1.0).normalize(),
                overlap: 1e-5 * (1.5 + load(c, s + 3)),
                weight: 0.75 + 0.25 * load(c, s + 4),
                weight_grad: DVec3::new(0.0, load(c, s + 5), 0.0),
            });
        }
    }

    /// A candidate's two bodies (of 12).
    fn bodies(c: &u32) -> (usize, Option<usize>) {
        ((c % 7) as usize, Some((7 + c % 5) as usize))
    }

    /// What a computation gives: force and torque bits, then the
    /// statistics' (touching, elastic, largest overlap and its body).
    fn bits(force: &[DVec3], torque: &[DVec3], stats: &ContactStats) -> Vec<u64> {
        (force.iter().chain(torque))
            .flat_map(|v| v.to_array())
            .map(f64::to_bits)
            .chain([
                stats.touching as u64,
                stats.elastic.to_bits(),
                stats.max_overlap_ratio.to_bits(),
                stats.max_overlap_body as u64,
            ])
            .collect()
    }

    /// Reference: the bits of [`ordered`] by a plain loop over the
    /// candidates in order, each point's loads (by the law) added at once.
    fn serial(n: usize) -> Vec<Vec<u64>> {
        let (table, centres) = fibres();
        let none = crate::body::Bodies::new();
        let laws = Laws::<Frictionless>::new(&table, &none, &[]);
        let side = |i: usize| Side {
            index: i,
            centre: centres[i],
        };
        let mut out = vec![];
        for salt in [1, 2] {
            let (mut force, mut torque) = (vec![DVec3::ZERO; 12], vec![DVec3::ZERO; 12]);
            let mut stats = ContactStats::default();
            for c in 0..n as u32 {
                let mut ps = vec![];
                points(c, salt, &mut ps);
                if ps.is_empty() {
                    continue;
                }
                let (a, b) = bodies(&c);
                let b = b.unwrap();
                let law = laws.pair(side(a), side(b));
                stats.touching += 1;
                for p in &ps {
                    let w = law.load(p, &mut Record::default());
                    force[a] += w.total.force;
                    torque[a] += w.total.torque_a;
                    force[b] -= w.total.force;
                    torque[b] -= w.total.torque_b;
                    stats.elastic += w.elastic;
                    stats.note_overlap(p.overlap / 0.01, a);
                    stats.note_overlap(p.overlap / 0.007, b);
                }
            }
            out.push(bits(&force, &torque, &stats));
        }
        out
    }

    /// Candidates `c` of bodies [`bodies`], whose points are [`points`];
    /// each counts its evaluations in its memory, and the blocks cost
    /// unevenly, so that they finish out of order.
    struct Synthetic<'a, 'l> {
        laws: &'a Laws<'l, Frictionless>,
        centres: &'a [DVec3],
        salt: u64,
    }

    impl<'l> Candidates<'l> for Synthetic<'_, 'l> {
        type Candidate = u32;
        type Memory = u32;
        type Keeping = Frictionless;
        /// (Points with torques: their adding is tested too.)
        const CENTRAL: bool = false;

        fn eval(
            &self,
            &c: &u32,
            times: &mut u32,
            buf: &mut Vec<ContactPoint>,
            _: &mut KernelCounters,
        ) {
            *times += 1;
            let spin = (load(c / BLOCK as u32, self.salt) + 1.0) * 2e4;
            (0..spin as u32).for_each(|i| {
                std::hint::black_box(i);
            });
            points(c, self.salt, buf);
        }

        fn touching(&self, c: &u32) -> Touching<'l, Frictionless> {
            let (a, b) = bodies(c);
            let b = b.unwrap();
            let side = |i: usize| Side {
                index: i,
                centre: self.centres[i],
            };
            Touching {
                law: self.laws.pair(side(a), side(b)),
                a: (a, 0.01),
                b: Some((b, 0.007)),
            }
        }

        fn bodies(&self, c: &u32) -> (usize, Option<usize>) {
            bodies(c)
        }

        fn key(&self, &c: &u32, s: usize, _: &ContactPoint) -> ContactKey {
            ContactKey {
                a: c,
                b: 0,
                slot: s as u8,
            }
        }

        fn recorded(&self) -> &[Entry] {
            &[]
        }
    }

    /// Forces, torques and statistics of `n` synthetic candidates added by
    /// [`Sums::in_order`] (`threads`, a ring of `size`, twice on one ring),
    /// or, with `size` 0, by [`Sums::direct`]; and how many times each
    /// candidate was computed.
    fn ordered(n: usize, threads: usize, size: usize) -> (Vec<Vec<u64>>, Vec<u32>) {
        let (table, centres) = fibres();
        let none = crate::body::Bodies::new();
        let laws = Laws::<Frictionless>::new(&table, &none, &[]);
        let candidates: Vec<u32> = (0..n as u32).collect();
        let mut computed = vec![0u32; n];
        let mut ring: Ring = vec![];
        let mut out = vec![];
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut counters = KernelCounters::default();
        let mut buf = vec![];
        for salt in [1, 2] {
            let (mut force, mut torque) = (vec![DVec3::ZERO; 12], vec![DVec3::ZERO; 12]);
            let mut sums = Sums {
                force: &mut force,
                torque: &mut torque,
                dissipative: None,
                stats: ContactStats::default(),
                counters: &mut counters,
                kept: vec![],
                spring: 0.0,
            };
            let list = Synthetic {
                laws: &laws,
                centres: &centres,
                salt,
            };
            pool.install(|| {
                let (c, m) = (&candidates, &mut computed);
                if size == 0 {
                    sums.direct(&list, c, m, &mut buf);
                } else {
                    sums.in_order(&list, c, m, &mut ring, size, threads, &mut buf);
                }
            });
            let stats = sums.stats;
            out.push(bits(&force, &torque, &stats));
        }
        (out, computed)
    }

    /// [`Sums::in_order`] adds every block once, in list order, with the
    /// bits of a plain loop over the candidates, on 1 to 8 threads, rings
    /// of 1 to 3 slots or the whole list, lists of 0 to 17 blocks (the
    /// last one partial), reusing its ring for a second list; and so does
    /// one worker's [`Sums::direct`]. Run on a watchdog: a hang (a wait
    /// that never ends) fails the test.
    #[test]
    fn blocks_are_added_once_each_in_list_order() {
        let (done, wait) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for blocks in [0, 1, 2, 3, 5, 17] {
                let n = (blocks * BLOCK).saturating_sub(BLOCK / 3);
                let reference = serial(n);
                for threads in [1, 2, 3, 8] {
                    for size in [0, 1, 2, 3, usize::MAX] {
                        if size == 0 && threads > 1 {
                            continue;
                        }
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
