//! Tolerance proportionality (DETEST, Hull et al. 1972): how a method's error follows the
//! tolerance asked, max_error ≈ C·tol^p, fitted by least squares in log10 over the method's
//! rows of a work–precision table. p = 1 and a small C: the error is proportional to the
//! tolerance; p < 1: tighter tolerances buy less than they promise.

use serde::{Deserialize, Serialize};

use crate::bench::BenchRow;

/// The fit of one method (the `fits` of `rsts bench --format json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToleranceFit {
    pub method: String,
    /// p of max_error ≈ C·tol^p.
    pub tolerance_exponent: f64,
    /// C of max_error ≈ C·tol^p.
    pub tolerance_constant: f64,
    /// Root-mean-square residual of the fit, in decades (log10).
    pub residual: f64,
    /// The largest max_error / tolerance over the method's rows.
    pub max_error_over_tolerance: f64,
    /// Rows fitted.
    pub points: usize,
}

impl ToleranceFit {
    /// `max error ≈ 3.1e2·tol^0.87 (rms 0.05 decades over 4 runs); max error/tol 1.2e1`.
    pub fn describe(&self) -> String {
        format!(
            "max error ≈ {:.2e}·tol^{:.3} (rms {:.2} decades over {} runs); max error/tol {:.2e}",
            self.tolerance_constant,
            self.tolerance_exponent,
            self.residual,
            self.points,
            self.max_error_over_tolerance
        )
    }

    /// The fitted error at `tol`.
    pub fn at(&self, tol: f64) -> f64 {
        self.tolerance_constant * tol.powf(self.tolerance_exponent)
    }
}

/// Fit each method of `rows` (in order of first appearance) over its rows with a finite
/// positive tolerance and error; a method with fewer than two distinct tolerances gets no fit.
pub fn fit_tolerances(rows: &[BenchRow]) -> Vec<ToleranceFit> {
    let mut methods: Vec<&str> = Vec::new();
    for r in rows {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    methods
        .into_iter()
        .filter_map(|m| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.method == m)
                .filter(|r| r.tolerance > 0.0 && r.tolerance.is_finite())
                .filter(|r| r.max_error > 0.0 && r.max_error.is_finite())
                .map(|r| (r.tolerance, r.max_error))
                .collect();
            fit(m, &points)
        })
        .collect()
}

/// Least squares of log10(error) against log10(tol) over (tol, error) pairs.
fn fit(method: &str, points: &[(f64, f64)]) -> Option<ToleranceFit> {
    let xy: Vec<(f64, f64)> = points.iter().map(|(t, e)| (t.log10(), e.log10())).collect();
    let n = xy.len() as f64;
    let mx = xy.iter().map(|p| p.0).sum::<f64>() / n;
    let my = xy.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if xy.len() < 2 || sxx <= 0.0 || !sxx.is_finite() {
        return None;
    }
    let p = xy.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum::<f64>() / sxx;
    let c = my - p * mx;
    let ss: f64 = xy.iter().map(|q| (q.1 - c - p * q.0).powi(2)).sum();
    Some(ToleranceFit {
        method: method.to_string(),
        tolerance_exponent: p,
        tolerance_constant: 10f64.powf(c),
        residual: (ss / n).sqrt(),
        max_error_over_tolerance: points.iter().map(|(t, e)| e / t).fold(0.0, f64::max),
        points: points.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(method: &str, tolerance: f64, max_error: f64) -> BenchRow {
        BenchRow {
            motion: None,
            method: method.into(),
            tolerance,
            max_error,
            correct_digits: Default::default(),
            integration_seconds: 1.0,
            time_min: 1.0,
            time_median: 1.0,
            time_max: 1.0,
            steps: Some(1),
            rhs_evals: Some(1),
            wall_seconds: None,
            events: None,
            dense: None,
        }
    }

    /// An exact power law is recovered with no residual; a method with one tolerance gets no
    /// fit; methods keep their order.
    #[test]
    fn a_power_law_is_recovered_and_single_tolerances_are_not_fitted() {
        let mut rows: Vec<BenchRow> = [1e-6, 1e-8, 1e-10, 1e-12]
            .iter()
            .map(|&t| row("b", t, 30.0 * f64::powf(t, 0.8)))
            .collect();
        rows.insert(0, row("a", 1e-8, 1e-7));
        rows.push(row("c", 1e-6, 2e-6));
        rows.push(row("c", 1e-9, 1e-8));
        let fits = fit_tolerances(&rows);
        assert_eq!(fits.len(), 2);
        let b = &fits[0];
        assert_eq!(b.method, "b");
        assert!((b.tolerance_exponent - 0.8).abs() < 1e-12, "{b:?}");
        assert!((b.tolerance_constant - 30.0).abs() < 1e-9, "{b:?}");
        assert!(b.residual < 1e-12);
        // The line counts the runs fitted (an ensemble has several per tolerance).
        assert!(b.describe().contains("over 4 runs"), "{}", b.describe());
        assert!((b.at(1e-10) - 30.0 * 1e-8).abs() < 1e-20);
        // 30·tol^-0.2 is largest at the smallest tolerance: 30·1e2.4.
        assert!((b.max_error_over_tolerance - 30.0 * 10f64.powf(2.4)).abs() < 1e-9);
        let c = &fits[1];
        assert!(
            (c.tolerance_exponent - (8.0 - 5.69897) / 3.0).abs() < 1e-5,
            "{c:?}"
        );
        assert!((c.max_error_over_tolerance - 10.0).abs() < 1e-12);
    }
}
