//! The force stage of a contact scene (Yade's chain: geometry → physical
//! parameters → force law). Built only when the scene can have contacts.
//!
//! Per computation: fibre poses → broad phase (a neighbour list, rebuilt
//! when bodies have moved) → the one candidate loop (`blocks.rs`): kernels
//! by shape pair ([`dispatch`](super::dispatch)) → the contact law per
//! point (`law/`, constants tabled at construction) → per-point loads added
//! to the bodies in list order → the ledger of the non-conservative loads
//! (`ledger.rs`). Deterministic: fixed blocks, sorted pairs, sums in list
//! order, on any number of threads. docs/architecture.md.

use super::blocks::{Blocks, Computed, Dissipative};
use super::broad::NeighbourList;
use super::damping::Restitution;
use super::fibre_fibre::PairMemory;
use super::history::History;
use super::law::{Frictional, Frictionless, Keeping, LawTable, Laws};
use super::ledger::WorkLedger;
use super::memory::{entries, Entry};
pub use super::shape::geom;
use super::shape::{shapes, ColliderKind, ColliderPose, ColliderShape, Shapes};
use super::{box_walls, contacts, Collider, FibreGeom, KernelCounters, Wall, Walls};
use crate::body::{Bodies, BodyState, Material};
use glam::DVec3;

/// What the last force computation saw.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStats {
    /// Touching pairs (body–body or body–wall).
    pub touching: usize,
    /// Largest overlap over the body's diameter, δ/D.
    pub max_overlap_ratio: f64,
    /// The body that largest overlap ratio is on.
    pub max_overlap_body: usize,
    /// Elastic energy of the live contacts, J.
    pub elastic: f64,
}

/// The contact force stage of a scene: walls, law constants, neighbour
/// list and the candidate loop's buffers, kept between steps.
#[derive(Debug, Clone)]
pub struct ContactStage {
    /// The six walls (none without a box).
    walls: Vec<Wall>,
    laws: LawTable,
    /// Each body's collider pose (`shape.rs`) at the last computation.
    poses: Vec<ColliderPose>,
    /// The collider shape of each distinct body value (`shape.rs`:
    /// [`Shapes`] reads it by body).
    shapes: Vec<ColliderShape>,
    /// Every body is a sphere (the candidate loop's `Spheres`).
    spheres: bool,
    neighbours: NeighbourList,
    counters: KernelCounters,
    /// The work of the laws' non-conservative loads, if they have any.
    ledger: Option<WorkLedger>,
    /// The candidate loop's buffers.
    blocks: Blocks,
    /// The touching contacts' records, if the law keeps them (friction).
    history: Option<History>,
    /// The energy stored in those contacts' springs at the last
    /// computation, J (0 without friction).
    spring: f64,
    /// Each body's motion bound since the last computation (m, rounded
    /// up), spent by its pairs' memories (`fibre_fibre/coherence.rs`).
    motion: Vec<f32>,
    /// MPI rank 0: every rank's pair memories, gathered for a checkpoint.
    #[cfg(feature = "mpi")]
    gathered: Option<Vec<Entry>>,
    /// MPI rank 0: every rank's contacts' records, gathered for a checkpoint.
    #[cfg(feature = "mpi")]
    gathered_history: Option<History>,
    /// What the last [`ContactStage::compute`] saw.
    pub stats: ContactStats,
}

/// Neighbour-list skin as a fraction of the thinnest body's diameter. Wider
/// means fewer rebuilds and more candidates to reject; at 0.2 D test case 2
/// (fibres at ≤ 5 m/s, δt = 1e-7 s) rebuilds once per ~1500 steps.
pub(crate) const SKIN_PER_DIAMETER: f64 = 0.2;

/// Put `new` in place of `p`; the motion bound between them
/// ([`super::shape::motion_bound`]) of a body of reach `reach`.
#[inline]
fn move_to(p: &mut ColliderPose, new: ColliderPose, reach: f64) -> f32 {
    let m = super::shape::motion_bound(p, &new, reach);
    *p = new;
    m
}

/// Put `new` in place of `p`, and the motion bound between them in `m`
/// unless the scene has spheres only: the bounds are read by fibre pairs'
/// memories only (`fibre_fibre/coherence.rs`), so a sphere scene's stay
/// unknown (`INFINITY`) and cost nothing.
#[inline(always)]
fn update(p: &mut ColliderPose, m: &mut f32, new: ColliderPose, reach: f64, spheres: bool) {
    if spheres {
        *p = new;
    } else {
        *m = move_to(p, new, reach);
    }
}

/// The stage's motion bound of a body (`shape.rs`), between two of its
/// kernel records.
#[inline]
pub fn motion_bound(old: &FibreGeom, new: &FibreGeom) -> f32 {
    let pose = |g: &FibreGeom| ColliderPose {
        centre: g.centre,
        axis: g.axis,
    };
    let reach = ColliderShape::reach_of(new.radius, new.half_length);
    super::shape::motion_bound(&pose(old), &pose(new), reach)
}

