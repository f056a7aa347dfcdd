//! Chart rendering for the integrator comparisons (energy error vs time,
//! error vs time step, error vs run time).
//!
//! Charts are written as PNG or SVG, chosen by the file extension. Text is
//! rendered with a bundled copy of DejaVu Sans (`assets/DejaVuSans.ttf`), so
//! no system font libraries are needed.
//!
//! Rendering never panics on odd input: non-finite values (and values ≤ 0 on a
//! log axis) are skipped, lines are broken at such gaps, and a chart with no
//! drawable data is written as empty axes with a note.

use std::collections::HashSet;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle};

/// Width of rendered charts, in pixels.
pub const WIDTH: u32 = 1000;
/// Height of rendered charts, in pixels.
pub const HEIGHT: u32 = 700;

/// Above this many points per horizontal pixel-column budget a line is
/// decimated (min/max per column are kept, so spikes stay visible).
const COLUMNS: f64 = 1000.0;

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
const FONT: &str = "sans-serif";

/// Okabe–Ito colour-blind-friendly palette; yellow last (weak on white).
const PALETTE: [RGBColor; 8] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0xF0, 0xE4, 0x42), // yellow
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// Solid line through the points.
    #[default]
    Line,
    /// Dashed line through the points (used for reference slopes).
    Dashed,
    /// Unconnected circular markers.
    Points,
    /// Published values overlaid on our data (the paper's Table 2): large
    /// filled black diamonds with a white rim, taking no palette colour, so
    /// they stand out however many series the chart has.
    Published,
    /// Solid line with a hollow marker at every point, the shape chosen by
    /// the series' colour slot (circle, square, triangle, diamond, ×, +,
    /// inverted triangle): series that coincide (e.g. scalar and direct on
    /// a convergence plot) stay visible as nested shapes. For short series.
    LineMarkers,
    /// Grey line that takes no palette colour (slope guides), so the data
    /// keep their colours however many guides a chart has. The k-th guide of
    /// a chart gets the k-th pattern of [`GUIDE_DASHES`] (dashes, dots,
    /// long dashes), in the plot and in the legend, so guides are told apart.
    Guide,
}

/// Dash length and gap (pixels) of the k-th slope guide of a chart, cycled.
pub const GUIDE_DASHES: [(u32, u32); 3] = [(10, 6), (2, 5), (22, 6)];
/// Dash length and gap of [`Style::Dashed`].
const DASH: (u32, u32) = (10, 6);

/// Horizontal dash segments `[start, end)` covering `0..len` px with `dash`.
fn dash_segments(len: i32, dash: (u32, u32)) -> Vec<(i32, i32)> {
    debug_assert!(len > 0);
    let (on, off) = (dash.0.max(1) as i32, dash.1 as i32);
    let mut out = vec![];
    let mut x = 0;
    while x < len {
        out.push((x, (x + on).min(len)));
        x += on + off;
    }
    out
}

/// Outline of a [`Style::Published`] marker, pixels around the point.
const PUBLISHED_DIAMOND: [(i32, i32); 5] = [(0, -9), (8, 0), (0, 9), (-8, 0), (0, -9)];

/// Number of distinct marker shapes of [`Style::LineMarkers`].
pub const MARKER_SHAPES: usize = 7;

/// The outline of marker `shape` around the origin, in pixels (closed
/// paths; the × and + are two strokes each, returned as two paths).
fn marker_paths(shape: usize) -> Vec<Vec<(i32, i32)>> {
    const R: i32 = 6;
    match shape % MARKER_SHAPES {
        // A 16-gon reads as a circle at this size and keeps one code path.
        0 => vec![(0..=16)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 16.0;
                (
                    (5.5 * a.cos()).round() as i32,
                    (5.5 * a.sin()).round() as i32,
                )
            })
            .collect()],
        1 => vec![vec![(-5, -5), (5, -5), (5, 5), (-5, 5), (-5, -5)]],
        2 => vec![vec![(0, -R), (R, 4), (-R, 4), (0, -R)]],
        3 => vec![vec![(0, -R - 1), (R, 0), (0, R + 1), (-R, 0), (0, -R - 1)]],
        4 => vec![vec![(-5, -5), (5, 5)], vec![(-5, 5), (5, -5)]],
        5 => vec![vec![(-R, 0), (R, 0)], vec![(0, -R), (0, R)]],
        _ => vec![vec![(0, R), (R, -4), (-R, -4), (0, R)]],
    }
}

