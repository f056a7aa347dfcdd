//! Reading back the VTK files fibresim writes (`fibresim render`, the
//! tests): `.pvd` collections and `.vtp` PolyData with appended raw data,
//! zlib-compressed (`header_type="UInt64"`) or not. Not a general VTK
//! reader: other layouts are refused with a message that says so.

use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The numbers of one array.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// `Float32`.
    F32(Vec<f32>),
    /// `Float64`.
    F64(Vec<f64>),
    /// `Int32`.
    I32(Vec<i32>),
    /// `Int64`.
    I64(Vec<i64>),
}

/// One `DataArray` read back.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadArray {
    /// Its `Name`.
    pub name: String,
    /// `NumberOfComponents`.
    pub components: usize,
    /// `ComponentName0…` if given.
    pub component_names: Vec<String>,
    /// The numbers, flat.
    pub values: Values,
}

impl ReadArray {
    /// Every value as f64 (exact for every type written).
    pub fn to_f64(&self) -> Vec<f64> {
        match &self.values {
            Values::F32(v) => v.iter().map(|&x| x as f64).collect(),
            Values::F64(v) => v.clone(),
            Values::I32(v) => v.iter().map(|&x| x as f64).collect(),
            Values::I64(v) => v.iter().map(|&x| x as f64).collect(),
        }
    }

    /// Number of tuples.
    pub fn tuples(&self) -> usize {
        let n = match &self.values {
            Values::F32(v) => v.len(),
            Values::F64(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::I64(v) => v.len(),
        };
        n / self.components.max(1)
    }
}

/// A PolyData file read back.
#[derive(Debug, Clone, PartialEq)]
pub struct Vtp {
    /// `FieldData` arrays (`TimeValue`, `step`).
    pub field: Vec<ReadArray>,
    /// Point coordinates.
    pub points: ReadArray,
    /// `CellData` arrays.
    pub cells: Vec<ReadArray>,
    /// `connectivity`, `offsets` of the lines.
    pub lines: Vec<ReadArray>,
    /// `NumberOfPoints`.
    pub n_points: usize,
    /// `NumberOfLines`.
    pub n_lines: usize,
}

impl Vtp {
    /// The cell array `name`.
    pub fn cell(&self, name: &str) -> Option<&ReadArray> {
        self.cells.iter().find(|a| a.name == name)
    }

    /// The field array `name`.
    pub fn field(&self, name: &str) -> Option<&ReadArray> {
        self.field.iter().find(|a| a.name == name)
    }
}

fn bad(path: &Path, msg: impl Into<String>) -> Error {
    Error::bad(path.display().to_string(), "<VTK file>", msg)
}

/// `key="value"` attributes of one tag's text.
fn attrs(tag: &str) -> Vec<(String, String)> {
    let mut out = vec![];
    let mut rest = tag;
    while let Some(eq) = rest.find("=\"") {
        let key = rest[..eq]
            .rsplit(|c: char| c.is_whitespace())
            .next()
            .unwrap_or("");
        let after = &rest[eq + 2..];
        let Some(end) = after.find('"') else { break };
        out.push((key.to_string(), after[..end].to_string()));
        rest = &after[end + 1..];
    }
    out
}

fn attr<'a>(a: &'a [(String, String)], key: &str) -> Option<&'a str> {
    a.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// Read a `.vtp` file written by fibresim.
