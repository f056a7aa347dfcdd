//! What a chart shows: its series, their styles and the legend placement.

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// Solid line through the points.
    #[default]
    Line,
    /// Dashed line through the points (used for reference slopes).
    Dashed,
    /// Unconnected circular markers.
    Points,
    /// Published values overlaid on our data (the paper's Table 2): large
    /// filled black diamonds with a white rim, taking no palette colour, so
    /// they stand out however many series the chart has.
    Published,
    /// Solid line with a hollow marker at every point, the shape chosen by
    /// the series' colour slot (circle, square, triangle, diamond, ×, +,
    /// inverted triangle): series that coincide (e.g. scalar and direct on
    /// a convergence plot) stay visible as nested shapes. For short series.
    LineMarkers,
    /// Grey line that takes no palette colour (slope guides), so the data
    /// keep their colours however many guides a chart has. The k-th guide of
    /// a chart gets the k-th pattern of [`GUIDE_DASHES`](super::GUIDE_DASHES) (dashes, dots,
    /// long dashes), in the plot and in the legend, so guides are told apart.
    Guide,
}

/// Where the legend goes. `Auto` picks a plot corner that covers no data,
/// else puts the legend outside the plot, on its right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPos {
    /// A corner that covers no data, else outside the plot on the right.
    #[default]
    Auto,
    /// Upper left corner of the plot.
    UpperLeft,
    /// Upper right corner of the plot.
    UpperRight,
    /// Lower left corner of the plot.
    LowerLeft,
    /// Lower right corner of the plot.
    LowerRight,
    /// Outside the plot, on its right.
    Outside,
    /// No legend.
    Hidden,
}

/// One data series. `x` and `y` must have the same length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Legend text; an empty label gets no legend entry.
    pub label: String,
    /// Abscissae, in data units.
    pub x: Vec<f64>,
    /// Ordinates, in data units.
    pub y: Vec<f64>,
    /// How the series is drawn.
    pub style: Style,
    /// Its palette slot (colour and marker shape), e.g. a rotator's place
    /// in the rotator list, so one rotator looks the same in every figure;
    /// `None`: the next slot in series order.
    pub slot: Option<usize>,
}

impl Series {
    /// A series from its label, points and style.
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, style: Style) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            style,
            slot: None,
        }
    }

    /// The same series in palette slot `slot`.
    pub fn in_slot(self, slot: usize) -> Self {
        Series {
            slot: Some(slot),
            ..self
        }
    }
}

/// A 2-D chart. Axis labels should include units, e.g. `"time step Δt (s)"`.
/// Colours are assigned in series order from a fixed palette, or by each
/// series' own `slot` (guides and published values take no palette slot).
/// A series that coincides with an earlier one (within a pixel) is drawn
/// dashed over it and its legend entry says `(= earlier)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Chart {
    /// Caption above the plot; empty for none.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// Logarithmic x axis (values ≤ 0 are skipped).
    pub log_x: bool,
    /// Logarithmic y axis (values ≤ 0 are skipped).
    pub log_y: bool,
    /// The data, drawn in order (later series on top).
    pub series: Vec<Series>,
    /// Where the legend goes.
    pub legend: LegendPos,
}

impl Chart {
    /// A linear–linear chart with no series and automatic legend placement.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Chart::default()
        }
    }
}

/// A dashed slope guide `y = anchor.1 * (x / anchor.0)^order` over `x.0..=x.1`,
/// meant for log–log charts (it is a straight line of slope `order` there).
pub fn reference_slope(label: &str, order: f64, x: (f64, f64), anchor: (f64, f64)) -> Series {
    const N: usize = 32;
    let (x0, x1) = x;
    let geometric = x0 > 0.0 && x1 > 0.0 && x0.is_finite() && x1.is_finite();
    let xs: Vec<f64> = (0..N)
        .map(|i| {
            let t = i as f64 / (N - 1) as f64;
            if geometric {
                x0 * (x1 / x0).powf(t)
            } else {
                x0 + (x1 - x0) * t
            }
        })
        .collect();
    let ys = xs
        .iter()
        .map(|&xv| anchor.1 * (xv / anchor.0).powf(order))
        .collect();
    Series::new(label, xs, ys, Style::Dashed)
}