impl ContactStage {
    /// The stage of `bodies` (made of `materials`) in the box `walls`, if
    /// any: the Hertz laws of every pair of contact kinds are built here.
    pub fn new(bodies: &Bodies, materials: &[Material], walls: Option<&Walls>) -> Self {
        let thinnest = bodies
            .iter()
            .map(|b| b.shape.diameter())
            .fold(f64::INFINITY, f64::min);
        ContactStage {
            walls: walls.map(box_walls).unwrap_or_default(),
            laws: LawTable::new(bodies, materials, walls),
            poses: Vec::with_capacity(bodies.len()),
            shapes: shapes(bodies),
            spheres: bodies
                .iter()
                .all(|b| ColliderKind::of(&b.shape) == Some(ColliderKind::Sphere)),
            neighbours: NeighbourList::new(SKIN_PER_DIAMETER * thinnest),
            counters: KernelCounters::default(),
            ledger: None,
            blocks: Blocks::default(),
            history: None,
            spring: 0.0,
            motion: vec![],
            #[cfg(feature = "mpi")]
            gathered: None,
            #[cfg(feature = "mpi")]
            gathered_history: None,
            stats: ContactStats::default(),
        }
    }

    /// The stage with Coulomb friction `f` (`None`: frictionless), its
    /// contacts' springs advanced by `dt` per computation (before
    /// [`ContactStage::with_damping`], which makes the ledger of every
    /// non-conservative load).
    pub fn with_friction(
        mut self,
        f: Option<crate::contact::tangential::Friction>,
        dt: f64,
    ) -> Self {
        self.laws = self.laws.with_friction(f, dt);
        self.history = self.laws.keeps_history().then(History::default);
        self
    }

    /// The stage with normal damping of restitution `e` (`None`: elastic)
    /// for `n` bodies stepped by `dt` under `gravity` (for the ledger of
    /// its work).
    pub fn with_damping(
        mut self,
        e: Option<Restitution>,
        n: usize,
        dt: f64,
        gravity: Option<DVec3>,
    ) -> Self {
        self.laws = self.laws.with_restitution(e);
        self.ledger = self
            .laws
            .reads_motion()
            .then(|| WorkLedger::new(n, dt, gravity));
        self
    }

    /// Tell the ledger whether the forces see the angular velocity at the
    /// middle of their torque's interval (`Rotator::SPIN_AT_MIDPOINT`).
    #[inline]
    pub fn ledger_spin_at_midpoint(&mut self, yes: bool) {
        if let Some(l) = &mut self.ledger {
            l.set_spin_at_midpoint(yes);
        }
    }

    /// Energy dissipated by the non-conservative loads up to the last
    /// computation's state, J (0 for an elastic law): the work done
    /// against them less what of it the friction springs hold
    /// ([`ContactStage::spring_energy`]), which they give back as they
    /// unload.
    #[inline]
    pub fn dissipated(&self) -> f64 {
        self.ledger
            .as_ref()
            .map_or(0.0, |l| l.dissipated - self.spring)
    }

    /// Energy held by the tangential springs of the touching contacts at
    /// the last computation, `Σ ½ k_t |ξ|²` with that computation's `k_t`,
    /// each `½ k_t |ξ|²` (`tangential::spring_energy`), J
    /// (0 without friction).
    #[inline]
    pub fn spring_energy(&self) -> f64 {
        self.spring
    }

    /// The ledger's state between steps (`None` for an elastic law;
    /// `ledger.rs`).
    pub fn damping_state(&self) -> Option<[f64; 2]> {
        self.ledger.as_ref().map(WorkLedger::state)
    }

    /// Put back a [`ContactStage::damping_state`]; false when the stage's
    /// law is elastic.
    pub fn set_damping_state(&mut self, state: [f64; 2]) -> bool {
        self.ledger.as_mut().map(|l| l.set_state(state)).is_some()
    }

    /// The touching contacts' records a checkpoint keeps (a law that keeps
    /// them: friction): those of the last computation, or, on an MPI rank
    /// 0, every rank's, gathered.
    pub(crate) fn kept_history(&self) -> Option<&History> {
        #[cfg(feature = "mpi")]
        if let Some(g) = &self.gathered_history {
            return Some(g);
        }
        self.history.as_ref()
    }

    /// Put back the records of [`ContactStage::kept_history`] (resuming;
    /// an MPI rank's at a rebuild); false when the law keeps none.
    /// `spring` is their energy ([`ContactStage::spring_energy`]).
    pub(crate) fn set_history(&mut self, h: History, spring: f64) -> bool {
        self.spring = spring;
        self.history.as_mut().map(|mine| *mine = h).is_some()
    }

