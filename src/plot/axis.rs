//! Axes: data to axis space (log10 on a log axis), padded ranges, tick
//! positions and tick labels.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Labels {
    /// Linear axis; `sci` selects `1.5e-7` style, else fixed with `decimals`.
    Linear { sci: bool, decimals: usize },
    /// Log axis labelled at decades as `10ⁿ`.
    Decades,
    /// Log axis spanning less than a couple of decades: plain numbers.
    LogPlain,
}

/// A continuous axis in "axis space" (log10 of the value on a log axis) with
/// precomputed tick positions.
#[derive(Debug, Clone)]
pub(super) struct Axis {
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) bold: Vec<f64>,
    light: Vec<f64>,
    labels: Labels,
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = ((value - self.lo) / (self.hi - self.lo)).clamp(-100.0, 100.0);
        let t = if t.is_nan() { 0.0 } else { t };
        (limit.0 as f64 + t * (limit.1 - limit.0) as f64).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl Axis {
    /// Map a data value to axis space; `None` if it cannot be shown.
    pub(super) fn to_axis(log: bool, v: f64) -> Option<f64> {
        if !v.is_finite() {
            None
        } else if log {
            (v > 0.0).then(|| v.log10())
        } else {
            Some(v.clamp(-1e300, 1e300))
        }
    }

    /// Build an axis covering `extent` (min, max in axis space), padded.
    pub(super) fn new(extent: Option<(f64, f64)>, log: bool) -> Axis {
        let (mut lo, mut hi) = extent.unwrap_or((0.0, 1.0));
        let span = hi - lo;
        let scale = lo.abs().max(hi.abs());
        if span <= 1e-12 * scale || span == 0.0 {
            let d = if log {
                0.5
            } else if scale == 0.0 {
                1.0
            } else {
                0.1 * scale
            };
            lo -= d;
            hi += d;
        } else if extent.is_some() {
            lo -= 0.04 * span;
            hi += 0.04 * span;
        }
        if log {
            log_axis(lo, hi)
        } else {
            linear_axis(lo, hi)
        }
    }

    pub(super) fn format(&self, v: f64) -> String {
        match self.labels {
            Labels::Linear { sci, decimals } => {
                let step = self
                    .bold
                    .windows(2)
                    .map(|w| w[1] - w[0])
                    .next()
                    .unwrap_or(1.0);
                let v = if v.abs() < step.abs() * 1e-6 { 0.0 } else { v };
                if v == 0.0 {
                    "0".to_string()
                } else if sci {
                    format!("{:.*e}", decimals, v)
                } else {
                    format!("{:.*}", decimals, v)
                }
            }
            Labels::Decades => format!("10{}", superscript(v.round() as i64)),
            Labels::LogPlain => format_sig(10f64.powf(v)),
        }
    }
}

fn linear_axis(lo: f64, hi: f64) -> Axis {
    let span = hi - lo;
    let raw = span / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    let norm = raw / mag;
    let (nice, sub) = if norm < 1.5 {
        (1.0, 5.0)
    } else if norm < 3.0 {
        (2.0, 4.0)
    } else if norm < 7.0 {
        (5.0, 5.0)
    } else {
        (10.0, 5.0)
    };
    let step = nice * mag;
    let ticks = |step: f64, max: usize| -> Vec<f64> {
        let first = (lo / step).ceil();
        (0..max)
            .map(|i| (first + i as f64) * step)
            .take_while(|&v| v <= hi + step * 1e-9)
            .collect()
    };
    let bold = ticks(step, 64);
    let light = ticks(step / sub, 320);
    let e = step.log10().floor() as i64;
    let scale = lo.abs().max(hi.abs());
    let sci = !(1e-3..1e5).contains(&scale);
    let decimals = if sci {
        (scale.log10().floor() as i64 - e).clamp(0, 6) as usize
    } else {
        (-e).clamp(0, 10) as usize
    };
    Axis {
        lo,
        hi,
        bold,
        light,
        labels: Labels::Linear { sci, decimals },
    }
}

fn log_axis(lo: f64, hi: f64) -> Axis {
    let d0 = lo.ceil() as i64;
    let d1 = hi.floor() as i64;
    let n_dec = (d1 - d0 + 1).max(0);
    let in_range = |v: &f64| *v >= lo - 1e-12 && *v <= hi + 1e-12;
    let multiples = |ms: &[f64]| -> Vec<f64> {
        let mut out = Vec::new();
        for d in (lo.floor() as i64)..=(hi.ceil() as i64) {
            for m in ms {
                out.push(d as f64 + m.log10());
            }
        }
        out.retain(in_range);
        out
    };
    let all: Vec<f64> = (1..=9).map(f64::from).collect();
    if n_dec >= 3 {
        let stride = ((n_dec + 9) / 10).max(1);
        let bold: Vec<f64> = (d0..=d1)
            .filter(|d| d.rem_euclid(stride) == 0)
            .map(|d| d as f64)
            .collect();
        let light = if stride == 1 && n_dec <= 12 {
            multiples(&all)
        } else {
            (d0..=d1).map(|d| d as f64).collect()
        };
        Axis {
            lo,
            hi,
            bold,
            light,
            labels: Labels::Decades,
        }
    } else {
        let mut bold = multiples(&[1.0, 2.0, 5.0]);
        if bold.len() < 3 {
            bold = multiples(&all);
        }
        Axis {
            lo,
            hi,
            bold,
            light: multiples(&all),
            labels: Labels::LogPlain,
        }
    }
}

fn superscript(n: i64) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            other => other,
        })
        .collect()
}

/// Up to 4 significant digits, trailing zeros trimmed; scientific outside [1e-3, 1e5).
fn format_sig(v: f64) -> String {
    let s = format!("{:.3e}", v);
    let Some((mant, exp)) = s.split_once('e') else {
        return s;
    };
    let exp: i32 = exp.parse().unwrap_or(0);
    let mant = if mant.contains('.') {
        mant.trim_end_matches('0').trim_end_matches('.')
    } else {
        mant
    };
    if (-3..5).contains(&exp) {
        let rounded: f64 = s.parse().unwrap_or(v);
        format!("{}", rounded)
    } else {
        format!("{}e{}", mant, exp)
    }
}
