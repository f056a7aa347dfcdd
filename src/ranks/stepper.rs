//! One rank's step: the one-process step with the bodies split between
//! the ranks, and the same bits.
//!
//! Every rank keeps the scene's arrays by global body index (the index of
//! the one-process scene), but only the entries of its own bodies and of
//! its ghosts are current. A step:
//! 1. opening stage (half-kick, drift, rotator `advance`) of the owned bodies;
//! 2. the rebuild test of the one-process neighbour list on the owned
//!    bodies, decided for all by one all-reduce; on a rebuild the owned
//!    states are all-gathered and the slabs cut again (migration), else
//!    the ghosts' poses are exchanged (all-to-all);
//! 3. forces on the owned bodies from this rank's candidates, which are
//!    exactly the one-process candidates touching an owned body, by
//!    global index, gathered per body in the one-process order;
//! 4. closing stage of the owned bodies and their ledger terms;
//! 5. the scene sums on rank 0 in the one-process order ([`super::tally`]),
//!    broadcast; the guards then decide the same on every rank.
//!
//! Per-body arithmetic is the one-process arithmetic, and every sum is in
//! the one-process order, so states, energies and guards are bit-identical
//! to one process for any number of ranks.

use super::carry::{Message, Received};
use super::comm::Comm;
use super::slabs::Slabs;
use super::tally::{self, HitKey};
use crate::body::{Bodies, BodyState};
use crate::contact::broad::{skin_limit2, NeighbourList, SkinRef};
use crate::contact::carry::listed;
use crate::contact::fibre_fibre::PairMemory;
use crate::contact::history::History;
use crate::contact::memory::{entries, place, Entry};
use crate::contact::shape::{shapes, ColliderPose, Shapes};
use crate::contact::stage::ContactStats;
use crate::energy::Ledger;
use crate::integrate::rotate::{AuxState, Rotator, RotatorFault};
use crate::integrate::scheme::Stage;
use crate::integrate::step::{body_is_sound, fault_diagnosis, World};
use crate::integrate::walk::Owned;
use crate::run::driver::Stepper;
use crate::stop::Diagnosis;
use glam::{DQuat, DVec3};
use mpi::Count;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Doubles of one body's state on the wire: x, v, q (xyzw), ω_b.
const STATE: usize = 13;
/// Doubles of one ghost's pose and motion: x, q, the motion bound of its
/// last step (its pairs' memories spend it).
const POSE: usize = 8;
/// Doubles of a ghost's velocities, sent after its pose when the contact
/// law reads them (damping, friction): v, ω_b.
const VELOCITIES: usize = 6;
/// Doubles of one body's share of the ledger of the non-conservative
/// loads per force stage: whether it has one, and its two terms.
const WORK: usize = 3;

/// One rank's share of the run and its clocks.
pub(crate) struct RankStep<'c> {
    pub comm: Comm<'c>,
    slabs: Slabs,
    /// Owned and ghost bodies, ascending.
    local: Vec<u32>,
    /// Ghost width along the cut axis: L_max + D_max + skin.
    width: f64,
    /// This rank's candidates by global index; `None` without contacts.
    list: Option<NeighbourList>,
    /// Pose of every body at the last build, and the bound of the skin
    /// test of those references (`contact/broad.rs`).
    built: Vec<SkinRef>,
    limit2: f64,
    /// Each body's motion bound over the last step, by global index (the
    /// owned bodies' and ghosts' current): what the one-process stage
    /// spends its pairs' memories by. Computed by the owner, whose
    /// geometry of the body is the last step's, and sent with the poses.
    motion: Vec<f32>,
    /// Per destination rank, the owned bodies it keeps as ghosts.
    sends: Vec<Vec<u32>>,
    /// Per source rank, its bodies this rank keeps as ghosts.
    recvs: Vec<Vec<u32>>,
    /// This step's message to rank 0: flags, ledger terms, hits.
    msg: Vec<f64>,
    /// This step's shares of the owned bodies in the ledger of the
    /// non-conservative loads, [`WORK`] per body and force stage (a law
    /// that reads velocities).
    work: Vec<f64>,
    /// Force stages this step.
    force_stages: usize,
    /// Rank 0: per-body ledger terms by global index.
    terms: Vec<[f64; 3]>,
    /// Rank 0: per force stage and body (by global index) its [`WORK`]
    /// share.
    shares: Vec<[f64; WORK]>,
    pub clocks: Clocks,
}