    /// The pair memories a checkpoint keeps ([`PairMemory::kept_by_checkpoints`]),
    /// by pair: those of the last computation's candidates (or, on an MPI
    /// rank 0, every rank's, gathered).
    pub fn memory_entries(&self) -> Vec<Entry> {
        #[cfg(feature = "mpi")]
        if let Some(g) = &self.gathered {
            return g.clone();
        }
        let list = &self.neighbours;
        entries(&list.pairs, &list.memory, PairMemory::kept_by_checkpoints).collect()
    }

    /// Resume with a checkpoint's pair memories at `states` (the
    /// checkpoint's): the next computation, at these states, rebuilds the
    /// list and gives each pair its memory, and sees no motion. Each
    /// memory left out (a fresh one) is made again by that computation's
    /// scan, as the run that wrote the checkpoint made it at this state.
    pub fn restore_memory(&mut self, memory: Vec<Entry>, bodies: &Bodies, states: &[BodyState]) {
        let shapes = Shapes::new(&self.shapes, bodies);
        self.poses.clear();
        self.poses.extend(
            (states.iter().enumerate()).map(|(i, s)| ColliderPose::of(shapes.get(i).kind, s)),
        );
        let list = &mut self.neighbours;
        list.built.clear();
        (list.pairs, list.memory) = memory.into_iter().unzip();
    }

    /// Neighbour-list builds so far.
    pub fn neighbour_builds(&self) -> u64 {
        self.neighbours.builds
    }

    /// The kernels' diagnostic counts, summed over every computation so far.
    pub fn kernel_counters(&self) -> KernelCounters {
        self.counters
    }

    /// Touching bodies and walls per body (storage order) at the states of
    /// the last [`ContactStage::compute`]: its candidates asked again
    /// through the kernels. For output frames (VTK cell data, `render`), so
    /// the step itself keeps no per-body counts and pays nothing for them.
    #[cold]
    #[inline(never)]
    pub fn touching_per_body(&self, bodies: &Bodies) -> Vec<u32> {
        let mut count = vec![0u32; self.poses.len()];
        let mut points = Vec::new();
        let mut counters = KernelCounters::default();
        let mut touch = |a: Collider, b: Collider| {
            points.clear();
            contacts(a, b, &mut points, &mut counters);
            !points.is_empty()
        };
        let shapes = Shapes::new(&self.shapes, bodies);
        let body = |i: usize| shapes.collider(i, &self.poses[i]);
        for &(i, k) in &self.neighbours.walls {
            let (i, wall) = (i as usize, &self.walls[k as usize]);
            count[i] += touch(body(i), Collider::Wall(wall)) as u32;
        }
        for &(a, b) in &self.neighbours.pairs {
            let (a, b) = (a as usize, b as usize);
            let t = touch(body(a), body(b)) as u32;
            count[a] += t;
            count[b] += t;
        }
        count
    }

    /// Contact forces and torques (world) at `states`, written into
    /// `force` and `torque` (overwritten), with the laws of the table
    /// built by [`ContactStage::new`].
    pub fn compute(
        &mut self,
        bodies: &Bodies,
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
    ) {
        let workers = workers(bodies.len());
        self.update_geometry(bodies, states, workers > 1);
        // The law's records chosen once: a frictionless loop has none.
        (self.stats, self.spring) = if self.laws.keeps_history() {
            self.candidates::<Frictional>(bodies, states, force, torque, workers)
        } else {
            self.candidates::<Frictionless>(bodies, states, force, torque, workers)
        };
        if let Some(l) = &mut self.ledger {
            l.account(bodies, states, (force, torque));
        }
    }

    /// The candidate loop over this stage's own list, with laws that keep
    /// records or not (`F`), its ledger and its history.
    #[inline(always)]
    fn candidates<F: Keeping>(
        &mut self,
        bodies: &Bodies,
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
        workers: usize,
    ) -> (ContactStats, f64) {
        candidate_loop(
            &mut self.blocks,
            &mut self.neighbours,
            (
                &self.poses,
                Shapes::new(&self.shapes, bodies),
                self.spheres,
                &self.motion,
                &self.walls,
            ),
            &Laws::<F>::new(&self.laws, bodies, states),
            (force, torque),
            &mut self.counters,
            self.ledger.as_mut().map(WorkLedger::loads),
            self.history.as_mut(),
            false,
            workers,
        )
    }

