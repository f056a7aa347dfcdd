//! Reading our CSV files back, and `fibresim plot`: one column of any of them
//! against another, one series per file (or per rotator for study tables).
//!
//! Axes are labelled with the column name and its unit (for the columns we
//! write; see `column_label`). An axis is logarithmic when asked
//! (`--log-x`, `--log-y`) or when its data call for it ([`wants_log`]).

use super::plot_error;
use crate::error::{Error, Result};
use crate::plot::{Chart, Series, Style};
use std::path::{Path, PathBuf};

/// A CSV file as text cells.
pub(crate) struct Table {
    /// The file read, for messages.
    pub(crate) path: PathBuf,
    /// Column names.
    pub(crate) header: Vec<String>,
    /// The cells, row by row.
    pub(crate) rows: Vec<Vec<String>>,
}

impl Table {
    /// Read `path`; unreadable or malformed CSV is bad input naming it.
    pub(crate) fn read(path: &Path) -> Result<Table> {
        let bad = |m: String| Error::bad(path.display().to_string(), "file", m);
        let mut r = csv::Reader::from_path(path).map_err(|e| bad(format!("cannot read: {e}")))?;
        let header = r
            .headers()
            .map_err(|e| bad(format!("no CSV header: {e}")))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for rec in r.records() {
            let rec = rec.map_err(|e| bad(format!("malformed CSV: {e}")))?;
            rows.push(rec.iter().map(str::to_string).collect());
        }
        Ok(Table {
            path: path.to_path_buf(),
            header,
            rows,
        })
    }

    /// Index of column `name`.
    pub(crate) fn index(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Index of `name`, or a BadInput naming the columns that exist.
    pub(crate) fn require(&self, name: &str, flag: &str) -> Result<usize> {
        self.index(name).ok_or_else(|| {
            Error::bad(
                self.path.display().to_string(),
                flag,
                format!(
                    "no column {name:?}; the columns are: {}",
                    self.header.join(", ")
                ),
            )
        })
    }

    /// Column `i` as numbers; empty or non-numeric cells are NaN.
    pub(crate) fn numbers(&self, i: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| {
                r.get(i)
                    .and_then(|c| c.parse::<f64>().ok())
                    .unwrap_or(f64::NAN)
            })
            .collect()
    }
}

/// Options of `fibresim plot`.
#[derive(Debug, Clone)]
pub struct PlotOptions {
    /// The CSV files, one series each (study tables: one per rotator).
    pub files: Vec<PathBuf>,
    /// The figure (`.png` or `.svg`); default `<first stem>_<column>.png`
    /// beside the first file.
    pub out: Option<PathBuf>,
    /// The y column; default by the kind of file.
    pub column: Option<String>,
    /// The x column; default `t`, else `dt`.
    pub x: Option<String>,
    /// Force a logarithmic x axis.
    pub log_x: bool,
    /// Force a logarithmic y axis.
    pub log_y: bool,
    /// Plot an energy error with its sign, `(E − E₀)/|E₀|`, from the
    /// energies (the files hold `|E − E₀|/|E₀|`).
    pub signed: bool,
}

/// Unit of one of our columns, `None` when unknown.
fn unit(name: &str) -> Option<&'static str> {
    Some(match name {
        "t" | "dt" | "wall_s" | "scene_dt" | "recommended_dt" | "largest_stable_dt" => "s",
        "e_grav" | "e_trans" | "e_rot" | "e_elastic" | "e_total" => "J",
        "ns_per_body_step" => "ns",
        "position_error_m" | "richardson_position_m" => "m",
        "factor" | "largest_stable_factor" | "hard_limit_factor" => "× δt_rec",
        "step" | "steps" | "steps_done" | "steps_planned" | "timing_runs" => "count",
        "qw" | "qx" | "qy" | "qz" | "ref_qw" | "ref_qx" | "ref_qy" | "ref_qz" | "ax" | "ay"
        | "az" | "order" | "order_finest3" | "nominal_order" | "r2" => "–",
        n if n.ends_with("_pct") => "%",
        n if n.ends_with("_rad") => "rad",
        _ => return None,
    })
}

/// What a column measures, where the name alone does not say it.
fn meaning(name: &str) -> Option<&'static str> {
    Some(match name {
        "t" => "time",
        "dt" => "time step",
        "e_total" => "Eq. 64 energy",
        "energy_error_pct" => "|E − E₀|/|E₀|, Eq. 65, no elastic energy",
        "energy_error_window_max_pct" => {
            "largest |E − E₀|/|E₀| since the previous row, Eq. 65, no elastic energy"
        }
        "energy_error_max_pct" | "energy_error_final_pct" => {
            "|E − E₀|/|E₀|, Eq. 65, no elastic energy"
        }
        "energy_error_full_window_max_pct" => {
            "largest |E − E₀|/|E₀| since the previous row, Eq. 65 with elastic energy"
        }
        n if n.starts_with("energy_error_full") => "|E − E₀|/|E₀|, Eq. 65 with elastic energy",
        "err_rad" | "geodesic_rad" => "geodesic angle to the reference",
        "alpha_rad" => "Eq. 67",
        "x_error_pct" => "Table 2 x-error",
        "position_error_m" => "largest distance of a body to the reference at T",
        "wall_s" => "wall time",
        "ax" | "ay" | "az" => "body x axis in the world",
        _ => return None,
    })
}

