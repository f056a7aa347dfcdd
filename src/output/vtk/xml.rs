//! A small writer of VTK XML files (`.vtp`) with appended raw binary data,
//! zlib-compressed in blocks (`vtkZLibDataCompressor`, `header_type="UInt64"`,
//! little endian) from [`COMPRESS_FROM`] bytes of data on, uncompressed
//! below. Why our own: the `vtkio` crate's release (0.6.3) writes
//! neither appended raw data nor `.pvd` collections.
//!
//! Layout of one array in the appended block (VTK's compressed format):
//! `[n_blocks, block_size, last_block_size, c_1 … c_n]` as u64, then the n
//! zlib streams; `last_block_size` is 0 when the last block is full. The
//! `offset` attribute of each `DataArray` counts from the byte after `_`.
//! Blocks are compressed in parallel; the bytes do not depend on the thread
//! count (each block is its own stream, joined in order).

use rayon::prelude::*;
use std::fmt::Write as _;

/// Uncompressed bytes per block (VTK's default).
pub(crate) const BLOCK: usize = 1 << 15;
/// zlib level: 1 is the fastest (`benches/frames.rs` measures a frame).
pub(crate) const LEVEL: u32 = 1;
/// Files with less data than this (bytes, about 250 fibres) are written
/// uncompressed.
pub(crate) const COMPRESS_FROM: usize = 1 << 15;

/// The numbers of one array, borrowed.
pub(crate) enum Data<'a> {
    F32(&'a [f32]),
    F64(&'a [f64]),
    I32(&'a [i32]),
    I64(&'a [i64]),
}

impl Data<'_> {
    fn type_name(&self) -> &'static str {
        match self {
            Data::F32(_) => "Float32",
            Data::F64(_) => "Float64",
            Data::I32(_) => "Int32",
            Data::I64(_) => "Int64",
        }
    }

    /// Little-endian bytes.
    fn bytes(&self) -> Vec<u8> {
        match self {
            Data::F32(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Data::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Data::I32(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Data::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }

    fn len(&self) -> usize {
        match self {
            Data::F32(v) => v.len(),
            Data::F64(v) => v.len(),
            Data::I32(v) => v.len(),
            Data::I64(v) => v.len(),
        }
    }
}

/// One `DataArray`: a name, its component count (and names), its numbers.
pub(crate) struct Array<'a> {
    pub name: &'a str,
    pub components: usize,
    pub component_names: &'a [&'a str],
    pub data: Data<'a>,
}

impl<'a> Array<'a> {
    /// An array of `components`-tuples.
    pub fn new(name: &'a str, components: usize, data: Data<'a>) -> Self {
        Array {
            name,
            components,
            component_names: &[],
            data,
        }
    }

    /// With component names (ParaView shows them instead of 0, 1, 2…).
    pub fn named(mut self, names: &'a [&'a str]) -> Self {
        self.component_names = names;
        self
    }
}

/// The sections of a PolyData piece, in the order VTK's schema wants them.
pub(crate) struct PolyPiece<'a> {
    /// Field data (whole-dataset values: `TimeValue`, …).
    pub field: Vec<Array<'a>>,
    /// Point coordinates, 3 per point.
    pub points: Array<'a>,
    /// Cell data of the lines.
    pub cells: Vec<Array<'a>>,
    /// `connectivity` and `offsets` of the lines.
    pub lines: [Array<'a>; 2],
    /// Number of points.
    pub n_points: usize,
    /// Number of line cells.
    pub n_lines: usize,
}

thread_local! {
    /// One zlib compressor per thread, reset between blocks: a new one
    /// allocates and clears ~300 KB of tables, which for small frames
    /// (test case 2's nine fibres) cost more than the data.
    static ZLIB: std::cell::RefCell<flate2::Compress> =
        std::cell::RefCell::new(flate2::Compress::new(flate2::Compression::new(LEVEL), true));
}

/// One block as a complete zlib stream.
fn zlib(block: &[u8]) -> Vec<u8> {
    ZLIB.with(|z| {
        let mut z = z.borrow_mut();
        z.reset();
        // Stored blocks bound the output: 5 bytes per 16 KiB, header, trailer.
        let mut out = Vec::with_capacity(block.len() + block.len() / 1000 + 64);
        let status = z
            .compress_vec(block, &mut out, flate2::FlushCompress::Finish)
            .expect("compressing into memory");
        assert_eq!(
            status,
            flate2::Status::StreamEnd,
            "the output has room for the stream"
        );
        out
    })
}

/// One array uncompressed: its byte count (u64), then the bytes.
fn plain(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 + bytes.len());
    out.extend((bytes.len() as u64).to_le_bytes());
    out.extend(bytes);
    out
}

