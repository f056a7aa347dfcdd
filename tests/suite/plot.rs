use crate::common;
use common::fibresim;

use std::path::PathBuf;
use std::time::Instant;

use fibresim::plot::{
    reference_slope, render, Chart, LegendPos, PlotError, Series, Style, HEIGHT, WIDTH,
};

fn out(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("plot-tests");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Energy error vs time for three integrators, 1e5 points each, with spikes.
fn energy_chart(n: usize) -> Chart {
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-4).collect();
    let mut chart = Chart::new(
        "Relative energy error vs time",
        "time t (s)",
        "relative energy error |ΔE/E₀| (–)",
    );
    chart.log_y = true;
    for (k, name) in ["explicit Euler", "Omelyan leapfrog", "RK4 (normalised)"]
        .iter()
        .enumerate()
    {
        let scale = 10f64.powi(-(2 * k as i32) - 3);
        let y = t
            .iter()
            .enumerate()
            .map(|(i, &ti)| {
                let spike = if i % 20_011 == 5_000 { 30.0 } else { 1.0 };
                scale * (1.0 + ti) * (1.1 + (ti * 40.0).sin()) * spike
            })
            .collect();
        chart
            .series
            .push(Series::new(*name, t.clone(), y, Style::Line));
    }
    chart
}

fn convergence_chart() -> Chart {
    let dt: Vec<f64> = (0..8).map(|i| 1e-3 / 2f64.powi(i)).collect();
    let e1: Vec<f64> = dt.iter().map(|d| 3.0 * d).collect();
    let e2: Vec<f64> = dt.iter().map(|d| 40.0 * d * d).collect();
    let e4: Vec<f64> = dt.iter().map(|d| 2e3 * d.powi(4)).collect();
    Chart {
        title: "Energy error vs time step".into(),
        x_label: "time step Δt (s)".into(),
        y_label: "max relative energy error (–)".into(),
        log_x: true,
        log_y: true,
        series: vec![
            Series::new("Euler", dt.clone(), e1, Style::Points),
            Series::new("leapfrog", dt.clone(), e2, Style::Points),
            Series::new("RK4", dt.clone(), e4, Style::Points),
            reference_slope("slope 1", 1.0, (dt[7], dt[0]), (dt[0], 6.0 * dt[0])),
            reference_slope(
                "slope 2",
                2.0,
                (dt[7], dt[0]),
                (dt[0], 80.0 * dt[0] * dt[0]),
            ),
            reference_slope("slope 4", 4.0, (dt[7], dt[0]), (dt[0], 4e3 * dt[0].powi(4))),
        ],
        legend: LegendPos::Auto,
    }
}

/// The palette's first three colours (series slots 1-3): blue, vermillion,
/// bluish green (Okabe and Ito's colour-blind-safe set, as the docs name it).
const BLUE: [u8; 3] = [0x00, 0x72, 0xB2];
const VERMILLION: [u8; 3] = [0xD5, 0x5E, 0x00];
const GREEN: [u8; 3] = [0x00, 0x9E, 0x73];

/// A decoded 8-bit RGB PNG.
struct Image {
    w: u32,
    h: u32,
    rgb: Vec<u8>,
}

/// The plotting area in pixels, found from the axis lines.
#[derive(Debug)]
struct Frame {
    left: u32,
    right: u32,
    top: u32,
    bottom: u32,
}

impl Image {
    fn read(path: &PathBuf) -> Image {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgb, png::BitDepth::Eight)
        );
        buf.truncate(info.buffer_size());
        Image {
            w: info.width,
            h: info.height,
            rgb: buf,
        }
    }

    fn at(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y * self.w + x) as usize;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Every pixel of exactly colour `c` (lines are not anti-aliased).
    fn pixels(&self, c: [u8; 3]) -> Vec<(u32, u32)> {
        (0..self.h)
            .flat_map(|y| (0..self.w).map(move |x| (x, y)))
            .filter(|&(x, y)| self.at(x, y) == c)
            .collect()
    }

    /// Longest run of black pixels along a row (`horizontal`) or a column:
    /// (row or column, first, last).
    fn longest_black_run(&self, horizontal: bool) -> (u32, u32, u32) {
        let (lines, len) = if horizontal {
            (self.h, self.w)
        } else {
            (self.w, self.h)
        };
        let mut best = (0, 0, 0);
        for line in 0..lines {
            let mut start = None;
            for i in 0..=len {
                let black = i < len
                    && if horizontal {
                        self.at(i, line) == [0; 3]
                    } else {
                        self.at(line, i) == [0; 3]
                    };
                match (black, start) {
                    (true, None) => start = Some(i),
                    (false, Some(a)) => {
                        if i - a > best.2 - best.1 + 1 || best == (0, 0, 0) {
                            best = (line, a, i - 1);
                        }
                        start = None;
                    }
                    _ => {}
                }
            }
        }
        best
    }

    /// The plotting area: the x axis is the longest black row, just below
    /// the area, and spans its width; the y axis the longest black column,
    /// just left of it, spanning its height.
    fn frame(&self) -> Frame {
        let (_, left, right) = self.longest_black_run(true);
        let (_, top, bottom) = self.longest_black_run(false);
        assert!(
            right > left + self.w / 2 && bottom > top + self.h / 2,
            "axes {left}..{right} x {top}..{bottom}"
        );
        Frame {
            left,
            right,
            top,
            bottom,
        }
    }
}

