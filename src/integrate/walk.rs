//! How a per-body stage walks the bodies: all of them on this thread
//! ([`Serial`]), all of them on the thread pool ([`Pool`]), or an MPI
//! rank's own ([`Owned`], `src/ranks/`). The stages themselves (the step's
//! open and close, `step.rs`) are written once, body by body; a walker
//! decides only where each body runs. Whatever the walker:
//! - each walked body runs exactly once, with the same arithmetic, so its
//!   state does not depend on the walker;
//! - every walked body runs even when another one's rotator refuses the
//!   step, and the refusal reported is the first in body order;
//! - what is summed over bodies (the ledger) is summed after, in body
//!   order, on the calling thread.

use super::rotate::AuxState;
use crate::body::{Bodies, Body, BodyState};
use crate::scenario::scene::{prescribed_on, Prescribed};
use crate::torque::PrescribedTorque;
use glam::DVec3;
use rayon::prelude::*;

/// What a per-body stage reads of the bodies besides their states: their
/// constants, their latest contact loads (by body index) and the
/// prescribed torques (sparse, sorted by body).
#[derive(Clone, Copy)]
pub(crate) struct Inputs<'a> {
    pub bodies: &'a Bodies,
    pub force: &'a [DVec3],
    pub torque: &'a [DVec3],
    pub prescribed: &'a [Prescribed],
}

/// One body's [`Inputs`].
#[derive(Clone, Copy)]
pub(crate) struct Input<'a> {
    pub body: &'a Body,
    /// Latest contact force (world).
    pub force: DVec3,
    /// Latest contact torque (world).
    pub torque: DVec3,
    /// Its prescribed torque, if any.
    pub prescribed: Option<&'a PrescribedTorque>,
}

impl<'a> Inputs<'a> {
    /// Body `i`'s (its prescribed torque found by a search).
    #[inline(always)]
    fn at(&self, i: usize) -> Input<'a> {
        Input {
            body: &self.bodies[i],
            force: self.force[i],
            torque: self.torque[i],
            prescribed: prescribed_on(self.prescribed, i),
        }
    }

    /// Every body's, in order (the prescribed torques walked alongside).
    #[inline(always)]
    fn iter(&self) -> impl Iterator<Item = Input<'a>> + 'a {
        let (bodies, each) = (self.bodies, self.force.iter().zip(self.torque));
        let (list, mut next) = (self.prescribed, 0);
        let any = !list.is_empty();
        each.enumerate().map(move |(i, (&force, &torque))| {
            let prescribed = if any {
                list.get(next).filter(|p| p.body == i).map(|p| {
                    next += 1;
                    &p.torque
                })
            } else {
                None
            };
            Input {
                body: &bodies[i],
                force,
                torque,
                prescribed,
            }
        })
    }
}

/// A way of walking the bodies (module docs).
pub(crate) trait Walk {
    /// Run `each(state, aux, input)` on every walked body `i`, with its
    /// rotator state `A` read from the flat per-body array `aux` and
    /// written back unless `each` refused, and its `inputs`; then
    /// `then(i, body, state)` on the same bodies in body order, on this
    /// thread. The first refusal in body order, with its body.
    fn walk<A: AuxState, E: Send>(
        &self,
        states: &mut [BodyState],
        aux: &mut [f64],
        inputs: Inputs,
        each: impl Fn(&mut BodyState, &mut A, Input) -> Result<(), E> + Sync,
        then: impl FnMut(usize, &Body, &BodyState),
    ) -> Result<(), (usize, E)>;
}

/// Every body, in order, on this thread.
pub(crate) struct Serial;

/// Every body on the thread pool.
pub(crate) struct Pool;

/// The bodies listed (ascending indices), in order, on this thread: an
/// MPI rank's own.
#[cfg(feature = "mpi")]
pub(crate) struct Owned<'a>(pub &'a [u32]);

/// Run `each` on a body with its rotator state read from `slot` and
/// written back unless it refused (`A::LEN` doubles; none when 0).
#[inline(always)]
fn with_aux<A: AuxState, E>(
    slot: &mut [f64],
    each: impl FnOnce(&mut A) -> Result<(), E>,
) -> Result<(), E> {
    if A::LEN == 0 {
        each(&mut A::default())
    } else {
        let mut a = A::read(slot);
        each(&mut a)?;
        a.write(slot);
        Ok(())
    }
}

impl Walk for Serial {
    #[inline(always)]
    fn walk<A: AuxState, E: Send>(
        &self,
        states: &mut [BodyState],
        aux: &mut [f64],
        inputs: Inputs,
        each: impl Fn(&mut BodyState, &mut A, Input) -> Result<(), E> + Sync,
        mut then: impl FnMut(usize, &Body, &BodyState),
    ) -> Result<(), (usize, E)> {
        let mut first = None;
        let mut note = |i: usize, r: Result<(), E>| {
            if let Err(e) = r {
                first.get_or_insert((i, e));
            }
        };
        let bodies = states.iter_mut().zip(inputs.iter());
        if A::LEN == 0 {
            for (i, (s, x)) in bodies.enumerate() {
                note(i, each(s, &mut A::default(), x));
                then(i, x.body, s);
            }
        } else {
            let slots = aux.chunks_exact_mut(A::LEN);
            for (i, ((s, x), slot)) in bodies.zip(slots).enumerate() {
                note(i, with_aux(slot, |a| each(s, a, x)));
                then(i, x.body, s);
            }
        }
        first.map_or(Ok(()), Err)
    }
}