/// Where a rank's time goes, and its load.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Clocks {
    pub steps: u64,
    pub rebuilds: u64,
    /// Bodies that migrated to this rank at the rebuilds.
    pub migrated: u64,
    pub forces: Duration,
    pub integrate: Duration,
    /// Sum over steps of the owned and ghost counts (for their means).
    pub owned: u64,
    pub ghosts: u64,
}

impl<'c> RankStep<'c> {
    pub fn new(comm: Comm<'c>) -> Self {
        RankStep {
            comm,
            slabs: Slabs::default(),
            local: vec![],
            width: 0.0,
            list: None,
            built: vec![],
            limit2: 0.0,
            motion: vec![],
            sends: vec![],
            recvs: vec![],
            msg: vec![],
            work: vec![],
            force_stages: 0,
            terms: vec![],
            shares: vec![],
            clocks: Clocks::default(),
        }
    }

    fn rank(&self) -> usize {
        self.comm.rank
    }

    /// Cut the slabs from the (current, complete) states of `w` and build
    /// this rank's candidates, with their pairs' memories and their
    /// contacts' records.
    fn decompose(&mut self, w: &mut World) {
        let scene = w.scene;
        // The pairs' touching memories and the contacts' records, while
        // the old slabs and list hold: at the start the one-process stage's
        // (its step 0, or a resume's; it keeps its records), then every
        // rank's.
        let (memories, records) = match (&w.contacts, &self.list) {
            (None, _) => (vec![], None),
            (Some(stage), None) => (stage.touching_memories(), None),
            (Some(stage), Some(_)) => {
                let mine = self.owned(stage.history(), PairMemory::is_touching);
                received(&self.comm.all_gather_any(&mine), stage.history().is_some())
            }
        };
        let centres: Vec<DVec3> = w.states.iter().map(|s| s.x).collect();
        let slabs = Slabs::new(&centres, self.comm.size, self.width);
        let me = self.rank();
        if self.slabs.owner.len() == slabs.owner.len() {
            // Owners that changed: bodies that migrated to this rank.
            self.clocks.migrated += (0..slabs.owner.len())
                .filter(|&i| slabs.owner[i] as usize == me && self.slabs.owner[i] != slabs.owner[i])
                .count() as u64;
        }
        self.slabs = slabs;
        self.local = self.slabs.local(me);
        self.sends = (0..self.comm.size)
            .map(|to| self.slabs.sends(me, to))
            .collect();
        self.recvs = (0..self.comm.size)
            .map(|from| self.slabs.sends(from, me))
            .collect();
        let Some(stage) = &w.contacts else { return };
        let (bodies, states) = (&scene.bodies, &w.states);
        // The local bodies' constants and collider shapes (by local index).
        let local_bodies: Bodies = self.local.iter().map(|&i| bodies[i as usize]).collect();
        let table = shapes(&local_bodies);
        let local_shapes = Shapes::new(&table, &local_bodies);
        let poses: Vec<ColliderPose> = (self.local.iter().enumerate())
            .map(|(k, &i)| ColliderPose::of(local_shapes.get(k).kind, &states[i as usize]))
            .collect();
        // The one-process build on the local bodies: local order is global
        // order, and whether a pair or a wall is listed depends on it alone.
        let mut local_list = NeighbourList::new(stage.skin());
        local_list.build(
            &poses,
            local_shapes,
            self.local.iter().map(|&i| states[i as usize].rot.q),
            stage.walls(),
        );
        let owner = &self.slabs.owner;
        let mine = |i: u32| owner[i as usize] as usize == me;
        let local = &self.local;
        let mut list = self
            .list
            .take()
            .unwrap_or_else(|| NeighbourList::new(stage.skin()));
        list.pairs = local_list
            .pairs
            .iter()
            .map(|&(a, b)| (local[a as usize], local[b as usize]))
            .filter(|&(a, b)| mine(a) || mine(b))
            .collect();
        list.walls = local_list
            .walls
            .iter()
            .map(|&(a, k)| (local[a as usize], k))
            .filter(|&(a, _)| mine(a))
            .collect();
        // Each kind of record takes those of the new candidates: the
        // memories in the list's order, the records in their stores.
        list.memory = place(&list.pairs, memories);
        list.builds += 1;
        self.list = Some(list);
        self.built = w.states.iter().map(|s| SkinRef::at(s.x, s.rot.q)).collect();
        let all = stage.shapes(bodies);
        let h = (0..w.states.len()).map(|i| all.get(i).half_length);
        self.limit2 = skin_limit2(0.5 * stage.skin(), &self.built, h);
        self.clocks.rebuilds += 1;
        if let (Some(h), Some(stage), Some(list)) = (records, &mut w.contacts, &self.list) {
            let h = History {
                walls: listed(&list.walls, h.walls),
                pairs: listed(&list.pairs, h.pairs),
            };
            stage.set_history(h, stage.spring_energy());
        }
    }

