//! Aitken dynamic relaxation (Irons & Tuck 1969; Küttler & Wall 2008).
//!
//! `xₖ₊₁ = xₖ + ωₖ rₖ` with the secant estimate, in the scaled inner product of the module
//! documentation,
//!
//! ```text
//! ωₖ = −ωₖ₋₁ · (rₖ₋₁ᵀ D² (rₖ − rₖ₋₁)) / ‖D (rₖ − rₖ₋₁)‖²        (k ≥ 1)
//! ```
//!
//! For a scalar linear map `H(x) = a x + b` this is exact: `ω₁ = 1 / (1 − a)` and the next
//! guess is the fixed point. `ωₖ` may be negative (when `H` expands without oscillating) and is
//! clipped to `|ωₖ| ≤ max_factor` (default 10) against near-zero denominators; when
//! `‖D Δr‖ = 0` or the estimate is 0 or not finite, the previous factor is kept.
//!
//! The residual history is reset at every step. The first factor of a step is, as in preCICE,
//! the initial relaxation capped by the last factor of the previous converged step:
//! `ω₀ = sign(ω_last) · min(ω_init, |ω_last|)`; in the first step `ω₀ = ω_init`. Stiff couplings
//! with small optimal factors thus do not restart each step with a too-large first update.

use super::{scaled_dot, Acceleration};

/// Aitken dynamic under-relaxation.
#[derive(Debug, Clone)]
pub struct Aitken {
    initial: f64,
    max_factor: f64,
    /// Factor used in the last iteration of the current step.
    omega: f64,
    /// Last factor of the last converged step.
    omega_last: f64,
    prev_r: Option<Vec<f64>>,
    dr: Vec<f64>,
}

impl Aitken {
    /// `initial`: the relaxation factor ω_init of the first iteration (e.g. 0.5).
    pub fn new(initial: f64) -> Self {
        Self {
            initial,
            max_factor: 10.0,
            omega: initial,
            omega_last: initial,
            prev_r: None,
            dr: Vec::new(),
        }
    }

    /// Bound on `|ω|` (default 10).
    pub fn with_max_factor(mut self, max_factor: f64) -> Self {
        self.max_factor = max_factor;
        self
    }

    /// The factor used in the most recent update.
    pub fn factor(&self) -> f64 {
        self.omega
    }
}

impl Acceleration for Aitken {
    fn name(&self) -> &str {
        "aitken"
    }

    fn initialize(&mut self, _n: usize) {
        self.omega = self.initial;
        self.omega_last = self.initial;
        self.prev_r = None;
    }

    fn begin_step(&mut self, _h: f64) {
        self.prev_r = None;
    }

    fn perform(&mut self, x: &[f64], x_tilde: &[f64], scale: &[f64], next: &mut [f64]) {
        let r: Vec<f64> = x_tilde.iter().zip(x).map(|(&t, &x)| t - x).collect();
        match &self.prev_r {
            None => {
                self.omega = self
                    .initial
                    .min(self.omega_last.abs())
                    .copysign(self.omega_last);
            }
            Some(prev) => {
                self.dr.clear();
                self.dr.extend(r.iter().zip(prev).map(|(&a, &b)| a - b));
                let den = scaled_dot(&self.dr, &self.dr, scale);
                if den > 0.0 {
                    let num = scaled_dot(prev, &self.dr, scale);
                    let omega = -self.omega * num / den;
                    if omega.is_finite() && omega != 0.0 {
                        self.omega = omega.clamp(-self.max_factor, self.max_factor);
                    }
                }
            }
        }
        for ((n, &x), &r) in next.iter_mut().zip(x).zip(&r) {
            *n = x + self.omega * r;
        }
        self.prev_r = Some(r);
    }

    fn end_step(&mut self, converged: bool) {
        if converged && self.prev_r.is_some() {
            self.omega_last = self.omega;
        }
    }
}
