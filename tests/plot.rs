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
    // Uniform noise on [0, 1) fills the frame with both series.
    let img = Image::read(&out("noise_1e5.png"));
    let frame = img.frame();
    for c in [BLUE, VERMILLION] {
        let f = inside(&frame, &img.pixels(c));
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
    // plus 2 strokes of the legend sample.
    let closed = svg
        .split("<polyline")
        .skip(1)
        .map(|e| e.split('>').next().unwrap_or(""))
        .filter(|e| e.contains("stroke=\"#0072B2\"") && e.matches(',').count() == 17)
        .count();
    assert_eq!(closed, 5 + 2, "circle markers");
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
