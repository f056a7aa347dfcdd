//! The few collectives the decomposed step uses (rsmpi), each timed and
//! counted: bytes this rank sends, and the time it spends in them.

use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;
use std::time::{Duration, Instant};

/// A communicator with its traffic counters.
pub(crate) struct Comm<'c> {
    pub world: &'c SimpleCommunicator,
    pub rank: usize,
    pub size: usize,
    /// Bytes this rank has sent.
    pub bytes: u64,
    /// Time in collectives (after the step's barrier: transfer, not waiting).
    pub time: Duration,
    /// Time in the step's barrier: waiting for the slowest rank.
    pub waiting: Duration,
}

fn displacements(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect()
}

impl<'c> Comm<'c> {
    pub fn new(world: &'c SimpleCommunicator) -> Self {
        Comm {
            world,
            rank: world.rank() as usize,
            size: world.size() as usize,
            bytes: 0,
            time: Duration::ZERO,
            waiting: Duration::ZERO,
        }
    }

    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    fn timed<T>(&mut self, sent: usize, f: impl FnOnce(&SimpleCommunicator) -> T) -> T {
        let t = Instant::now();
        let out = f(self.world);
        self.time += t.elapsed();
        self.bytes += sent as u64;
        out
    }

    /// Wait for every rank (the time is the load imbalance).
    pub fn barrier(&mut self) {
        let t = Instant::now();
        self.world.barrier();
        self.waiting += t.elapsed();
    }

    /// Whether `mine` holds on any rank.
    pub fn any(&mut self, mine: bool) -> bool {
        let mut out = 0u8;
        self.timed(1, |w| {
            w.all_reduce_into(&(mine as u8), &mut out, SystemOperation::max())
        });
        out != 0
    }

    /// Every rank's `send`, concatenated in rank order, on every rank
    /// (`counts[r]`: the length rank r sends).
    pub fn all_gather(&mut self, send: &[f64], counts: &[Count]) -> Vec<f64> {
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut out = vec![0.0; total];
        let displs = displacements(counts);
        self.timed(8 * send.len(), |w| {
            let mut part = PartitionMut::new(&mut out[..], counts, &displs[..]);
            w.all_gather_varcount_into(send, &mut part);
        });
        out
    }

    /// Every rank's `send`, of any length, concatenated in rank order, on
    /// every rank (the lengths gathered first).
    pub fn all_gather_any(&mut self, send: &[f64]) -> Vec<f64> {
        let n = send.len() as Count;
        let mut counts = vec![0 as Count; self.size];
        self.timed(4, |w| w.all_gather_into(&n, &mut counts[..]));
        self.all_gather(send, &counts)
    }

    /// Every rank's `send` on rank 0, with each rank's length; `None`
    /// elsewhere.
    pub fn gather(&mut self, send: &[f64]) -> Option<(Vec<f64>, Vec<Count>)> {
        let root = self.world.process_at_rank(0);
        let n = send.len() as Count;
        if self.is_root() {
            let mut counts = vec![0 as Count; self.size];
            self.timed(4, |_| root.gather_into_root(&n, &mut counts[..]));
            let displs = displacements(&counts);
            let mut out = vec![0.0; counts.iter().map(|&c| c as usize).sum()];
            self.timed(8 * send.len(), |_| {
                let mut part = PartitionMut::new(&mut out[..], &counts[..], &displs[..]);
                root.gather_varcount_into_root(send, &mut part);
            });
            Some((out, counts))
        } else {
            self.timed(4, |_| root.gather_into(&n));
            self.timed(8 * send.len(), |_| root.gather_varcount_into(send));
            None
        }
    }

    /// Rank 0's `buf` on every rank.
    pub fn broadcast(&mut self, buf: &mut [f64]) {
        let sent = if self.is_root() { 8 * buf.len() } else { 0 };
        self.timed(sent, |w| w.process_at_rank(0).broadcast_into(buf));
    }

    /// Send `send` (cut into `send_counts` per destination) and receive
    /// `recv_counts` per source.
    pub fn all_to_all(
        &mut self,
        send: &[f64],
        send_counts: &[Count],
        recv_counts: &[Count],
    ) -> Vec<f64> {
        let sd = displacements(send_counts);
        let rd = displacements(recv_counts);
        let mut out = vec![0.0; recv_counts.iter().map(|&c| c as usize).sum()];
        self.timed(8 * send.len(), |w| {
            let sp = Partition::new(send, send_counts, &sd[..]);
            let mut rp = PartitionMut::new(&mut out[..], recv_counts, &rd[..]);
            w.all_to_all_varcount_into(&sp, &mut rp);
        });
        out
    }
}
