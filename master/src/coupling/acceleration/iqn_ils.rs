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
//! optionally followed by the columns of the last `reuse_steps` converged steps. The residual
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
//! [`Implicit`](crate::coupling::Implicit)). Without it the least-squares problem would fit
//! only the largest-magnitude variables (forces ~1e5 N) and ignore small ones (displacements
//! ~1e-3 m). The columns are stored unscaled, so reused columns are scaled with the scaling of
//! the step that uses them. The coefficients `c` are dimensionless and apply to the unscaled
//! `W`.
//!
//! # Least squares and filtering
//!
//! `D V` is factorised `Q R` by modified Gram–Schmidt with one reorthogonalisation pass,
//! column by column, newest first. A column whose part orthogonal to the columns already
//! accepted has norm `≤ filter_limit · ‖column‖` (preCICE's QR2 filter) is dropped for this
//! solve, which removes (nearly) linearly dependent, typically older, information. At most `n`
//! columns are kept. Then `R c = −Qᵀ D rₖ` is solved by back substitution.
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

use std::collections::VecDeque;

use super::Acceleration;

/// The columns of one time step, oldest first.
#[derive(Debug, Clone, Default)]
struct Columns {
    v: Vec<Vec<f64>>,
    w: Vec<Vec<f64>>,
}

/// IQN-ILS quasi-Newton acceleration.
#[derive(Debug, Clone)]
pub struct IqnIls {
    initial: f64,
    reuse_steps: usize,
    filter_limit: f64,
    h: Option<f64>,
    /// `(rₖ, x̃ₖ)` of the previous iteration of the current step.
    prev: Option<(Vec<f64>, Vec<f64>)>,
    current: Columns,
    /// Columns of previous converged steps, newest step first.
    reused: VecDeque<Columns>,
    used_columns: usize,
    /// Buffers of an update (no allocation per iteration once they have grown): the
    /// least-squares workspace, the scaled right-hand side, the coefficients and column
    /// vectors given back by dropped steps.
    ls: LeastSquares,
    rhs: Vec<f64>,
    coefficients: Vec<f64>,
    spare: Vec<Vec<f64>>,
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
            current: Columns::default(),
            reused: VecDeque::new(),
            used_columns: 0,
            ls: LeastSquares::default(),
            rhs: Vec::new(),
            coefficients: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// A vector of `n` values from `f`, in a recycled allocation when there is one.
    fn vector(&mut self, n: usize, f: impl Fn(usize) -> f64) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v.extend((0..n).map(f));
        v
    }

    /// Give the vectors of `c` back for reuse.
    fn recycle(&mut self, c: Columns) {
        self.spare.extend(c.v);
        self.spare.extend(c.w);
    }

    /// Relative limit of the QR2 filter (default 1e-4).
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
        self.prev = None;
        self.current = Columns::default();
        self.reused.clear();
        self.used_columns = 0;
    }

    fn begin_step(&mut self, h: f64) {
        // The Jacobian of H depends on the step size: columns of other step sizes mislead.
        if self.h.is_some_and(|old| (old - h).abs() > 1e-9 * h.abs()) {
            self.reused.clear();
        }
        self.h = Some(h);
        if let Some((r, t)) = self.prev.take() {
            self.spare.push(r);
            self.spare.push(t);
        }
        let current = std::mem::take(&mut self.current);
        self.recycle(current);
    }

    fn perform(&mut self, x: &[f64], x_tilde: &[f64], scale: &[f64], next: &mut [f64]) {
        let n = x.len();
        let r = self.vector(n, |i| x_tilde[i] - x[i]);
        if let Some((pr, pt)) = self.prev.take() {
            let v = self.vector(n, |i| r[i] - pr[i]);
            let w = self.vector(n, |i| x_tilde[i] - pt[i]);
            self.current.v.push(v);
            self.current.w.push(w);
            self.spare.push(pr);
            self.spare.push(pt);
        }
        // Newest first: this step's columns, then those of the previous steps.
        let columns = self
            .current
            .v
            .iter()
            .zip(&self.current.w)
            .rev()
            .chain(self.reused.iter().flat_map(|c| c.v.iter().zip(&c.w).rev()));
        self.rhs.clear();
        self.rhs.extend(r.iter().zip(scale).map(|(&r, &s)| -r * s));
        self.ls.solve(
            columns.clone().map(|(v, _)| v.as_slice()),
            scale,
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
            for (&cj, (_, w)) in c.iter().zip(columns) {
                if cj != 0.0 {
                    for (n, &wi) in next.iter_mut().zip(w.iter()) {
                        *n += cj * wi;
                    }
                }
            }
        }
        let t = self.vector(n, |i| x_tilde[i]);
        self.prev = Some((r, t));
    }

    fn end_step(&mut self, converged: bool) {
        let columns = std::mem::take(&mut self.current);
        if let Some((r, t)) = self.prev.take() {
            self.spare.push(r);
            self.spare.push(t);
        }
        if converged && self.reuse_steps > 0 && !columns.v.is_empty() {
            self.reused.push_front(columns);
            while self.reused.len() > self.reuse_steps {
                let old = self.reused.pop_back().expect("longer than reuse_steps");
                self.recycle(old);
            }
        } else {
            self.recycle(columns);
        }
    }
}

