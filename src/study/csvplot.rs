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
}

/// Unit of one of our columns, `None` when unknown.
fn unit(name: &str) -> Option<&'static str> {
    Some(match name {
        "t" | "dt" | "wall_s" | "scene_dt" | "recommended_dt" | "largest_stable_dt" => "s",
        "e_grav" | "e_trans" | "e_rot" | "e_elastic" | "e_total" => "J",
        "ns_per_body_step" => "ns",
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
        "energy_error_pct" | "energy_error_window_max_pct" => "Eq. 65, no elastic energy",
        "energy_error_max_pct" | "energy_error_final_pct" => "Eq. 65, no elastic energy",
        n if n.starts_with("energy_error_full") => "Eq. 65 with elastic energy",
        "err_rad" | "geodesic_rad" => "geodesic angle to the reference",
        "alpha_rad" => "Eq. 67",
        "x_error_pct" => "Table 2 x-error",
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

/// Default y column: the Eq. 65 error for energy files, the reference angle
/// error for orientation files, the Eq. 67 error for convergence tables.
fn default_column(t: &Table) -> Option<&'static str> {
    [
        "energy_error_pct",
        "err_rad",
        "alpha_rad",
        "energy_error_max_pct",
        "max_error",
    ]
    .into_iter()
    .find(|c| t.index(c).is_some())
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
            None => {
                let c = default_column(&t).ok_or_else(|| {
                    Error::bad(
                        f.display().to_string(),
                        "--column",
                        format!(
                            "no default column in this file; choose one with --column from: {}",
                            t.header.join(", ")
                        ),
                    )
                })?;
                t.require(c, "--column")?
            }
        };
        let default_x = if t.index("t").is_some() { "t" } else { "dt" };
        let xc = t.require(opts.x.as_deref().unwrap_or(default_x), "--x")?;
        y_name = t.header[yc].clone();
        x_name = t.header[xc].clone();
        y_label = column_label(&y_name, &t);
        x_label = column_label(&x_name, &t);
        let xs = t.numbers(xc);
        let ys = t.numbers(yc);
        let label = f
            .parent()
            .and_then(|p| p.file_name())
            .map_or_else(|| f.display().to_string(), |n| n.to_string_lossy().into());
        // Study tables hold many rotators: one series each. Orientation files
        // hold one row per body: plot body 0.
        let rot = t.index("rotator");
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
            chart.series.push(Series::new(k, x, y, Style::Line));
        }
    }
    chart.title = format!("{y_name} vs {x_name}");
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
    crate::plot::render(&chart, &out).map_err(plot_error)?;
    Ok(out)
}
