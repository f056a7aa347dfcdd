//! Reading our CSV files back, and `fibresim plot`: one column of any of them
//! against another, one series per file (or per rotator for study tables).

use super::plot_error;
use crate::error::{Error, Result};
use crate::plot::{Chart, Series, Style};
use std::path::{Path, PathBuf};

/// A CSV file as text cells.
pub struct Table {
    pub path: PathBuf,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn read(path: &Path) -> Result<Table> {
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

    pub fn index(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// Index of `name`, or a BadInput naming the columns that exist.
    pub fn require(&self, name: &str, flag: &str) -> Result<usize> {
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
    pub fn numbers(&self, i: usize) -> Vec<f64> {
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
    pub files: Vec<PathBuf>,
    pub out: Option<PathBuf>,
    pub column: Option<String>,
    pub x: Option<String>,
    pub log_x: bool,
    pub log_y: bool,
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
    chart.x_label = x_name;
    chart.y_label = y_name.clone();
    chart.log_x = opts.log_x;
    chart.log_y = opts.log_y;
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