/// Where the legend goes. `Auto` picks the plot corner that covers the least data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPos {
    #[default]
    Auto,
    UpperLeft,
    UpperRight,
    LowerLeft,
    LowerRight,
    /// No legend.
    Hidden,
}

/// One data series. `x` and `y` must have the same length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub style: Style,
}

impl Series {
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, style: Style) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style,
        }
    }
}

/// A 2-D chart. Axis labels should include units, e.g. `"time step Δt (s)"`.
/// Colours are assigned by series index from a fixed palette.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
    pub legend: LegendPos,
}

impl Chart {
    /// A linear–linear chart with no series and automatic legend placement.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Chart::default()
        }
    }
}

/// Errors from [`render`]. Every message names the output path.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("cannot write chart {}: unsupported file extension (expected .png or .svg)", path.display())]
    UnsupportedFormat { path: PathBuf },
    #[error("cannot plot chart {}: series {index} ({label:?}) has {nx} x values but {ny} y values", path.display())]
    LengthMismatch {
        path: PathBuf,
        index: usize,
        label: String,
        nx: usize,
        ny: usize,
    },
    #[error("cannot render chart {}: the bundled font could not be loaded", path.display())]
    Font { path: PathBuf },
    #[error("failed to draw chart {}: {message}", path.display())]
    Draw { path: PathBuf, message: String },
    #[error("failed to encode PNG {}: {message}", path.display())]
    Encode { path: PathBuf, message: String },
    #[error("failed to write chart {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// A dashed slope guide `y = anchor.1 * (x / anchor.0)^order` over `x.0..=x.1`,
/// meant for log–log charts (it is a straight line of slope `order` there).
pub fn reference_slope(label: &str, order: f64, x: (f64, f64), anchor: (f64, f64)) -> Series {
    const N: usize = 32;
    let (x0, x1) = x;
    let geometric = x0 > 0.0 && x1 > 0.0 && x0.is_finite() && x1.is_finite();
    let xs: Vec<f64> = (0..N)
        .map(|i| {
            let t = i as f64 / (N - 1) as f64;
            if geometric {
                x0 * (x1 / x0).powf(t)
            } else {
                x0 + (x1 - x0) * t
            }
        })
        .collect();
    let ys = xs
        .iter()
        .map(|&xv| anchor.1 * (xv / anchor.0).powf(order))
        .collect();
    Series::new(label, xs, ys, Style::Dashed)
}

/// Render `chart` to `path`; the format follows the extension (`.png` or `.svg`,
/// case-insensitive). The output is deterministic for a given chart.
pub fn render(chart: &Chart, path: &Path) -> Result<(), PlotError> {
    enum Format {
        Png,
        Svg,
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match ext.as_deref() {
        Some("png") => Format::Png,
        Some("svg") => Format::Svg,
        _ => {
            return Err(PlotError::UnsupportedFormat {
                path: path.to_path_buf(),
            })
        }
    };
    for (index, s) in chart.series.iter().enumerate() {
        if s.x.len() != s.y.len() {
            return Err(PlotError::LengthMismatch {
                path: path.to_path_buf(),
                index,
                label: s.label.clone(),
                nx: s.x.len(),
                ny: s.y.len(),
            });
        }
    }
    if !font_registered() {
        return Err(PlotError::Font {
            path: path.to_path_buf(),
        });
    }
    let draw_err = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let io_err = |source: std::io::Error| PlotError::Io {
        path: path.to_path_buf(),
        source,
    };
    match format {
        Format::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
                draw_chart(&root, chart).map_err(draw_err)?;
                root.present().map_err(|e| draw_err(e.to_string()))?;
            }
            std::fs::write(path, svg).map_err(io_err)
        }
        Format::Png => {
            let mut buf = vec![0u8; WIDTH as usize * HEIGHT as usize * 3];
            {
                let root =
                    BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)).into_drawing_area();
                draw_chart(&root, chart).map_err(draw_err)?;
                root.present().map_err(|e| draw_err(e.to_string()))?;
            }
            write_png(path, &buf, WIDTH, HEIGHT)
        }
    }
}

