//! One picture of a frame: the box's back edges, the fibres back to front,
//! the front edges, a title line and the colour bar with its unit.

use super::camera::Camera;
use super::field::{ColourScale, Field, PALETTE};
use super::frame::Frame;
use super::{draw, text};
use tiny_skia::{
    Color, GradientStop, LinearGradient, Paint, Pixmap, Point, Rect, SpreadMode, Transform,
};

/// Pixels kept free on the right for the colour bar, and on top for the title.
pub(crate) const BAR_MARGIN: f64 = 150.0;
/// (See [`BAR_MARGIN`].)
pub(crate) const TITLE_MARGIN: f64 = 40.0;

/// What every picture of one render shares.
pub(crate) struct Look {
    pub camera: Camera,
    pub scale: ColourScale,
    pub capsule: bool,
    pub width: u32,
    pub height: u32,
    /// Draw the fibres in bands on the thread pool (a still), or in one
    /// pass (frames of an animation, themselves drawn in parallel).
    pub bands: bool,
}

/// The drawing area of a `width` × `height` picture (x, y, w, h).
pub(crate) fn area(width: u32, height: u32) -> [f64; 4] {
    [
        10.0,
        TITLE_MARGIN,
        (width as f64 - BAR_MARGIN - 10.0).max(10.0),
        (height as f64 - TITLE_MARGIN - 10.0).max(10.0),
    ]
}

/// Draw `frame` as `look` says.
pub(crate) fn picture(frame: &Frame, look: &Look) -> Pixmap {
    let mut pm = Pixmap::new(look.width, look.height).expect("a non-empty picture");
    pm.fill(Color::WHITE);
    let cam = &look.camera;
    if let Some(w) = frame.walls {
        draw::box_edges(&mut pm, cam, w, true);
    }
    // Back to front by the depth of the centre; ties by index (deterministic).
    let mut order: Vec<(f64, u32)> = frame
        .fibres
        .iter()
        .enumerate()
        .map(|(i, f)| (cam.project(f.centre).2, i as u32))
        .collect();
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    fibres(&mut pm, frame, look, &order);
    if let Some(w) = frame.walls {
        draw::box_edges(&mut pm, cam, w, false);
    }
    let font = text::font();
    let title = format!(
        "t = {} s    step {}    {}",
        short(frame.t),
        frame.step,
        census(frame)
    );
    text::draw(&mut pm, &font, 18.0, (12.0, 26.0), &title, [30, 30, 30]);
    match look.scale.field {
        Field::None => {}
        Field::Material => legend(&mut pm, &font, frame),
        _ => bar(&mut pm, &font, &look.scale),
    }
    pm
}

/// Rows of one band of the fibre pass. Bands are drawn in parallel, each
/// with every fibre that reaches it, back to front; a fixed height, so the
/// picture's bytes do not depend on the thread count.
const BAND_ROWS: usize = 128;
/// Rows drawn above and below a band and then dropped: tiny-skia's
/// anti-aliasing differs within a few pixels of where a path is clipped, so
/// no kept pixel is near a band's own edge (seams stay invisible).
const BAND_MARGIN: usize = 8;

/// The fibres in `order` (back to front), band by band.
fn fibres(pm: &mut Pixmap, frame: &Frame, look: &Look, order: &[(f64, u32)]) {
    use rayon::prelude::*;
    let cam = &look.camera;
    // Each fibre's screen rows: its end points ± its radius, plus 2 px for
    // the rim (0.8 px) and anti-aliasing.
    let spans: Vec<(f64, f64, u32)> = order
        .iter()
        .map(|&(_, i)| {
            let f = &frame.fibres[i as usize];
            let h = 0.5 * f.length * f.axis;
            let (y1, y2) = (cam.project(f.centre - h).1, cam.project(f.centre + h).1);
            let r = 0.5 * f.diameter * cam.scale + 2.0;
            (y1.min(y2) - r, y1.max(y2) + r, i)
        })
        .collect();
    let (width, height) = (pm.width() as usize, pm.height() as usize);
    let row = 4 * width;
    let (rows_per_band, margin) = if look.bands {
        (BAND_ROWS, BAND_MARGIN)
    } else {
        (height, 0)
    };
    let background: &Pixmap = pm;
    let bands: Vec<(usize, Vec<u8>)> = (0..height.div_ceil(rows_per_band))
        .into_par_iter()
        .map(|k| {
            let top = (k * rows_per_band).saturating_sub(margin);
            let bottom = ((k + 1) * rows_per_band + margin).min(height);
            let mut rows = background.data()[top * row..bottom * row].to_vec();
            let mut band =
                tiny_skia::PixmapMut::from_bytes(&mut rows, width as u32, (bottom - top) as u32)
                    .expect("a band of the picture");
            let mut cam = *cam;
            cam.origin.1 -= top as f64;
            for &(y0, y1, i) in &spans {
                if y1 >= top as f64 && y0 <= bottom as f64 {
                    let f = &frame.fibres[i as usize];
                    draw::fibre(&mut band, &cam, f, look.scale.colour(f), look.capsule);
                }
            }
            let keep = k * rows_per_band - top..((k + 1) * rows_per_band).min(height) - top;
            (k, rows[keep.start * row..keep.end * row].to_vec())
        })
        .collect();
    let data = pm.data_mut();
    for (k, rows) in bands {
        let at = k * rows_per_band * row;
        data[at..at + rows.len()].copy_from_slice(&rows);
    }
}

/// A number with at most 6 significant digits, without trailing zeros.
fn short(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if x.abs() >= 1e-3 && x.abs() < 1e5 {
        let s = format!(
            "{:.*}",
            (5 - x.abs().log10().floor() as i32).max(0) as usize,
            x
        );
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        return s;
    }
    format!("{x:.4e}")
}

