//! Constant under-relaxation: `xₖ₊₁ = xₖ + ω (x̃ₖ − xₖ) = ω x̃ₖ + (1 − ω) xₖ`.
//!
//! For a linear map `H(x) = A x + b` the error contracts with the spectral radius of
//! `(1 − ω) I + ω A`; for a real eigenvalue `λ < 1` of `A` that needs `ω < 2 / (1 − λ)`.

use super::Acceleration;

/// Constant relaxation with factor `ω ∈ (0, 1]`; `ω = 1` is the plain fixed-point iteration.
#[derive(Debug, Clone)]
pub struct ConstantRelaxation {
    omega: f64,
}

impl ConstantRelaxation {
    pub fn new(omega: f64) -> Self {
        Self { omega }
    }
}

impl Acceleration for ConstantRelaxation {
    fn name(&self) -> &str {
        "constant"
    }

    fn initialize(&mut self, _n: usize) {}

    fn begin_step(&mut self, _h: f64) {}

    fn perform(&mut self, x: &[f64], x_tilde: &[f64], _scale: &[f64], next: &mut [f64]) {
        for ((n, &x), &t) in next.iter_mut().zip(x).zip(x_tilde) {
            *n = x + self.omega * (t - x);
        }
    }

    fn end_step(&mut self, _converged: bool) {}
}