/// Encode an RGB buffer of `w × h` pixels as PNG at `path`.
fn write_png(path: &Path, buf: &[u8], w: u32, h: u32) -> Result<(), PlotError> {
    let io_err = |source: std::io::Error| PlotError::Io {
        path: path.to_path_buf(),
        source,
    };
    let enc_err = |e: png::EncodingError| PlotError::Encode {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    let file = File::create(path).map_err(io_err)?;
    let mut out = BufWriter::new(file);
    {
        let mut encoder = png::Encoder::new(&mut out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        // Charts are flat colour: the best deflate level and adaptive
        // filtering shrink them 2-3x for a few ms.
        encoder.set_compression(png::Compression::Best);
        encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        let mut writer = encoder.write_header().map_err(enc_err)?;
        writer.write_image_data(buf).map_err(enc_err)?;
        writer.finish().map_err(enc_err)?;
    }
    out.flush().map_err(io_err)
}

fn font_registered() -> bool {
    static OK: OnceLock<bool> = OnceLock::new();
    *OK.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok())
}

// ---------------------------------------------------------------------------
// Axes

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
struct Axis {
    lo: f64,
    hi: f64,
    bold: Vec<f64>,
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
    fn to_axis(log: bool, v: f64) -> Option<f64> {
        if !v.is_finite() {
            None
        } else if log {
            (v > 0.0).then(|| v.log10())
        } else {
            Some(v.clamp(-1e300, 1e300))
        }
    }

    /// Build an axis covering `extent` (min, max in axis space), padded.
    fn new(extent: Option<(f64, f64)>, log: bool) -> Axis {
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

    fn format(&self, v: f64) -> String {
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

// ---------------------------------------------------------------------------
// Data preparation

/// A series mapped to axis space, split into runs of drawable points and
/// decimated for drawing.
struct Prepared {
    runs: Vec<Vec<(f64, f64)>>,
}

fn valid_runs(s: &Series, log_x: bool, log_y: bool) -> Vec<Vec<(f64, f64)>> {
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
fn decimate_line(run: &[(f64, f64)], x: &Axis) -> Vec<(f64, f64)> {
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
fn simplify_collinear(run: &[(f64, f64)], x: &Axis, y: &Axis) -> Vec<(f64, f64)> {
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
fn decimate_points(run: &[(f64, f64)], x: &Axis, y: &Axis) -> Vec<(f64, f64)> {
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

fn extent(runs: &[Vec<Vec<(f64, f64)>>], pick: fn(&(f64, f64)) -> f64) -> Option<(f64, f64)> {
    runs.iter()
        .flatten()
        .flatten()
        .map(pick)
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((a, b)) => Some((a.min(v), b.max(v))),
        })
}

// ---------------------------------------------------------------------------
// Legend placement

/// Fraction of sampled data inside a corner box of normalised size (w, h).
fn corner_score(
    prepared: &[Prepared],
    x: &Axis,
    y: &Axis,
    corner: LegendPos,
    w: f64,
    h: f64,
) -> usize {
    let (u0, u1) = match corner {
        LegendPos::UpperLeft | LegendPos::LowerLeft => (0.0, w),
        _ => (1.0 - w, 1.0),
    };
    let (v0, v1) = match corner {
        LegendPos::LowerLeft | LegendPos::LowerRight => (0.0, h),
        _ => (1.0 - h, 1.0),
    };
    let norm = |p: &(f64, f64)| ((p.0 - x.lo) / (x.hi - x.lo), (p.1 - y.lo) / (y.hi - y.lo));
    let inside = |(u, v): (f64, f64)| u >= u0 && u <= u1 && v >= v0 && v <= v1;
    let mut score = 0;
    for run in prepared.iter().flat_map(|p| &p.runs) {
        if run.len() == 1 {
            score += usize::from(inside(norm(&run[0])));
        }
        for seg in run.windows(2) {
            let (a, b) = (norm(&seg[0]), norm(&seg[1]));
            let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
            let k = ((len / 0.01).ceil() as usize).clamp(1, 100);
            for i in 0..=k {
                let t = i as f64 / k as f64;
                score += usize::from(inside((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))));
            }
        }
    }
    score
}

// ---------------------------------------------------------------------------
// Drawing

fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

fn draw_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &Chart,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;

    let raw: Vec<Vec<Vec<(f64, f64)>>> = chart
        .series
        .iter()
        .map(|s| valid_runs(s, chart.log_x, chart.log_y))
        .collect();
    let has_data = raw.iter().any(|r| !r.is_empty());
    let xa = Axis::new(extent(&raw, |p| p.0), chart.log_x);
    let ya = Axis::new(extent(&raw, |p| p.1), chart.log_y);

    let prepared: Vec<Prepared> = chart
        .series
        .iter()
        .zip(raw)
        .map(|(s, runs)| Prepared {
            runs: runs
                .iter()
                .map(|r| match s.style {
                    Style::Points | Style::Published => decimate_points(r, &xa, &ya),
                    Style::Line | Style::LineMarkers => decimate_line(r, &xa),
                    Style::Dashed | Style::Guide => {
                        simplify_collinear(&decimate_line(r, &xa), &xa, &ya)
                    }
                })
                .collect(),
        })
        .collect();

    let tick_font = (FONT, 16).into_font();
    let y_tick_w = ya
        .bold
        .iter()
        .map(|&v| root.estimate_text_size(&ya.format(v), &tick_font.clone().into_text_style(root)))
        .filter_map(Result::ok)
        .map(|(w, _)| w)
        .max()
        .unwrap_or(30);

    let mut builder = ChartBuilder::on(root);
    builder
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(y_tick_w + 45);
    if !chart.title.is_empty() {
        builder.caption(&chart.title, (FONT, 26));
    }
    let mut ctx = builder
        .build_cartesian_2d(xa.clone(), ya.clone())
        .map_err(err)?;

    let fx = |v: &f64| xa.format(*v);
    let fy = |v: &f64| ya.format(*v);
    ctx.configure_mesh()
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .axis_desc_style((FONT, 20))
        .label_style(tick_font.clone())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .bold_line_style(RGBColor(205, 205, 205))
        .light_line_style(RGBColor(238, 238, 238))
        .draw()
        .map_err(err)?;

    let mut any_label = false;
    let mut slot = 0;
    let mut guide = 0;
    for (s, p) in chart.series.iter().zip(&prepared) {
        let color = if s.style == Style::Guide {
            RGBColor(120, 120, 120)
        } else if s.style == Style::Published {
            BLACK
        } else {
            slot += 1;
            PALETTE[(slot - 1) % PALETTE.len()]
        };
        let dash = if s.style == Style::Guide {
            guide += 1;
            GUIDE_DASHES[(guide - 1) % GUIDE_DASHES.len()]
        } else {
            DASH
        };
        let line = color.stroke_width(2);
        let fill = color.filled();
        for run in &p.runs {
            match s.style {
                Style::Points => ctx.draw_series(run.iter().map(|&pt| Circle::new(pt, 3, fill))),
                Style::Published => ctx.draw_series(run.iter().map(|&pt| {
                    EmptyElement::at(pt)
                        + Polygon::new(PUBLISHED_DIAMOND.to_vec(), fill)
                        + PathElement::new(PUBLISHED_DIAMOND.to_vec(), WHITE.stroke_width(2))
                })),
                _ if run.len() == 1 => {
                    ctx.draw_series(std::iter::once(Circle::new(run[0], 2, fill)))
                }
                Style::Line => ctx.draw_series(LineSeries::new(run.iter().copied(), line)),
                Style::LineMarkers => {
                    ctx.draw_series(LineSeries::new(run.iter().copied(), line))
                        .map_err(err)?;
                    let paths = marker_paths(slot - 1);
                    ctx.draw_series(run.iter().flat_map(|&pt| {
                        paths.iter().map(move |path| {
                            EmptyElement::at(pt) + PathElement::new(path.clone(), line)
                        })
                    }))
                }
                Style::Dashed | Style::Guide => ctx.draw_series(DashedLineSeries::new(
                    run.iter().copied(),
                    dash.0,
                    dash.1,
                    line,
                )),
            }
            .map_err(err)?;
        }
        if s.label.is_empty() {
            continue;
        }
        // The legend entry hangs off an empty series so that broken lines
        // (several runs) still get exactly one entry.
        let anno = ctx
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(err)?;
        any_label = true;
        let label = if p.runs.is_empty() {
            format!("{} (no drawable data)", s.label)
        } else {
            s.label.clone()
        };
        anno.label(label);
        match s.style {
            Style::Line => {
                anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], line));
            }
            Style::LineMarkers => {
                // Up to two strokes per shape (× and +); a closed shape repeats.
                let paths = marker_paths(slot - 1);
                let stroke = move |i: usize| {
                    let p: Vec<(i32, i32)> = paths[i.min(paths.len() - 1)]
                        .iter()
                        .map(|&(a, b)| (a + 12, b))
                        .collect();
                    PathElement::new(p, line)
                };
                anno.legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (24, 0)], line)
                        + stroke(0)
                        + stroke(1)
                });
            }
            Style::Dashed | Style::Guide => {
                // The line's own dash pattern over the 24 px sample: at most
                // 4 dashes (the shortest pattern), padded by repeating the last.
                let segs = dash_segments(24, dash);
                let seg = move |i: usize| {
                    let (a, b) = segs[i.min(segs.len() - 1)];
                    PathElement::new(vec![(a, 0), (b, 0)], line)
                };
                anno.legend(move |(x, y)| {
                    EmptyElement::at((x, y)) + seg(0) + seg(1) + seg(2) + seg(3)
                });
            }
            Style::Published => {
                anno.legend(move |(x, y)| {
                    EmptyElement::at((x + 12, y))
                        + Polygon::new(PUBLISHED_DIAMOND.to_vec(), fill)
                        + PathElement::new(PUBLISHED_DIAMOND.to_vec(), WHITE.stroke_width(2))
                });
            }
            Style::Points => {
                anno.legend(move |(x, y)| Circle::new((x + 12, y), 4, fill));
            }
        }
    }

    if !has_data {
        let msg = if chart.series.is_empty() {
            "no data series"
        } else {
            "no finite data to plot"
        };
        let style = (FONT, 22)
            .into_font()
            .color(&RGBColor(120, 120, 120))
            .pos(Pos::new(HPos::Center, VPos::Center));
        ctx.plotting_area()
            .draw(&Text::new(
                msg,
                ((xa.lo + xa.hi) / 2.0, (ya.lo + ya.hi) / 2.0),
                style,
            ))
            .map_err(err)?;
    }

    if any_label && chart.legend != LegendPos::Hidden {
        let legend_font = (FONT, 16).into_font();
        let (pw, ph) = ctx.plotting_area().dim_in_pixel();
        let labelled: Vec<&Series> = chart
            .series
            .iter()
            .filter(|s| !s.label.is_empty())
            .collect();
        let text_w = labelled
            .iter()
            .filter_map(|s| {
                root.estimate_text_size(&s.label, &legend_font.clone().into_text_style(root))
                    .ok()
            })
            .map(|(w, _)| w)
            .max()
            .unwrap_or(0);
        let box_w = f64::from(text_w + 75) / f64::from(pw.max(1));
        let box_h = (labelled.len() as f64 * 22.0 + 30.0) / f64::from(ph.max(1));
        let pos = match chart.legend {
            LegendPos::Auto => {
                let order = [
                    LegendPos::UpperRight,
                    LegendPos::UpperLeft,
                    LegendPos::LowerRight,
                    LegendPos::LowerLeft,
                ];
                let mut best = (usize::MAX, LegendPos::UpperRight);
                for c in order {
                    let s = corner_score(&prepared, &xa, &ya, c, box_w, box_h);
                    if s < best.0 {
                        best = (s, c);
                    }
                }
                best.1
            }
            other => other,
        };
        let pos = match pos {
            LegendPos::UpperLeft => SeriesLabelPosition::UpperLeft,
            LegendPos::LowerLeft => SeriesLabelPosition::LowerLeft,
            LegendPos::LowerRight => SeriesLabelPosition::LowerRight,
            _ => SeriesLabelPosition::UpperRight,
        };
        ctx.configure_series_labels()
            .position(pos)
            .margin(12)
            .legend_area_size(34)
            .label_font(legend_font)
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(150, 150, 150))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Categorical cell maps (the stress study's stability map)

/// One panel of a [`CellMap`]: a grid of coloured cells, `rows` top to bottom
/// and `x_ticks` left to right.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MapPanel {
    pub title: String,
    pub x_ticks: Vec<String>,
    pub rows: Vec<String>,
    /// `cells[row][col]`: class index into [`CellMap::classes`] and a short
    /// text drawn in the cell; `None` = not run (left blank).
    pub cells: Vec<Vec<Option<(usize, String)>>>,
    /// Vertical markers at fractional column positions (0 = left edge of the
    /// first column), e.g. a limit that falls between two columns.
    pub marks: Vec<(f64, String)>,
}

