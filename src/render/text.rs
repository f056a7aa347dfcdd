//! Text on a pixmap with the bundled DejaVu Sans (`assets/`), rasterised by
//! ab_glyph: the title line and the colour bar's labels.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use tiny_skia::Pixmap;

static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The bundled font.
pub(crate) fn font() -> FontRef<'static> {
    FontRef::try_from_slice(FONT_BYTES).expect("the bundled DejaVu Sans parses")
}

/// Width of `text` at `size` px.
pub(crate) fn width(font: &FontRef, size: f32, text: &str) -> f32 {
    let f = font.as_scaled(PxScale::from(size));
    let mut w = 0.0;
    let mut prev = None;
    for ch in text.chars() {
        let id = f.glyph_id(ch);
        if let Some(p) = prev {
            w += f.kern(p, id);
        }
        w += f.h_advance(id);
        prev = Some(id);
    }
    w
}

/// Draw `text` with its baseline at `y`, starting at `x`, in `rgb` (over
/// an opaque picture).
pub(crate) fn draw(
    pm: &mut Pixmap,
    font: &FontRef,
    size: f32,
    (x, y): (f32, f32),
    text: &str,
    rgb: [u8; 3],
) {
    let scale = PxScale::from(size);
    let f = font.as_scaled(scale);
    let (w, h) = (pm.width() as i32, pm.height() as i32);
    let pixels = pm.pixels_mut();
    let mut pen = x;
    let mut prev = None;
    for ch in text.chars() {
        let id = f.glyph_id(ch);
        if let Some(p) = prev {
            pen += f.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scale, ab_glyph::point(pen, y));
        pen += f.h_advance(id);
        prev = Some(id);
        let Some(og) = font.outline_glyph(glyph) else {
            continue;
        };
        let b = og.px_bounds();
        og.draw(|gx, gy, cov| {
            let (px, py) = (b.min.x as i32 + gx as i32, b.min.y as i32 + gy as i32);
            if px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let p = &mut pixels[(py * w + px) as usize];
            let a = cov.clamp(0.0, 1.0);
            let mix = |old: u8, new: u8| (old as f32 * (1.0 - a) + new as f32 * a).round() as u8;
            *p = tiny_skia::PremultipliedColorU8::from_rgba(
                mix(p.red(), rgb[0]),
                mix(p.green(), rgb[1]),
                mix(p.blue(), rgb[2]),
                255,
            )
            .expect("opaque");
        });
    }
}
