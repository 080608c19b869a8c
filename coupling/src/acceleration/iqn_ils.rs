//! Interface quasi-Newton with an inverse Jacobian from a least-squares model (IQN-ILS;
//! Degroote, Bathe & Vierendeels 2009; the default quasi-Newton method of preCICE).
//!
//! # Update
//!
//! In iteration `k ≥ 1` of a step the differences of the previous iterates are collected,
//! newest first,
//!
//! ```text
//! V = [rₖ − rₖ₋₁, rₖ₋₁ − rₖ₋₂, …, r₁ − r₀]     (residual differences)
//! W = [x̃ₖ − x̃ₖ₋₁, x̃ₖ₋₁ − x̃ₖ₋₂, …, x̃₁ − x̃₀]  (output differences)
//! ```
//!
//! optionally followed by the columns of the last `reuse_steps` converged steps. The sweep that
//! meets the convergence criterion adds its differences too ([`Acceleration::converged`], as
//! preCICE's `iterationsConverged`), so a step that converged in its second sweep leaves the
//! column `(r₁ − r₀, x̃₁ − x̃₀)`, the map on the direction of its first residual, for the steps
//! after it. Without those columns a reused step would bring one column fewer, and a step of
//! two sweeps none: on the bench case of `tbi bench` 2.47 sweeps per step instead of 2.10.
//! The residual
//! change that would cancel `rₖ` is approximated in the span of `V`, `−rₖ ≈ V c`, and the same
//! combination of output changes is applied:
//!
//! ```text
//! c = argmin ‖D (V c + rₖ)‖₂ ,   xₖ₊₁ = x̃ₖ + W c ,
//! ```
//!
//! which is `xₖ₊₁ = xₖ + J⁻¹(−rₖ)` with the minimum-norm inverse Jacobian `J⁻¹` of the residual
//! that satisfies the secant equations `J⁻¹ V = W − V`. For a linear `H` on `ℝⁿ` (where the
//! method is equivalent to GMRES) `xₙ₊₁` is the fixed point in exact arithmetic: at most `n + 2`
//! sweeps, the last one confirming convergence.
//!
//! # Scaling
//!
//! `D = diag(s)` is the per-variable scaling handed in by the scheme (`sᵢ = 1 / (rtol·X + atol)`
//! with `X` the magnitude of the variable's block, normalised to `max sᵢ = 1`; see
//! [`Implicit`](crate::Implicit)). Without it the least-squares problem would fit
//! only the largest-magnitude variables (forces ~1e5 N) and ignore small ones (displacements
//! ~1e-3 m). The columns are stored unscaled, so reused columns are scaled with the scaling of
//! the step that uses them. The coefficients `c` are dimensionless and apply to the unscaled
//! `W`.
//!
//! # Least squares and filtering
//!
//! The columns and their inner products are kept in a [`Window`] and the least squares solved
//! by the filtered normal equations of [`Cholesky`] (see [`super::secant`]): an update costs
//! `O(m n + m³)` for `m` columns instead of the `O(m² n)` of a QR factorisation repeated in
//! every iteration, so that reusing many steps pays. A column whose part orthogonal to the
//! newer columns kept has norm `≤ filter_limit · ‖D v‖` is dropped for the solve (preCICE's QR2
//! filter), which removes (nearly) linearly dependent, typically older, information.
//!
//! The default limit 1e-4 sits above the relative round-off of difference columns formed near
//! convergence (machine ε / rtol ≈ 1e-6 for rtol = 1e-10), so directions that are pure noise
//! are dropped, and well below the near-dependence that costs iterations on linear interfaces
//! (preCICE's tutorials use 1e-2 to 1e-3 for nonlinear flow problems).
//!
//! # First iteration
//!
//! With no columns (the first iteration of a step, unless columns of earlier steps are reused)
//! the update is constant relaxation `x₁ = x₀ + ω r₀`.

use super::secant::{Cholesky, Window};
use super::{scaled_dots, Acceleration};

/// IQN-ILS quasi-Newton acceleration.
#[derive(Debug, Clone)]
pub struct IqnIls {
    initial: f64,
    reuse_steps: usize,
    filter_limit: f64,
    h: Option<f64>,
    /// `(rₖ, x̃ₖ)` of the previous iteration of the current step.
    prev: Option<(Vec<f64>, Vec<f64>)>,
    window: Window,
    used_columns: usize,
    /// Buffers of an update (no allocation per iteration once they have grown).
    ls: Cholesky,
    rhs: Vec<f64>,
    coefficients: Vec<f64>,
}

