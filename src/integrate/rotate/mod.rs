//! Quaternion rotators: the schemes compared by fibresim.
//!
//! A rotator is the rotation part of the step's stages (see
//! [`crate::integrate::scheme`]): it advances one body's `(q, ω_b)`.
//! - [`Rotator::advance`] runs in an opening stage, before forces: one-stage
//!   schemes do their whole step here; kick–drift–kick schemes their first
//!   half-kick and drift.
//! - [`Rotator::finish`] runs in the closing stage, after forces at the new
//!   positions: a closing half-kick, or nothing (the default).
//!
//! Torque is asked for through a closure `torque(t) -> τ_world`: a prescribed
//! torque evaluates its function of time exactly at `t`; a contact torque
//! answers with the latest computed world torque, whatever `t` is asked. The
//! orientation half of a rotator's torque contract is the frame it rotates
//! that world torque into (`q_n`, a predicted `q'`, a stage orientation).
//! Each rotator states its contract as data in [`RotatorInfo`].
//!
//! **Adding a rotator**: one file here, implementing [`Rotator`], and one
//! line in the `rotator_list!` call below. The list generates the module,
//! the [`RotatorKind`] variant, `--rotator`'s values and help, `fibresim
//! rotators`, docs/rotators.md's table (`fibresim rotators --markdown`) and the
//! dispatch ([`RotatorKind::visit`]); the order tests iterate it.
//! Dispatch happens once per run, so every scheme compiles to its own loop.

use crate::body::{Inertia, RotState};
use crate::integrate::scheme::{Stage, VERLET};
use glam::DVec3;