/// Panels of categorical cells sharing one legend (`classes`: label and RGB).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CellMap {
    pub title: String,
    pub x_label: String,
    pub classes: Vec<(String, [u8; 3])>,
    pub panels: Vec<MapPanel>,
    /// Panels per row of the figure (≥ 1).
    pub columns: usize,
}

const MAP_CELL_W: u32 = 58;
const MAP_CELL_H: u32 = 24;
const MAP_ROW_LABEL_W: u32 = 100;
const MAP_PANEL_TITLE_H: u32 = 46;
const MAP_PANEL_FOOT_H: u32 = 58;
const MAP_HEADER_H: u32 = 50;
const MAP_MARGIN: u32 = 20;

impl CellMap {
    fn panel_size(&self) -> (u32, u32) {
        let cols = self
            .panels
            .iter()
            .map(|p| p.x_ticks.len())
            .max()
            .unwrap_or(1) as u32;
        let rows = self.panels.iter().map(|p| p.rows.len()).max().unwrap_or(1) as u32;
        (
            MAP_ROW_LABEL_W + cols.max(1) * MAP_CELL_W + MAP_MARGIN,
            MAP_PANEL_TITLE_H + rows.max(1) * MAP_CELL_H + MAP_PANEL_FOOT_H,
        )
    }