    /// The kernels' geometry of the bodies at `states` and each body's
    /// motion bound since the last computation, and the neighbour list
    /// rebuilt if a body left its skin. One thread updates only the
    /// bodies in a candidate while the list holds (the others' geometry is
    /// not read); the pool tests and updates every body in one pass.
    fn update_geometry(&mut self, bodies: &Bodies, states: &[BodyState], pool: bool) {
        use rayon::prelude::*;
        let spheres = self.spheres;
        let shapes = Shapes::new(&self.shapes, bodies);
        self.poses.resize(bodies.len(), ColliderPose::default());
        self.motion.resize(bodies.len(), f32::INFINITY);
        let valid = if pool {
            // Each body is tested at its new pose.
            let within = self.neighbours.within_skin(bodies.len());
            self.poses
                .par_iter_mut()
                .zip(self.motion.par_iter_mut())
                .zip(states.par_iter())
                .enumerate()
                .map(|(i, ((p, m), s))| {
                    let shape = shapes.get(i);
                    let kept = within
                        .as_ref()
                        .is_some_and(|w| w(i, s.x, s.rot.q, shape.half_length));
                    update(p, m, ColliderPose::of(shape.kind, s), shape.reach, spheres);
                    kept
                })
                .reduce(|| true, |x, y| x && y)
        } else {
            let poses =
                (states.iter().enumerate()).map(|(i, s)| (s.x, s.rot.q, shapes.get(i).half_length));
            let valid = self.neighbours.still_valid(poses);
            if valid {
                if spheres {
                    // A sphere's pose moves with its centre only (its axis
                    // is the fixed one of the last full update).
                    for &i in &self.neighbours.active {
                        let i = i as usize;
                        self.poses[i].centre = states[i].x;
                    }
                } else {
                    for &i in &self.neighbours.active {
                        let i = i as usize;
                        let shape = shapes.get(i);
                        let new = ColliderPose::of(shape.kind, &states[i]);
                        self.motion[i] = move_to(&mut self.poses[i], new, shape.reach);
                    }
                }
            } else {
                let each = self.poses.iter_mut().zip(&mut self.motion).zip(states);
                for (i, ((p, m), s)) in each.enumerate() {
                    let shape = shapes.get(i);
                    update(p, m, ColliderPose::of(shape.kind, s), shape.reach, spheres);
                }
            }
            valid
        };
        if !valid {
            let rotations = states.iter().map(|s| s.rot.q);
            (self.neighbours).build(&self.poses, shapes, rotations, &self.walls);
        }
    }
}

/// The candidate loop ([`Blocks::compute`]) with the kernels, or, in a
/// measuring build that replays recorded answers, with those
/// (`replay.rs`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn candidate_loop<F: Keeping>(
    blocks: &mut Blocks,
    list: &mut NeighbourList,
    scene: (&[ColliderPose], Shapes, bool, &[f32], &[Wall]),
    laws: &Laws<F>,
    loads: (&mut [DVec3], &mut [DVec3]),
    counters: &mut KernelCounters,
    dissipative: Option<Dissipative>,
    history: Option<&mut History>,
    keep_hits: bool,
    workers: usize,
) -> (ContactStats, f64) {
    #[cfg(feature = "replay")]
    if super::replay::active() {
        let kernel = super::replay::Replaying;
        return blocks.compute(
            &kernel,
            list,
            scene,
            laws,
            loads,
            counters,
            dissipative,
            history,
            keep_hits,
            workers,
        );
    }
    blocks.compute(
        &Computed,
        list,
        scene,
        laws,
        loads,
        counters,
        dissipative,
        history,
        keep_hits,
        workers,
    )
}

/// Scenes of at least this many bodies compute their forces on the thread
/// pool (when it has more than one thread); smaller ones stay on one
/// thread, where the pool's overhead would cost more than it saves. Both
/// give the same bits.
pub const PARALLEL_MIN_BODIES: usize = 256;

/// Whether a scene of `n` bodies runs its stages on the thread pool.
#[inline]
pub fn parallel(n: usize) -> bool {
    n >= PARALLEL_MIN_BODIES && rayon::current_num_threads() > 1
}

/// The threads the candidate loop of a scene of `n` bodies runs on.
#[inline]
fn workers(n: usize) -> usize {
    if parallel(n) {
        rayon::current_num_threads()
    } else {
        1
    }
}

impl ContactStats {
    #[inline]
    pub(crate) fn note_overlap(&mut self, ratio: f64, body: usize) {
        if ratio > self.max_overlap_ratio {
            self.max_overlap_ratio = ratio;
            self.max_overlap_body = body;
        }
    }

    /// A contact's overlap on its body A and its body B (none for a wall),
    /// each `(index, diameter)`: as [`ContactStats::note_overlap`] of
    /// `δ/D_A` on A, then of `δ/D_B` on B. B's ratio is taken only when
    /// B is the thinner: else it is no larger than A's (a rounded division
    /// is monotone in its divisor), which has just been noted, and a tie
    /// keeps the first.
    #[inline(always)]
    pub(crate) fn note_contact_overlap(
        &mut self,
        overlap: f64,
        (a, d_a): (usize, f64),
        b: Option<(usize, f64)>,
    ) {
        self.note_overlap(overlap / d_a, a);
        if let Some((b, d_b)) = b {
            if d_b < d_a {
                self.note_overlap(overlap / d_b, b);
            }
        }
    }
}