/// Generates, from one list of `module::Type` lines: the modules, the
/// re-exports, [`RotatorKind`] with its variant per type, the lists and the
/// visitor dispatch. A line may carry attributes (`#[cfg(test)]`).
macro_rules! rotator_list {
    ($( $(#[$attr:meta])* $module:ident :: $Type:ident ),+ $(,)?) => {
        $( $(#[$attr])* mod $module; )+
        $( $(#[$attr])* pub use $module::$Type; )+

        /// The selectable rotators (`--rotator`, scenario key
        /// `simulation.rotator`). Each one's description lives in its
        /// [`RotatorInfo`].
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum RotatorKind {
            $( $(#[$attr])* #[doc = concat!("[`", stringify!($Type), "`]")] $Type, )+
        }

        impl RotatorKind {
            /// Everything `--rotator` accepts, in list order: the schemes and
            /// the diagnostics.
            pub const SELECTABLE: &'static [RotatorKind] = &[
                $( $(#[$attr])* RotatorKind::$Type, )+
            ];

            /// The scheme's facts.
            pub const fn info(self) -> RotatorInfo {
                match self {
                    $( $(#[$attr])* RotatorKind::$Type => <$Type as Rotator>::INFO, )+
                }
            }

            /// Call `v` with the type of this rotator: the one place a run
            /// dispatches on the enum.
            pub fn visit<V: RotatorVisitor>(self, v: V) -> V::Output {
                match self {
                    $( $(#[$attr])* RotatorKind::$Type => v.visit::<$Type>(), )+
                }
            }
        }
    };
}

rotator_list! {
    euler::Euler,
    leapfrog::Leapfrog,
    scalar::Scalar,
    direct::Direct,
    pcdm::Pcdm,
    pcdm_start::PcdmStart,
    pcdm_staggered::PcdmStaggered,
    rk4::Rk4,
    nosquish::NoSquish,
    richardson::Richardson,
    omelyan::Omelyan,
    cayley_cd::CayleyCd,
    fincham::Fincham,
    fincham_mid::FinchamMid,
    spiral::Spiral,
    spiral_vv::SpiralVv,
    rkmk4::Rkmk4,
    split::Split,
    split4::Split4,
    frozen::Frozen,
    #[cfg(test)]
    midpoint_demo::MidpointDemo,
}

#[cfg(test)]
mod list_tests;

/// Why a rotator could not take a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RotatorFault {
    /// The scalar factor `tan(‖δq‖)` of Eq. 41–45 reached its pole:
    /// `‖δq‖ = ‖ω‖δt/2 ≥ π/2`.
    ScalarSingularity {
        /// `‖ω‖δt/2`, rad.
        half_angle: f64,
    },
}

/// The torque contract every kick–drift–kick scheme shares (half-kicks of
/// the angular momentum around a torque-free drift).
pub(crate) const KDK_TORQUE_CONTRACT: &str =
    "half-kicks with the torque at (t_n, q_n) and (t_n+1, q_n+1), one evaluation per step";
/// The contact contract every kick–drift–kick scheme shares.
pub(crate) const KDK_CONTACT_CONTRACT: &str =
    "opening half-kick with the start-of-step contact torque, closing half-kick with the torque of the new configuration";

/// Facts about a scheme, read by `--help`, `fibresim rotators`, the table
/// of docs/rotators.md and the tests: the one place each is written.
#[derive(Debug, Clone, Copy)]
pub struct RotatorInfo {
    /// The name `--rotator` and the scenario take.
    pub name: &'static str,
    /// One line saying what the scheme is.
    pub title: &'static str,
    /// The paper's equations this scheme implements.
    pub equations: &'static str,
    /// Global order of accuracy in δt for the orientation with a general
    /// (asymmetric inertia, time-dependent torque) load, as measured by
    /// [`crate::study::order`] (0 for a diagnostic).
    pub order: u32,
    /// Global order in torque-free motion of an asymmetric body (the same
    /// harness); 0: exact to rounding.
    pub order_free: u32,
    /// Whether the map is symplectic for torques that derive from a
    /// potential (a composition of exact Hamiltonian flows).
    pub symplectic: bool,
    /// Whether the step is time-symmetric, `Φ₋ₕ = Φₕ⁻¹`: stepping back with
    /// the angular velocity reversed returns to the start to rounding
    /// (`tests/suite/free_flight.rs`, `reversibility_is_as_listed`).
    pub reversible: bool,
    /// Torque evaluations per step.
    pub torque_evals: u32,
    /// When a prescribed torque is evaluated, and at which orientation it is
    /// taken into the body frame.
    pub torque_contract: &'static str,
    /// What a contact torque means to the scheme: contact torques are known
    /// only where forces were computed (docs/physics.md §4).
    pub contact_contract: &'static str,
    /// Whether `finish` applies a closing half-kick with the torque of the
    /// new configuration (so a contact torque enters at both ends of the step).
    pub closing_kick: bool,
    /// A diagnostic (not an integration scheme): left out of
    /// [`RotatorKind::ALL`], the studies' `all` and the order tests.
    pub diagnostic: bool,
}

/// Per-body state a scheme keeps from one step to the next (a half-step
/// momentum, say), stored by the world as `LEN` doubles per body so that
/// checkpoints (and, later, rank migration) carry it as plain numbers, like
/// LAMMPS's per-atom fix arrays. `()` for the schemes that keep none.
pub trait AuxState: Copy + Default + Send + Sync + 'static {
    /// Doubles per body.
    const LEN: usize;
    /// The state of one body from its `LEN` doubles.
    fn read(from: &[f64]) -> Self;
    /// Store the state in `LEN` doubles.
    fn write(&self, to: &mut [f64]);
}

impl AuxState for () {
    const LEN: usize = 0;
    #[inline]
    fn read(_: &[f64]) -> Self {}
    #[inline]
    fn write(&self, _: &mut [f64]) {}
}

/// A cached torque, first-same-as-last: the closing kick of one sub-step
/// and the opening kick of the next ask for the torque at the same time and
/// configuration, so kick–drift–kick schemes evaluate it once per sub-step.
/// For a prescribed torque (a function of time) and a contact torque (the
/// latest computed one) the cached value is the value, bit for bit.
#[derive(Debug, Clone, Copy)]
pub struct Fsal {
    /// Time of the cached torque (NaN: none).
    pub t: f64,
    /// The world torque there.
    pub tau: DVec3,
}

impl Default for Fsal {
    fn default() -> Self {
        Fsal {
            t: f64::NAN,
            tau: DVec3::ZERO,
        }
    }
}

impl Fsal {
    /// The torque at `t`: the cached one if it was taken there.
    #[inline]
    pub fn at<T: Fn(f64) -> DVec3>(&self, t: f64, torque: &T) -> DVec3 {
        if self.t == t {
            self.tau
        } else {
            torque(t)
        }
    }

    /// Evaluate the torque at `t` and keep it.
    #[inline]
    pub fn take<T: Fn(f64) -> DVec3>(&mut self, t: f64, torque: &T) -> DVec3 {
        self.tau = torque(t);
        self.t = t;
        self.tau
    }

    /// The closing half-kick of the world angular momentum, held in the
    /// body frame: `ω_b += (h/2) I⁻¹ q* τ(t_end) q`, the torque kept for the
    /// next opening kick (the `finish` of the kick–drift–kick schemes whose
    /// drift is torque-free).
    #[inline]
    pub fn closing_half_kick<T: Fn(f64) -> DVec3>(
        &mut self,
        rot: &mut RotState,
        inertia: &Inertia,
        torque: &T,
        t_end: f64,
        h: f64,
    ) {
        let tau = self.take(t_end, torque);
        if !crate::math::is_zero(tau) {
            rot.omega_b += (0.5 * h) * inertia.inverse * crate::math::to_body(rot.q, tau);
        }
    }
}

impl AuxState for Fsal {
    const LEN: usize = 4;
    #[inline]
    fn read(from: &[f64]) -> Self {
        Fsal {
            t: from[0],
            tau: DVec3::new(from[1], from[2], from[3]),
        }
    }
    #[inline]
    fn write(&self, to: &mut [f64]) {
        to[0] = self.t;
        to[1..4].copy_from_slice(&self.tau.to_array());
    }
}

impl AuxState for DVec3 {
    const LEN: usize = 3;
    #[inline]
    fn read(from: &[f64]) -> Self {
        DVec3::new(from[0], from[1], from[2])
    }
    #[inline]
    fn write(&self, to: &mut [f64]) {
        to[..3].copy_from_slice(&self.to_array());
    }
}

/// One quaternion integration scheme. All state is in [`RotState`] and the
/// scheme's [`Rotator::Aux`].
pub trait Rotator {
    /// The scheme's facts.
    const INFO: RotatorInfo;

    /// The stages of one whole step ([`VERLET`]: open, forces, close). A
    /// composition lists several sub-steps, each with its own forces.
    const STAGES: &'static [Stage] = VERLET;

    /// Per-body state kept between steps.
    type Aux: AuxState;

    /// Whether `advance` can refuse a step ([`RotatorFault`]). The step then
    /// stops at the first refusing body with the later bodies untouched, so
    /// its opening stage stays on one thread.
    const MAY_FAULT: bool = false;

    /// Whether the angular velocity `advance` leaves for the forces is the
    /// one at the middle of the interval their torque drives (a staggered
    /// scheme's predicted whole-step `ω`), rather than the one half a kick
    /// before it (a half-step or start-of-step `ω`). The work ledger takes
    /// a torque's work at that middle (`src/contact/ledger.rs`).
    const SPIN_AT_MIDPOINT: bool = false;

    /// The auxiliary state of a body at the start of a run.
    #[inline]
    fn start(_rot: &RotState, _inertia: &Inertia) -> Self::Aux {
        Self::Aux::default()
    }

    /// Advance `(q, ω_b)` over the sub-step `[t, t + h]`, before its forces
    /// are computed.
    fn advance<T: Fn(f64) -> DVec3>(
        rot: &mut RotState,
        aux: &mut Self::Aux,
        inertia: &Inertia,
        torque: T,
        t: f64,
        h: f64,
    ) -> Result<(), RotatorFault>;

    /// Close the sub-step ending at `t_end`, after forces at the new
    /// positions. Always called; a no-op for one-stage schemes.
    #[inline]
    fn finish<T: Fn(f64) -> DVec3>(
        _rot: &mut RotState,
        _aux: &mut Self::Aux,
        _inertia: &Inertia,
        _torque: T,
        _t_end: f64,
        _h: f64,
    ) {
    }
}

/// A computation generic over the rotator, for [`RotatorKind::visit`].
pub trait RotatorVisitor {
    /// What the computation returns.
    type Output;
    /// Run the computation with rotator `R`.
    fn visit<R: Rotator>(self) -> Self::Output;
}

/// Number of schemes (the list less its diagnostics), for [`RotatorKind::ALL`].
const SCHEME_COUNT: usize = {
    let (mut n, mut i) = (0, 0);
    while i < RotatorKind::SELECTABLE.len() {
        if !RotatorKind::SELECTABLE[i].info().diagnostic {
            n += 1;
        }
        i += 1;
    }
    n
};

impl RotatorKind {
    /// Every integration scheme, in list order (diagnostics left out).
    pub const ALL: [RotatorKind; SCHEME_COUNT] = {
        let mut out = [RotatorKind::SELECTABLE[0]; SCHEME_COUNT];
        let (mut i, mut k) = (0, 0);
        while i < RotatorKind::SELECTABLE.len() {
            if !RotatorKind::SELECTABLE[i].info().diagnostic {
                out[k] = RotatorKind::SELECTABLE[i];
                k += 1;
            }
            i += 1;
        }
        out
    };

    /// The rotator of a scene that names none (`simulation.rotator`): the
    /// most accurate per unit of run time on contact scenes, from the
    /// work–precision study in docs/studies.md ("The default rotator").
    pub const DEFAULT: RotatorKind = RotatorKind::Omelyan;

    /// The paper's four rotators, in the order of its Figs. 2–4.
    pub const PAPER: [RotatorKind; 4] = [
        RotatorKind::Pcdm,
        RotatorKind::Scalar,
        RotatorKind::Euler,
        RotatorKind::Leapfrog,
    ];

    /// Force evaluations per step: the [`Stage::Forces`] stages of its
    /// [`Rotator::STAGES`].
    pub fn force_evaluations(self) -> usize {
        struct Count;
        impl RotatorVisitor for Count {
            type Output = usize;
            fn visit<R: Rotator>(self) -> usize {
                R::STAGES
                    .iter()
                    .filter(|s| matches!(s, Stage::Forces))
                    .count()
            }
        }
        self.visit(Count)
    }

    /// Why this scheme refuses a scene that computes contacts, if it does:
    /// a composition evaluates forces several times per step, and the
    /// contact stage (its damping ledger, its per-step impact bounds) is
    /// written for one evaluation per step of `δt`.
    pub fn contact_refusal(self) -> Option<String> {
        let n = self.force_evaluations();
        (n > 1).then(|| {
            format!(
                "rotator `{}` evaluates forces {n} times per step (sub-steps of other lengths than dt, one backwards) and is for contact-free scenes only: the contact stage is written for one force evaluation per step. Use `split` (second order, one evaluation) here, or remove the `[box]` and keep one body",
                self.name()
            )
        })
    }

    /// The rotator's name (`--rotator`).
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// The rotator of this name, if any.
    pub fn from_name(s: &str) -> Option<Self> {
        Self::SELECTABLE.iter().copied().find(|k| k.name() == s)
    }
}

impl std::fmt::Display for RotatorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl serde::Serialize for RotatorKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for RotatorKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        RotatorKind::from_name(&s)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown rotator `{s}`")))
    }
}

/// `--rotator` values, with help generated from [`RotatorInfo`].
impl clap::ValueEnum for RotatorKind {
    fn value_variants<'a>() -> &'a [Self] {
        Self::SELECTABLE
    }

    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        let i = self.info();
        let source = match i.order {
            0 => String::new(),
            n => format!(" ({}, order {n})", i.equations),
        };
        Some(clap::builder::PossibleValue::new(i.name).help(format!(
            "{}{source}. Prescribed torque: {}. Contact torque: {}",
            i.title, i.torque_contract, i.contact_contract
        )))
    }
}

/// How an order reads in the tables: `—` for a diagnostic, `exact` for a
/// scheme exact to rounding.
fn order_text(i: &RotatorInfo, order: u32) -> String {
    match (i.diagnostic, order) {
        (true, _) => "—".to_string(),
        (false, 0) => "exact".to_string(),
        (false, n) => n.to_string(),
    }
}

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

/// `fibresim rotators`: one block per rotator, from its [`RotatorInfo`].
pub fn rotator_table() -> String {
    use std::fmt::Write;
    let kinds = RotatorKind::SELECTABLE;
    let w = kinds
        .iter()
        .map(|k| k.info().equations.len())
        .max()
        .unwrap_or(0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<14} {:<w$} {:>5} {:>5} {:>4} {:>4} {:>5}  scheme",
        "name", "equations / source", "order", "free", "sympl", "rev", "evals"
    );
    for k in kinds {
        let i = k.info();
        let _ = writeln!(
            s,
            "{:<14} {:<w$} {:>5} {:>5} {:>4} {:>4} {:>5}  {}",
            i.name,
            i.equations,
            order_text(&i, i.order),
            order_text(&i, i.order_free),
            yes_no(i.symplectic),
            yes_no(i.reversible),
            i.torque_evals,
            i.title
        );
        let _ = writeln!(s, "{:14} prescribed torque: {}", "", i.torque_contract);
        let _ = writeln!(s, "{:14} contact torque:    {}", "", i.contact_contract);
    }
    let _ = writeln!(
        s,
        "\ndefault: {} (scenes that name no rotator; the most accurate per unit of run time on contact scenes, docs/studies.md)",
        RotatorKind::DEFAULT.name()
    );
    let _ = writeln!(s, "order: measured global order for a general load, free: in torque-free motion of an asymmetric body (study::order, tests/suite/rotator_order.rs); sympl: symplectic; rev: time-reversible; evals: torque evaluations per step");
    s
}

/// docs/rotators.md's rotator table (`fibresim rotators --markdown`), from
/// each rotator's [`RotatorInfo`]; a test keeps the page equal to it.
pub fn rotator_markdown() -> String {
    use std::fmt::Write;
    let mut s = String::from(
        "| name | equations / source | order (measured) | torque-free order | symplectic | reversible | torque evals / step | prescribed torque | contact torque |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    // A `|` inside a cell would end it.
    let cell = |t: &str| t.replace('|', "\\|");
    for k in RotatorKind::SELECTABLE {
        let i = k.info();
        let (sym, rev) = if i.diagnostic {
            ("—", "—")
        } else {
            (yes_no(i.symplectic), yes_no(i.reversible))
        };
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {} | {} | {} | {} |",
            i.name,
            i.equations,
            order_text(&i, i.order),
            order_text(&i, i.order_free),
            sym,
            rev,
            i.torque_evals,
            cell(i.torque_contract),
            cell(i.contact_contract)
        );
    }
    s
}