    /// Legend lines: classes packed into lines no wider than the figure.
    fn legend_lines(&self, width: u32) -> Vec<Vec<usize>> {
        let mut lines: Vec<Vec<usize>> = vec![vec![]];
        let mut x = MAP_MARGIN;
        for (i, (label, _)) in self.classes.iter().enumerate() {
            // ~8.5 px per character at 15 px, plus the swatch.
            let w = 40 + (label.chars().count() as u32 * 17) / 2;
            if x + w > width && !lines.last().unwrap().is_empty() {
                lines.push(vec![]);
                x = MAP_MARGIN;
            }
            lines.last_mut().unwrap().push(i);
            x += w;
        }
        lines
    }

    /// Figure size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let (pw, ph) = self.panel_size();
        let cols = self.columns.clamp(1, self.panels.len().max(1)) as u32;
        let rows = (self.panels.len() as u32).div_ceil(cols).max(1);
        let w = 2 * MAP_MARGIN + cols * pw;
        let legend = self.legend_lines(w).len() as u32 * 24 + 10;
        (w, MAP_HEADER_H + legend + rows * ph + MAP_MARGIN)
    }
}

/// Render `map` to `path` (`.png` or `.svg`); deterministic like [`render`].
pub fn render_map(map: &CellMap, path: &Path) -> Result<(), PlotError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("png" | "svg")) {
        return Err(PlotError::UnsupportedFormat {
            path: path.to_path_buf(),
        });
    }
    if !font_registered() {
        return Err(PlotError::Font {
            path: path.to_path_buf(),
        });
    }
    let draw_err = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let (w, h) = map.size();
    if ext.as_deref() == Some("svg") {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
            draw_map(&root, map).map_err(draw_err)?;
            root.present().map_err(|e| draw_err(e.to_string()))?;
        }
        std::fs::write(path, svg).map_err(|source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        })
    } else {
        let mut buf = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            draw_map(&root, map).map_err(draw_err)?;
            root.present().map_err(|e| draw_err(e.to_string()))?;
        }
        write_png(path, &buf, w, h)
    }
}