impl Frame {
    /// Pixel `(x, y)` as fractions of the area: 0 at the left and bottom,
    /// 1 at the right and top.
    fn fraction(&self, (x, y): (u32, u32)) -> (f64, f64) {
        (
            (x as f64 - self.left as f64) / (self.right - self.left) as f64,
            (self.bottom as f64 - y as f64) / (self.bottom - self.top) as f64,
        )
    }
}

/// Fractions of `pixels` in `frame`, checking each lies inside it.
fn inside(frame: &Frame, pixels: &[(u32, u32)]) -> Vec<(f64, f64)> {
    let tol = 0.01;
    pixels
        .iter()
        .map(|&p| {
            let f = frame.fraction(p);
            assert!(
                (-tol..=1.0 + tol).contains(&f.0) && (-tol..=1.0 + tol).contains(&f.1),
                "pixel {p:?} outside {frame:?}"
            );
            f
        })
        .collect()
}

fn mean_height(fractions: &[(f64, f64)]) -> f64 {
    fractions.iter().map(|f| f.1).sum::<f64>() / fractions.len() as f64
}

fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    })
}

/// Two lines over equal data ranges on both axes: `y = x` must lie on the
/// frame's rising diagonal and `y = 1 - x` on the falling one, whatever the
/// axis padding, since both axes map [0, 1] alike.
#[test]
fn png_draws_series_where_their_data_are() {
    let x: Vec<f64> = (0..=50).map(|i| i as f64 / 50.0).collect();
    let up = x.clone();
    let down: Vec<f64> = x.iter().map(|v| 1.0 - v).collect();
    let chart = Chart {
        series: vec![
            Series::new("up", x.clone(), up, Style::Line),
            Series::new("down", x, down, Style::Line),
        ],
        legend: LegendPos::Hidden,
        ..Chart::new("diagonals", "x (m)", "y (m)")
    };
    let p = out("diagonals.png");
    render(&chart, &p).unwrap();
    let img = Image::read(&p);
    assert_eq!((img.w, img.h), (WIDTH, HEIGHT));
    let frame = img.frame();
    // Within 3 px of the diagonal, over most of its length.
    let tol = 3.0 / (frame.bottom - frame.top) as f64;
    for (colour, on_line) in [
        (BLUE, (|(u, v): (f64, f64)| u - v) as fn((f64, f64)) -> f64),
        (VERMILLION, |(u, v)| u + v - 1.0),
    ] {
        let f = inside(&frame, &img.pixels(colour));
        assert!(f.len() > 500, "{colour:?}: {} pixels", f.len());
        for &p in &f {
            assert!(on_line(p).abs() < tol, "{colour:?} pixel at {p:?}");
        }
        let (lo, hi) = span(f.iter().map(|p| p.0));
        assert!(lo < 0.1 && hi > 0.9, "{colour:?} spans {lo}..{hi}");
    }
}

/// Three series two decades apart on a log axis: each is drawn across the
/// frame, the largest on top.
#[test]
fn png_has_signature_and_size() {
    let p = out("energy.png");
    render(&energy_chart(2_000), &p).unwrap();
    let img = Image::read(&p);
    assert_eq!((img.w, img.h), (WIDTH, HEIGHT));
    let frame = img.frame();
    let heights: Vec<f64> = [BLUE, VERMILLION, GREEN]
        .iter()
        .map(|&c| {
            let f = inside(&frame, &img.pixels(c));
            let (lo, hi) = span(f.iter().map(|p| p.0));
            assert!(hi - lo > 0.9, "{c:?} spans {lo}..{hi}");
            mean_height(&f)
        })
        .collect();
    assert!(
        heights[0] > heights[1] && heights[1] > heights[2],
        "{heights:?}"
    );
}