/// Axis label of column `name` of `table`: `name: meaning (unit)`. The
/// study tables' `max_error`/`final_error` take the unit of their `metric`
/// column (e.g. `angle to rk4 at δt/10 (rad)`).
pub(crate) fn column_label(name: &str, table: &Table) -> String {
    let unit = unit(name).map(str::to_string).or_else(|| {
        if !matches!(name, "max_error" | "final_error") {
            return None;
        }
        let m = table.index("metric")?;
        let text = table.rows.first()?.get(m)?;
        let open = text.rfind('(')?;
        Some(text[open + 1..].trim_end_matches(')').to_string())
    });
    match (meaning(name), unit) {
        (Some(m), Some(u)) => format!("{name}: {m} ({u})"),
        (None, Some(u)) => format!("{name} ({u})"),
        (Some(m), None) => format!("{name}: {m}"),
        (None, None) => name.to_string(),
    }
}

/// Whether an axis showing `values` should be logarithmic: no negative
/// value, the positive ones span at least 2 decades, and they are spread
/// over them — fewer than 3/4 in the top decade, which keeps linear grids
/// such as `t` or `step` (90 % in their top decade) linear. Zeros and NaN
/// are ignored (a log axis skips them).
pub fn wants_log(values: &[f64]) -> bool {
    let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.iter().any(|&v| v < 0.0) {
        return false;
    }
    let pos: Vec<f64> = finite.into_iter().filter(|&v| v > 0.0).collect();
    let (lo, hi) = pos
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
    if pos.len() < 2 || hi < 100.0 * lo {
        return false;
    }
    let top = pos.iter().filter(|&&v| v >= hi / 10.0).count();
    (top as f64) < 0.75 * pos.len() as f64
}

/// Default y column: the first of these with a finite value (the
/// full-budget Eq. 65 error, the conserved quantity, for energy files; the
/// reference angle for orientation files, the Eq. 67 error for convergence
/// tables, the errors of compare and stress tables, the orders; the axis
/// for orientation files without a reference, the energy for energy files
/// whose Eq. 65 is undefined, E₀ = 0).
const DEFAULT_Y: &[&str] = &[
    "energy_error_full_pct",
    "err_rad",
    "alpha_rad",
    "energy_error_full_max_pct",
    "max_error",
    "order",
    "richardson_alpha_rad",
    "largest_stable_factor",
    "ax",
    "e_total",
];

/// Default x column: the first of these the file has with data (time; time step;
/// the stress factor; run time, for compare tables; the nominal order, for
/// orders tables; the recommended δt, for the stress summary).
const DEFAULT_X: &[&str] = &[
    "t",
    "dt",
    "factor",
    "wall_s",
    "nominal_order",
    "recommended_dt",
];

/// The first of `names` that `t` has with a finite value in some row.
fn first_with_data(t: &Table, names: &[&str]) -> Option<usize> {
    names
        .iter()
        .filter_map(|c| t.index(c))
        .find(|&i| t.numbers(i).iter().any(|v| v.is_finite()))
}

/// The default column of `t` for `flag`: the first of `names` with data,
/// else the first present; else bad input listing the columns.
fn default_of(t: &Table, names: &[&str], flag: &str) -> Result<usize> {
    first_with_data(t, names)
        .or_else(|| {
            (flag == "--x")
                .then(|| names.iter().find_map(|c| t.index(c)))
                .flatten()
        })
        .ok_or_else(|| {
            Error::bad(
                t.path.display().to_string(),
                flag,
                format!(
                    "no default column in this file; choose one with {flag} from: {}",
                    t.header.join(", ")
                ),
            )
        })
}

/// The signed energy error `(E − E₀)/|E₀| · 100` of an energy file, for
/// column `name` (`energy_error_pct`: Eq. 64's energy; `energy_error_full_pct`:
/// with the elastic energy).
fn signed_error(t: &Table, name: &str) -> Result<Vec<f64>> {
    let parts: &[&str] = match name {
        "energy_error_pct" => &["e_total"],
        "energy_error_full_pct" => &["e_total", "e_elastic"],
        other => {
            return Err(Error::bad(
                t.path.display().to_string(),
                "--signed",
                format!("{other} has no sign to show; --signed plots energy_error_pct or energy_error_full_pct of an energy.csv (the window maxima are maxima of |error|)"),
            ))
        }
    };
    let cols = parts
        .iter()
        .map(|p| t.require(p, "--signed").map(|i| t.numbers(i)))
        .collect::<Result<Vec<_>>>()?;
    let e: Vec<f64> = (0..t.rows.len())
        .map(|r| cols.iter().map(|c| c[r]).sum())
        .collect();
    let e0 = e.first().copied().unwrap_or(f64::NAN);
    Ok(e.iter().map(|x| (x - e0) / e0.abs() * 100.0).collect())
}