/// Black or white text, whichever reads better on `c` (relative luminance).
fn text_on(c: [u8; 3]) -> RGBColor {
    let l = 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]);
    if l > 140.0 {
        BLACK
    } else {
        WHITE
    }
}

fn draw_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    map: &CellMap,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let (w, _) = map.size();
    let centre = |size: u32, color: RGBColor| {
        (FONT, size)
            .into_font()
            .color(&color)
            .pos(Pos::new(HPos::Center, VPos::Center))
    };
    let left = |size: u32, color: RGBColor| {
        (FONT, size)
            .into_font()
            .color(&color)
            .pos(Pos::new(HPos::Left, VPos::Center))
    };
    let right = |size: u32| {
        (FONT, size)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Right, VPos::Center))
    };
    let px = |v: u32| v as i32;
    root.draw(&Text::new(
        map.title.as_str(),
        (px(w / 2), px(MAP_HEADER_H / 2)),
        centre(24, BLACK),
    ))
    .map_err(err)?;
    // Legend.
    let lines = map.legend_lines(w);
    for (li, line) in lines.iter().enumerate() {
        let y = px(MAP_HEADER_H + li as u32 * 24 + 10);
        let mut x = px(MAP_MARGIN);
        for &i in line {
            let (label, c) = &map.classes[i];
            let col = RGBColor(c[0], c[1], c[2]);
            root.draw(&Rectangle::new([(x, y - 8), (x + 28, y + 8)], col.filled()))
                .map_err(err)?;
            root.draw(&Rectangle::new(
                [(x, y - 8), (x + 28, y + 8)],
                RGBColor(90, 90, 90).stroke_width(1),
            ))
            .map_err(err)?;
            root.draw(&Text::new(label.as_str(), (x + 34, y), left(15, BLACK)))
                .map_err(err)?;
            x += px(40 + (label.chars().count() as u32 * 17) / 2);
        }
    }
    let top = MAP_HEADER_H + lines.len() as u32 * 24 + 10;
    let (pw, ph) = map.panel_size();
    let cols = map.columns.clamp(1, map.panels.len().max(1));
    for (k, p) in map.panels.iter().enumerate() {
        let x0 = MAP_MARGIN + (k % cols) as u32 * pw;
        let y0 = top + (k / cols) as u32 * ph;
        let gx = x0 + MAP_ROW_LABEL_W;
        let gy = y0 + MAP_PANEL_TITLE_H;
        let ncol = p.x_ticks.len() as u32;
        root.draw(&Text::new(
            p.title.as_str(),
            (
                px(gx + ncol * MAP_CELL_W / 2),
                px(y0 + MAP_PANEL_TITLE_H / 2),
            ),
            centre(17, BLACK),
        ))
        .map_err(err)?;
        for (r, name) in p.rows.iter().enumerate() {
            let y = gy + r as u32 * MAP_CELL_H;
            root.draw(&Text::new(
                name.as_str(),
                (px(gx - 8), px(y + MAP_CELL_H / 2)),
                right(14),
            ))
            .map_err(err)?;
            for c in 0..ncol {
                let x = gx + c * MAP_CELL_W;
                let cell = p
                    .cells
                    .get(r)
                    .and_then(|row| row.get(c as usize))
                    .cloned()
                    .flatten();
                let rect = [(px(x), px(y)), (px(x + MAP_CELL_W), px(y + MAP_CELL_H))];
                if let Some((class, text)) = cell {
                    let rgb = map.classes.get(class).map_or([200, 200, 200], |x| x.1);
                    root.draw(&Rectangle::new(
                        rect,
                        RGBColor(rgb[0], rgb[1], rgb[2]).filled(),
                    ))
                    .map_err(err)?;
                    if !text.is_empty() {
                        root.draw(&Text::new(
                            text,
                            (px(x + MAP_CELL_W / 2), px(y + MAP_CELL_H / 2)),
                            centre(12, text_on(rgb)),
                        ))
                        .map_err(err)?;
                    }
                }
                root.draw(&Rectangle::new(rect, WHITE.stroke_width(1)))
                    .map_err(err)?;
            }
        }
        let gh = p.rows.len() as u32 * MAP_CELL_H;
        for (c, tick) in p.x_ticks.iter().enumerate() {
            root.draw(&Text::new(
                tick.as_str(),
                (
                    px(gx + c as u32 * MAP_CELL_W + MAP_CELL_W / 2),
                    px(gy + gh + 11),
                ),
                centre(13, BLACK),
            ))
            .map_err(err)?;
        }
        root.draw(&Text::new(
            map.x_label.as_str(),
            (px(gx + ncol * MAP_CELL_W / 2), px(gy + gh + 32)),
            centre(14, RGBColor(60, 60, 60)),
        ))
        .map_err(err)?;
        for (pos, label) in &p.marks {
            if !pos.is_finite() || *pos < 0.0 || *pos > f64::from(ncol) {
                continue;
            }
            let x = px(gx) + (pos * f64::from(MAP_CELL_W)).round() as i32;
            let line = RGBColor(40, 40, 40).stroke_width(1);
            root.draw(&PathElement::new(
                vec![(x, px(gy) - 4), (x, px(gy + gh) + 2)],
                line,
            ))
            .map_err(err)?;
            root.draw(&Text::new(
                label.as_str(),
                (x + 3, px(gy) - 10),
                left(12, BLACK),
            ))
            .map_err(err)?;
        }
    }
    Ok(())
}