/// One array compressed into VTK's block format (header and streams).
fn compress(bytes: &[u8]) -> Vec<u8> {
    let blocks: Vec<Vec<u8>> = if bytes.is_empty() {
        vec![]
    } else if bytes.len() <= BLOCK {
        vec![zlib(bytes)]
    } else {
        bytes.par_chunks(BLOCK).map(zlib).collect()
    };
    let last = (bytes.len() % BLOCK) as u64;
    let mut out =
        Vec::with_capacity(24 + 8 * blocks.len() + blocks.iter().map(Vec::len).sum::<usize>());
    for h in [blocks.len() as u64, BLOCK as u64, last] {
        out.extend(h.to_le_bytes());
    }
    for b in &blocks {
        out.extend((b.len() as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend(b);
    }
    out
}

/// XML-escape an attribute value (names come from our own constants, but a
/// comment may carry a scenario's material names).
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace("--", "- -")
}

/// The whole `.vtp` file of one PolyData piece; `comment` is written as an
/// XML comment under the root (a human note, e.g. the material table).
pub(crate) fn polydata(piece: &PolyPiece, comment: &str) -> Vec<u8> {
    let arrays: Vec<&Array> = piece
        .field
        .iter()
        .chain([&piece.points])
        .chain(&piece.cells)
        .chain(&piece.lines)
        .collect();
    let raw: Vec<Vec<u8>> = arrays.iter().map(|a| a.data.bytes()).collect();
    // Small files stay uncompressed: resetting a zlib compressor clears
    // ~150 KB of tables, more than a few hundred fibres' data costs to write.
    let compressed = raw.iter().map(Vec::len).sum::<usize>() >= COMPRESS_FROM;
    let blobs: Vec<Vec<u8>> = raw
        .iter()
        .map(|b| if compressed { compress(b) } else { plain(b) })
        .collect();
    let mut offsets = Vec::with_capacity(blobs.len());
    let mut at = 0usize;
    for b in &blobs {
        offsets.push(at);
        at += b.len();
    }
    let mut k = 0;
    let mut tag = |x: &mut String, a: &Array, field: bool| {
        let _ = write!(
            x,
            "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"",
            a.data.type_name(),
            a.name,
            a.components
        );
        for (i, c) in a.component_names.iter().enumerate() {
            let _ = write!(x, " ComponentName{i}=\"{c}\"");
        }
        if field {
            let _ = write!(x, " NumberOfTuples=\"{}\"", a.data.len() / a.components);
        }
        let _ = writeln!(x, " format=\"appended\" offset=\"{}\"/>", offsets[k]);
        k += 1;
    };
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\"?>\n");
    x.push_str("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"");
    x.push_str(if compressed {
        " compressor=\"vtkZLibDataCompressor\">\n"
    } else {
        ">\n"
    });
    if !comment.is_empty() {
        let _ = writeln!(x, "<!-- {} -->", escape(comment));
    }
    x.push_str("<PolyData>\n<FieldData>\n");
    for a in &piece.field {
        tag(&mut x, a, true);
    }
    x.push_str("</FieldData>\n");
    let _ = writeln!(
        x,
        "<Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        piece.n_points, piece.n_lines
    );
    x.push_str("<Points>\n");
    tag(&mut x, &piece.points, false);
    x.push_str("</Points>\n<CellData>\n");
    for a in &piece.cells {
        tag(&mut x, a, false);
    }
    x.push_str("</CellData>\n<Lines>\n");
    for a in &piece.lines {
        tag(&mut x, a, false);
    }
    x.push_str("</Lines>\n</Piece>\n</PolyData>\n<AppendedData encoding=\"raw\">\n_");
    let mut out = x.into_bytes();
    out.reserve(at + 32);
    for b in &blobs {
        out.extend(b);
    }
    out.extend(b"\n</AppendedData>\n</VTKFile>\n");
    out
}