/// Plot and return the path written.
pub fn plot_files(opts: &PlotOptions) -> Result<PathBuf> {
    if opts.files.is_empty() {
        return Err(Error::bad(
            "command line",
            "CSV",
            "give at least one CSV file",
        ));
    }
    // A format we do not write is refused before any work.
    if let Some(out) = &opts.out {
        crate::plot::check_format(out).map_err(plot_error)?;
    }
    let mut chart = Chart::new("", "", "");
    let mut y_name = String::new();
    let mut x_name = String::new();
    let (mut y_label, mut x_label) = (String::new(), String::new());
    for f in &opts.files {
        if !f.is_file() {
            return Err(Error::bad(f.display().to_string(), "CSV", "no such file"));
        }
        let t = Table::read(f)?;
        let yc = match &opts.column {
            Some(c) => t.require(c, "--column")?,
            None => default_of(&t, DEFAULT_Y, "--column")?,
        };
        let xc = match &opts.x {
            Some(c) => t.require(c, "--x")?,
            None => default_of(&t, DEFAULT_X, "--x")?,
        };
        y_name = t.header[yc].clone();
        x_name = t.header[xc].clone();
        let xs = t.numbers(xc);
        let ys = if opts.signed {
            signed_error(&t, &y_name)?
        } else {
            t.numbers(yc)
        };
        y_label = if opts.signed {
            format!(
                "{y_name}, signed: (E − E₀)/|E₀|{} (%)",
                if y_name.contains("full") {
                    ", with elastic energy"
                } else {
                    ""
                }
            )
        } else {
            column_label(&y_name, &t)
        };
        x_label = column_label(&x_name, &t);
        let label = f
            .parent()
            .and_then(|p| p.file_name())
            .map_or_else(|| f.display().to_string(), |n| n.to_string_lossy().into());
        // Study tables hold many rotators: one series each (as does a table
        // with a `series` column, e.g. docs/figures/bed_scaling.csv).
        // Orientation files hold one row per body: plot body 0.
        let rot = t.index("rotator").or_else(|| t.index("series"));
        let body = t.index("body");
        let mut groups: Vec<(String, Vec<f64>, Vec<f64>)> = Vec::new();
        for (i, row) in t.rows.iter().enumerate() {
            if body.is_some_and(|b| row.get(b).map(String::as_str) != Some("0")) {
                continue;
            }
            let key = rot.map_or(label.clone(), |r| {
                let name = row.get(r).cloned().unwrap_or_default();
                if opts.files.len() > 1 {
                    format!("{label}/{name}")
                } else {
                    name
                }
            });
            let g = match groups.iter().position(|g| g.0 == key) {
                Some(p) => p,
                None => {
                    groups.push((key, vec![], vec![]));
                    groups.len() - 1
                }
            };
            groups[g].1.push(xs[i]);
            groups[g].2.push(ys[i]);
        }
        for (k, x, y) in groups {
            // Few points get markers (one per rotator, as in the study
            // figures); points out of x order are not joined.
            let sorted = x
                .windows(2)
                .all(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Less));
            let style = match (sorted, x.len()) {
                (false, _) => Style::Points,
                (true, n) if n <= 50 => Style::LineMarkers,
                _ => Style::Line,
            };
            let slot = super::slot_of_label(&k);
            let s = Series::new(k, x, y, style);
            chart.series.push(match slot {
                Some(slot) => s.in_slot(slot),
                None => s,
            });
        }
    }
    let view = if opts.signed {
        " (signed: above 0 is a gain)"
    } else if y_name.starts_with("energy_error") {
        " (absolute: |E − E₀|/|E₀|)"
    } else {
        ""
    };
    chart.title = format!("{y_name} vs {x_name}{view}");
    chart.x_label = x_label;
    chart.y_label = y_label;
    let all = |pick: fn(&crate::plot::Series) -> &Vec<f64>| -> Vec<f64> {
        chart.series.iter().flat_map(|s| pick(s).clone()).collect()
    };
    chart.log_x = opts.log_x || wants_log(&all(|s| &s.x));
    chart.log_y = opts.log_y || wants_log(&all(|s| &s.y));
    let out = opts.out.clone().unwrap_or_else(|| {
        let first = &opts.files[0];
        first.with_file_name(format!(
            "{}_{}.png",
            first
                .file_stem()
                .map_or("plot".into(), |s| s.to_string_lossy()),
            y_name
        ))
    });
    crate::output::create_parent_dir(&out, "--out")?;
    crate::plot::render(&chart, &out).map_err(plot_error)?;
    Ok(out)
}
