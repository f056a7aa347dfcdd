//! Data preparation: series mapped to axis space, broken at undrawable
//! points, and thinned to what the pixels can show.

use std::collections::HashSet;

use super::axis::Axis;
use super::{Series, HEIGHT, WIDTH};

/// Above this many points per horizontal pixel-column budget a line is
/// decimated (min/max per column are kept, so spikes stay visible).
const COLUMNS: f64 = 1000.0;

/// A series mapped to axis space, split into runs of drawable points and
/// decimated for drawing.
pub(super) struct Prepared {
    pub(super) runs: Vec<Vec<(f64, f64)>>,
}

pub(super) fn valid_runs(s: &Series, log_x: bool, log_y: bool) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut cur = Vec::new();
    for (&x, &y) in s.x.iter().zip(&s.y) {
        match (Axis::to_axis(log_x, x), Axis::to_axis(log_y, y)) {
            (Some(a), Some(b)) => cur.push((a, b)),
            _ => {
                if !cur.is_empty() {
                    runs.push(std::mem::take(&mut cur));
                }
            }
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}

/// Min/max-per-column decimation (M4): consecutive points falling into the same
/// pixel column are reduced to first, min, max, last (in their original order).
pub(super) fn decimate_line(run: &[(f64, f64)], x: &Axis) -> Vec<(f64, f64)> {
    if run.len() as f64 <= 4.0 * COLUMNS {
        return run.to_vec();
    }
    let col = |v: f64| (((v - x.lo) / (x.hi - x.lo)) * COLUMNS).floor() as i64;
    let mut out = Vec::with_capacity((8.0 * COLUMNS) as usize);
    let mut start = 0;
    while start < run.len() {
        let c = col(run[start].0);
        let mut end = start + 1;
        while end < run.len() && col(run[end].0) == c {
            end += 1;
        }
        let group = &run[start..end];
        let (mut imin, mut imax) = (0, 0);
        for (i, p) in group.iter().enumerate() {
            if p.1 < group[imin].1 {
                imin = i;
            }
            if p.1 > group[imax].1 {
                imax = i;
            }
        }
        let mut idx = vec![0, imin, imax, group.len() - 1];
        idx.sort_unstable();
        idx.dedup();
        out.extend(idx.into_iter().map(|i| group[i]));
        start = end;
    }
    out
}

/// Drop interior points that lie (within a fraction of a pixel) on the line
/// between their neighbours, so dash patterns run smoothly along straight
/// stretches (e.g. a reference slope on log–log axes).
pub(super) fn simplify_collinear(run: &[(f64, f64)], x: &Axis, y: &Axis) -> Vec<(f64, f64)> {
    let px = |p: &(f64, f64)| {
        (
            (p.0 - x.lo) / (x.hi - x.lo) * f64::from(WIDTH),
            (p.1 - y.lo) / (y.hi - y.lo) * f64::from(HEIGHT),
        )
    };
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(run.len());
    for (i, p) in run.iter().enumerate() {
        if out.is_empty() || i + 1 == run.len() {
            out.push(*p);
            continue;
        }
        let (a, b, c) = (px(&out[out.len() - 1]), px(p), px(&run[i + 1]));
        let (dx, dy) = (c.0 - a.0, c.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        let dist = if len > 0.0 {
            ((b.0 - a.0) * dy - (b.1 - a.1) * dx).abs() / len
        } else {
            f64::INFINITY
        };
        // Also require b to lie between a and c, so reversals are kept.
        let between = (b.0 - a.0) * dx + (b.1 - a.1) * dy >= 0.0
            && (c.0 - b.0) * dx + (c.1 - b.1) * dy >= 0.0;
        if !(dist < 0.25 && between) {
            out.push(*p);
        }
    }
    out
}

/// Drop markers that would land within ~2 px of an already drawn marker
/// (markers have a 3 px radius, so this is visually lossless).
pub(super) fn decimate_points(run: &[(f64, f64)], x: &Axis, y: &Axis) -> Vec<(f64, f64)> {
    if run.len() <= 2000 {
        return run.to_vec();
    }
    let cell = |p: &(f64, f64)| {
        (
            (((p.0 - x.lo) / (x.hi - x.lo)) * f64::from(WIDTH / 2)).floor() as i64,
            (((p.1 - y.lo) / (y.hi - y.lo)) * f64::from(HEIGHT / 2)).floor() as i64,
        )
    };
    let mut seen = HashSet::new();
    run.iter()
        .filter(|p| seen.insert(cell(p)))
        .copied()
        .collect()
}

pub(super) fn extent(
    runs: &[Vec<Vec<(f64, f64)>>],
    pick: fn(&(f64, f64)) -> f64,
) -> Option<(f64, f64)> {
    runs.iter()
        .flatten()
        .flatten()
        .map(pick)
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((a, b)) => Some((a.min(v), b.max(v))),
        })
}
