//! The reference a run is measured against: the scene's closed form, an rk4
//! run on the fine grid (its own error estimated by Richardson), in energy
//! mode the end state of a fine run of a chosen rotator (`--trajectory`), or
//! none.

use super::grid::{gcd, Grid};
use super::Mode;
use crate::error::{Error, Result};
use crate::integrate::rotate::RotatorKind;
use crate::math::{angle_between, geodesic_angle};
use crate::run::integrate_observed;
use crate::scenario::{ClosedForm, Scene};
use crate::study::{sample_orientations, with_params, Progress};
use glam::{DQuat, DVec3};
use std::time::Instant;

/// Where the reference comes from. Displayed as in `reference.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceKind {
    /// The scene's closed-form orientation (test case 3).
    ClosedForm,
    /// rk4 on the fine grid.
    Rk4,
    /// Energy mode with `--trajectory`: the end state of this rotator on the
    /// fine grid.
    Fine(RotatorKind),
    /// No reference orientation: energy mode.
    None,
}

impl ReferenceKind {
    /// The reference a study of `scene` measuring `mode` uses.
    pub(super) fn of(scene: &Scene, mode: Mode, trajectory: Option<RotatorKind>) -> ReferenceKind {
        match (mode, &scene.reference) {
            (Mode::Energy, _) => trajectory.map_or(ReferenceKind::None, ReferenceKind::Fine),
            (Mode::Orientation, Some(_)) => ReferenceKind::ClosedForm,
            (Mode::Orientation, None) => ReferenceKind::Rk4,
        }
    }
}

impl std::fmt::Display for ReferenceKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ReferenceKind::ClosedForm => "closed form",
            ReferenceKind::Rk4 => "rk4",
            ReferenceKind::Fine(k) => k.name(),
            ReferenceKind::None => "none",
        })
    }
}

/// How the reference was obtained and how good it is.
#[derive(Debug, Clone)]
pub struct ReferenceInfo {
    /// Where the reference comes from.
    pub kind: ReferenceKind,
    /// The reference run's step, s (NaN for a closed form or none).
    pub dt: f64,
    /// The reference run's steps (0 otherwise).
    pub steps: u64,
    /// Wall time of the reference run, s (0 otherwise).
    pub wall_s: f64,
    /// Richardson estimates of the reference's own Eq. 67 and geodesic
    /// errors, rad: 0 for a closed form, NaN without a reference (Eq. 67:
    /// NaN for a trajectory reference, which keeps the end state only).
    pub alpha_err: f64,
    /// See [`ReferenceInfo::alpha_err`].
    pub geodesic_err: f64,
    /// A trajectory reference's own position error at T, m (NaN otherwise).
    pub position_err: f64,
}

/// The reference orientation at fine-grid multiples of `stride`.
pub(super) enum Reference {
    Closed(ClosedForm),
    /// `q[k * bodies + i]` at step `k * stride` of the fine grid.
    Sampled {
        q: Vec<DQuat>,
        stride: u64,
        bodies: usize,
    },
    /// Every body's position and orientation at T.
    End {
        x: Vec<DVec3>,
        q: Vec<DQuat>,
    },
    None,
}

impl Reference {
    /// The reference of a study of `scene` measuring `mode` on `grid`.
    pub(super) fn new(
        scene: &Scene,
        mode: Mode,
        grid: &Grid,
        t_end: f64,
        progress: &Progress,
        trajectory: Option<RotatorKind>,
    ) -> Result<(Reference, ReferenceInfo)> {
        let kind = ReferenceKind::of(scene, mode, trajectory);
        let (reference, own_error) = match (kind, &scene.reference) {
            (ReferenceKind::Rk4, _) => return rk4(scene, grid, t_end, progress),
            (ReferenceKind::Fine(k), _) => return end_state(scene, k, grid, t_end, progress),
            (ReferenceKind::ClosedForm, Some(c)) => (Reference::Closed(c.clone()), 0.0),
            _ => (Reference::None, f64::NAN),
        };
        let info = ReferenceInfo {
            kind,
            dt: f64::NAN,
            steps: 0,
            wall_s: 0.0,
            alpha_err: own_error,
            geodesic_err: own_error,
            position_err: f64::NAN,
        };
        Ok((reference, info))
    }

    /// Body `body`'s reference orientation at step `fine_step` of the fine
    /// grid (a multiple of the stride), time `t`.
    pub(super) fn at(&self, fine_step: u64, t: f64, body: usize) -> Option<DQuat> {
        match self {
            Reference::Closed(c) => (body == 0).then(|| c.orientation(t)),
            Reference::Sampled { q, stride, bodies } => {
                debug_assert_eq!(fine_step % stride, 0);
                Some(q[(fine_step / stride) as usize * bodies + body])
            }
            Reference::End { .. } | Reference::None => None,
        }
    }
}

