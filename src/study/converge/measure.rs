//! Measuring one (rotator, δt) point: the errors along an observed run, and
//! the wall time of unobserved runs.

use super::reference::{end_errors, Reference};
use super::{Mode, Point};
use crate::energy::error_pct;
use crate::error::Result;
use crate::integrate::rotate::RotatorKind;
use crate::math::{angle_between, geodesic_angle};
use crate::run::integrate_observed;
use crate::scenario::Scene;
use crate::study::{with_params, Progress};
use glam::DVec3;
use std::time::Instant;

/// What every measured run of a study shares.
pub(super) struct Study<'a> {
    pub(super) scene: &'a Scene,
    pub(super) mode: Mode,
    pub(super) t_end: f64,
    /// The fine grid's step: a run's step is a whole multiple of it.
    pub(super) dt_ref: f64,
    pub(super) reference: &'a Reference,
    pub(super) progress: &'a Progress,
}

/// Per-step accumulation of the metrics of one run.
struct Acc {
    alpha_sum: f64,
    alpha_n: u64,
    e0: f64,
    e_max: f64,
    e_last: f64,
    full_max: f64,
    full_last: f64,
}

/// Run `kind` at `m` fine steps per step and measure it against the reference.
pub(super) fn measure(study: &Study, kind: RotatorKind, m: u64) -> Result<Point> {
    let &Study {
        scene,
        mode,
        t_end,
        dt_ref,
        reference,
        progress,
    } = study;
    let dt = m as f64 * dt_ref;
    let s = with_params(scene, kind, dt, t_end)?;
    let nb = scene.bodies.len();
    let work = s.sim.steps() * nb as u64;

    let b0: Vec<DVec3> = scene.initial.iter().map(|b| b.rot.q * DVec3::X).collect();
    // The world's ledger is measured after every step (the energy guard
    // reads it) and includes the elastic energy of the live contacts.
    let w0 = crate::integrate::step::World::new(&s);
    let mut acc = Acc {
        alpha_sum: 0.0,
        alpha_n: 0,
        e0: w0.ledger.total(),
        e_max: 0.0,
        e_last: 0.0,
        full_max: 0.0,
        full_last: 0.0,
    };
    let bar = progress.step_bar(&format!("{kind} dt={dt:.2e}"), s.sim.steps());
    let observed = integrate_observed(&s, |w| {
        match mode {
            Mode::Orientation => {
                let time = w.time();
                for (i, st) in w.states.iter().enumerate() {
                    if let Some(r) = reference.at(w.step * m, time, i) {
                        // Eq. 66.
                        let a = angle_between(st.rot.q * DVec3::X, b0[i]);
                        let b = angle_between(r * DVec3::X, b0[i]);
                        acc.alpha_sum += (a - b).abs();
                        acc.alpha_n += 1;
                    }
                }
            }
            Mode::Energy => {
                let e = error_pct(w.ledger.total(), acc.e0);
                acc.e_max = acc.e_max.max(e);
                acc.e_last = e;
                let f = error_pct(w.ledger.total_full(), w.e0_full);
                acc.full_max = acc.full_max.max(f);
                acc.full_last = f;
            }
        }
        bar.at(w.step);
    });
    bar.finish();
    progress.done(work);

    let mut p = Point {
        rotator: kind,
        dt,
        steps: s.sim.steps(),
        alpha_rad: f64::NAN,
        geodesic_rad: f64::NAN,
        x_error_pct: f64::NAN,
        position_m: f64::NAN,
        energy_max_pct: f64::NAN,
        energy_final_pct: f64::NAN,
        energy_full_max_pct: f64::NAN,
        energy_full_final_pct: f64::NAN,
        wall_s: f64::NAN,
        timing_runs: 0,
        stopped: None,
    };
    let world = match observed {
        Err(d) => {
            p.stopped = Some(d.to_string());
            return Ok(p);
        }
        Ok(w) => w,
    };
    match mode {
        Mode::Orientation => {
            // Eq. 67: δt/T Σ_n α_n = the mean over the n_final steps, averaged over bodies.
            p.alpha_rad = acc.alpha_sum / acc.alpha_n.max(1) as f64;
            let mut geo = 0.0f64;
            for (i, st) in world.states.iter().enumerate() {
                if let Some(r) = reference.at(world.step * m, world.time(), i) {
                    geo = geo.max(geodesic_angle(st.rot.q, r));
                    if matches!(reference, Reference::Closed(..)) {
                        let ax = (st.rot.q * DVec3::X).x;
                        let rx = (r * DVec3::X).x;
                        p.x_error_pct = ((ax - rx) / rx).abs() * 100.0;
                    }
                }
            }
            p.geodesic_rad = geo;
        }
        Mode::Energy => {
            p.energy_max_pct = acc.e_max;
            p.energy_final_pct = acc.e_last;
            p.energy_full_max_pct = acc.full_max;
            p.energy_full_final_pct = acc.full_last;
            if let Reference::End { x, q } = reference {
                let xs: Vec<DVec3> = world.states.iter().map(|b| b.x).collect();
                let qs: Vec<_> = world.states.iter().map(|b| b.rot.q).collect();
                (p.position_m, p.geodesic_rad) = end_errors(&xs, &qs, x, q);
            }
        }
    }
    Ok(p)
}

/// Wall time of unobserved runs of `s` (stepping only, so the metric's cost
/// is not counted), run one after another: the median of 5 runs under 50 ms,
/// of 3 under 0.5 s, else one run. Returns (seconds, runs).
pub(super) fn time_run(s: &Scene) -> (f64, u32) {
    let once = || {
        let t0 = Instant::now();
        // A stopped run is timed up to its stop, as it ran.
        let _ = integrate_observed(s, |_| {});
        t0.elapsed().as_secs_f64()
    };
    let first = once();
    let n = if first < 0.05 {
        5
    } else if first < 0.5 {
        3
    } else {
        1
    };
    let mut t: Vec<f64> = std::iter::once(first)
        .chain((1..n).map(|_| once()))
        .collect();
    t.sort_by(f64::total_cmp);
    (t[t.len() / 2], n)
}
