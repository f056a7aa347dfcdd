//! The canvas: one path from a figure to a PNG or SVG file. A figure draws
//! itself once, generically over plotters' `DrawingBackend`; only the
//! backend and the final write differ between the formats.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
/// The family name the bundled font is registered under.
pub(super) const FONT: &str = "sans-serif";

/// Errors from [`render`](super::render). Every message names the output path.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The path ends neither in `.png` nor in `.svg`.
    #[error("cannot write chart {}: unsupported file extension (expected .png or .svg)", path.display())]
    UnsupportedFormat {
        /// The output path.
        path: PathBuf,
    },
    /// A series has more x than y values, or fewer.
    #[error("cannot plot chart {}: series {index} ({label:?}) has {nx} x values but {ny} y values", path.display())]
    LengthMismatch {
        /// The output path.
        path: PathBuf,
        /// Index of the series in the chart.
        index: usize,
        /// Label of the series.
        label: String,
        /// Number of x values.
        nx: usize,
        /// Number of y values.
        ny: usize,
    },
    /// The bundled font could not be registered.
    #[error("cannot render chart {}: the bundled font could not be loaded", path.display())]
    Font {
        /// The output path.
        path: PathBuf,
    },
    /// plotters failed while drawing.
    #[error("failed to draw chart {}: {message}", path.display())]
    Draw {
        /// The output path.
        path: PathBuf,
        /// plotters' message.
        message: String,
    },
    /// The PNG encoder failed.
    #[error("failed to encode PNG {}: {message}", path.display())]
    Encode {
        /// The output path.
        path: PathBuf,
        /// The encoder's message.
        message: String,
    },
    /// The file could not be written.
    #[error("failed to write chart {}: {source}", path.display())]
    Io {
        /// The output path.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

impl PlotError {
    /// The output path the error is about.
    pub fn path(&self) -> &Path {
        match self {
            PlotError::UnsupportedFormat { path }
            | PlotError::LengthMismatch { path, .. }
            | PlotError::Font { path }
            | PlotError::Draw { path, .. }
            | PlotError::Encode { path, .. }
            | PlotError::Io { path, .. } => path,
        }
    }
}

/// Something that can be drawn on a canvas of its own size.
pub(super) trait Figure {
    /// Canvas size in pixels.
    fn size(&self) -> (u32, u32);

    /// Checks of the input made before any drawing; errors name `path`.
    fn check(&self, _path: &Path) -> Result<(), PlotError> {
        Ok(())
    }

    /// Draw the whole figure on `root` (which covers [`Figure::size`]);
    /// `raster` is true for PNG (plotters' bitmap backend draws lines wider
    /// than 1 px as one polygon per line, which spiky data turns inside out:
    /// plotters issue #549).
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        raster: bool,
    ) -> Result<(), String>;
}

pub(super) enum Format {
    Png,
    Svg,
}

impl Format {
    /// The format named by the extension of `path`, case-insensitive.
    pub(super) fn of(path: &Path) -> Result<Format, PlotError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("svg") => Ok(Format::Svg),
            _ => Err(PlotError::UnsupportedFormat {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// Draw `figure` into `path`, PNG or SVG by the extension. The output is
/// deterministic for a given figure.
pub(super) fn render_figure<F: Figure>(figure: &F, path: &Path) -> Result<(), PlotError> {
    let format = Format::of(path)?;
    figure.check(path)?;
    if !font_registered() {
        return Err(PlotError::Font {
            path: path.to_path_buf(),
        });
    }
    let draw_err = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let (w, h) = figure.size();
    match format {
        Format::Svg => {
            let mut svg = String::new();
            paint(SVGBackend::with_string(&mut svg, (w, h)), figure, false).map_err(draw_err)?;
            std::fs::write(path, svg).map_err(|source| PlotError::Io {
                path: path.to_path_buf(),
                source,
            })
        }
        Format::Png => {
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            paint(BitMapBackend::with_buffer(&mut rgb, (w, h)), figure, true).map_err(draw_err)?;
            write_png(path, &rgb, w, h)
        }
    }
}

/// The one drawing path of every format.
fn paint<DB: DrawingBackend, F: Figure>(
    backend: DB,
    figure: &F,
    raster: bool,
) -> Result<(), String> {
    let root = backend.into_drawing_area();
    figure.draw(&root, raster)?;
    root.present().map_err(err)
}

/// Encode an RGB buffer of `w × h` pixels as PNG at `path`.
fn write_png(path: &Path, rgb: &[u8], w: u32, h: u32) -> Result<(), PlotError> {
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
        writer.write_image_data(rgb).map_err(enc_err)?;
        writer.finish().map_err(enc_err)?;
    }
    out.flush().map_err(io_err)
}

fn font_registered() -> bool {
    static OK: OnceLock<bool> = OnceLock::new();
    *OK.get_or_init(|| register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok())
}

/// A drawing error as text (plotters' errors are generic over the backend).
pub(super) fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}
