//! How series are told apart: palette colours, dash patterns and marker shapes.

use plotters::style::RGBColor;

/// Okabe–Ito colour-blind-friendly palette, with brown and wine added so
/// that ten series (every rotator) get their own colour; yellow last (weak
/// on white).
pub(super) const PALETTE: [RGBColor; 10] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x8C, 0x56, 0x4B), // brown
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0x88, 0x22, 0x55), // wine
    RGBColor(0xF0, 0xE4, 0x42), // yellow
];

/// The RGB colour of palette slot `slot` (cycled).
pub fn slot_colour(slot: usize) -> [u8; 3] {
    let c = PALETTE[slot % PALETTE.len()];
    [c.0, c.1, c.2]
}

/// Dash length and gap (pixels) of the k-th slope guide of a chart, cycled.
pub const GUIDE_DASHES: [(u32, u32); 3] = [(10, 6), (2, 5), (22, 6)];
/// Dash length and gap of [`Style::Dashed`](super::Style::Dashed).
pub(super) const DASH: (u32, u32) = (10, 6);
/// Dash patterns of lines drawn over an identical earlier line: the first,
/// second, third such line over the same one (their dashes fall in
/// different places, so each shows).
pub(super) const TWIN_DASHES: [(u32, u32); 3] = [(10, 6), (4, 12), (16, 10)];

/// Horizontal dash segments `[start, end)` covering `0..len` px with `dash`.
pub(super) fn dash_segments(len: i32, dash: (u32, u32)) -> Vec<(i32, i32)> {
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

/// Outline of a [`Style::Published`](super::Style::Published) marker, pixels around the point.
pub(super) const PUBLISHED_DIAMOND: [(i32, i32); 5] = [(0, -9), (8, 0), (0, 9), (-8, 0), (0, -9)];

/// Number of distinct marker shapes of [`Style::LineMarkers`](super::Style::LineMarkers).
pub const MARKER_SHAPES: usize = 7;

/// The outline of marker `shape` around the origin, in pixels (closed
/// paths; the × and + are two strokes each, returned as two paths).
pub(super) fn marker_paths(shape: usize) -> Vec<Vec<(i32, i32)>> {
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
