//! Newton update with the interface Jacobian of the step map.
//!
//! For the sweep map `x̃ = H(x)` of a step and its residual `R(x) = H(x) − x`, the update is
//!
//! ```text
//! xₖ₊₁ = xₖ + (I − J)⁻¹ (x̃ₖ − xₖ),     J = ∂H/∂x ,
//! ```
//!
//! which reaches the fixed point in one update when `H` is affine and `J` exact; the next
//! sweep confirms it. `J` is computed by the implicit scheme, by finite differences of each
//! participant's step through rollback (conforming to FMI 2.0: see
//! [`StepJacobian`](crate::jacobian::StepJacobian), which keeps the structure it
//! learns from step to step), whenever
//! [`Acceleration::needs_jacobian`] says so: at the first step, after a change of the step
//! size, and after a step that needed more than one update (the interface has drifted away
//! from the Jacobian in use: the wheelsets moved, a load came on the deck). Between refreshes
//! the factorised `I − J` is reused, a chord (simplified Newton) iteration that converges at
//! the rate of that drift.

use super::Acceleration;
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// Newton (chord) update with a reused interface Jacobian.
#[derive(Debug, Clone)]
pub struct Newton {
    n: usize,
    lu: Option<LU<f64, Dyn, Dyn>>,
    h: Option<f64>,
    stale: bool,
    /// Updates performed in the current step.
    updates: usize,
    /// Jacobians computed so far.
    refreshes: usize,
}

impl Default for Newton {
    fn default() -> Self {
        Self::new()
    }
}

impl Newton {
    pub fn new() -> Self {
        Self {
            n: 0,
            lu: None,
            h: None,
            stale: true,
            updates: 0,
            refreshes: 0,
        }
    }

    /// How many interface Jacobians were computed.
    pub fn refreshes(&self) -> usize {
        self.refreshes
    }
}

impl Acceleration for Newton {
    fn name(&self) -> &str {
        "newton"
    }

    fn initialize(&mut self, n: usize) {
        self.n = n;
        self.lu = None;
        self.stale = true;
    }

    fn begin_step(&mut self, h: f64) {
        // (communication steps computed as t₁ − t differ in their last bits)
        if !self.h.is_some_and(|h0| (h - h0).abs() <= 1e-9 * h0.abs()) {
            self.h = Some(h);
            self.stale = true;
        }
        self.updates = 0;
    }

    fn needs_jacobian(&self) -> bool {
        self.stale || self.lu.is_none()
    }

    fn set_jacobian(&mut self, j: DMatrix<f64>) {
        assert_eq!(j.shape(), (self.n, self.n), "an n × n interface Jacobian");
        let m = DMatrix::identity(self.n, self.n) - j;
        self.lu = Some(m.lu());
        self.stale = false;
        self.refreshes += 1;
    }

    fn perform(&mut self, x: &[f64], x_tilde: &[f64], _scale: &[f64], next: &mut [f64]) {
        self.updates += 1;
        let r = DVector::from_iterator(x.len(), x_tilde.iter().zip(x).map(|(a, b)| a - b));
        match self.lu.as_ref().and_then(|lu| lu.solve(&r)) {
            Some(d) => {
                for ((n, xi), di) in next.iter_mut().zip(x).zip(d.iter()) {
                    *n = xi + di;
                }
            }
            // I − J singular: a plain fixed-point update, and a fresh Jacobian next step
            None => {
                next.copy_from_slice(x_tilde);
                self.stale = true;
            }
        }
    }

    fn end_step(&mut self, converged: bool) {
        if !converged || self.updates > 1 {
            self.stale = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On an affine map H(x) = A x + b with its exact Jacobian, one update lands on the
    /// fixed point x* = (I − A)⁻¹ b.
    #[test]
    fn one_update_solves_an_affine_map() {
        let a = DMatrix::from_row_slice(3, 3, &[0.5, -2.0, 0.1, 1.5, 0.2, 0.0, 0.3, 0.7, -3.0]);
        let b = DVector::from_row_slice(&[1.0, -2.0, 0.5]);
        let h = |x: &DVector<f64>| &a * x + &b;
        let exact = (DMatrix::identity(3, 3) - &a).lu().solve(&b).unwrap();
        let mut newton = Newton::new();
        newton.initialize(3);
        newton.begin_step(0.1);
        assert!(newton.needs_jacobian());
        newton.set_jacobian(a.clone());
        let x = DVector::from_row_slice(&[10.0, 3.0, -7.0]);
        let xt = h(&x);
        let mut next = [0.0; 3];
        newton.perform(x.as_slice(), xt.as_slice(), &[1.0; 3], &mut next);
        for i in 0..3 {
            assert!(
                (next[i] - exact[i]).abs() <= 1e-12 * exact.amax(),
                "{next:?} vs {exact}"
            );
        }
        newton.end_step(true);
        assert!(!newton.needs_jacobian(), "reused after a one-update step");
        newton.begin_step(0.2);
        assert!(
            newton.needs_jacobian(),
            "a new step size needs a new Jacobian"
        );
    }
}
