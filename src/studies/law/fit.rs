//! Ordinary least squares with nalgebra: coefficients, their standard
//! errors from the residual variance and (X^T X)^-1, and the residuals.

use anyhow::{bail, Result};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// A least-squares fit y ~ X b.
#[derive(Debug, Clone, Serialize)]
pub struct Fit {
    /// The columns' names, as the coefficients'.
    pub names: Vec<String>,
    pub coef: Vec<f64>,
    /// Standard errors: sqrt(s^2 diag((X^T X)^-1)), s^2 = RSS / (n - k)
    /// (NaN with no degree of freedom left).
    pub se: Vec<f64>,
    /// y - X b, per point in order.
    pub residuals: Vec<f64>,
    /// sqrt(RSS / n): the typical residual.
    pub rms: f64,
    /// n - k.
    pub dof: usize,
}

/// Fit `y` by the columns `x` (each as long as `y`), named `names`.
pub fn least_squares(names: &[&str], x: &[Vec<f64>], y: &[f64]) -> Result<Fit> {
    let (n, k) = (y.len(), x.len());
    if k == 0 || x.iter().any(|c| c.len() != n) || names.len() != k {
        bail!("a fit needs as many names as columns, each as long as y");
    }
    if n < k {
        bail!("{n} points cannot fit {k} coefficients");
    }
    let xm = DMatrix::from_fn(n, k, |i, j| x[j][i]);
    let yv = DVector::from_column_slice(y);
    let xtx = xm.transpose() * &xm;
    let Some(inv) = xtx.clone().try_inverse() else {
        bail!(
            "the fit's columns ({}) are not independent on these points",
            names.join(", ")
        );
    };
    let b = &inv * xm.transpose() * &yv;
    let r = &yv - &xm * &b;
    let rss = r.norm_squared();
    let dof = n - k;
    let s2 = if dof > 0 { rss / dof as f64 } else { f64::NAN };
    Ok(Fit {
        names: names.iter().map(|s| s.to_string()).collect(),
        coef: b.iter().copied().collect(),
        se: (0..k).map(|j| (s2 * inv[(j, j)]).sqrt()).collect(),
        residuals: r.iter().copied().collect(),
        rms: (rss / n as f64).sqrt(),
        dof,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift), uniform in [-1, 1).
    fn noise(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    #[test]
    fn recovers_known_exponents_within_their_standard_errors() {
        // log c = log 0.7 - 0.5 log N - 0.25 log Re + 1.5 alpha + noise,
        // on the law's grid shape (N x Re x alpha), noise of 0.05 in log.
        let truth = [0.7f64.ln(), -0.5, -0.25, 1.5];
        let (mut one, mut ln_n, mut ln_re, mut al, mut y) =
            (vec![], vec![], vec![], vec![], vec![]);
        let mut st = 0x9e3779b97f4a7c15u64;
        for n in [6.0f64, 8.0, 10.0, 14.0, 20.0] {
            for re in [1.0f64, 3.0, 10.0, 30.0] {
                for a in [0.0, 0.1] {
                    one.push(1.0);
                    ln_n.push(n.ln());
                    ln_re.push(re.ln());
                    al.push(a);
                    let v = truth[0] + truth[1] * n.ln() + truth[2] * re.ln() + truth[3] * a;
                    y.push(v + 0.05 * noise(&mut st));
                }
            }
        }
        let fit = least_squares(
            &["1", "ln N", "ln Re", "alpha"],
            &[one, ln_n, ln_re, al],
            &y,
        )
        .unwrap();
        assert_eq!(fit.dof, 36);
        for (j, want) in truth.iter().enumerate() {
            // within 3 standard errors (a 99.7 % band), and the errors are
            // of the size the noise implies (not zero, not huge)
            assert!(
                (fit.coef[j] - want).abs() < 3.0 * fit.se[j],
                "{}: {} vs {} +- {}",
                fit.names[j],
                fit.coef[j],
                want,
                fit.se[j]
            );
            assert!(fit.se[j] > 1e-4 && fit.se[j] < 0.5, "{fit:?}");
        }
        // uniform noise of half-width 0.05 has RMS 0.05 / sqrt 3
        assert!((fit.rms - 0.05 / 3f64.sqrt()).abs() < 0.01, "{}", fit.rms);
        let mean: f64 = fit.residuals.iter().sum::<f64>() / fit.residuals.len() as f64;
        assert!(
            mean.abs() < 1e-12,
            "an intercept leaves residuals of mean 0"
        );
    }

    #[test]
    fn refuses_dependent_columns_and_too_few_points() {
        let x = vec![vec![1.0, 1.0, 1.0], vec![2.0, 2.0, 2.0]];
        assert!(least_squares(&["a", "b"], &x, &[1.0, 2.0, 3.0]).is_err());
        assert!(least_squares(&["a", "b"], &x, &[1.0]).is_err());
    }
}