#[test]
fn svg_contains_labels() {
    let chart = convergence_chart();
    let p = out("convergence.svg");
    render(&chart, &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"));
    assert!(svg.trim_end().ends_with("</svg>"));
    for s in &chart.series {
        assert!(svg.contains(&s.label), "missing label {}", s.label);
    }
    assert!(svg.contains("time step Δt (s)"));
    assert!(svg.contains("max relative energy error (–)"));

    // Text is XML-escaped.
    let mut odd = Chart::new("a < b & c", "x (s)", "y (J)");
    odd.series.push(Series::new(
        "E<sub>k</sub> & co",
        vec![1.0, 2.0],
        vec![1.0, 2.0],
        Style::Line,
    ));
    let p = out("escaped.svg");
    render(&odd, &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    assert!(svg.contains("E&lt;sub&gt;k&lt;/sub&gt; &amp; co"));
    assert!(!svg.contains("<sub>"));
}

/// Errors 3 δt, 40 δt² and 2e3 δt⁴ for δt ≤ 1e-3: first order on top.
#[test]
fn log_log_with_reference_slopes_png() {
    let p = out("convergence.png");
    render(&convergence_chart(), &p).unwrap();
    let img = Image::read(&p);
    assert_eq!((img.w, img.h), (WIDTH, HEIGHT));
    let frame = img.frame();
    let heights: Vec<f64> = [BLUE, VERMILLION, GREEN]
        .iter()
        .map(|&c| mean_height(&inside(&frame, &img.pixels(c))))
        .collect();
    assert!(
        heights[0] > heights[1] && heights[1] > heights[2],
        "{heights:?}"
    );
}

#[test]
fn svg_is_deterministic() {
    let chart = energy_chart(5_000);
    let (a, b) = (out("det_a.svg"), out("det_b.svg"));
    render(&chart, &a).unwrap();
    render(&chart, &b).unwrap();
    assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
}

#[test]
fn png_is_deterministic() {
    let chart = convergence_chart();
    let (a, b) = (out("det_a.png"), out("det_b.png"));
    render(&chart, &a).unwrap();
    render(&chart, &b).unwrap();
    assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
}

#[test]
fn odd_inputs_do_not_panic() {
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    let cases: Vec<(&str, Chart)> = vec![
        ("empty", Chart::default()),
        (
            "empty_vectors",
            Chart {
                series: vec![Series::new("none", vec![], vec![], Style::Line)],
                ..Chart::default()
            },
        ),
        (
            "all_nan",
            Chart {
                log_x: true,
                log_y: true,
                series: vec![Series::new(
                    "nan",
                    vec![nan, inf],
                    vec![nan, -inf],
                    Style::Line,
                )],
                ..Chart::new("all NaN", "x (s)", "y (J)")
            },
        ),
        (
            "single_point",
            Chart {
                series: vec![Series::new("one", vec![2.0], vec![3.0], Style::Dashed)],
                ..Chart::new("single", "x (s)", "y (J)")
            },
        ),
        (
            "single_point_log",
            Chart {
                log_x: true,
                log_y: true,
                series: vec![Series::new("one", vec![2.0], vec![3.0], Style::Points)],
                ..Chart::default()
            },
        ),
        (
            "constant_zero",
            Chart {
                series: vec![Series::new("zero", vec![0.0; 5], vec![0.0; 5], Style::Line)],
                ..Chart::default()
            },
        ),
        (
            "constant_tiny",
            Chart {
                series: vec![Series::new(
                    "tiny",
                    vec![1.0, 2.0, 3.0],
                    vec![1e-300; 3],
                    Style::Line,
                )],
                ..Chart::default()
            },
        ),
        (
            "huge_range",
            Chart {
                series: vec![Series::new(
                    "huge",
                    vec![-f64::MAX, f64::MAX],
                    vec![f64::MIN_POSITIVE, f64::MAX],
                    Style::Line,
                )],
                ..Chart::default()
            },
        ),
        (
            "log_nonpositive_and_gaps",
            Chart {
                log_y: true,
                legend: LegendPos::LowerLeft,
                series: vec![Series::new(
                    "gaps",
                    vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
                    vec![1.0, 0.0, -1.0, 2.0, nan, 3.0],
                    Style::Line,
                )],
                ..Chart::default()
            },
        ),
        (
            "unlabelled",
            Chart {
                legend: LegendPos::Hidden,
                series: vec![Series::new("", vec![1.0, 2.0], vec![1.0, 4.0], Style::Line)],
                ..Chart::default()
            },
        ),
        (
            "many_series",
            Chart {
                series: (0..12)
                    .map(|k| {
                        Series::new(
                            format!("s{k}"),
                            vec![0.0, 1.0],
                            vec![k as f64, 0.0],
                            Style::Line,
                        )
                    })
                    .collect(),
                ..Chart::default()
            },
        ),
    ];
    for (name, chart) in cases {
        for ext in ["png", "svg"] {
            let p = out(&format!("odd_{name}.{ext}"));
            render(&chart, &p).unwrap_or_else(|e| panic!("{name}.{ext}: {e}"));
        }
    }
}

#[test]
fn errors_name_the_path() {
    let p = out("chart.pdf");
    let e = render(&convergence_chart(), &p).unwrap_err();
    assert!(matches!(e, PlotError::UnsupportedFormat { .. }));
    assert!(e.to_string().contains("chart.pdf"), "{e}");

    let bad = Chart {
        series: vec![Series::new("bad", vec![1.0, 2.0], vec![1.0], Style::Line)],
        ..Chart::default()
    };
    let p = out("bad.svg");
    let e = render(&bad, &p).unwrap_err();
    assert!(matches!(e, PlotError::LengthMismatch { .. }));
    assert!(e.to_string().contains("bad.svg"), "{e}");

    let p = out("no-such-dir/x.png");
    let e = render(&convergence_chart(), &p).unwrap_err();
    assert!(matches!(e, PlotError::Io { .. }));
    assert!(e.to_string().contains("x.png"), "{e}");
}

/// The polylines drawn in colour `stroke` in an SVG, as point lists.
fn polylines(svg: &str, stroke: &str) -> Vec<Vec<(f64, f64)>> {
    let key = format!("stroke=\"{stroke}\"");
    svg.split("<polyline")
        .skip(1)
        .filter(|e| e.contains(&key))
        .filter_map(|e| {
            let pts = e.split("points=\"").nth(1)?.split('"').next()?;
            Some(
                pts.split_whitespace()
                    .filter_map(|xy| {
                        let (x, y) = xy.split_once(',')?;
                        Some((x.parse().ok()?, y.parse().ok()?))
                    })
                    .collect(),
            )
        })
        .collect()
}

/// 3 × 1e5 points with spikes: decimated to what the pixels show, yet the
/// spikes (the data maximum) and the dips (the minimum) are still drawn.
#[test]
fn large_series_render() {
    let mut chart = energy_chart(100_000);
    // No legend: its samples would sit where the extremes are looked for.
    chart.legend = LegendPos::Hidden;
    for ext in ["png", "svg"] {
        let p = out(&format!("energy_1e5.{ext}"));
        let t0 = Instant::now();
        render(&chart, &p).unwrap();
        let dt = t0.elapsed();
        // Timing is printed, not asserted (shared machine).
        eprintln!("3 series x 1e5 points -> {ext}: {dt:?}");
    }
    let img = Image::read(&out("energy_1e5.png"));
    let frame = img.frame();
    for c in [BLUE, VERMILLION, GREEN] {
        let f = inside(&frame, &img.pixels(c));
        let (lo, hi) = span(f.iter().map(|p| p.0));
        assert!(hi - lo > 0.9, "{c:?} spans {lo}..{hi}");
    }
    // The blue spikes hold the data maximum and the green dips the minimum;
    // the axis pads both ends alike, so they lie symmetric in the frame (the
    // y axis line spans it). Had decimation dropped the spikes, blue would
    // top out 0.6 decades lower. The SVG gives the vertices exactly.
    let svg = std::fs::read_to_string(out("energy_1e5.svg")).unwrap();
    let y_axis = polylines(&svg, "#000000")
        .into_iter()
        .filter(|p| p.len() == 2 && p[0].0 == p[1].0)
        .max_by(|a, b| (a[1].1 - a[0].1).total_cmp(&(b[1].1 - b[0].1)))
        .unwrap();
    let (top, bottom) = (y_axis[0].1, y_axis[1].1);
    let lines = |stroke| polylines(&svg, stroke);
    let (blue, green) = (lines("#0072B2"), lines("#009E73"));
    let (highest, _) = span(blue.iter().flatten().map(|p| p.1));
    let (_, lowest) = span(green.iter().flatten().map(|p| p.1));
    assert!(
        ((highest - top) - (bottom - lowest)).abs() <= 1.0,
        "maximum {highest}, minimum {lowest}, frame {top}..{bottom}"
    );
    for stroke in ["#0072B2", "#D55E00", "#009E73"] {
        // One line per series, thinned to a few points per pixel column.
        let n: Vec<usize> = lines(stroke).iter().map(Vec::len).collect();
        assert_eq!(n.len(), 1, "{stroke}: {n:?}");
        assert!(
            n[0] > WIDTH as usize / 2 && n[0] < 10_000,
            "{stroke}: {n:?}"
        );
    }

    // Worst cases: 1e5 noisy points as markers and as a dashed line.
    let n = 100_000;
    let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut state = 12345u64;
    let y: Vec<f64> = (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect();
    let mut chart = Chart::new("noise", "sample (–)", "value (–)");
    chart
        .series
        .push(Series::new("points", x.clone(), y.clone(), Style::Points));
    chart
        .series
        .push(Series::new("dashed", x, y, Style::Dashed));
    for ext in ["png", "svg"] {
        let p = out(&format!("noise_1e5.{ext}"));
        let t0 = Instant::now();
        render(&chart, &p).unwrap();
        let dt = t0.elapsed();
        let size = std::fs::metadata(&p).unwrap().len();
        eprintln!("1e5 noisy points + 1e5 dashed -> {ext}: {dt:?}, {size} bytes");
    }
    // Uniform noise on [0, 1) fills the frame with both series; it covers
    // every corner, so the legend (with its samples) is right of the frame.
    let img = Image::read(&out("noise_1e5.png"));
    let frame = img.frame();
    for c in [BLUE, VERMILLION] {
        let (data, legend): (Vec<_>, Vec<_>) = img
            .pixels(c)
            .into_iter()
            .partition(|p| p.0 <= frame.right + 2);
        assert!(legend.iter().all(|p| p.0 > frame.right + 5), "{c:?}");
        assert!(!legend.is_empty(), "{c:?}: the legend sample, outside");
        let f = inside(&frame, &data);
        let (x0, x1) = span(f.iter().map(|p| p.0));
        let (y0, y1) = span(f.iter().map(|p| p.1));
        assert!(
            x1 - x0 > 0.9 && y1 - y0 > 0.9,
            "{c:?}: {x0}..{x1} x {y0}..{y1}"
        );
    }
    let svg = std::fs::read_to_string(out("noise_1e5.svg")).unwrap();
    let markers = svg.matches("fill=\"#0072B2\"").count();
    assert!(markers > 1000 && markers < n, "{markers} markers");
}

/// Lengths (px) of the two-point strokes of colour `stroke` in an SVG.
fn stroke_lengths(svg: &str, stroke: &str) -> Vec<f64> {
    polylines(svg, stroke)
        .into_iter()
        .filter(|p| p.len() == 2)
        .map(|p| (p[1].0 - p[0].0).hypot(p[1].1 - p[0].1))
        .collect()
}

/// Slope guides are all grey; the second and third get their own dash
/// patterns (dots, long dashes), in the plot and in the legend.
#[test]
fn slope_guides_have_distinct_dash_patterns() {
    use fibresim::plot::GUIDE_DASHES;
    let mut chart = convergence_chart();
    for s in chart.series.iter_mut().filter(|s| s.style == Style::Dashed) {
        s.style = Style::Guide;
    }
    let p = out("guides.svg");
    render(&chart, &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    let len = stroke_lengths(&svg, "#787878");
    let near = |d: u32| len.iter().filter(|&&l| (l - d as f64).abs() < 1.5).count();
    // Each pattern's dash length occurs along its line (tens of dashes),
    // not only as the odd clipped stub at a line's end.
    for (dash, _) in GUIDE_DASHES {
        assert!(near(dash) >= 5, "dash {dash}: {} of {len:?}", near(dash));
    }
}

/// Line-with-markers series: one marker outline per point, each slot its
/// own shape, and the legend shows the shape too.
#[test]
fn line_markers_draw_one_shape_per_point() {
    let x: Vec<f64> = (0..5).map(|i| 10f64.powi(-i)).collect();
    let mut chart = Chart::new("markers", "dt (s)", "err (rad)");
    chart.log_x = true;
    chart.log_y = true;
    for k in 0..fibresim::plot::MARKER_SHAPES {
        let y = x.iter().map(|v| v * (k + 1) as f64).collect();
        chart.series.push(Series::new(
            format!("s{k}"),
            x.clone(),
            y,
            Style::LineMarkers,
        ));
    }
    let p = out("markers.svg");
    render(&chart, &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    // The first slot (blue circles, drawn as closed 17-point paths): 5 points
    // plus the legend sample's.
    let closed = svg
        .split("<polyline")
        .skip(1)
        .map(|e| e.split('>').next().unwrap_or(""))
        .filter(|e| e.contains("stroke=\"#0072B2\"") && e.matches(',').count() == 17)
        .count();
    assert_eq!(closed, 5 + 1, "circle markers");
    // Published values: black filled diamonds on top, one per point + legend,
    // taking no palette slot (the blue series keeps its colour).
    chart.series.insert(
        0,
        Series::new("paper", vec![1e-2, 1e-3], vec![0.1, 0.01], Style::Published),
    );
    render(&chart, &p).unwrap();
    let svg2 = std::fs::read_to_string(&p).unwrap();
    let diamonds = svg2
        .split("<polygon")
        .skip(1)
        .map(|e| e.split('>').next().unwrap_or(""))
        .filter(|e| e.contains("fill=\"#000000\"") && e.matches(',').count() == 5)
        .count();
    assert_eq!(diamonds, 2 + 1, "published diamonds");
    assert_eq!(
        svg2.matches("#0072B2").count(),
        svg.matches("#0072B2").count()
    );
    let png = out("markers.png");
    render(&chart, &png).unwrap();
    let img = Image::read(&png);
    let frame = img.frame();
    assert!(!inside(&frame, &img.pixels(BLUE)).is_empty());
}

/// A spiky series (plotters issue #549) drawn with a
/// 2 px line puts no pixel of its colour outside the frame in PNG (before,
/// the line's outline polygon covered the tick labels and the title).
#[test]
fn png_lines_stay_inside_the_frame() {
    let n = 3000;
    let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
    // Every other point 0 or the maximum, with narrow spikes between.
    let y: Vec<f64> = (0..n)
        .map(|i| match i % 7 {
            0 => 9.0,
            3 => 0.0,
            _ => 1.0 + (i % 3) as f64,
        })
        .collect();
    let chart = Chart {
        series: vec![Series::new("contacts", x, y, Style::Line)],
        legend: LegendPos::Hidden,
        ..Chart::new("spiky contacts", "time t (s)", "contacts (count)")
    };
    let p = out("spiky.png");
    render(&chart, &p).unwrap();
    let img = Image::read(&p);
    // The frame from the SVG of the same chart (the same layout, exact
    // axis lines), so what the PNG's lines cover cannot hide it.
    let svg_path = out("spiky.svg");
    render(&chart, &svg_path).unwrap();
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let axes: Vec<Vec<(f64, f64)>> = polylines(&svg, "#000000")
        .into_iter()
        .filter(|l| l.len() == 2)
        .collect();
    let longest = |horizontal: bool| {
        axes.iter()
            .filter(|l| (l[0].1 == l[1].1) == horizontal)
            .max_by(|a, b| {
                let len = |l: &Vec<(f64, f64)>| (l[1].0 - l[0].0).abs() + (l[1].1 - l[0].1).abs();
                len(a).total_cmp(&len(b))
            })
            .unwrap()
            .clone()
    };
    let (xa, ya) = (longest(true), longest(false));
    let frame = Frame {
        left: xa[0].0.min(xa[1].0) as u32,
        right: xa[0].0.max(xa[1].0) as u32,
        top: ya[0].1.min(ya[1].1) as u32,
        bottom: ya[0].1.max(ya[1].1) as u32,
    };
    assert!(
        frame.right > frame.left + 500 && frame.bottom > frame.top + 400,
        "{frame:?}"
    );
    let outside: Vec<(u32, u32)> = img
        .pixels(BLUE)
        .into_iter()
        .filter(|&(x, y)| {
            x + 1 < frame.left || x > frame.right + 1 || y + 1 < frame.top || y > frame.bottom + 1
        })
        .collect();
    assert!(
        outside.is_empty(),
        "{} data pixels outside {frame:?}, e.g. {:?}",
        outside.len(),
        &outside[..outside.len().min(5)]
    );
    // The line is drawn: it reaches the top and the bottom of the data.
    let f = inside(&frame, &img.pixels(BLUE));
    let (lo, hi) = span(f.iter().map(|p| p.1));
    assert!(lo < 0.06 && hi > 0.94, "{lo}..{hi}");
}

/// The `<rect>` of the legend box in an SVG (its border is grey #969696).
fn legend_rect(svg: &str) -> Option<(f64, f64, f64, f64)> {
    svg.split("<rect").skip(1).find_map(|r| {
        let r = r.split('>').next()?;
        if !r.contains("stroke=\"#969696\"") {
            return None;
        }
        let attr = |k: &str| -> Option<f64> {
            r.split(&format!(" {k}=\""))
                .nth(1)?
                .split('"')
                .next()?
                .parse()
                .ok()
        };
        Some((attr("x")?, attr("y")?, attr("width")?, attr("height")?))
    })
}

/// No data line or marker of a palette colour passes under the legend box:
/// every vertex, and points every 2 px along every segment, of the data
/// polylines lie outside it (the samples in the box's left strip excepted).
fn assert_legend_covers_no_data(svg: &str, what: &str) {
    let (x, y, w, h) = legend_rect(svg).unwrap_or_else(|| panic!("{what}: no legend"));
    let inside = |p: (f64, f64)| p.0 > x && p.0 < x + w && p.1 > y && p.1 < y + h;
    let strip = |p: &(f64, f64)| p.0 >= x && p.0 <= x + 12.0 + 34.0 && p.1 >= y && p.1 <= y + h;
    let palette: Vec<String> = (0..10)
        .map(|k| {
            let c = fibresim::plot::slot_colour(k);
            format!("#{:02X}{:02X}{:02X}", c[0], c[1], c[2])
        })
        .collect();
    for colour in &palette {
        for line in polylines(svg, colour) {
            if line.iter().all(strip) {
                continue; // a legend sample
            }
            for seg in line.windows(2) {
                let (a, b) = (seg[0], seg[1]);
                let k = ((b.0 - a.0).hypot(b.1 - a.1) / 2.0).ceil().max(1.0) as usize;
                for i in 0..=k {
                    let t = i as f64 / k as f64;
                    let p = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                    assert!(
                        !inside(p),
                        "{what}: {colour} data at {p:?} under the legend {x} {y} {w} {h}"
                    );
                }
            }
        }
    }
}

/// Four lines with markers through all four corners of the frame (no free
/// corner for a legend), labelled `label 0` … `label 3`.
fn corner_lines(title: &str, label: &str) -> Chart {
    let x: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
    let mut chart = Chart::new(title, "x (m)", "y (m)");
    for (k, f) in [|v: f64| v, |v: f64| 1.0 - v, |_| 0.98, |_| 0.02]
        .iter()
        .enumerate()
    {
        chart.series.push(Series::new(
            format!("{label} {k}"),
            x.clone(),
            x.iter().map(|&v| f(v)).collect(),
            Style::LineMarkers,
        ));
    }
    chart
}

/// the legend goes to a free corner, else outside the
/// plot, never over data; with data in every corner it is outside, right
/// of the frame.
#[test]
fn legends_cover_no_data() {
    let p = out("legend_conv.svg");
    render(&convergence_chart(), &p).unwrap();
    assert_legend_covers_no_data(&std::fs::read_to_string(&p).unwrap(), "convergence chart");
    let p = out("legend_corners.svg");
    render(&corner_lines("corners", "line"), &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    assert_legend_covers_no_data(&svg, "corners");
    let y_axis_x = polylines(&svg, "#000000")
        .into_iter()
        .filter(|p| p.len() == 2 && p[0].1 == p[1].1)
        .map(|p| p[0].0.max(p[1].0))
        .fold(0.0, f64::max);
    let (lx, ..) = legend_rect(&svg).unwrap();
    assert!(
        lx > y_axis_x,
        "legend at x = {lx}, frame ends at {y_axis_x}"
    );
}

/// A long title over a chart whose legend sits outside (data in every
/// corner) is centred on the canvas and wholly on it: plotters' caption
/// centred it on the area left of the legend, and the convergence figure of
/// docs/studies.md lost its first letters off the left edge.
#[test]
fn long_title_stays_on_the_canvas_beside_an_outside_legend() {
    let chart = corner_lines(
        "torque_fibre.toml: Eq. 66-67 angle error vs time step (T = 0.1 s)",
        "a long legend entry",
    );
    let svg_path = out("long_title.svg");
    render(&chart, &svg_path).unwrap();
    let svg = std::fs::read_to_string(&svg_path).unwrap();
    let (lx, ..) = legend_rect(&svg).expect("a legend");
    assert!(lx > 600.0, "legend outside, right of the frame: x = {lx}");
    let p = out("long_title.png");
    render(&chart, &p).unwrap();
    let img = Image::read(&p);
    let frame = img.frame();
    // Dark (text) pixels above the frame, left of the legend's top edge.
    let dark: Vec<u32> = (0..frame.top.saturating_sub(5))
        .flat_map(|y| (0..img.w).map(move |x| (x, y)))
        .filter(|&(x, y)| img.at(x, y).iter().all(|&c| c < 110))
        .map(|(x, _)| x)
        .collect();
    let (lo, hi) = (*dark.iter().min().unwrap(), *dark.iter().max().unwrap());
    assert!(
        lo >= 5 && hi + 5 <= img.w,
        "title spans x = {lo}..{hi} of {}",
        img.w
    );
    let centre = f64::from(lo + hi) / 2.0;
    assert!(
        (centre - f64::from(img.w) / 2.0).abs() < 15.0,
        "title centred at {centre}, canvas at {}",
        img.w / 2
    );
}

/// a series equal to an earlier one is dashed over it
/// and its legend says `(= …)`; one within a pixel says `(≈ …)`.
#[test]
fn coincident_series_are_told_apart() {
    let x: Vec<f64> = (0..200).map(|i| i as f64).collect();
    let a: Vec<f64> = x.iter().map(|v| (v / 30.0).sin()).collect();
    let near: Vec<f64> = a.iter().map(|v| v + 1e-6).collect();
    let other: Vec<f64> = a.iter().map(|v| v + 0.5).collect();
    let chart = Chart {
        series: vec![
            Series::new("euler", x.clone(), a.clone(), Style::Line),
            Series::new("scalar", x.clone(), a, Style::Line),
            Series::new("direct", x.clone(), near, Style::Line),
            Series::new("pcdm", x, other, Style::Line),
        ],
        ..Chart::new("twins", "t (s)", "error (rad)")
    };
    let p = out("twins.svg");
    render(&chart, &p).unwrap();
    let svg = std::fs::read_to_string(&p).unwrap();
    let text = |t: &str| svg.lines().any(|l| l.trim() == t);
    assert!(text("scalar (= euler)"), "scalar's entry");
    assert!(
        text("direct (≈ scalar)") || text("direct (≈ euler)"),
        "direct's entry"
    );
    assert!(text("pcdm") && text("euler"));
    // euler: one polyline; scalar (vermillion) and direct (green): dashes.
    let count = |c: &str| {
        polylines(&svg, c)
            .into_iter()
            .filter(|l| l.len() >= 2)
            .count()
    };
    assert_eq!(count("#0072B2"), 2, "euler's line and legend sample");
    assert!(
        count("#D55E00") > 20 && count("#009E73") > 20,
        "dashed twins"
    );
    assert_eq!(count("#CC79A7"), 2, "pcdm's line and legend sample");
}

/// `#RRGGBB` of rotator `name`'s colour: its place in the rotator list.
fn rotator_colour(name: &str) -> String {
    let k = fibresim::integrate::rotate::RotatorKind::SELECTABLE
        .iter()
        .position(|r| r.name() == name)
        .unwrap();
    let c = fibresim::plot::slot_colour(k);
    format!("#{:02X}{:02X}{:02X}", c[0], c[1], c[2])
}

fn run_ok(args: &[&str]) {
    let o = fibresim(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// a rotator has one colour in every figure, whatever
/// else is in it: pcdm alone is drawn in pcdm's colour, not in the first
/// palette colour (euler's), in `compare`, `converge`, `plot` and the
/// stress map (its row marker).
#[test]
fn one_colour_per_rotator_in_every_figure() {
    let dir = tempfile::tempdir().unwrap();
    let d = |s: &str| dir.path().join(s).display().to_string();
    let (pcdm, euler) = (rotator_colour("pcdm"), rotator_colour("euler"));
    assert_ne!(pcdm, euler);
    let svg = |p: String| std::fs::read_to_string(p).unwrap();
    let drawn = |svg: &str, c: &str| polylines(svg, c).iter().any(|l| l.len() > 2);
    for rotators in ["pcdm", "euler,pcdm", "rk4,pcdm,euler"] {
        let o = d(&format!("cmp_{rotators}"));
        run_ok(&[
            "compare",
            "scenarios/torque_sphere.toml",
            "--rotators",
            rotators,
            "--t-end",
            "0.05",
            "-q",
            "--out",
            &o,
        ]);
        let s = svg(format!("{o}/angle_error_closed_form.svg"));
        assert!(drawn(&s, &pcdm), "compare {rotators}: pcdm in {pcdm}");
        assert_eq!(
            drawn(&s, &euler),
            rotators.contains("euler"),
            "compare {rotators}"
        );
        // plot of the runs of that compare: labelled by their folder.
        let p = d(&format!("plot_{rotators}.svg"));
        let files: Vec<String> = rotators
            .split(',')
            .map(|r| format!("{o}/{r}/orientation.csv"))
            .collect();
        let mut args = vec!["plot"];
        args.extend(files.iter().map(String::as_str));
        args.extend(["-o", &p]);
        run_ok(&args);
        let s = svg(p);
        assert!(drawn(&s, &pcdm), "plot {rotators}");
        assert_eq!(
            drawn(&s, &euler),
            rotators.contains("euler"),
            "plot {rotators}"
        );
    }
    let o = d("conv");
    run_ok(&[
        "converge",
        "scenarios/torque_sphere.toml",
        "--rotators",
        "rk4,pcdm",
        "--points",
        "3",
        "-q",
        "--out",
        &o,
    ]);
    let s = svg(format!("{o}/convergence.svg"));
    assert!(drawn(&s, &pcdm) && drawn(&s, &rotator_colour("rk4")) && !drawn(&s, &euler));
    let o = d("stress");
    run_ok(&[
        "stress",
        "--cases",
        "spin",
        "--rotators",
        "pcdm",
        "--factors",
        "1",
        "-q",
        "--out",
        &o,
    ]);
    let s = svg(format!("{o}/stability_map.svg"));
    assert!(
        !polylines(&s, &pcdm).is_empty(),
        "stress map: pcdm's row marker"
    );
    assert!(polylines(&s, &euler).is_empty(), "stress map");
}

/// `plot --signed` shows gain and loss; the default is
/// the absolute error, and each figure's title says which.
#[test]
fn signed_energy_error() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("energy.csv");
    // E = 1, 1.1, 0.9 J: +10 % and −10 %; the files hold |E − E₀|/|E₀|.
    std::fs::write(
        &csv,
        "step,t,e_total,e_elastic,energy_error_pct,energy_error_full_pct,energy_error_window_max_pct\n\
         0,0,1,0,0,0,0\n1,0.1,1.1,0,10,10,10\n2,0.2,0.9,0,10,10,10\n",
    )
    .unwrap();
    let c = csv.to_str().unwrap();
    let (abs, signed) = (dir.path().join("abs.svg"), dir.path().join("signed.svg"));
    run_ok(&["plot", c, "-o", abs.to_str().unwrap()]);
    run_ok(&["plot", c, "--signed", "-o", signed.to_str().unwrap()]);
    let (a, s) = (
        std::fs::read_to_string(&abs).unwrap(),
        std::fs::read_to_string(&signed).unwrap(),
    );
    assert!(a.contains("(absolute: |E − E₀|/|E₀|)"), "absolute title");
    assert!(s.contains("(signed: above 0 is a gain)"), "signed title");
    let ticks = |svg: &str| -> Vec<f64> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| t.split('>').nth(1)?.split('<').next()?.trim().parse().ok())
            .collect()
    };
    let (ta, ts) = (ticks(&a), ticks(&s));
    assert!(ta.iter().all(|&v| v >= 0.0) && ta.contains(&10.0), "{ta:?}");
    assert!(ts.contains(&-10.0) && ts.contains(&10.0), "{ts:?}");
    let o = fibresim(&[
        "plot",
        c,
        "--signed",
        "--column",
        "energy_error_window_max_pct",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--signed"));
}

/// every CSV file `plot --help` names plots with its
/// defaults, and the help names every CSV file the commands write.
#[test]
fn every_file_plot_help_names_is_plottable() {
    let help = String::from_utf8(fibresim(&["plot", "--help"]).stdout).unwrap();
    let named: std::collections::BTreeSet<String> = help
        .split(|c: char| c.is_whitespace() || c == ',' || c == ':' || c == '(' || c == ')')
        .filter(|w| w.ends_with(".csv"))
        .map(str::to_string)
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let d = |s: &str| dir.path().join(s).display().to_string();
    run_ok(&[
        "run",
        "scenarios/torque_fibre.toml",
        "--t-end",
        "0.001",
        "-q",
        "--out",
        &d("run"),
    ]);
    run_ok(&[
        "run",
        "scenarios/single_fibre.toml",
        "--t-end",
        "1e-4",
        "-q",
        "--out",
        &d("contact"),
    ]);
    run_ok(&[
        "compare",
        "scenarios/torque_sphere.toml",
        "--t-end",
        "0.05",
        "-q",
        "--out",
        &d("compare"),
    ]);
    run_ok(&[
        "converge",
        "scenarios/torque_sphere.toml",
        "--rotators",
        "pcdm,euler",
        "--points",
        "3",
        "-q",
        "--out",
        &d("converge"),
    ]);
    run_ok(&[
        "stress",
        "--cases",
        "spin",
        "--factors",
        "1,2",
        "--rotators",
        "pcdm",
        "-q",
        "--out",
        &d("stress"),
    ]);
    let mut written = std::collections::BTreeSet::new();
    let mut plotted = 0;
    for sub in [
        "run",
        "contact",
        "compare",
        "compare/pcdm",
        "converge",
        "stress",
    ] {
        for e in std::fs::read_dir(d(sub)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_none_or(|x| x != "csv") {
                continue;
            }
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            assert!(
                named.contains(&name),
                "plot --help does not name {name}: {named:?}"
            );
            written.insert(name);
            let fig = p.with_extension("svg");
            let o = fibresim(&["plot", p.to_str().unwrap(), "-o", fig.to_str().unwrap()]);
            assert!(
                o.status.success(),
                "{}: {}",
                p.display(),
                String::from_utf8_lossy(&o.stderr)
            );
            let svg = std::fs::read_to_string(&fig).unwrap();
            assert!(
                !svg.contains("no finite data"),
                "{}: nothing drawn",
                p.display()
            );
            plotted += 1;
        }
    }
    assert_eq!(written, named, "the files written are the files named");
    assert!(plotted >= 9, "{plotted}");
}

/// A table with a `series` column (the bed scaling figure's) is plotted one
/// series per value, each named in the legend (without the column, one
/// series named after the file's folder).
#[test]
fn series_column_makes_one_series_each() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("scaling.csv");
    std::fs::write(
        &csv,
        "series,fibres,fibre_steps_per_s\nours 1 thread,1000,3e5\npeer A,10000,1.2e6\n\
         ours 1 thread,10000,2.9e5\npeer A,100000,1.1e6\n",
    )
    .unwrap();
    let svg = dir.path().join("s.svg");
    run_ok(&[
        "plot",
        csv.to_str().unwrap(),
        "--x",
        "fibres",
        "--column",
        "fibre_steps_per_s",
        "-o",
        svg.to_str().unwrap(),
    ]);
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.contains("ours 1 thread") && s.contains("peer A"), "{s}");
}