/// Least squares `min ‖A c − b‖₂` over the columns `A = [a₀, a₁, …]` (each of length `n = b.len()`)
/// that pass a QR2 filter, taken in the given order: modified Gram–Schmidt with one
/// reorthogonalisation pass; column `j` is dropped when the norm of its part orthogonal to the
/// columns kept so far is `≤ limit · ‖aⱼ‖` (or when it is zero or not finite), and at most `n`
/// columns are kept. Returns `c` with `cⱼ = 0` for dropped columns.
pub fn filtered_least_squares(columns: &[Vec<f64>], b: &[f64], limit: f64) -> Vec<f64> {
    let mut c = Vec::new();
    let ones = vec![1.0; b.len()];
    LeastSquares::default().solve(columns.iter().map(Vec::as_slice), &ones, b, limit, &mut c);
    c
}

/// The workspace of [`filtered_least_squares`], kept between solves so that they allocate
/// nothing once it has grown.
#[derive(Debug, Clone, Default)]
struct LeastSquares {
    /// Orthonormal columns kept, and column j of R (length j + 1) for each.
    q: Vec<Vec<f64>>,
    r: Vec<Vec<f64>>,
    kept: Vec<usize>,
    y: Vec<f64>,
}

impl LeastSquares {
    /// [`filtered_least_squares`] of the columns `D aⱼ` (`D = diag(scale)`, applied on the fly)
    /// into `c`.
    fn solve<'a>(
        &mut self,
        columns: impl Iterator<Item = &'a [f64]>,
        scale: &[f64],
        b: &[f64],
        limit: f64,
        c: &mut Vec<f64>,
    ) {
        let n = b.len();
        let mut m = 0; // columns kept
        self.kept.clear();
        let mut count = 0;
        for (j, a) in columns.enumerate() {
            count = j + 1;
            if m == n {
                continue;
            }
            assert_eq!(a.len(), n, "least-squares column {j} has the wrong length");
            if self.q.len() <= m {
                self.q.push(Vec::new());
                self.r.push(Vec::new());
            }
            let (done, rest) = self.q.split_at_mut(m);
            let v = &mut rest[0];
            v.clear();
            v.extend(a.iter().zip(scale).map(|(&a, &s)| a * s));
            let norm_a = norm(v);
            if norm_a == 0.0 || !norm_a.is_finite() {
                continue;
            }
            let rj = &mut self.r[m];
            rj.clear();
            rj.resize(m + 1, 0.0);
            for _pass in 0..2 {
                for (i, qi) in done.iter().enumerate() {
                    let p = dot(qi, v);
                    rj[i] += p;
                    v.iter_mut().zip(qi).for_each(|(v, &qk)| *v -= p * qk);
                }
            }
            let rho = norm(v);
            if rho <= limit * norm_a {
                continue;
            }
            v.iter_mut().for_each(|v| *v /= rho);
            rj[m] = rho;
            self.kept.push(j);
            m += 1;
        }
        // R y = Qᵀ b by back substitution (R stored by columns).
        self.y.clear();
        self.y.extend(self.q[..m].iter().map(|qi| dot(qi, b)));
        let y = &mut self.y;
        for i in (0..m).rev() {
            y[i] /= self.r[i][i];
            let yi = y[i];
            for (k, yk) in y.iter_mut().enumerate().take(i) {
                *yk -= self.r[i][k] * yi;
            }
        }
        c.clear();
        c.resize(count, 0.0);
        for (&j, &yj) in self.kept.iter().zip(y.iter()) {
            c[j] = yj;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(&a, &b)| a * b).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coupling_least_squares_matches_normal_equations() {
        // A = [[1, 0], [1, 1], [1, 2]], b = [1, 2, 4]: c = (AᵀA)⁻¹Aᵀb = [5/6, 3/2].
        let a = vec![vec![1.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]];
        let c = filtered_least_squares(&a, &[1.0, 2.0, 4.0], 1e-12);
        assert!((c[0] - 5.0 / 6.0).abs() < 1e-14, "{c:?}");
        assert!((c[1] - 1.5).abs() < 1e-14, "{c:?}");
    }

    #[test]
    fn coupling_least_squares_drops_dependent_columns() {
        let a = vec![
            vec![1.0, 2.0, 0.0],
            vec![2.0, 4.0, 1e-9], // nearly parallel to the first
            vec![0.0, 0.0, 1.0],
        ];
        // b is not in span{a₀, a₂}: the filtered solution is its projection there.
        let b = [1.0, 2.5, 3.0];
        let c = filtered_least_squares(&a, &b, 1e-2);
        assert_eq!(c[1], 0.0);
        assert!(
            (c[0] - 1.2).abs() < 1e-14 && (c[2] - 3.0).abs() < 1e-14,
            "{c:?}"
        );
        // Without the filter the nearly parallel column is kept and fits b exactly with a
        // huge coefficient.
        let c = filtered_least_squares(&a, &b, 0.0);
        assert!(c[1].abs() > 1e6, "{c:?}");
    }

    #[test]
    fn coupling_least_squares_keeps_at_most_n_columns() {
        let a = vec![vec![1.0, 0.0], vec![0.0, 1.0], vec![1.0, 1.0]];
        let c = filtered_least_squares(&a, &[2.0, 3.0], 0.0);
        assert_eq!(c, vec![2.0, 3.0, 0.0]);
    }

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
}
