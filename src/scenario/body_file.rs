//! Body files: bodies in bulk, one CSV row per fibre (a scenario's
//! `[bodies] file = "…"`), read in one streaming pass and written back with
//! every float in shortest round-trip form, so a file read back gives the
//! same bits (the state is stored as the step holds it: `ω` in the body
//! frame, the quaternion as it is).
//!
//! ```text
//! id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material
//! 0,0.15,0.15,0.0051,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.01,0.03,pa66
//! ```
//!
//! Every row is a fibre, unless the header ends in an 18th column `shape`
//! (`fibre` or `sphere`); a sphere's `length` is left empty:
//!
//! ```text
//! id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wbx,wby,wbz,diameter,length,material,shape
//! 0,0.15,0.15,0.0051,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.01,0.03,pa66,fibre
//! 1,0.15,0.17,0.0051,1.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.01,,pa66,sphere
//! ```
//!
//! Lines starting with `#` and empty lines are skipped. `material` names a
//! `[material.NAME]` table of the scenario. Every check is per row (O(N));
//! an error names the file, the line, the column and the fix.

use super::check::Ctx;
use super::file::MaterialSection;
use super::ids::Ids;
use super::SPEED_OF_LIGHT;
use crate::body::{Bodies, Body, BodyState, MaterialId, RotState, Shape};
use crate::error::{Error, Result};
use crate::fmt::short;
use glam::{DQuat, DVec3};
use std::collections::{BTreeMap, HashMap, HashSet};
use std::io::{BufRead, Write};
use std::path::Path;

/// The header of a body file, in order (ω in the body frame, rad/s), and
/// the optional 18th column `shape` of a file that holds spheres.
pub const COLUMNS: [&str; 18] = [
    "id", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wbx", "wby", "wbz", "diameter",
    "length", "material", "shape",
];

/// The columns of a file of fibres only (without `shape`).
const FIBRE_COLUMNS: usize = 17;

/// A quaternion this close to unit norm is kept bit for bit (the rotators
/// keep `‖q‖` within 1e-13); up to [`QUAT_INPUT_TOLERANCE`] it is input
/// rounding and is normalised; beyond, it is an error.
const QUAT_KEEP_TOLERANCE: f64 = 1e-12;
/// Largest `|‖q‖ − 1|` accepted as input rounding (as for `[[body]]`).
const QUAT_INPUT_TOLERANCE: f64 = 1e-6;

/// Bodies read from a body file, in file order.
pub(super) struct FileBodies {
    pub(super) bodies: Bodies,
    pub(super) initial: Vec<BodyState>,
    pub(super) ids: Vec<u64>,
    /// The file's line of each body (1-based), for messages.
    pub(super) lines: Vec<u32>,
    /// The line of the header, for a message about a file without rows.
    pub(super) header_line: usize,
}

/// Where a row's error is: `file:line:column: key`.
struct At<'a> {
    file: &'a str,
    line: usize,
}

impl At<'_> {
    fn err(&self, col: usize, msg: impl Into<String>) -> Error {
        Error::BadInput {
            file: self.file.to_string(),
            line: Some((self.line, col + 1)),
            key: COLUMNS.get(col).copied().unwrap_or("row").to_string(),
            message: msg.into(),
        }
    }
}