    /// This rank's message of what its contacts keep: its pair memories
    /// that `keep` accepts, then the records of `history` (a law that
    /// keeps them), each entry by the owner of its first body (each is
    /// some rank's once).
    fn owned(&self, history: Option<&History>, keep: fn(&PairMemory) -> bool) -> Vec<f64> {
        let (owner, me) = (&self.slabs.owner, self.rank());
        let mine = |i: u32| owner[i as usize] as usize == me;
        let mut msg = Message::default();
        match &self.list {
            Some(list) => msg.add(entries(&list.pairs, &list.memory, keep), mine),
            None => msg.add::<PairMemory>(std::iter::empty::<Entry>(), mine),
        }
        if let Some(h) = history {
            msg.add(h.walls.iter().copied(), mine);
            msg.add(h.pairs.iter().copied(), mine);
        }
        msg.words()
    }

    /// Every rank's owned states (and rotator state; with `loads`, the
    /// last contact force and torque) on every rank, or on rank 0 only
    /// (`everywhere` false).
    fn gather_states(&mut self, w: &mut World, everywhere: bool, loads: bool) {
        let len = w.aux.len() / w.states.len().max(1);
        let per = STATE + len + if loads { 6 } else { 0 };
        let me = self.rank();
        let mut send = Vec::with_capacity(per * self.slabs.owned[me].len());
        for &i in &self.slabs.owned[me] {
            let i = i as usize;
            let s = &w.states[i];
            let q = s.rot.q;
            send.extend(s.x.to_array());
            send.extend(s.v.to_array());
            send.extend([q.x, q.y, q.z, q.w]);
            send.extend(s.rot.omega_b.to_array());
            send.extend(&w.aux[i * len..(i + 1) * len]);
            if loads {
                send.extend(w.force[i].to_array());
                send.extend(w.torque[i].to_array());
            }
        }
        let all = if everywhere {
            let counts: Vec<Count> = self
                .slabs
                .owned
                .iter()
                .map(|o| (o.len() * per) as Count)
                .collect();
            Some(self.comm.all_gather(&send, &counts))
        } else {
            self.comm.gather(&send).map(|(all, _)| all)
        };
        let Some(all) = all else { return };
        let order = self.slabs.owned.iter().flatten();
        for (&i, d) in order.zip(all.chunks_exact(per)) {
            let i = i as usize;
            w.states[i] = BodyState {
                x: DVec3::new(d[0], d[1], d[2]),
                v: DVec3::new(d[3], d[4], d[5]),
                rot: crate::body::RotState {
                    q: DQuat::from_xyzw(d[6], d[7], d[8], d[9]),
                    omega_b: DVec3::new(d[10], d[11], d[12]),
                },
            };
            w.aux[i * len..(i + 1) * len].copy_from_slice(&d[STATE..STATE + len]);
            if loads {
                let l = &d[STATE + len..];
                w.force[i] = DVec3::new(l[0], l[1], l[2]);
                w.torque[i] = DVec3::new(l[3], l[4], l[5]);
            }
        }
    }

