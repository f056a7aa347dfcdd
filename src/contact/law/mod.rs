//! The contact law: a contact point's geometry and the motion of its two
//! bodies → the point's loads (Yade's chain: geometry → physical
//! parameters → law). The one place a contact's loads are made: the
//! candidate loop (`contact/blocks.rs`) calls [`CandidateLaw::load`] for
//! every point of every touching candidate, whatever the thread or the
//! MPI rank.
//!
//! A point's loads, in its candidate's frame (body A, and body B or a
//! wall; docs/architecture.md):
//! - **normal, elastic**: the Hertz force `w F(δ) n` at the point
//!   (`hertz.rs`), its energy `w U(δ)`, and the pure couple `−U(δ) ∇w` of
//!   an orientation-dependent weight ([`ContactPoint`]);
//! - **normal, non-conservative**: the restitution damping `w η(δ) δ̇`
//!   (`damping.rs`), where the scene declares a restitution;
//! - **tangential**: where the scene declares friction, Coulomb friction
//!   with a tangential spring (`tangential.rs`): from the relative
//!   velocity at the point, the normal force (elastic and damping) and
//!   the contact's history [`Record`], a force at the point added to the
//!   total and to the non-conservative part (its lever arms give the
//!   torques).
//!
//! The non-conservative part of each point's wrench is handed back apart
//! ([`PointLoad::dissipative`]): the ledger sums it per body and accounts
//! its exact work (`contact/ledger.rs`), whatever produced it.

mod table;

pub(crate) use table::{body_law, body_wall_law, LawTable, TangentialLaw};

use super::tangential::{spring_energy, step_spring};
use super::{ContactPoint, HertzLaw};
use crate::body::{Bodies, BodyState};
use glam::DVec3;
use std::marker::PhantomData;

/// Whether a scene's laws keep a [`Record`] per contact (friction's
/// spring): a type chosen once per run, [`Frictionless`] or
/// [`Frictional`], as the candidate loop's [`PairKernel`] is. The law and
/// the loop are compiled for each, so a frictionless scene's loop has no
/// history lookup, no record write and no tangential branch: it pays
/// nothing for friction.
///
/// [`PairKernel`]: super::blocks::PairKernel
pub(crate) trait Keeping: Copy + Send + Sync + 'static {
    /// The laws keep a record per contact.
    const RECORDS: bool;
    /// What a candidate's law holds of its tangential law: nothing (a
    /// zero-sized value) for laws that keep no records.
    type Tangential: Copy;
    /// The tangential law `t` gives, if any (never without records).
    fn tangential(held: Self::Tangential) -> Option<TangentialLaw>;
    /// What a candidate's law holds of the tangential law `t` gives
    /// (`t` is not called without records).
    fn hold(t: impl FnOnce() -> Option<TangentialLaw>) -> Self::Tangential;
}

/// Laws without a tangential part: no record per contact.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frictionless;

impl Keeping for Frictionless {
    const RECORDS: bool = false;
    type Tangential = ();
    #[inline(always)]
    fn tangential((): ()) -> Option<TangentialLaw> {
        None
    }
    #[inline(always)]
    fn hold(_: impl FnOnce() -> Option<TangentialLaw>) {}
}

/// Laws with Coulomb friction: a record (the spring) per contact.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frictional;

impl Keeping for Frictional {
    const RECORDS: bool = true;
    type Tangential = Option<TangentialLaw>;
    #[inline(always)]
    fn tangential(held: Option<TangentialLaw>) -> Option<TangentialLaw> {
        held
    }
    #[inline(always)]
    fn hold(t: impl FnOnce() -> Option<TangentialLaw>) -> Option<TangentialLaw> {
        t()
    }
}

/// A load on a candidate's two bodies: a force on A (B gets minus it) and
/// the torques about each body's own centre (A's added, B's subtracted;
/// zero on a wall's side).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Wrench {
    pub force: DVec3,
    pub torque_a: DVec3,
    pub torque_b: DVec3,
}