/// Read and check the body file at `path` (shown as `shown`): materials by
/// name from the scenario's `[material.*]` tables (interned into
/// `materials`), ids unique and distinct from `taken` (the `[[body]]` ids).
pub(super) fn read(
    path: &Path,
    shown: &str,
    named: &BTreeMap<String, MaterialSection>,
    cx: &Ctx,
    taken: u64,
    materials: &mut super::bodies::Materials,
) -> Result<FileBodies> {
    let f = std::fs::File::open(path).map_err(|e| {
        cx.err(
            "bodies.file",
            format!(
                "cannot read the body file {shown}: {e}; give a path relative to the scenario's folder"
            ),
        )
    })?;
    let mut r = std::io::BufReader::with_capacity(1 << 20, f);
    let mut out = FileBodies {
        bodies: Bodies::new(),
        initial: vec![],
        ids: vec![],
        lines: vec![],
        header_line: 0,
    };
    // Material name → id, looked up without allocating per row.
    let mut by_name: HashMap<String, MaterialId> = HashMap::new();
    let mut seen: HashSet<u64> = HashSet::new();
    // Bytes, not a String per line: fields are checked as UTF-8 one by one.
    let mut text: Vec<u8> = Vec::with_capacity(512);
    let mut line = 0usize;
    let mut header = false;
    // 17, or 18 with the `shape` column.
    let mut columns = FIBRE_COLUMNS;
    loop {
        text.clear();
        let n = r
            .read_until(b'\n', &mut text)
            .map_err(|e| Error::BadInput {
                file: shown.to_string(),
                line: Some((line + 1, 1)),
                key: "row".into(),
                message: format!("cannot read the line: {e}"),
            })?;
        if n == 0 {
            break;
        }
        line += 1;
        let mut row: &[u8] = &text;
        while let [rest @ .., b'\n' | b'\r'] = row {
            row = rest;
        }
        if row.iter().all(u8::is_ascii_whitespace) || row.first() == Some(&b'#') {
            continue;
        }
        let at = At { file: shown, line };
        if !header {
            let row = String::from_utf8_lossy(row);
            let got: Vec<&str> = row.split(',').map(str::trim).collect();
            if got != COLUMNS[..FIBRE_COLUMNS] && got != COLUMNS {
                return Err(Error::BadInput {
                    file: shown.to_string(),
                    line: Some((line, 1)),
                    key: "header".into(),
                    message: format!(
                        "the first row must be the header `{}` (with `,shape` at the end if the file holds spheres), got `{row}`",
                        COLUMNS[..FIBRE_COLUMNS].join(",")
                    ),
                });
            }
            columns = got.len();
            header = true;
            out.header_line = line;
            continue;
        }
        let (id, body, state) = parse_row(row, columns, &at, named, materials, &mut by_name)?;
        if id < taken || !seen.insert(id) {
            let why = if id < taken {
                format!("is the id of [[body]] {id} of the scenario")
            } else {
                "appears twice in the file".to_string()
            };
            return Err(at.err(0, format!("id {id} {why}; give every body its own id")));
        }
        out.ids.push(id);
        out.bodies.push(body);
        out.initial.push(state);
        out.lines.push(line as u32);
    }
    if !header {
        return Err(Error::bad(
            shown,
            "header",
            format!(
                "the body file is empty; it needs the header `{}` and one row per body",
                COLUMNS[..FIBRE_COLUMNS].join(",")
            ),
        ));
    }
    Ok(out)
}

/// Field `f` as trimmed text (`\u{fffd}` where it is not UTF-8, which no
/// number or material name matches).
fn text(f: &[u8]) -> &str {
    std::str::from_utf8(f).map_or("\u{fffd}", str::trim)
}