    /// The ghosts' poses from their owners, and their velocities when the
    /// law reads them (`velocities`).
    fn exchange(&mut self, w: &mut World, velocities: bool) {
        let per = POSE + if velocities { VELOCITIES } else { 0 };
        let mut send = Vec::new();
        let mut send_counts = Vec::with_capacity(self.comm.size);
        for to in &self.sends {
            for &i in to {
                let s = &w.states[i as usize];
                let q = s.rot.q;
                send.extend(s.x.to_array());
                send.extend([q.x, q.y, q.z, q.w]);
                send.push(f64::from(self.motion[i as usize]));
                if velocities {
                    send.extend(s.v.to_array());
                    send.extend(s.rot.omega_b.to_array());
                }
            }
            send_counts.push((to.len() * per) as Count);
        }
        let recv_counts: Vec<Count> = self
            .recvs
            .iter()
            .map(|r| (r.len() * per) as Count)
            .collect();
        let got = self.comm.all_to_all(&send, &send_counts, &recv_counts);
        for (&i, d) in self.recvs.iter().flatten().zip(got.chunks_exact(per)) {
            let s = &mut w.states[i as usize];
            s.x = DVec3::new(d[0], d[1], d[2]);
            s.rot.q = DQuat::from_xyzw(d[3], d[4], d[5], d[6]);
            // (An f32 sent as f64: exact.)
            self.motion[i as usize] = d[7] as f32;
            if velocities {
                s.v = DVec3::new(d[8], d[9], d[10]);
                s.rot.omega_b = DVec3::new(d[11], d[12], d[13]);
            }
        }
    }

    /// The force stage: rebuild test, migration or ghost exchange, forces.
    fn forces(&mut self, w: &mut World) {
        let (Some(_), Some(stage)) = (&self.list, &w.contacts) else {
            return;
        };
        let me = self.rank();
        let shapes = stage.shapes(&w.scene.bodies);
        let moved = self.slabs.owned[me].iter().any(|&i| {
            let s = &w.states[i as usize];
            let h = shapes.get(i as usize).half_length;
            !NeighbourList::body_within_skin(s.x, s.rot.q, h, &self.built[i as usize], self.limit2)
        });
        let (bodies, states) = (&w.scene.bodies, &w.states);
        self.motion.resize(states.len(), f32::INFINITY);
        for &i in &self.slabs.owned[me] {
            let i = i as usize;
            self.motion[i] = stage.motion_since_last(i, bodies, &states[i]);
        }
        if self.comm.any(moved) {
            // Every body's motion from its owner (before the slabs move).
            let owned = &self.slabs.owned[me];
            let mine: Vec<f64> = owned
                .iter()
                .map(|&i| f64::from(self.motion[i as usize]))
                .collect();
            let all = self.comm.all_gather_any(&mine);
            for (&i, &m) in self.slabs.owned.iter().flatten().zip(&all) {
                self.motion[i as usize] = m as f32;
            }
            self.gather_states(w, true, false);
            self.decompose(w);
        } else {
            let velocities = w.contacts.as_ref().is_some_and(|c| c.reads_motion());
            self.exchange(w, velocities);
        }
        let t = Instant::now();
        let scene = w.scene;
        let (Some(stage), Some(list)) = (&mut w.contacts, &mut self.list) else {
            return;
        };
        stage.compute_listed(
            list,
            &self.local,
            &self.motion,
            &scene.bodies,
            &w.states,
            &mut w.force,
            &mut w.torque,
        );
        if stage.reads_motion() {
            // The owned bodies' shares of the ledger, for rank 0 to sum.
            for &i in &self.slabs.owned[me] {
                let i = i as usize;
                let share =
                    stage.body_work(i, &scene.bodies[i], &w.states[i], (w.force[i], w.torque[i]));
                self.work.extend(match share {
                    Some([c, f]) => [1.0, c, f],
                    None => [0.0; WORK],
                });
            }
        }
        self.force_stages += 1;
        self.clocks.forces += t.elapsed();
    }