pub fn read_vtp(path: &Path) -> Result<Vtp> {
    let bytes = std::fs::read(path).map_err(|e| {
        bad(
            path,
            format!("cannot read: {e}; give a frame written by `fibresim run --vtk-every N`"),
        )
    })?;
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or_else(|| {
            bad(
                path,
                "has no appended raw data: not a VTK frame written by fibresim",
            )
        })?;
    let head = std::str::from_utf8(&bytes[..at])
        .map_err(|_| bad(path, "the XML before the data is not UTF-8"))?;
    let underscore = bytes[at..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or_else(|| bad(path, "the appended data has no `_` start mark"))?;
    let data = &bytes[at + underscore + 1..];
    let root = head
        .find("<VTKFile")
        .map(|i| &head[i..head[i..].find('>').map_or(head.len(), |j| i + j)])
        .ok_or_else(|| bad(path, "no <VTKFile> root"))?;
    let ra = attrs(root);
    if attr(&ra, "type") != Some("PolyData") || attr(&ra, "byte_order") != Some("LittleEndian") {
        return Err(bad(path, "only little-endian PolyData files are read"));
    }
    let compressed = match attr(&ra, "compressor") {
        None => false,
        Some("vtkZLibDataCompressor") => true,
        Some(c) => {
            return Err(bad(
                path,
                format!("compressor `{c}` is not read; only zlib"),
            ))
        }
    };
    if attr(&ra, "header_type").unwrap_or("UInt32") != "UInt64" {
        return Err(bad(path, "only header_type=\"UInt64\" is read"));
    }
    let piece = head
        .find("<Piece")
        .map(|i| attrs(&head[i..i + head[i..].find('>').unwrap_or(0)]))
        .ok_or_else(|| bad(path, "no <Piece>"))?;
    let count = |k: &str| {
        attr(&piece, k)
            .and_then(|v| v.parse::<usize>().ok())
            .unwrap_or(0)
    };
    let mut vtp = Vtp {
        field: vec![],
        points: ReadArray {
            name: String::new(),
            components: 3,
            component_names: vec![],
            values: Values::F64(vec![]),
        },
        cells: vec![],
        lines: vec![],
        n_points: count("NumberOfPoints"),
        n_lines: count("NumberOfLines"),
    };
    // Walk the tags in order; the open section decides where an array goes.
    let mut section = "";
    for tag in head.split('<').skip(1) {
        let tag = tag.split('>').next().unwrap_or("");
        let name = tag.split_whitespace().next().unwrap_or("");
        match name {
            "FieldData" | "Points" | "CellData" | "PointData" | "Lines" | "Verts" | "Polys"
            | "Strips" => section = name,
            "DataArray" => {
                let a = attrs(tag);
                let array = read_array(path, &a, data, compressed)?;
                match section {
                    "FieldData" => vtp.field.push(array),
                    "Points" => vtp.points = array,
                    "CellData" => vtp.cells.push(array),
                    "Lines" => vtp.lines.push(array),
                    _ => {}
                }
            }
            _ => {}
        }
    }
    Ok(vtp)
}

fn u64_at(b: &[u8], k: usize) -> Option<u64> {
    b.get(8 * k..8 * k + 8)
        .map(|s| u64::from_le_bytes(s.try_into().expect("8 bytes")))
}

fn read_array(
    path: &Path,
    a: &[(String, String)],
    data: &[u8],
    compressed: bool,
) -> Result<ReadArray> {
    let name = attr(a, "Name").unwrap_or("").to_string();
    let broken = |what: &str| bad(path, format!("array `{name}`: {what}"));
    if attr(a, "format") != Some("appended") {
        return Err(broken("only format=\"appended\" is read"));
    }
    let offset: usize = attr(a, "offset")
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| broken("no offset"))?;
    let block = data
        .get(offset..)
        .ok_or_else(|| broken("offset past the end"))?;
    let raw = if compressed {
        let n = u64_at(block, 0).ok_or_else(|| broken("truncated header"))? as usize;
        let mut sizes = Vec::with_capacity(n);
        for k in 0..n {
            sizes.push(u64_at(block, 3 + k).ok_or_else(|| broken("truncated header"))? as usize);
        }
        let mut at = 8 * (3 + n);
        let mut raw = vec![];
        for s in sizes {
            let z = block
                .get(at..at + s)
                .ok_or_else(|| broken("truncated data"))?;
            flate2::read::ZlibDecoder::new(z)
                .read_to_end(&mut raw)
                .map_err(|e| broken(&format!("bad zlib stream: {e}")))?;
            at += s;
        }
        raw
    } else {
        let n = u64_at(block, 0).ok_or_else(|| broken("truncated header"))? as usize;
        block
            .get(8..8 + n)
            .ok_or_else(|| broken("truncated data"))?
            .to_vec()
    };
    let values = match attr(a, "type") {
        Some("Float32") => Values::F32(
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().expect("4")))
                .collect(),
        ),
        Some("Float64") => Values::F64(
            raw.chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().expect("8")))
                .collect(),
        ),
        Some("Int32") => Values::I32(
            raw.chunks_exact(4)
                .map(|c| i32::from_le_bytes(c.try_into().expect("4")))
                .collect(),
        ),
        Some("Int64") => Values::I64(
            raw.chunks_exact(8)
                .map(|c| i64::from_le_bytes(c.try_into().expect("8")))
                .collect(),
        ),
        t => return Err(broken(&format!("type {t:?} is not read"))),
    };
    let components = attr(a, "NumberOfComponents")
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let component_names = (0..components)
        .map_while(|i| attr(a, &format!("ComponentName{i}")).map(str::to_string))
        .collect();
    Ok(ReadArray {
        name,
        components,
        component_names,
        values,
    })
}

/// The frames of a `.pvd` collection: (time, file), in file order, with the
/// file paths resolved against the collection's folder.
pub fn read_pvd(path: &Path) -> Result<Vec<(f64, PathBuf)>> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        bad(
            path,
            format!("cannot read: {e}; give the fibres.pvd a run wrote with --vtk-every N"),
        )
    })?;
    if !text.contains("type=\"Collection\"") {
        return Err(bad(path, "not a VTK collection (.pvd)"));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut frames = vec![];
    for tag in text.split("<DataSet").skip(1) {
        let a = attrs(tag.split('>').next().unwrap_or(""));
        let t = attr(&a, "timestep")
            .and_then(|v| v.parse::<f64>().ok())
            .ok_or_else(|| bad(path, "a DataSet without a numeric timestep"))?;
        let file = attr(&a, "file").ok_or_else(|| bad(path, "a DataSet without a file"))?;
        frames.push((t, dir.join(file)));
    }
    Ok(frames)
}