impl Wrench {
    /// The wrench of the force `f` at `p` between A (centre `ca`) and B
    /// (centre `cb`, none for a wall), with the pure `couple` on A (and
    /// its opposite on B) if any: torques `(p − c) × f (+ couple)`.
    #[inline(always)]
    pub(crate) fn at(
        f: DVec3,
        p: DVec3,
        couple: Option<DVec3>,
        ca: DVec3,
        cb: Option<DVec3>,
    ) -> Self {
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

/// One contact point's loads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointLoad {
    /// Every part: what the bodies feel.
    pub total: Wrench,
    /// Elastic energy stored at the point, `w U(δ)`, J.
    pub elastic: f64,
    /// The non-conservative part of `total` (the damping; a tangential
    /// law's force alike), for the ledger; `None` for a law that has none.
    pub dissipative: Option<Wrench>,
    /// Energy the point's tangential spring holds after this computation,
    /// `½ k_t |ξ|²` with this computation's `k_t`
    /// (`tangential::spring_energy`), J (0 without friction).
    pub spring: f64,
}

/// What the law keeps of one contact point between steps, carried by the
/// contact's identity (`contact/history.rs`): friction's tangential
/// spring, and where its point was. A frictionless scene keeps none.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Record {
    /// The tangential spring ξ, m (`tangential.rs`).
    pub xi: DVec3,
    /// The point at this record's computation relative to body A's
    /// centre, `p − x_A` (world), m: what a body pair's next points are
    /// matched by, with the weight (`history::recall_by_place`).
    pub place: DVec3,
    /// The point's weight at this record's computation.
    pub weight: f64,
}

/// One side of a candidate: a body by index, with its centre (a wall
/// side has none: it does not move).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Side {
    pub index: usize,
    pub centre: DVec3,
}

/// The bodies' motion at a force computation, for the parts of a law that
/// depend on velocities: masses, velocities, angular velocities.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Motion<'a> {
    bodies: &'a Bodies,
    states: &'a [BodyState],
}

impl<'a> Motion<'a> {
    pub(crate) fn new(bodies: &'a Bodies, states: &'a [BodyState]) -> Self {
        Motion { bodies, states }
    }

    /// The velocity of side `s`'s material point at `p` (world):
    /// `v + ω × (p − c)`, `ω = q ω_b` the world angular velocity.
    #[inline(always)]
    fn velocity_at(&self, s: &Side, p: DVec3) -> DVec3 {
        let st = &self.states[s.index];
        st.v + (st.rot.q * st.rot.omega_b).cross(p - s.centre)
    }

    /// The translational reduced mass of `a` and `b` (`m_a` on a wall).
    #[inline(always)]
    fn reduced_mass(&self, a: &Side, b: Option<&Side>) -> f64 {
        let ma = self.bodies[a.index].mass;
        match b {
            Some(b) => {
                let mb = self.bodies[b.index].mass;
                ma * mb / (ma + mb)
            }
            None => ma,
        }
    }
}

/// The laws of one force computation: the table of the contact kinds'
/// constants and, when the scene's law depends on velocities, the bodies'
/// motion at this computation; `F` says whether they keep records
/// ([`Keeping`]: the table's friction, chosen once).
#[derive(Clone, Copy)]
pub(crate) struct Laws<'a, F> {
    table: &'a LawTable,
    motion: Option<Motion<'a>>,
    keeping: PhantomData<F>,
}

impl<'a, F: Keeping> Laws<'a, F> {
    /// The laws of `table` at the motion `bodies`/`states` (read only if
    /// the table's laws depend on velocities); `F` must be the table's
    /// [`LawTable::keeps_history`].
    pub(crate) fn new(table: &'a LawTable, bodies: &'a Bodies, states: &'a [BodyState]) -> Self {
        assert_eq!(
            F::RECORDS,
            table.keeps_history(),
            "the laws' records as their table's friction"
        );
        Laws {
            table,
            motion: table.reads_motion().then(|| Motion::new(bodies, states)),
            keeping: PhantomData,
        }
    }

    /// The law of body `a` against a wall.
    #[inline(always)]
    pub(crate) fn wall(&self, a: Side) -> CandidateLaw<'a, F> {
        let hertz = *self.table.wall(a.index);
        let nc = self.motion.map(|motion| NonConservative {
            alpha: self.table.alpha_wall(),
            root_mk: (motion.reduced_mass(&a, None) * hertz.stiffness()).sqrt(),
            motion,
            tangential: F::hold(|| self.table.tangential_wall(a.index)),
        });
        CandidateLaw {
            hertz,
            a,
            b: None,
            nc,
            keeping: PhantomData,
        }
    }

    /// The law of body `a` (the pair's first) against body `b`: laws that
    /// keep records take the Hertz and the tangential law in one lookup.
    /// The motion is read with a `match`, not a closure (in the frictional
    /// candidate loop the closure was not inlined).
    #[inline(always)]
    pub(crate) fn pair(&self, a: Side, b: Side) -> CandidateLaw<'a, F> {
        let (hertz, tangential) = if F::RECORDS {
            self.table.pair_with_tangential(a.index, b.index)
        } else {
            (self.table.pair(a.index, b.index), None)
        };
        let nc = match self.motion {
            Some(motion) => Some(NonConservative {
                alpha: self.table.alpha_pair(),
                root_mk: (motion.reduced_mass(&a, Some(&b)) * hertz.stiffness()).sqrt(),
                motion,
                tangential: F::hold(|| tangential),
            }),
            None => None,
        };
        CandidateLaw {
            hertz,
            a,
            b: Some(b),
            nc,
            keeping: PhantomData,
        }
    }
}