    /// An opening stage of the owned bodies ([`World::open`]): the first
    /// body (by index) whose rotator refuses the step, if any.
    fn open<R: Rotator>(
        &mut self,
        w: &mut World,
        start: f64,
        h: f64,
    ) -> Option<(usize, RotatorFault)> {
        let owned = Owned(&self.slabs.owned[self.comm.rank]);
        w.open::<R, _>(&owned, start, h).err()
    }

    /// A closing stage of the owned bodies ([`World::close`]); the last one
    /// also writes their ledger terms into the message and says whether
    /// each passed the per-body guard.
    fn close<R: Rotator>(&mut self, w: &mut World, end: f64, h: f64, last: bool) -> bool {
        let g = w.scene.gravity.unwrap_or(DVec3::ZERO);
        let owned = Owned(&self.slabs.owned[self.comm.rank]);
        let msg = &mut self.msg;
        let mut sound = true;
        w.close::<R, _>(&owned, end, h, |_, body, s| {
            if last {
                msg.extend(tally::body_terms(body, s, g));
                sound &= body_is_sound(s);
            }
        });
        sound
    }

    /// A rotator's refusal on any rank stops every rank with the
    /// one-process diagnosis: that of the lowest body index.
    fn fault(
        &mut self,
        w: &World,
        mine: Option<(usize, RotatorFault)>,
        start: f64,
    ) -> Result<(), Box<Diagnosis>> {
        let send = match mine {
            Some((i, RotatorFault::ScalarSingularity { half_angle })) => [i as f64, half_angle],
            None => [-1.0, 0.0],
        };
        let all = self.comm.all_gather(&send, &vec![2; self.comm.size]);
        let first = all
            .chunks_exact(2)
            .filter(|c| c[0] >= 0.0)
            .min_by(|a, b| a[0].total_cmp(&b[0]));
        match first {
            None => Ok(()),
            Some(c) => {
                let t = (w.step as f64 + start) * w.scene.sim.dt();
                let f = RotatorFault::ScalarSingularity { half_angle: c[1] };
                Err(Box::new(fault_diagnosis(
                    f,
                    w.scene.ids.get(c[0] as usize),
                    w.step,
                    t,
                )))
            }
        }
    }

