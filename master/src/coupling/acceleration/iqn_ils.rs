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
//! The columns are kept newest first together with their scaled inner products
//! `Gₚ_q = (D vₚ)ᵀ(D v_q)`: a new column costs one pass over the columns already kept, and a
//! column leaving the window costs nothing. The least squares are solved by the normal equations
//! `Gc = −(D V)ᵀ D rₖ` through a Cholesky factorisation taken column by column, newest first,
//! which drops column `j` when its pivot (the squared norm of its part orthogonal to the
//! columns accepted so far) is `≤ filter_limit² · ‖D vⱼ‖²`: the QR2 filter of preCICE, which
//! removes (nearly) linearly dependent, typically older, information. At most `n` columns are
//! kept. An update therefore costs `O(m n + m³)` for `m` columns instead of the `O(m² n)` of a
//! QR factorisation repeated in every iteration, so that reusing many steps pays. When the
//! scaling `D` changes (a block reaches a new largest magnitude) the inner products are
//! recomputed once.
//!
//! The normal equations square the condition of `D V`; the filter bounds it, and the pivots are
//! resolved to a relative accuracy of about `ε / filter_limit²` (1e-8 at the default limit),
//! so limits below 1e-6 are raised to 1e-6. The update's accuracy affects only how fast the
//! iteration converges, never the fixed point it converges to.
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

use super::{scaled_dot, Acceleration};

/// Smallest effective filter limit of the normal equations (see the module documentation).
const MIN_FILTER_LIMIT: f64 = 1e-6;

/// One secant pair with its inner products.
#[derive(Debug, Clone, Default)]
struct Column {
    v: Vec<f64>,
    w: Vec<f64>,
    /// `(D v)ᵀ(D v)`.
    norm2: f64,
    /// `(D v)ᵀ(D v_q)` with the columns older than this one, nearest first.
    dots: Vec<f64>,
}

/// The secant columns of the current step and of the reused steps, newest first.
#[derive(Debug, Clone, Default)]
struct Window {
    columns: VecDeque<Column>,
    /// Columns per step, newest step first; the first entry is the current step's.
    per_step: VecDeque<usize>,
    /// The scaling the inner products were taken with.
    scale: Vec<f64>,
    /// Whether the newest entry of `per_step` is the current, unfinished step.
    open: bool,
    /// Vectors of dropped columns, reused for new ones.
    spare: Vec<Vec<f64>>,
}

impl Window {
    fn clear(&mut self) {
        while let Some(c) = self.columns.pop_front() {
            self.recycle(c);
        }
        self.per_step.clear();
        self.open = false;
    }

    fn recycle(&mut self, c: Column) {
        self.spare.push(c.v);
        self.spare.push(c.w);
        self.spare.push(c.dots);
    }

    fn vector(&mut self) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v
    }

    /// Starts a new (current) step with no columns.
    fn open_step(&mut self) {
        self.per_step.push_front(0);
        self.open = true;
    }

    /// Drops the current step's columns, if a step is open.
    fn drop_current(&mut self) {
        if !std::mem::take(&mut self.open) {
            return;
        }
        let k = self.per_step.pop_front().expect("a step is open");
        for _ in 0..k {
            let c = self.columns.pop_front().expect("counted");
            self.recycle(c);
        }
    }

    /// Keeps the current step's columns (if any) and at most `keep` steps in all.
    fn close_step(&mut self, keep: usize) {
        if std::mem::take(&mut self.open) && self.per_step.front() == Some(&0) {
            self.per_step.pop_front();
        }
        while self.per_step.len() > keep {
            let k = self.per_step.pop_back().expect("longer than keep");
            for _ in 0..k {
                let c = self.columns.pop_back().expect("counted");
                self.recycle(c);
            }
        }
        let len = self.columns.len();
        for (p, c) in self.columns.iter_mut().enumerate() {
            c.dots.truncate(len - 1 - p);
        }
    }

    /// Inner products under `scale`, recomputed when it differs from the one they were taken
    /// with.
    fn rescale(&mut self, scale: &[f64]) {
        if self.scale.as_slice() == scale {
            return;
        }
        self.scale.clear();
        self.scale.extend_from_slice(scale);
        let cols: Vec<&Vec<f64>> = self.columns.iter().map(|c| &c.v).collect();
        let fresh: Vec<(f64, Vec<f64>)> = (0..cols.len())
            .map(|p| {
                let dots = cols[p + 1..]
                    .iter()
                    .map(|q| scaled_dot(cols[p], q, scale))
                    .collect();
                (scaled_dot(cols[p], cols[p], scale), dots)
            })
            .collect();
        for (c, (norm2, dots)) in self.columns.iter_mut().zip(fresh) {
            c.norm2 = norm2;
            c.dots = dots;
        }
    }

    /// Adds the newest column `(v, w)` of the current step (`scale` as in [`Window::rescale`]).
    fn push(&mut self, v: Vec<f64>, w: Vec<f64>, scale: &[f64]) {
        self.rescale(scale);
        let mut dots = self.vector();
        dots.extend(self.columns.iter().map(|c| scaled_dot(&v, &c.v, scale)));
        let norm2 = scaled_dot(&v, &v, scale);
        self.columns.push_front(Column { v, w, norm2, dots });
        *self.per_step.front_mut().expect("a step is open") += 1;
    }

    /// `Gₚ_q` for `p < q`.
    fn gram(&self, p: usize, q: usize) -> f64 {
        self.columns[p].dots[q - p - 1]
    }
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
        if let Some((pr, pt)) = self.prev.take() {
            let v = self.vector(n, |i| r[i] - pr[i]);
            let w = self.vector(n, |i| x_tilde[i] - pt[i]);
            self.window.push(v, w, scale);
            self.window.spare.push(pr);
            self.window.spare.push(pt);
        } else {
            self.window.rescale(scale);
        }
        // −(D V)ᵀ D r, newest column first.
        self.rhs.clear();
        self.rhs.extend(
            self.window
                .columns
                .iter()
                .map(|c| -scaled_dot(&c.v, &r, scale)),
        );
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
                    for (n, &wi) in next.iter_mut().zip(col.w.iter()) {
                        *n += cj * wi;
                    }
                }
            }
        }
        let t = self.vector(n, |i| x_tilde[i]);
        self.prev = Some((r, t));
    }

    fn end_step(&mut self, converged: bool) {
        self.forget_previous();
        if !(converged && self.reuse_steps > 0) {
            self.window.drop_current();
        }
        self.window.close_step(self.reuse_steps);
    }
}