impl Walk for Pool {
    #[inline]
    fn walk<A: AuxState, E: Send>(
        &self,
        states: &mut [BodyState],
        aux: &mut [f64],
        inputs: Inputs,
        each: impl Fn(&mut BodyState, &mut A, Input) -> Result<(), E> + Sync,
        mut then: impl FnMut(usize, &Body, &BodyState),
    ) -> Result<(), (usize, E)> {
        let len = A::LEN;
        let refused = |i: usize, r: Result<(), E>| r.err().map(|e| (i, e));
        let first = if len == 0 {
            states
                .par_iter_mut()
                .enumerate()
                .filter_map(|(i, s)| refused(i, each(s, &mut A::default(), inputs.at(i))))
                .min_by_key(|&(i, _)| i)
        } else {
            states
                .par_iter_mut()
                .zip(aux.par_chunks_mut(len))
                .enumerate()
                .filter_map(|(i, (s, slot))| {
                    refused(i, with_aux(slot, |a| each(s, a, inputs.at(i))))
                })
                .min_by_key(|&(i, _)| i)
        };
        for (i, s) in states.iter().enumerate() {
            then(i, &inputs.bodies[i], s);
        }
        first.map_or(Ok(()), Err)
    }
}

#[cfg(feature = "mpi")]
impl Walk for Owned<'_> {
    #[inline]
    fn walk<A: AuxState, E: Send>(
        &self,
        states: &mut [BodyState],
        aux: &mut [f64],
        inputs: Inputs,
        each: impl Fn(&mut BodyState, &mut A, Input) -> Result<(), E> + Sync,
        mut then: impl FnMut(usize, &Body, &BodyState),
    ) -> Result<(), (usize, E)> {
        let mut first = None;
        for &i in self.0 {
            let (i, x) = (i as usize, inputs.at(i as usize));
            let s = &mut states[i];
            let slot = &mut aux[i * A::LEN..(i + 1) * A::LEN];
            if let Err(e) = with_aux(slot, |a| each(s, a, x)) {
                first.get_or_insert((i, e));
            }
            then(i, x.body, s);
        }
        first.map_or(Ok(()), Err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::RotState;
    use glam::DQuat;

    /// A rotator state of one double per body.
    #[derive(Default, Clone, Copy)]
    struct One(f64);

    impl AuxState for One {
        const LEN: usize = 1;
        fn read(s: &[f64]) -> Self {
            One(s[0])
        }
        fn write(&self, s: &mut [f64]) {
            s[0] = self.0;
        }
    }

    /// A walk of the states and aux, noting the order of `then`.
    type Walked<'a> =
        dyn Fn(&mut [BodyState], &mut [f64], &mut Vec<usize>) -> Result<(), (usize, f64)> + 'a;

    fn bodies(n: usize) -> Bodies {
        let shape = crate::body::Shape::Sphere { diameter: 0.01 };
        Bodies::uniform(Body::new(shape, 0, 1000.0), n)
    }

    fn states(n: usize) -> Vec<BodyState> {
        (0..n)
            .map(|i| BodyState {
                x: DVec3::splat(i as f64),
                v: DVec3::ZERO,
                rot: RotState {
                    q: DQuat::IDENTITY,
                    omega_b: DVec3::ZERO,
                },
            })
            .collect()
    }

    /// Reference: a plain loop over the bodies. Every walker runs every
    /// body once (bodies 3 and 7 refuse, leaving their state as `each`
    /// left it and their aux unwritten), reports body 3's refusal, and
    /// calls `then` in body order; the pool on 1 to 4 threads.
    #[test]
    fn every_walker_runs_each_body_once_and_reports_the_first_refusal() {
        let n = 600;
        let each = |s: &mut BodyState, a: &mut One, x: Input| {
            s.x += x.force;
            let i = x.force.y;
            a.0 += 1.0 + i;
            if i == 3.0 || i == 7.0 {
                Err(i)
            } else {
                Ok(())
            }
        };
        let (b, zero) = (bodies(n), vec![DVec3::ZERO; n]);
        let force: Vec<DVec3> = (0..n).map(|i| DVec3::new(1.0, i as f64, 0.0)).collect();
        let inputs = Inputs {
            bodies: &b,
            force: &force,
            torque: &zero,
            prescribed: &[],
        };
        let mut want_states = states(n);
        let mut want_aux = vec![0.5; n];
        for (i, s) in want_states.iter_mut().enumerate() {
            s.x += force[i];
            if i != 3 && i != 7 {
                want_aux[i] += 1.0 + i as f64;
            }
        }
        let check = |walk: &Walked<'_>, what: &str| {
            let (mut s, mut aux, mut order) = (states(n), vec![0.5; n], vec![]);
            let r = walk(&mut s, &mut aux, &mut order);
            assert_eq!(r, Err((3, 3.0)), "{what}");
            assert_eq!(s, want_states, "{what}");
            assert_eq!(aux, want_aux, "{what}");
            assert_eq!(order, (0..n).collect::<Vec<_>>(), "{what}");
        };
        check(
            &|s, aux, order| Serial.walk(s, aux, inputs, each, |i, _, _| order.push(i)),
            "serial",
        );
        for threads in 1..=4 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            check(
                &|s, aux, order| {
                    pool.install(|| Pool.walk(s, aux, inputs, each, |i, _, _| order.push(i)))
                },
                &format!("pool of {threads}"),
            );
        }
    }
}