    /// Rank 0 sums this step's ledger and contact statistics in the
    /// one-process order and every rank gets them; whether every body
    /// passed the per-body guard.
    fn reduce(&mut self, w: &mut World, sound: bool) -> bool {
        self.comm.barrier();
        let me = self.rank();
        let interrupted = crate::run::INTERRUPTED.load(Ordering::Relaxed);
        let mut head = vec![sound as u8 as f64, interrupted as u8 as f64];
        head.extend([0.0; tally::PEAK]);
        head.append(&mut self.msg);
        head.append(&mut self.work);
        self.msg = head;
        let stages = std::mem::take(&mut self.force_stages);
        let reads_motion = w.contacts.as_ref().is_some_and(|c| c.reads_motion());
        let work = if reads_motion { WORK * stages } else { 0 };
        let mut peak = tally::Peak::default();
        if let (Some(stage), Some(list)) = (&w.contacts, &self.list) {
            let owner = &self.slabs.owner;
            let msg = &mut self.msg;
            let mut hits = Vec::new();
            stage.for_each_hit(list, &w.scene.bodies, |wall, c, points, springs| {
                let key = if wall {
                    let (a, k) = list.walls[c as usize];
                    HitKey {
                        pair: false,
                        a,
                        b: k,
                    }
                } else {
                    let (a, b) = list.pairs[c as usize];
                    // A pair is summed once: by the owner of its body A.
                    if owner[a as usize] as usize != me {
                        return;
                    }
                    HitKey { pair: true, a, b }
                };
                let points = points.collect::<smallvec::SmallVec<[[f64; 3]; 2]>>();
                let springs = smallvec::SmallVec::<[f64; 2]>::from_slice(springs);
                hits.push((key, points, springs));
            });
            // The rank's notes in the one-process order: walls, then pairs.
            hits.sort_by_key(|(k, ..)| (k.pair, k.a, k.b));
            for (k, points, springs) in &hits {
                let (pair, a, b) = (k.pair as u8 as f64, k.a as f64, k.b as f64);
                for (j, p) in points.iter().enumerate() {
                    peak.note(p[1], [pair, a, b, j as f64, 0.0], k.a);
                    if k.pair {
                        peak.note(p[2], [pair, a, b, j as f64, 1.0], k.b);
                    }
                }
                tally::push_hit(msg, *k, points.iter().map(|p| p[0]), springs);
            }
        }
        self.msg[2..2 + tally::PEAK].copy_from_slice(&peak.to_array());
        let gathered = self.comm.gather(&self.msg);
        self.msg.clear();
        let mut out = [0.0; 12];
        if let Some((all, counts)) = gathered {
            let n = w.states.len();
            self.terms.resize(n, [0.0; 3]);
            self.shares.resize(n * work / WORK, [0.0; WORK]);
            let (mut sound_all, mut stop) = (true, false);
            let mut hits = Vec::new();
            let mut peaks = Vec::new();
            let mut at = 0;
            for (r, &c) in counts.iter().enumerate() {
                let m = &all[at..at + c as usize];
                at += c as usize;
                sound_all &= m[0] != 0.0;
                stop |= m[1] != 0.0;
                peaks.push(tally::Peak::from_slice(&m[2..2 + tally::PEAK]));
                let owned = &self.slabs.owned[r];
                let (terms, rest) = m[2 + tally::PEAK..].split_at(3 * owned.len());
                for (&i, t) in owned.iter().zip(terms.chunks_exact(3)) {
                    self.terms[i as usize] = [t[0], t[1], t[2]];
                }
                let (shares, rest) = rest.split_at(work * owned.len());
                // Stage by stage, each the owned bodies' shares in order.
                for (k, stage) in shares.chunks_exact(WORK * owned.len().max(1)).enumerate() {
                    for (&i, d) in owned.iter().zip(stage.chunks_exact(WORK)) {
                        self.shares[k * n + i as usize] = [d[0], d[1], d[2]];
                    }
                }
                hits.extend_from_slice(rest);
            }
            if let Some(stage) = w.contacts.as_mut().filter(|_| work > 0) {
                // The ledger's sums in body order, as `WorkLedger::account`.
                for per_stage in self.shares.chunks_exact(n.max(1)) {
                    let (mut closing, mut full) = (0.0, 0.0);
                    for &[has, c, f] in per_stage {
                        if has != 0.0 {
                            closing += c;
                            full += f;
                        }
                    }
                    stage.close_work(closing, full);
                }
            }
            let (stats, spring) = tally::contact_stats(&hits, &peaks);
            if let Some(stage) = &mut w.contacts {
                // Before the dissipated energy, which is net of it.
                stage.set_spring_energy(spring);
            }
            let l = tally::ledger(&self.terms, stats.elastic, w.dissipated());
            out = [
                l.gravity,
                l.translation,
                l.rotation,
                stats.elastic,
                stats.touching as f64,
                stats.max_overlap_ratio,
                stats.max_overlap_body as f64,
                sound_all as u8 as f64,
                stop as u8 as f64,
                0.0,
                0.0,
                spring,
            ];
            let ledger = w.contacts.as_ref().and_then(|c| c.damping_state());
            out[9..11].copy_from_slice(&ledger.unwrap_or_default());
        }
        self.comm.broadcast(&mut out);
        if let Some(stage) = w.contacts.as_mut() {
            if work > 0 {
                stage.set_damping_state([out[9], out[10]]);
            }
            stage.set_spring_energy(out[11]);
        }
        w.ledger = Ledger {
            gravity: out[0],
            translation: out[1],
            rotation: out[2],
            elastic: out[3],
            dissipated: w.dissipated(),
            spring: out[11],
        };
        if let Some(stage) = &mut w.contacts {
            stage.stats = ContactStats {
                touching: out[4] as usize,
                max_overlap_ratio: out[5],
                max_overlap_body: out[6] as usize,
                elastic: out[3],
            };
        }
        crate::run::INTERRUPTED.store(out[8] != 0.0, Ordering::Relaxed);
        out[7] != 0.0
    }
}