impl IqnIls {
    /// `initial`: relaxation factor of the first iteration (e.g. 0.5); `reuse_steps`: number of
    /// previous converged steps whose columns enter the least-squares problem (0: none).
    pub fn new(initial: f64, reuse_steps: usize) -> Self {
        Self {
            initial,
            reuse_steps,
            filter_limit: 1e-4,
            h: None,
            prev: None,
            window: Window::default(),
            used_columns: 0,
            ls: Cholesky::default(),
            rhs: Vec::new(),
            coefficients: Vec::new(),
        }
    }

    /// A vector of `n` values from `f`, in a recycled allocation when there is one.
    fn vector(&mut self, n: usize, f: impl Fn(usize) -> f64) -> Vec<f64> {
        let mut v = self.window.vector();
        v.extend((0..n).map(f));
        v
    }

    /// The column `(r − rₖ₋₁, x̃ − x̃ₖ₋₁)` of this sweep's residual `r(i)` and outputs against
    /// the step's previous sweep, pushed into the window; false when there is none.
    fn push_difference(
        &mut self,
        r: impl Fn(usize) -> f64,
        x_tilde: &[f64],
        scale: &[f64],
    ) -> bool {
        let Some((pr, pt)) = self.prev.take() else {
            return false;
        };
        let n = x_tilde.len();
        let v = self.vector(n, |i| r(i) - pr[i]);
        let w = self.vector(n, |i| x_tilde[i] - pt[i]);
        self.window.push(v, w, scale);
        self.window.spare.push(pr);
        self.window.spare.push(pt);
        true
    }

    fn forget_previous(&mut self) {
        if let Some((r, t)) = self.prev.take() {
            self.window.spare.push(r);
            self.window.spare.push(t);
        }
    }

    /// Relative limit of the QR2 filter (default 1e-4; at least 1e-6).
    pub fn with_filter_limit(mut self, limit: f64) -> Self {
        self.filter_limit = limit;
        self
    }

    /// Columns that survived the filter in the last update (0: constant relaxation was used).
    pub fn used_columns(&self) -> usize {
        self.used_columns
    }
}

impl Acceleration for IqnIls {
    fn name(&self) -> &str {
        "iqn-ils"
    }

    fn initialize(&mut self, _n: usize) {
        self.h = None;
        self.forget_previous();
        self.window.clear();
        self.used_columns = 0;
    }

    fn begin_step(&mut self, h: f64) {
        self.forget_previous();
        // An unfinished step's columns are forgotten.
        self.window.drop_current();
        // The Jacobian of H depends on the step size: columns of other step sizes mislead.
        if self.h.is_some_and(|old| (old - h).abs() > 1e-9 * h.abs()) {
            self.window.clear();
        }
        self.h = Some(h);
        self.window.open_step();
    }

    fn perform(&mut self, x: &[f64], x_tilde: &[f64], scale: &[f64], next: &mut [f64]) {
        let n = x.len();
        let r = self.vector(n, |i| x_tilde[i] - x[i]);
        if !self.push_difference(|i| r[i], x_tilde, scale) {
            self.window.rescale(scale);
        }
        // −(D V)ᵀ D r, newest column first.
        self.rhs.clear();
        let columns = self.window.columns.iter().map(|c| c.v.as_slice());
        scaled_dots(&r, columns, scale, &mut self.rhs);
        self.rhs.iter_mut().for_each(|d| *d = -*d);
        let window = &self.window;
        self.ls.solve(
            window.columns.len(),
            n,
            |p| window.columns[p].norm2,
            |p, q| window.gram(p, q),
            &self.rhs,
            self.filter_limit,
            &mut self.coefficients,
        );
        let c = &self.coefficients;
        self.used_columns = c.iter().filter(|&&c| c != 0.0).count();
        if self.used_columns == 0 {
            for ((n, &x), &r) in next.iter_mut().zip(x).zip(&r) {
                *n = x + self.initial * r;
            }
        } else {
            next.copy_from_slice(x_tilde);
            for (&cj, col) in c.iter().zip(&self.window.columns) {
                if cj != 0.0 {
                    // nᵢ + cⱼ wᵢ, vectorised where the processor allows (the same roundings)
                    tbi_numerics::simd::axpy(next, cj, &col.w);
                }
            }
        }
        let t = self.vector(n, |i| x_tilde[i]);
        self.prev = Some((r, t));
    }