/// Least squares `min ‖A c − b‖₂` over the columns `A = [a₀, a₁, …]` (each of length `n = b.len()`)
/// that pass a QR2 filter, taken in the given order: column `j` is dropped when the norm of its
/// part orthogonal to the columns kept so far is `≤ limit · ‖aⱼ‖` (or when it is zero or not
/// finite; `limit` is raised to 1e-6, see the module documentation), and at most `n` columns are
/// kept. Solved by the normal equations as in [`IqnIls`]. Returns `c` with `cⱼ = 0` for dropped
/// columns.
pub fn filtered_least_squares(columns: &[Vec<f64>], b: &[f64], limit: f64) -> Vec<f64> {
    let ones = vec![1.0; b.len()];
    let rhs: Vec<f64> = columns.iter().map(|a| scaled_dot(a, b, &ones)).collect();
    let mut c = Vec::new();
    Cholesky::default().solve(
        columns.len(),
        b.len(),
        |p| scaled_dot(&columns[p], &columns[p], &ones),
        |p, q| scaled_dot(&columns[p], &columns[q], &ones),
        &rhs,
        limit,
        &mut c,
    );
    c
}

/// The filtered normal-equation solver of [`IqnIls`] with its workspace (no allocation once it
/// has grown).
#[derive(Debug, Clone, Default)]
struct Cholesky {
    /// Rows of the factor `L` of the kept columns, row `a` holding `a + 1` entries.
    l: Vec<f64>,
    kept: Vec<usize>,
    y: Vec<f64>,
}

impl Cholesky {
    /// Solves `G c = rhs` over the columns `0..m` that pass the filter, `G` given by its
    /// diagonal `diag(p)` and its entries `gram(p, q)` for `p < q`; at most `n` columns are
    /// kept. `c` gets `m` entries, 0 for dropped columns.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        m: usize,
        n: usize,
        diag: impl Fn(usize) -> f64,
        gram: impl Fn(usize, usize) -> f64,
        rhs: &[f64],
        limit: f64,
        c: &mut Vec<f64>,
    ) {
        let limit2 = limit.max(MIN_FILTER_LIMIT).powi(2);
        self.l.clear();
        self.kept.clear();
        // Row a of L starts at a (a + 1) / 2.
        for p in 0..m {
            if self.kept.len() == n {
                break;
            }
            let gpp = diag(p);
            if !(gpp > 0.0 && gpp.is_finite()) {
                continue;
            }
            let start = self.l.len();
            let mut d = gpp;
            for (a, &ka) in self.kept.iter().enumerate() {
                let row_a = a * (a + 1) / 2;
                let mut s = gram(ka, p);
                for b in 0..a {
                    s -= self.l[start + b] * self.l[row_a + b];
                }
                let lpa = s / self.l[row_a + a];
                self.l.push(lpa);
                d -= lpa * lpa;
            }
            if d.is_nan() || d <= limit2 * gpp {
                self.l.truncate(start);
                continue;
            }
            self.l.push(d.sqrt());
            self.kept.push(p);
        }
        // L y = rhs (kept), then Lᵀ z = y.
        let k = self.kept.len();
        self.y.clear();
        for a in 0..k {
            let row = a * (a + 1) / 2;
            let mut s = rhs[self.kept[a]];
            for b in 0..a {
                s -= self.l[row + b] * self.y[b];
            }
            self.y.push(s / self.l[row + a]);
        }
        for a in (0..k).rev() {
            let row = a * (a + 1) / 2;
            self.y[a] /= self.l[row + a];
            let ya = self.y[a];
            for b in 0..a {
                self.y[b] -= self.l[row + b] * ya;
            }
        }
        c.clear();
        c.resize(m, 0.0);
        for (&p, &yp) in self.kept.iter().zip(&self.y) {
            c[p] = yp;
        }
    }
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
            vec![2.0, 4.0, 1e-4], // nearly parallel to the first: 2.2e-5 of it is orthogonal
            vec![0.0, 0.0, 1.0],  // in the span of the first two
        ];
        // b is not in span{a₀, a₂}: the filtered solution is its projection there.
        let b = [1.0, 2.5, 3.0];
        let c = filtered_least_squares(&a, &b, 1e-2);
        assert_eq!(c[1], 0.0);
        assert!(
            (c[0] - 1.2).abs() < 1e-14 && (c[2] - 3.0).abs() < 1e-14,
            "{c:?}"
        );
        // Below the nearly parallel column's orthogonal part it is kept, the third column is
        // then dependent and dropped, and b's third component is fitted by a₁ with a huge
        // coefficient: 1e-4 c₁ = 3.
        let c = filtered_least_squares(&a, &b, 1e-6);
        assert_eq!(c[2], 0.0, "{c:?}");
        assert!((c[1] / 3e4 - 1.0).abs() < 1e-6, "{c:?}");
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