impl<'s> Stepper<'s> for RankStep<'_> {
    fn start(&mut self, w: &mut World<'s>) {
        let b = &w.scene.bodies;
        let longest = b
            .iter()
            .map(|b| match b.shape {
                crate::body::Shape::Fibre { length, .. } => length,
                ref other => other.diameter(),
            })
            .fold(0.0, f64::max);
        let widest = b.iter().map(|b| b.shape.diameter()).fold(0.0, f64::max);
        let skin = w.contacts.as_ref().map_or(0.0, |c| c.skin());
        // The neighbour list keeps pairs of axis segments within
        // D + skin (+1e-6 of the reach), so centres within L + D + skin;
        // the factor covers that margin.
        self.width = (longest + widest + skin) * (1.0 + 1e-5);
        self.decompose(w);
    }

    fn step<R: Rotator>(&mut self, w: &mut World<'s>) -> Result<(), Box<Diagnosis>> {
        if w.aux.len() != R::Aux::LEN * w.states.len() {
            if R::Aux::LEN > 0 {
                w.start_aux::<R>();
            } else {
                w.aux.clear();
            }
        }
        w.ledger_follows::<R>();
        let me = self.rank();
        self.clocks.steps += 1;
        self.clocks.owned += self.slabs.owned[me].len() as u64;
        self.clocks.ghosts += self.slabs.ghosts[me].len() as u64;
        let last = R::STAGES.len() - 1;
        let mut sound = true;
        for (k, stage) in R::STAGES.iter().enumerate() {
            let t = Instant::now();
            match *stage {
                Stage::Open { start, h } => {
                    let fault = self.open::<R>(w, start, h);
                    self.clocks.integrate += t.elapsed();
                    if R::MAY_FAULT {
                        self.fault(w, fault, start)?;
                    }
                }
                Stage::Forces => self.forces(w),
                Stage::Close { end, h } => {
                    sound = self.close::<R>(w, end, h, k == last);
                    self.clocks.integrate += t.elapsed();
                }
            }
        }
        w.step += 1;
        let sound = self.reduce(w, sound);
        if sound && w.scene_is_sound() {
            return Ok(());
        }
        // A guard fired somewhere: every rank takes every state and names
        // the same diagnosis, as one process would.
        self.gather_states(w, true, false);
        w.diagnose_state().map_or(Ok(()), |d| Err(Box::new(d)))
    }

    fn sync(&mut self, w: &mut World<'s>) {
        // A checkpoint of a law that reads velocities keeps the last loads.
        let reads_motion = w.contacts.as_ref().is_some_and(|c| c.reads_motion());
        self.gather_states(w, false, reads_motion);
        // The memories and records a checkpoint keeps, on rank 0.
        let history = w.contacts.as_ref().and_then(|c| c.history());
        let mine = self.owned(history, PairMemory::kept_by_checkpoints);
        if let Some((all, _)) = self.comm.gather(&mine) {
            if let Some(stage) = &mut w.contacts {
                let (memories, records) = received(&all, stage.history().is_some());
                stage.set_gathered_memories(memories);
                if let Some(h) = records {
                    stage.set_gathered_history(h);
                }
            }
        }
    }

    fn whole_contact_stage(&self) -> bool {
        self.comm.size == 1
    }
}

/// The pair memories, and the contacts' records if `records`, of every
/// rank's message ([`RankStep::owned`]).
fn received(words: &[f64], records: bool) -> (Vec<Entry>, Option<History>) {
    let mut got = Received::new(words);
    let memories = got.take();
    let records = records.then(|| History {
        walls: got.take(),
        pairs: got.take(),
    });
    (memories, records)
}