    /// The converged sweep's differences join the step's columns (kept by
    /// [`Acceleration::end_step`] for the steps that reuse them; without reused steps the
    /// step's columns are dropped, and so is this one).
    fn converged(&mut self, x: &[f64], x_tilde: &[f64], scale: &[f64]) {
        if self.reuse_steps == 0 {
            return;
        }
        self.push_difference(|i| x_tilde[i] - x[i], x_tilde, scale);
    }

    fn end_step(&mut self, converged: bool) {
        self.forget_previous();
        if !(converged && self.reuse_steps > 0) {
            self.window.drop_current();
        }
        self.window.close_step(self.reuse_steps);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coupling_iqn_ils_solves_linear_fixed_point_in_n_plus_two_sweeps() {
        // H(x) = A x + b with a non-symmetric A of spectral radius > 1.
        let a = [[-2.0, 0.5, 0.0], [0.3, -1.5, 0.2], [0.0, 0.4, 0.8]];
        let b = [1.0, -2.0, 0.5];
        let h = |x: &[f64]| -> Vec<f64> {
            (0..3)
                .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i])
                .collect()
        };
        let mut acc = IqnIls::new(0.5, 0);
        acc.initialize(3);
        acc.begin_step(1.0);
        let scale = [1.0; 3];
        let mut x = vec![0.0; 3];
        let mut sweeps = 0;
        loop {
            let xt = h(&x);
            sweeps += 1;
            let r: f64 = xt
                .iter()
                .zip(&x)
                .map(|(t, x)| (t - x).abs())
                .fold(0.0, f64::max);
            if r < 1e-12 {
                break;
            }
            assert!(
                sweeps <= 5,
                "no convergence after {sweeps} sweeps (|r| = {r})"
            );
            let mut next = vec![0.0; 3];
            acc.perform(&x, &xt, &scale, &mut next);
            x = next;
        }
        assert_eq!(
            sweeps, 5,
            "n + 1 updates for n = 3, then the confirming sweep"
        );
    }

    #[test]
    fn a_step_converged_in_its_second_sweep_leaves_its_column() {
        // H(x) = A x + b, A = diag(0.5, −0.3). Step 1: b along e₁, and the first update, the
        // relaxation x₀ + 2 r₀, lands on the fixed point (2 = 1 / (1 − 0.5)), so the second
        // sweep converges without a secant update.
        let h = |x: &[f64], b: [f64; 2]| vec![0.5 * x[0] + b[0], -0.3 * x[1] + b[1]];
        let scale = [1.0; 2];
        let mut acc = IqnIls::new(2.0, 1);
        acc.initialize(2);
        acc.begin_step(0.1);
        let b1 = [1.0, 0.0];
        let x0 = vec![0.0; 2];
        let mut x1 = vec![0.0; 2];
        acc.perform(&x0, &h(&x0, b1), &scale, &mut x1);
        assert_eq!(acc.used_columns(), 0);
        assert_eq!(x1, vec![2.0, 0.0]);
        acc.converged(&x1, &h(&x1, b1), &scale);
        acc.end_step(true);
        // Step 2 from x₀ = (0, 0) with b = (3, 1): the first update fits r₀ with the column
        // step 1 left, (r₁ − r₀, x̃₁ − x̃₀) = ((0, 0) − (1, 0), (2, 0) − (1, 0)), which carries
        // the map on e₁ exactly; the rest, along e₂, is a Gauss–Seidel step.
        acc.begin_step(0.1);
        let b2 = [3.0, 1.0];
        let mut next = vec![0.0; 2];
        acc.perform(&x0, &h(&x0, b2), &scale, &mut next);
        assert_eq!(
            acc.used_columns(),
            1,
            "the converged sweep's column is reused"
        );
        assert!((next[0] - 6.0).abs() < 1e-14, "{next:?}");
        assert!((next[1] - 1.0).abs() < 1e-14, "{next:?}");
    }
}