/// One row of a file of `columns` columns (17, or 18 with `shape`) into
/// `(id, body, state)`.
fn parse_row(
    row: &[u8],
    columns: usize,
    at: &At,
    named: &BTreeMap<String, MaterialSection>,
    materials: &mut super::bodies::Materials,
    by_name: &mut HashMap<String, MaterialId>,
) -> Result<(u64, Body, BodyState)> {
    let header = || COLUMNS[..columns].join(",");
    let mut fields = [""; 18];
    let mut n = 0;
    for f in row.split(|&b| b == b',') {
        if n == columns {
            return Err(at.err(
                columns,
                format!(
                    "the row has more than {columns} columns; give exactly `{}`",
                    header()
                ),
            ));
        }
        fields[n] = text(f);
        n += 1;
    }
    if n < columns {
        return Err(at.err(
            n.min(columns - 1),
            format!(
                "the row has {n} columns, the header {columns}; give a value for `{}`",
                COLUMNS[n]
            ),
        ));
    }
    let sphere = match fields[17] {
        _ if columns == FIBRE_COLUMNS => false,
        "fibre" => false,
        "sphere" => true,
        other => return Err(at.err(17, format!("unknown shape `{other}`; give fibre or sphere"))),
    };
    if sphere && !fields[15].is_empty() {
        return Err(at.err(
            15,
            format!(
                "a sphere has no length, got `{}`; leave the column empty, or give shape fibre",
                fields[15]
            ),
        ));
    }
    let id: u64 = fields[0].parse().map_err(|_| {
        at.err(
            0,
            format!("`{}` is not a body id; give a whole number >= 0", fields[0]),
        )
    })?;
    let mut v = [0.0; 15];
    for (k, x) in v.iter_mut().enumerate() {
        let s = fields[k + 1];
        if sphere && k + 1 == 15 {
            continue;
        }
        *x = match s.parse::<f64>() {
            Ok(x) if x.is_finite() => x,
            _ => {
                return Err(at.err(
                    k + 1,
                    format!("`{s}` is not a finite number; give a number (e.g. 0.01)"),
                ))
            }
        };
    }
    let (diameter, length) = (v[13], v[14]);
    let sizes: &[(usize, f64)] = match sphere {
        true => &[(14, diameter)],
        false => &[(14, diameter), (15, length)],
    };
    for &(col, x) in sizes {
        if x <= 0.0 {
            return Err(at.err(
                col,
                format!("must be > 0 m, got {}; give a positive size", short(x)),
            ));
        }
    }
    let q = DQuat::from_xyzw(v[4], v[5], v[6], v[3]);
    let norm = q.length();
    let q = if (norm - 1.0).abs() <= QUAT_KEEP_TOLERANCE {
        q
    } else if (norm - 1.0).abs() <= QUAT_INPUT_TOLERANCE {
        // Input rounding only (as for a `[[body]]` quaternion).
        q.normalize()
    } else {
        return Err(at.err(
            4,
            format!(
                "qw,qx,qy,qz must be a unit quaternion (norm {}); normalise it",
                short(norm)
            ),
        ));
    };
    let shape = match sphere {
        true => Shape::Sphere { diameter },
        false => Shape::Fibre { diameter, length },
    };
    let x = DVec3::new(v[0], v[1], v[2]);
    let vel = DVec3::new(v[7], v[8], v[9]);
    let omega_b = DVec3::new(v[10], v[11], v[12]);
    for (col, speed, what) in [
        (8, vel.length(), "speed"),
        (
            11,
            omega_b.length() * shape.bounding_radius(),
            "rim speed |omega| x bounding radius",
        ),
    ] {
        if speed >= SPEED_OF_LIGHT {
            return Err(at.err(col, format!("{what} {} m/s is not physical (fibresim is Newtonian); give a speed far below 3e8 m/s", short(speed))));
        }
    }
    let name = fields[16];
    let material = match by_name.get(name) {
        Some(&m) => m,
        None => {
            let m = named.get(name).ok_or_else(|| {
                let known: Vec<&String> = named.keys().collect();
                at.err(
                    16,
                    format!("unknown material `{name}`; define [material.{name}] in the scenario (defined: {known:?})"),
                )
            })?;
            let (Some(e), Some(nu)) = (m.young, m.poisson) else {
                return Err(at.err(
                    16,
                    format!("material `{name}` needs `young` and `poisson`: bodies in a body file can touch"),
                ));
            };
            let id = materials.intern(Some(name), m.density, e, nu, m.friction);
            by_name.insert(name.to_string(), id);
            id
        }
    };
    let density = materials.table[material as usize].density;
    Ok((
        id,
        Body::new(shape, material, density),
        BodyState {
            x,
            v: vel,
            rot: RotState { q, omega_b },
        },
    ))
}

/// Write `states` of `bodies` (global ids `ids`, material names
/// `material_names`) as a body file at `path`, every float in shortest
/// round-trip form.
pub fn write(
    path: &Path,
    ids: &Ids,
    bodies: &Bodies,
    states: &[BodyState],
    material_names: &[String],
) -> Result<()> {
    let f = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut w = std::io::BufWriter::with_capacity(1 << 20, f);
    let io = |e| Error::io(path, e);
    // The `shape` column only when the file holds spheres: a file of
    // fibres keeps the 17 columns.
    let spheres = bodies
        .iter()
        .any(|b| matches!(b.shape, Shape::Sphere { .. }));
    let columns = if spheres { 18 } else { FIBRE_COLUMNS };
    writeln!(w, "{}", COLUMNS[..columns].join(",")).map_err(io)?;
    let mut buf = ryu::Buffer::new();
    let mut line = String::with_capacity(400);
    for ((id, b), s) in ids.iter().zip(bodies).zip(states) {
        let (diameter, length, shape) = match b.shape {
            Shape::Fibre { diameter, length } => (diameter, Some(length), "fibre"),
            Shape::Sphere { diameter } => (diameter, None, "sphere"),
            Shape::Rigid { .. } => {
                return Err(Error::bad(
                    path.display().to_string(),
                    "shape",
                    "body files hold fibres and spheres only",
                ))
            }
        };
        line.clear();
        line.push_str(&id.to_string());
        let q = s.rot.q;
        for x in
            s.x.to_array()
                .into_iter()
                .chain([q.w, q.x, q.y, q.z])
                .chain(s.v.to_array())
                .chain(s.rot.omega_b.to_array())
                .chain([diameter])
        {
            line.push(',');
            line.push_str(buf.format(x));
        }
        line.push(',');
        if let Some(l) = length {
            line.push_str(buf.format(l));
        }
        line.push(',');
        line.push_str(&material_names[b.material as usize]);
        if spheres {
            line.push(',');
            line.push_str(shape);
        }
        line.push('\n');
        w.write_all(line.as_bytes()).map_err(io)?;
    }
    w.flush().map_err(io)
}