/// Tick values: about 5 round numbers inside [lo, hi].
fn ticks(lo: f64, hi: f64, integer: bool) -> Vec<f64> {
    let span = hi - lo;
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let mut step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.0)
        .unwrap_or(10.0 * mag);
    if integer {
        step = step.max(1.0).round();
    }
    let first = (lo / step).ceil();
    (0..)
        .map(|k| (first + k as f64) * step)
        .take_while(|&v| v <= hi + 1e-9 * span)
        .take(12)
        .collect()
}

/// The colour bar of a numeric field: viridis from lo (bottom) to hi.
fn bar(pm: &mut Pixmap, font: &ab_glyph::FontRef, s: &ColourScale) {
    let (w, h) = (pm.width() as f32, pm.height() as f32);
    let (x, top, bw) = (w - BAR_MARGIN as f32 + 25.0, 70.0f32, 22.0f32);
    let bottom = (h - 40.0).max(top + 20.0);
    let stops = (0..=8)
        .map(|k| {
            // Stops ascend from the top (hi) to the bottom (lo).
            let c = super::field::viridis(1.0 - k as f64 / 8.0);
            GradientStop::new(k as f32 / 8.0, Color::from_rgba8(c[0], c[1], c[2], 255))
        })
        .collect();
    if let (Some(shader), Some(rect)) = (
        LinearGradient::new(
            Point::from_xy(x, top),
            Point::from_xy(x, bottom),
            stops,
            SpreadMode::Pad,
            Transform::identity(),
        ),
        Rect::from_ltrb(x, top, x + bw, bottom),
    ) {
        let paint = Paint {
            shader,
            ..Paint::default()
        };
        pm.fill_rect(rect, &paint, Transform::identity(), None);
    }
    let title = s.field.label();
    let tw = text::width(font, 15.0, title);
    let tx = (x + 0.5 * bw - 0.5 * tw)
        .min(w - tw - 4.0)
        .max(w - BAR_MARGIN as f32);
    text::draw(pm, font, 15.0, (tx, top - 14.0), title, [30, 30, 30]);
    let integer = s.field.integer();
    for v in ticks(s.lo, s.hi, integer) {
        let y = bottom - ((v - s.lo) / (s.hi - s.lo)) as f32 * (bottom - top);
        let mut paint = Paint::default();
        paint.set_color(Color::from_rgba8(30, 30, 30, 255));
        if let Some(r) = Rect::from_xywh(x + bw, y - 0.5, 5.0, 1.0) {
            pm.fill_rect(r, &paint, Transform::identity(), None);
        }
        let label = if integer {
            format!("{}", v.round() as i64)
        } else {
            short(v)
        };
        text::draw(
            pm,
            font,
            13.0,
            (x + bw + 8.0, y + 5.0),
            &label,
            [30, 30, 30],
        );
    }
}

/// The material swatches with their names.
fn legend(pm: &mut Pixmap, font: &ab_glyph::FontRef, frame: &Frame) {
    let x = pm.width() as f32 - BAR_MARGIN as f32 + 15.0;
    text::draw(pm, font, 15.0, (x, 56.0), "material", [30, 30, 30]);
    for (k, name) in frame.materials.iter().enumerate().take(20) {
        let y = 70.0 + 22.0 * k as f32;
        let c = PALETTE[k % PALETTE.len()];
        let mut paint = Paint::default();
        paint.set_color(Color::from_rgba8(c[0], c[1], c[2], 255));
        if let Some(r) = Rect::from_xywh(x, y, 16.0, 16.0) {
            pm.fill_rect(r, &paint, Transform::identity(), None);
        }
        text::draw(pm, font, 13.0, (x + 22.0, y + 13.0), name, [30, 30, 30]);
    }
}

/// What the frame holds (a sphere is a body of zero length).
fn census(frame: &Frame) -> String {
    let spheres = frame.fibres.iter().filter(|f| f.length == 0.0).count();
    crate::fmt::census(frame.fibres.len() - spheres, spheres)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: the ticks a person would choose for these ranges.
    #[test]
    fn ticks_are_round_numbers_inside_the_range() {
        let labels: Vec<String> = ticks(0.0, 1.0, false).into_iter().map(short).collect();
        assert_eq!(labels, ["0", "0.2", "0.4", "0.6", "0.8", "1"]);
        assert_eq!(ticks(0.0, 3.0, true), vec![0.0, 1.0, 2.0, 3.0]);
        assert_eq!(short(0.5), "0.5");
        assert_eq!(short(1.2345678), "1.23457");
    }

    /// The title counts fibres and spheres (a body of zero length) apart.
    #[test]
    fn the_title_names_fibres_and_spheres() {
        let body = |length| crate::render::frame::Fibre {
            centre: glam::DVec3::ZERO,
            axis: glam::DVec3::X,
            diameter: 0.01,
            length,
            velocity: glam::DVec3::ZERO,
            omega: glam::DVec3::ZERO,
            kinetic_energy: 0.0,
            contacts: 0,
            material: 0,
            id: 0,
        };
        let frame = |bodies: Vec<f64>| Frame {
            step: 0,
            t: 0.0,
            fibres: bodies.into_iter().map(body).collect(),
            walls: None,
            materials: vec![],
        };
        assert_eq!(census(&frame(vec![0.03])), "1 fibre");
        assert_eq!(census(&frame(vec![0.0, 0.0])), "2 spheres");
        assert_eq!(
            census(&frame(vec![0.03, 0.03, 0.0])),
            "2 fibres and 1 sphere"
        );
        assert_eq!(census(&frame(vec![])), "0 fibres");
    }
}
