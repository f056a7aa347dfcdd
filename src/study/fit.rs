//! Observed order of convergence: least-squares slope of log(error) on log(δt).

/// A fitted power law `error ≈ c · δt^order`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderFit {
    /// The fitted exponent `order`.
    pub order: f64,
    /// `ln c`.
    pub log_c: f64,
    /// Coefficient of determination of the log–log line.
    pub r2: f64,
    /// Points used (finite, positive errors only).
    pub points: usize,
}

impl OrderFit {
    /// The fitted error at `dt`.
    pub fn at(&self, dt: f64) -> f64 {
        (self.log_c + self.order * dt.ln()).exp()
    }
}

/// Fit `error = c δt^p` by least squares in log–log space. Non-finite or
/// non-positive errors (stopped runs, exact zeros) are skipped; `None` if fewer
/// than two points remain or the δt are all equal.
pub fn fit_order(dts: &[f64], errors: &[f64]) -> Option<OrderFit> {
    let pts: Vec<(f64, f64)> = dts
        .iter()
        .zip(errors)
        .filter(|(d, e)| d.is_finite() && **d > 0.0 && e.is_finite() && **e > 0.0)
        .map(|(d, e)| (d.ln(), e.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let order = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Some(OrderFit {
        order,
        log_c: my - order * mx,
        r2,
        points: pts.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_exact_order_and_constant() {
        let dts = [1e-5, 3.2e-6, 1e-6, 3.2e-7, 1e-7];
        for p in [1.0, 2.0, 4.0] {
            let errs: Vec<f64> = dts.iter().map(|d: &f64| 3.5 * d.powf(p)).collect();
            let f = fit_order(&dts, &errs).unwrap();
            assert!((f.order - p).abs() < 1e-12, "{f:?}");
            assert!((f.log_c - 3.5f64.ln()).abs() < 1e-9, "{f:?}");
            assert!((f.r2 - 1.0).abs() < 1e-12);
            assert!((f.at(1e-6) / (3.5 * 1e-6f64.powf(p)) - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn skips_bad_points() {
        let f = fit_order(&[1.0, 0.5, 0.25], &[2.0, f64::NAN, 0.5]).unwrap();
        assert_eq!(f.points, 2);
        assert!((f.order - 1.0).abs() < 1e-12);
        assert!(fit_order(&[1.0, 0.5], &[1.0, 0.0]).is_none());
    }
}