/// rk4 on the fine grid and its Richardson twin at twice the step, in
/// parallel; the twin's difference / (2⁴ − 1) estimates the reference's error.
fn rk4(
    scene: &Scene,
    grid: &Grid,
    t_end: f64,
    progress: &Progress,
) -> Result<(Reference, ReferenceInfo)> {
    let &Grid {
        n_ref,
        dt_ref,
        stride,
        ..
    } = grid;
    let nb = scene.bodies.len();
    let fine = with_params(scene, RotatorKind::Rk4, dt_ref, t_end)?;
    let coarse = with_params(scene, RotatorKind::Rk4, 2.0 * dt_ref, t_end)?;
    let timed = |s: &Scene, every: u64, label: &str| {
        let t0 = Instant::now();
        sample_orientations(s, every, progress, label).map(|q| (q, t0.elapsed().as_secs_f64()))
    };
    // The twin samples where its step lands on the stored grid: every
    // `stride / gcd(stride, 2)` of its steps.
    let twin_every = stride / gcd(stride, 2);
    let (rf, rc) = rayon::join(
        || timed(&fine, stride, "rk4 reference"),
        || timed(&coarse, twin_every, "rk4 reference x2"),
    );
    let (qf, wall) = rf.map_err(Error::Unstable)?;
    let (qc, _) = rc.map_err(Error::Unstable)?;
    // Compare on the common grid: twin sample j is at fine step 2·j·twin_every.
    let b0: Vec<DVec3> = scene.initial.iter().map(|b| b.rot.q * DVec3::X).collect();
    let (mut asum, mut an, mut geo) = (0.0, 0u64, 0.0f64);
    let nc = qc.len() / nb;
    for j in 1..nc {
        let fine_step = 2 * j as u64 * twin_every;
        if !fine_step.is_multiple_of(stride) {
            continue;
        }
        let k = (fine_step / stride) as usize;
        for (i, b) in b0.iter().enumerate() {
            let a = angle_between(qc[j * nb + i] * DVec3::X, *b);
            let r = angle_between(qf[k * nb + i] * DVec3::X, *b);
            asum += (a - r).abs();
            an += 1;
        }
    }
    for i in 0..nb {
        geo = geo.max(geodesic_angle(qc[(nc - 1) * nb + i], qf[qf.len() - nb + i]));
    }
    let info = ReferenceInfo {
        kind: ReferenceKind::Rk4,
        dt: dt_ref,
        steps: n_ref,
        wall_s: wall,
        alpha_err: asum / an.max(1) as f64 / 15.0,
        geodesic_err: geo / 15.0,
        position_err: f64::NAN,
    };
    Ok((
        Reference::Sampled {
            q: qf,
            stride,
            bodies: nb,
        },
        info,
    ))
}

/// The end state of `kind` on the fine grid, and of its twin at twice the
/// step, in parallel. Contact scenes are at most second order (velocity
/// Verlet, the contact torque), and first order with a one-stage rotator, so
/// the twin's whole difference is taken as the reference's own error: the
/// Richardson estimate for order 1, an upper bound for order 2 (3x).
fn end_state(
    scene: &Scene,
    kind: RotatorKind,
    grid: &Grid,
    t_end: f64,
    progress: &Progress,
) -> Result<(Reference, ReferenceInfo)> {
    let fine = with_params(scene, kind, grid.dt_ref, t_end)?;
    let coarse = with_params(scene, kind, 2.0 * grid.dt_ref, t_end)?;
    let run = |s: &Scene, label: &str| {
        let t0 = Instant::now();
        let bar = progress.step_bar(label, s.sim.steps());
        let r = integrate_observed(s, |w| bar.at(w.step));
        bar.finish();
        progress.done(s.sim.steps() * s.bodies.len() as u64);
        r.map(|w| {
            let x: Vec<DVec3> = w.states.iter().map(|b| b.x).collect();
            let q: Vec<DQuat> = w.states.iter().map(|b| b.rot.q).collect();
            (x, q, t0.elapsed().as_secs_f64())
        })
    };
    let label = format!("{kind} reference");
    let (rf, rc) = rayon::join(
        || run(&fine, &label),
        || run(&coarse, &format!("{label} x2")),
    );
    let (x, q, wall) = rf.map_err(Error::Unstable)?;
    let (xc, qc, _) = rc.map_err(Error::Unstable)?;
    let (position_err, geodesic_err) = end_errors(&xc, &qc, &x, &q);
    let info = ReferenceInfo {
        kind: ReferenceKind::Fine(kind),
        dt: grid.dt_ref,
        steps: grid.n_ref,
        wall_s: wall,
        alpha_err: f64::NAN,
        geodesic_err,
        position_err,
    };
    Ok((Reference::End { x, q }, info))
}

/// The largest distance and geodesic angle, over the bodies, between the
/// end states `(x, q)` and the reference's `(xr, qr)`: (m, rad).
pub(super) fn end_errors(x: &[DVec3], q: &[DQuat], xr: &[DVec3], qr: &[DQuat]) -> (f64, f64) {
    let pos = x
        .iter()
        .zip(xr)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    let geo = q
        .iter()
        .zip(qr)
        .map(|(a, b)| geodesic_angle(*a, *b))
        .fold(0.0, f64::max);
    (pos, geo)
}
