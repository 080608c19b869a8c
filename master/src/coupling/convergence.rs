//! The convergence measure of the interface iteration.
//!
//! For the guess `x ∈ ℝⁿ` of the interface values and the values `x̃ = H(x)` that one sweep
//! returns, the measure is the weighted root mean square of the change
//!
//! ```text
//!            ┌  1   n   ⎛      x̃ᵢ − xᵢ       ⎞² ┐ ½
//! ‖x̃ − x‖ = │ ───  Σ   ⎜ ────────────────── ⎟  │
//!            └  n  i=1  ⎝ rtol·|x̃ᵢ| + atol  ⎠  ┘
//! ```
//!
//! and the iteration has converged when `‖x̃ − x‖ ≤ 1`. Each value is thus compared with its
//! own magnitude, so positions (~1e3 m), displacements (~1e-3 m) and forces (~1e5 N) can share
//! one interface. With `n = 0` (no feedback) the measure is 0.

/// Weighted RMS of the interface change with relative and absolute tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeightedRms {
    /// Relative tolerance (dimensionless).
    pub rtol: f64,
    /// Absolute tolerance, in the units of the interface values; must be > 0.
    pub atol: f64,
}

impl WeightedRms {
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { rtol, atol }
    }

    /// `‖x̃ − x‖` as defined in the module documentation.
    pub fn evaluate(&self, x: &[f64], x_tilde: &[f64]) -> f64 {
        assert_eq!(
            x.len(),
            x_tilde.len(),
            "interface vectors of different length"
        );
        if x.is_empty() {
            return 0.0;
        }
        let sum: f64 = x
            .iter()
            .zip(x_tilde)
            .map(|(&xi, &ti)| {
                let e = (ti - xi) / (self.rtol * ti.abs() + self.atol);
                e * e
            })
            .sum();
        (sum / x.len() as f64).sqrt()
    }

    /// Whether `x̃` is converged with respect to `x`.
    pub fn converged(&self, x: &[f64], x_tilde: &[f64]) -> bool {
        self.evaluate(x, x_tilde) <= 1.0
    }
}