/// The hooks of an MPI rank's force stage (`src/ranks/`): the rank lists
/// its own candidates (global body indices, sorted as the one-process list)
/// and the stage computes them with the one candidate loop, so every owned
/// body gathers its contacts in the one-process order.
#[cfg(feature = "mpi")]
impl ContactStage {
    /// Body `i`'s motion bound from its geometry at the last computation
    /// to `state` (the one-process stage's, for the rank that owns it).
    pub(crate) fn motion_since_last(&self, i: usize, bodies: &Bodies, state: &BodyState) -> f32 {
        let shape = Shapes::new(&self.shapes, bodies).get(i);
        let new = ColliderPose::of(shape.kind, state);
        super::shape::motion_bound(&self.poses[i], &new, shape.reach)
    }

    /// The touching pair memories of this stage's own list (every
    /// candidate's, at the start of an MPI run), by pair.
    pub(crate) fn touching_memories(&self) -> Vec<Entry> {
        let list = &self.neighbours;
        entries(&list.pairs, &list.memory, PairMemory::is_touching).collect()
    }

    /// Rank 0: every rank's memories that a checkpoint keeps
    /// ([`ContactStage::memory_entries`] then answers these).
    pub(crate) fn set_gathered_memories(&mut self, all: Vec<Entry>) {
        self.gathered = Some(all);
    }

    /// Rank 0: every rank's contacts' records that a checkpoint keeps
    /// ([`ContactStage::kept_history`] then answers these).
    pub(crate) fn set_gathered_history(&mut self, all: History) {
        self.gathered_history = Some(all);
    }

    /// The records of this stage's last computation (a law that keeps
    /// them).
    pub(crate) fn history(&self) -> Option<&History> {
        self.history.as_ref()
    }

    /// Whether the law reads the bodies' velocities (a ghost then needs
    /// them with its pose).
    pub(crate) fn reads_motion(&self) -> bool {
        self.laws.reads_motion()
    }

    /// Body `i`'s share of the ledger's sums after the last
    /// [`Self::compute_listed`] (`WorkLedger::body_work`; `None`: no
    /// non-conservative load, or an elastic frictionless law), `loads` its
    /// total contact force and torque.
    pub(crate) fn body_work(
        &self,
        i: usize,
        b: &crate::body::Body,
        s: &BodyState,
        loads: (DVec3, DVec3),
    ) -> Option<[f64; 2]> {
        self.ledger.as_ref()?.body_work(i, b, s, loads)
    }

    /// Rank 0: close the ledger with the one-process sums of every body's
    /// share ([`WorkLedger::close`]).
    pub(crate) fn close_work(&mut self, closing: f64, full: f64) {
        if let Some(l) = &mut self.ledger {
            l.close(closing, full);
        }
    }

    /// Each body's collider shape (`shape.rs`), `bodies` being the
    /// stage's.
    pub(crate) fn shapes<'a>(&'a self, bodies: &'a Bodies) -> Shapes<'a> {
        Shapes::new(&self.shapes, bodies)
    }

    /// The box walls, in the order the neighbour list numbers them.
    pub(crate) fn walls(&self) -> &[Wall] {
        &self.walls
    }

    /// The neighbour-list skin of the one-process stage, m.
    pub(crate) fn skin(&self) -> f64 {
        self.neighbours.skin()
    }