/// The non-conservative parts of a candidate's law, with the motion they
/// read: the restitution damping `η(δ) = α √(m* k) δ^{1/4}`
/// (`damping.rs`), and the friction law with its time step, if the
/// candidate's contacts are frictional.
#[derive(Clone, Copy)]
struct NonConservative<'a, F: Keeping> {
    motion: Motion<'a>,
    alpha: f64,
    /// `√(m* k)`, `k` the Hertz stiffness.
    root_mk: f64,
    tangential: F::Tangential,
}

/// The law of one candidate (its kinds' constants, its two sides).
#[derive(Clone, Copy)]
pub(crate) struct CandidateLaw<'a, F: Keeping> {
    hertz: HertzLaw,
    a: Side,
    b: Option<Side>,
    nc: Option<NonConservative<'a, F>>,
    keeping: PhantomData<F>,
}

impl<F: Keeping> CandidateLaw<'_, F> {
    /// Whether the candidate's contacts keep a [`Record`] (they are
    /// frictional; never for [`Frictionless`] laws).
    #[inline(always)]
    pub(crate) fn keeps_history(&self) -> bool {
        F::RECORDS
            && self
                .nc
                .is_some_and(|nc| F::tangential(nc.tangential).is_some())
    }

    /// The loads of contact point `c` of this candidate, with the
    /// contact's history `record` (read and written by friction; left as
    /// it is by a frictionless law).
    #[inline(always)]
    pub(crate) fn load(&self, c: &ContactPoint, record: &mut Record) -> PointLoad {
        let (ca, cb) = (self.a.centre, self.b.map(|b| b.centre));
        let u = self.hertz.energy(c.overlap);
        let mut f_n = c.weight * self.hertz.force(c.overlap);
        if let Some(nc) = &self.nc {
            // The relative velocity of A's and B's material points at the
            // contact (a wall stands still).
            let mut rel = nc.motion.velocity_at(&self.a, c.point);
            if let Some(b) = &self.b {
                rel -= nc.motion.velocity_at(b, c.point);
            }
            // Normal: the damping, with δ̇ = −n·(v_A(p) − v_B(p))
            // (n = −∂δ/∂x_A).
            let rate = -c.normal.dot(rel);
            let f_d = c.weight * nc.alpha * nc.root_mk * c.overlap.sqrt().sqrt() * rate;
            f_n += f_d;
            let tangential = F::tangential(nc.tangential);
            let Some(t) = &tangential else {
                return PointLoad {
                    total: Wrench::at(f_n * c.normal, c.point, Some(-u * c.weight_grad), ca, cb),
                    elastic: c.weight * u,
                    dissipative: Some(Wrench::at(f_d * c.normal, c.point, None, ca, cb)),
                    spring: 0.0,
                };
            };
            // Tangential: the spring of `tangential.rs`, weighted as the
            // normal force is (a blend's points share one contact's
            // stiffness); η_t = 2 η_n √(G*/E*) with η_n the damping's
            // `w α √(m* k) δ^{1/4}` (the root tabled per kind pair); the cap μ max(F_n, 0) with F_n the
            // point's whole normal force, elastic and damping.
            let k_t = c.weight * t.law.stiffness(self.hertz.r_star, c.overlap);
            let eta_n = c.weight * nc.alpha * nc.root_mk * c.overlap.sqrt().sqrt();
            let eta_t = 2.0 * eta_n * t.root_g_over_e;
            let cap = t.law.mu * f_n.max(0.0);
            let f_t = if k_t > 0.0 {
                // (A split contact's normal is not unit: its plane's is.)
                let n = c.normal.normalize();
                step_spring(&mut record.xi, n, rel, t.dt, k_t, eta_t, cap).force
            } else {
                record.xi = DVec3::ZERO;
                DVec3::ZERO
            };
            (record.place, record.weight) = (c.point - ca, c.weight);
            let couple = Some(-u * c.weight_grad);
            return PointLoad {
                total: Wrench::at(f_n * c.normal + f_t, c.point, couple, ca, cb),
                elastic: c.weight * u,
                dissipative: Some(Wrench::at(f_d * c.normal + f_t, c.point, None, ca, cb)),
                spring: spring_energy(record.xi, k_t),
            };
        }
        PointLoad {
            total: Wrench::at(f_n * c.normal, c.point, Some(-u * c.weight_grad), ca, cb),
            elastic: c.weight * u,
            dissipative: None,
            spring: 0.0,
        }
    }
}
