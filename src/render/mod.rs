//! `fibresim render`: a quick look with no other software. Draws a frame
//! (a VTK frame, a trajectory step, a checkpoint or a scenario's start) as a
//! PNG, or every frame of a run as a GIF: fibres as shaded cylinders or
//! capsules in depth order, an orthographic camera fitted to the box, the
//! box edges, a colour bar with its unit. tiny-skia rasterises, `png` and
//! `gif` encode.

pub mod camera;
mod draw;
pub mod field;
pub mod frame;
mod picture;
pub mod source;
mod text;

pub use camera::{view_direction, Camera};
pub use field::{ColourScale, Field};
pub use frame::{Fibre, Frame};
pub use source::Source;

use crate::error::{Error, Result};
use glam::DVec3;
use std::path::{Path, PathBuf};

/// How to draw.
#[derive(Debug, Clone)]
pub struct RenderOptions {
    /// Colour field.
    pub field: Field,
    /// Colour range; `None`: the data's (over every frame drawn).
    pub range: Option<(f64, f64)>,
    /// Unit vector from the scene toward the camera.
    pub view: DVec3,
    /// Zoom factor (1: fit).
    pub zoom: f64,
    /// Picture size, pixels.
    pub width: u32,
    /// (See `width`.)
    pub height: u32,
    /// Capsules instead of flat-ended cylinders.
    pub capsule: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            field: Field::Speed,
            range: None,
            view: view_direction("iso").expect("a named view"),
            zoom: 1.0,
            width: 1000,
            height: 800,
            capsule: false,
        }
    }
}

/// The bounds the camera fits: the box, else every fibre's ends.
fn bounds<'a>(frames: impl Iterator<Item = &'a Frame>) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for f in frames {
        if let Some((a, b)) = f.walls {
            return (a, b);
        }
        for b in &f.fibres {
            let h = 0.5 * b.length * b.axis;
            let r = DVec3::splat(0.5 * b.diameter);
            lo = lo.min(b.centre - h - r).min(b.centre + h - r);
            hi = hi.max(b.centre - h + r).max(b.centre + h + r);
        }
    }
    if lo.x > hi.x {
        return (DVec3::ZERO, DVec3::ONE);
    }
    (lo, hi)
}

/// The camera and the colour scale shared by the pictures of `frames`.
fn look(frames: &[&Frame], o: &RenderOptions, bands: bool) -> picture::Look {
    let area = picture::area(o.width, o.height);
    let camera = Camera::fit(o.view, bounds(frames.iter().copied()), area, o.zoom);
    let scale = match o.range {
        Some((lo, hi)) => ColourScale {
            field: o.field,
            lo,
            hi,
        },
        None => ColourScale::fit(o.field, frames.iter().flat_map(|f| &f.fibres)),
    };
    picture::Look {
        camera,
        scale,
        capsule: o.capsule,
        width: o.width,
        height: o.height,
        bands,
    }
}

/// The RGBA pixels of `frame` drawn with `o` (its own camera and range).
pub fn draw_frame(frame: &Frame, o: &RenderOptions) -> tiny_skia::Pixmap {
    picture::picture(frame, &look(&[frame], o, true))
}

/// Opaque RGB bytes of a picture (drawn on white: premultiplied = straight).
fn rgb(pm: &tiny_skia::Pixmap) -> Vec<u8> {
    pm.data()
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// Write a picture as PNG.
pub fn write_png(pm: &tiny_skia::Pixmap, path: &Path) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), pm.width(), pm.height());
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let io = |e: png::EncodingError| Error::io(path, std::io::Error::other(e.to_string()));
    let mut w = enc.write_header().map_err(io)?;
    w.write_image_data(&rgb(pm)).map_err(io)?;
    w.finish().map_err(io)
}

/// Draw frame `k` of `source` (for a still: the step asked for, else the last).
pub fn still(source: &Source, step: Option<u64>, o: &RenderOptions, out: &Path) -> Result<Frame> {
    let frame = match step {
        None => source.frame(source.len() - 1)?,
        Some(s) => {
            let mut found = None;
            for k in 0..source.len() {
                let f = source.frame(k)?;
                if f.step == s {
                    found = Some(f);
                    break;
                }
            }
            found.ok_or_else(|| {
                Error::bad(
                    "command line",
                    "--step",
                    format!("no frame at step {s}; give a step the input holds"),
                )
            })?
        }
    };
    write_png(&draw_frame(&frame, o), out)?;
    Ok(frame)
}

/// NeuQuant sampling factor of the GIF palettes (1 best … 30 fastest).
const GIF_SPEED: i32 = 10;

/// Animate every frame of `source` into a GIF at `fps`, one camera and one
/// colour range for all (the data's over every frame unless `o.range`).
pub fn animate(source: &Source, o: &RenderOptions, fps: f64, out: &Path) -> Result<usize> {
    let n = source.len();
    // Read the frames once for the shared range and bounds; then draw.
    let frames = (0..n)
        .map(|k| source.frame(k))
        .collect::<Result<Vec<_>>>()?;
    let refs: Vec<&Frame> = frames.iter().collect();
    // The frames are drawn in parallel already: each in one band.
    let look = look(&refs, o, false);
    let file = std::fs::File::create(out).map_err(|e| Error::io(out, e))?;
    let io = |e: gif::EncodingError| Error::io(out, std::io::Error::other(e.to_string()));
    let (w, h) = (o.width as u16, o.height as u16);
    let mut enc = gif::Encoder::new(std::io::BufWriter::new(file), w, h, &[]).map_err(io)?;
    enc.set_repeat(gif::Repeat::Infinite).map_err(io)?;
    let delay = (100.0 / fps).round().clamp(2.0, 6000.0) as u16;
    // Drawing and palette quantisation in parallel, a few frames at a time
    // (each is a pure function of its frame); written in order.
    use rayon::prelude::*;
    for chunk in frames.chunks(2 * rayon::current_num_threads().max(1)) {
        let encoded: Vec<gif::Frame> = chunk
            .par_iter()
            .map(|f| {
                let pm = picture::picture(f, &look);
                let mut gf = gif::Frame::from_rgb_speed(w, h, &rgb(&pm), GIF_SPEED);
                gf.delay = delay;
                gf
            })
            .collect();
        for gf in &encoded {
            enc.write_frame(gf).map_err(io)?;
        }
    }
    Ok(n)
}

/// The default output beside `input`: `<stem>.png` or `<stem>.gif`.
pub fn default_output(input: &Path, gif: bool) -> PathBuf {
    let stem = input
        .file_stem()
        .map_or("render".into(), |s| s.to_string_lossy().into_owned());
    input.with_file_name(format!("{stem}.{}", if gif { "gif" } else { "png" }))
}