    /// Forces and torques from the candidates of `list` (global indices)
    /// at `states`, for the bodies `local` (ascending; the geometry of no
    /// other body is read), whose pairs' memories spend `motion` (by
    /// global index, from each body's owner). Bodies outside `local` get
    /// partial sums, which the rank ignores; so do their non-conservative
    /// loads (for the ledger's shares, [`Self::body_work`]). The contacts'
    /// records are read from and written to this stage's store, which the
    /// rank keeps holding those of its candidates.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn compute_listed(
        &mut self,
        list: &mut NeighbourList,
        local: &[u32],
        motion: &[f32],
        bodies: &Bodies,
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
    ) {
        let shapes = Shapes::new(&self.shapes, bodies);
        self.poses.resize(bodies.len(), ColliderPose::default());
        self.motion.resize(bodies.len(), f32::INFINITY);
        for &i in local {
            let i = i as usize;
            self.poses[i] = ColliderPose::of(shapes.get(i).kind, &states[i]);
            self.motion[i] = motion[i];
        }
        // The rank's share of the springs' energy is not this stage's: rank
        // 0 sums every rank's in the one-process order (`ranks/tally.rs`).
        if self.laws.keeps_history() {
            self.listed::<Frictional>(list, bodies, states, force, torque);
        } else {
            self.listed::<Frictionless>(list, bodies, states, force, torque);
        }
    }

    /// The candidate loop over `list`, keeping its hits, with laws that
    /// keep records or not (`F`).
    fn listed<F: Keeping>(
        &mut self,
        list: &mut NeighbourList,
        bodies: &Bodies,
        states: &[BodyState],
        force: &mut [DVec3],
        torque: &mut [DVec3],
    ) {
        candidate_loop(
            &mut self.blocks,
            list,
            (
                &self.poses,
                Shapes::new(&self.shapes, bodies),
                self.spheres,
                &self.motion,
                &self.walls,
            ),
            &Laws::<F>::new(&self.laws, bodies, states),
            (force, torque),
            &mut self.counters,
            self.ledger.as_mut().map(WorkLedger::loads),
            self.history.as_mut(),
            true,
            workers(bodies.len()),
        );
    }

    /// The springs' energy of the whole scene at the last computation
    /// (an MPI rank's, summed by rank 0 in the one-process order), J.
    pub(crate) fn set_spring_energy(&mut self, spring: f64) {
        self.spring = spring;
    }

    /// Each touching candidate of the last [`Self::compute_listed`]:
    /// `(wall, candidate, [(weight·U, δ/D on A, δ/D on B)], springs'
    /// energies)` in list order.
    pub(crate) fn for_each_hit(
        &self,
        list: &NeighbourList,
        bodies: &Bodies,
        f: impl FnMut(bool, u32, &mut dyn Iterator<Item = [f64; 3]>, &[f64]),
    ) {
        let shapes = Shapes::new(&self.shapes, bodies);
        self.blocks.for_each_hit(list, shapes, f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::blocks::BLOCK;
    use crate::contact::damping::Restitution;
    use crate::contact::law::{Record, Side};
    use crate::contact::{contacts_remembering, ContactPoint};
    use glam::DQuat;

    /// A block of 4 × 12 × 12 fibres along x (D = 0.01 m, L = 0.025 m),
    /// each overlapping its side and end neighbours by ~10 µm and the outer
    /// ones pressing on the box, tilted by up to 2 mrad and moving at up to
    /// 0.3 m/s: two blocks of wall candidates and twelve of pairs.
    fn packed(seed: u64) -> crate::scenario::Scene {
        packed_of(seed, Some(0.025), 4)
    }

    /// [`packed`] of fibres of length `length`, or of spheres (`None`, D =
    /// 0.01 m), `nx` along x.
    fn packed_of(seed: u64, length: Option<f64>, nx: usize) -> crate::scenario::Scene {
        let (d, squeeze) = (0.01, 1e-5);
        let (ny, nz) = (12, 12);
        let (px, py) = (length.unwrap_or(d) - squeeze, d - squeeze);
        let max = [px * nx as f64, py * ny as f64, py * nz as f64];
        let shape = match length {
            Some(l) => format!("shape = \"fibre\"\ndiameter = {d}\nlength = {l}"),
            None => format!("shape = \"sphere\"\ndiameter = {d}"),
        };
        let text = format!(
            "[simulation]\ndt = 1e-6\nt_end = 1e-6\n[box]\nmin = [0.0, 0.0, 0.0]\nmax = [{}, {}, {}]\nyoung = 5e7\npoisson = 0.23\n[[body]]\n{shape}\ndensity = 1100.0\nyoung = 5e7\npoisson = 0.35\nposition = [0.1, 0.1, 0.1]\n",
            max[0] + 0.1, max[1] + 0.1, max[2] + 0.1
        );
        let mut scene = crate::scenario::parse_str(&text, "<packed>").expect("one-body template");
        // The box, squeezed onto the block (the template's is loose so that
        // the single body loads).
        let walls = scene.walls.as_mut().expect("a box");
        walls.max = DVec3::from_array(max) + DVec3::splat(squeeze);
        walls.min = -DVec3::splat(squeeze);
        let template = scene.bodies[0];
        let mut seed = seed;
        let mut r = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            2.0 * ((seed >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        scene.bodies = Default::default();
        scene.initial.clear();
        for i in 0..nx {
            for j in 0..ny {
                for k in 0..nz {
                    let axis = DVec3::new(1.0, 2e-3 * r(), 2e-3 * r()).normalize();
                    let x = DVec3::new(
                        px * (i as f64 + 0.5),
                        py * (j as f64 + 0.5),
                        py * (k as f64 + 0.5),
                    ) + if length.is_none() {
                        // Spheres off the grid by up to 3 µm: normals off
                        // the axes.
                        3e-6 * DVec3::new(r(), r(), r())
                    } else {
                        DVec3::ZERO
                    };
                    scene.bodies.push(template);
                    scene.initial.push(BodyState {
                        x,
                        v: 0.3 * DVec3::new(r(), r(), r()),
                        rot: crate::body::RotState {
                            q: DQuat::from_rotation_arc(DVec3::X, axis),
                            omega_b: DVec3::new(r(), r(), r()),
                        },
                    });
                }
            }
        }
        scene
    }

    /// Forces, torques, statistics and dissipated energy of `stage` at
    /// `states`, on a pool of `threads`.
    fn on_pool(
        stage: &mut ContactStage,
        bodies: &Bodies,
        states: &[BodyState],
        threads: usize,
    ) -> (Vec<[u64; 6]>, ContactStats, u64) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let n = bodies.len();
        let (mut force, mut torque) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        pool.install(|| stage.compute(bodies, states, &mut force, &mut torque));
        let bits = force
            .iter()
            .zip(&torque)
            .map(|(f, t)| {
                let (f, t) = (f.to_array(), t.to_array());
                [f[0], f[1], f[2], t[0], t[1], t[2]].map(f64::to_bits)
            })
            .collect();
        (bits, stage.stats, stage.dissipated().to_bits())
    }

    /// Reference: a plain loop over the candidates of `stage` at `states`,
    /// each touching one's points through the law and added straight to
    /// the bodies (no block, no buffer of loads), the statistics noted as
    /// it goes; with its ledger's work. `stage` is the one-thread stage
    /// before the computation (its memories as the computation finds
    /// them).
    fn plain_loop(
        stage: &mut ContactStage,
        bodies: &Bodies,
        states: &[BodyState],
    ) -> (Vec<[u64; 6]>, ContactStats, u64) {
        stage.update_geometry(bodies, states, false);
        let n = bodies.len();
        let (mut force, mut torque) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let (mut df, mut dt) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let mut stats = ContactStats::default();
        let (mut points, mut counters) = (Vec::<ContactPoint>::new(), KernelCounters::default());
        let table = stage.laws.clone();
        let laws = Laws::<Frictionless>::new(&table, bodies, states);
        let shapes = Shapes::new(&stage.shapes, bodies);
        let geoms: Vec<FibreGeom> = (stage.poses.iter().enumerate())
            .map(|(i, p)| shapes.get(i).fibre(p))
            .collect();
        let collider = |i: usize| shapes.collider(i, &stage.poses[i]);
        let side = |i: usize| Side {
            index: i,
            centre: geoms[i].centre,
        };
        let mut add = |law: &crate::contact::law::CandidateLaw<Frictionless>,
                       points: &[ContactPoint],
                       a: usize,
                       b: Option<usize>| {
            if points.is_empty() {
                return;
            }
            stats.touching += 1;
            for c in points {
                let l = law.load(c, &mut Record::default());
                force[a] += l.total.force;
                torque[a] += l.total.torque_a;
                let d = l.dissipative.unwrap_or_default();
                df[a] += d.force;
                dt[a] += d.torque_a;
                stats.elastic += l.elastic;
                stats.note_overlap(c.overlap / (2.0 * geoms[a].radius), a);
                if let Some(b) = b {
                    force[b] -= l.total.force;
                    torque[b] -= l.total.torque_b;
                    df[b] -= d.force;
                    dt[b] -= d.torque_b;
                    stats.note_overlap(c.overlap / (2.0 * geoms[b].radius), b);
                }
            }
        };
        for &(i, k) in &stage.neighbours.walls {
            let i = i as usize;
            points.clear();
            let wall = Collider::Wall(&stage.walls[k as usize]);
            contacts(collider(i), wall, &mut points, &mut counters);
            add(&laws.wall(side(i)), &points, i, None);
        }
        let list = &mut stage.neighbours;
        for (&(a, b), memory) in list.pairs.iter().zip(&mut list.memory) {
            let (a, b) = (a as usize, b as usize);
            let motion = f64::from(stage.motion[a]) + f64::from(stage.motion[b]);
            points.clear();
            let (fa, fb) = (collider(a), collider(b));
            contacts_remembering(fa, fb, &mut points, &mut counters, Some((memory, motion)));
            add(&laws.pair(side(a), side(b)), &points, a, Some(b));
        }
        let dissipated = stage.ledger.as_mut().map_or(0.0, |l| {
            let (f, t) = l.loads();
            f.copy_from_slice(&df);
            t.copy_from_slice(&dt);
            l.account(bodies, states, (&force, &torque));
            l.dissipated
        });
        let bits = force
            .iter()
            .zip(&torque)
            .map(|(f, t)| {
                let (f, t) = (f.to_array(), t.to_array());
                [f[0], f[1], f[2], t[0], t[1], t[2]].map(f64::to_bits)
            })
            .collect();
        (bits, stats, dissipated.to_bits())
    }

    /// The candidate loop (`blocks.rs`: candidates in fixed blocks, added
    /// one at a time in order) gives the bits of a plain loop over the
    /// candidates ([`plain_loop`]) on one thread and on the pool (rings of
    /// several sizes), on a scene of several blocks of walls and pairs,
    /// elastic and damped, at a first and at a second configuration (the
    /// blocks' buffers reused, some contacts gone, others new).
    #[test]
    fn the_loop_gives_the_bits_of_a_plain_loop_on_any_thread_count() {
        let scene = packed(0x9e37_79b9_7f4a_7c15);
        let (bodies, n) = (&scene.bodies, scene.bodies.len());
        // The second configuration: every fibre moved by 3 µs of its velocity
        // and turned a little (within the skin: the list is kept).
        let moved: Vec<BodyState> = scene
            .initial
            .iter()
            .map(|s| {
                let mut s = *s;
                s.x += 3e-6 * s.v;
                s.rot.q = (s.rot.q * DQuat::from_scaled_axis(3e-6 * s.rot.omega_b)).normalize();
                s
            })
            .collect();
        for damping in [
            None,
            Some(Restitution {
                fibre: 0.5,
                wall: 0.7,
            }),
        ] {
            let new = || {
                ContactStage::new(bodies, &scene.materials, scene.walls.as_ref())
                    .with_damping(damping, n, 1e-6, None)
            };
            let mut one = new();
            let mut plain = one.clone();
            let first = on_pool(&mut one, bodies, &scene.initial, 1);
            assert!(
                plain_loop(&mut plain, bodies, &scene.initial) == first,
                "one thread, first configuration, damping {damping:?}"
            );
            let second = on_pool(&mut one, bodies, &moved, 1);
            assert!(
                plain_loop(&mut plain, bodies, &moved) == second,
                "one thread, second configuration, damping {damping:?}"
            );
            let list = &one.neighbours;
            assert!(
                list.walls.len() > BLOCK && list.pairs.len() > 2 * BLOCK,
                "several blocks: {} wall and {} pair candidates",
                list.walls.len(),
                list.pairs.len()
            );
            assert!(
                first.1.touching > BLOCK && second.1.touching > BLOCK,
                "live contacts: {} then {}",
                first.1.touching,
                second.1.touching
            );
            assert_eq!(one.neighbour_builds(), 1, "the list is kept");
            // Rings of 1 and 2 slots: the walls' two blocks and the pairs'
            // twelve computed at most one or two ahead of the adding (the
            // default holds them all).
            for (threads, ring) in [(2, None), (3, None), (2, Some(1)), (3, Some(2))] {
                let mut many = new();
                if let Some(r) = ring {
                    many.blocks.ring = r;
                }
                assert!(
                    on_pool(&mut many, bodies, &scene.initial, threads) == first,
                    "{threads} threads, ring {ring:?}, first configuration, damping {damping:?}"
                );
                assert!(
                    on_pool(&mut many, bodies, &moved, threads) == second,
                    "{threads} threads, ring {ring:?}, second configuration, damping {damping:?}"
                );
            }
        }
    }

    /// A scene of spheres only is looped as such (`blocks.rs`, `Spheres`:
    /// the sphere–sphere kernel for every pair, central contacts). Its
    /// forces, statistics and dissipation are the bits of the plain loop's
    /// (which reads every body's kind and goes through the dispatch), on
    /// one thread and on the pool, and its torques are exactly zero, as
    /// those of a frictionless central contact are (Newton: the force's
    /// line passes through both centres), where the plain loop's
    /// `(p − c) × F` leaves rounding. (Mutants tried: the sphere list
    /// calling no kernel; the law's torques added for central contacts.)
    #[test]
    fn a_sphere_scene_has_the_forces_of_the_generic_loop_and_no_torques() {
        let scene = packed_of(0x2545_f491_4f6c_dd1d, None, 10);
        let (bodies, n) = (&scene.bodies, scene.bodies.len());
        for damping in [
            None,
            Some(Restitution {
                fibre: 0.5,
                wall: 0.7,
            }),
        ] {
            let new = || {
                ContactStage::new(bodies, &scene.materials, scene.walls.as_ref())
                    .with_damping(damping, n, 1e-6, None)
            };
            let mut plain = new();
            let (bits, stats, dissipated) = plain_loop(&mut plain, bodies, &scene.initial);
            assert!(
                stats.touching > 2 * BLOCK,
                "live contacts: {}",
                stats.touching
            );
            // The plain loop's torques: rounding, on some sphere at least.
            assert!(bits.iter().any(|b| b[3..] != [0; 3]));
            for threads in [1, 2, 3] {
                let mut stage = new();
                let (got, got_stats, got_dissipated) =
                    on_pool(&mut stage, bodies, &scene.initial, threads);
                assert_eq!(got_stats, stats, "{threads} threads, damping {damping:?}");
                for (i, (g, p)) in got.iter().zip(&bits).enumerate() {
                    assert_eq!(g[..3], p[..3], "force on {i}, {threads} threads");
                    assert_eq!(g[3..], [0; 3], "torque on {i}, {threads} threads");
                }
                // The ledger's work: the damping's torques did no work
                // worth a bit here either way.
                let (a, b) = (f64::from_bits(got_dissipated), f64::from_bits(dissipated));
                assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} vs {b}");
            }
        }
    }
}
