//! Secant columns of the quasi-Newton accelerations and their filtered least squares.
//!
//! [`Window`] keeps the columns `(vⱼ, wⱼ)` (residual and output differences) newest first,
//! grouped by time step, together with their scaled inner products
//! `Gₚ_q = (D vₚ)ᵀ(D v_q)`: a new column costs one pass over the columns already kept, and a
//! column leaving the window costs nothing. When the scaling `D` changes the inner products are
//! recomputed once.
//!
//! [`Cholesky`] solves `min ‖D (V c + r)‖₂` by the normal equations `G c = −(D V)ᵀ D r`,
//! factorising `G` column by column, newest first, and dropping column `j` when its pivot (the
//! squared norm of its part orthogonal to the columns accepted so far) is
//! `≤ limit² · ‖D vⱼ‖²`: the QR2 filter of preCICE. At most `n` columns are kept. The normal
//! equations square the condition of `D V`; the filter bounds it, and the pivots are resolved
//! to a relative accuracy of about `ε / limit²`, so limits below 1e-6 are raised to 1e-6. The
//! accuracy of an update affects only how fast the iteration converges, never the fixed point.

use std::collections::VecDeque;

use super::{scaled_dot, scaled_dots};

/// Smallest effective filter limit of the normal equations (see the module documentation).
const MIN_FILTER_LIMIT: f64 = 1e-6;

/// One secant pair with its inner products.
#[derive(Debug, Clone, Default)]
pub(super) struct Column {
    pub(super) v: Vec<f64>,
    pub(super) w: Vec<f64>,
    /// `(D v)ᵀ(D v)`.
    pub(super) norm2: f64,
    /// `(D v)ᵀ(D v_q)` with the columns older than this one, nearest first.
    dots: Vec<f64>,
}

/// The secant columns of the current step and of the reused steps, newest first.
#[derive(Debug, Clone, Default)]
pub(super) struct Window {
    pub(super) columns: VecDeque<Column>,
    /// Columns per step, newest step first; the first entry is the current step's.
    pub(super) per_step: VecDeque<usize>,
    /// The scaling the inner products were taken with.
    scale: Vec<f64>,
    /// Whether the newest entry of `per_step` is the current, unfinished step.
    open: bool,
    /// Vectors of dropped columns, reused for new ones.
    pub(super) spare: Vec<Vec<f64>>,
}

impl Window {
    pub(super) fn clear(&mut self) {
        while let Some(c) = self.columns.pop_front() {
            self.recycle(c);
        }
        self.per_step.clear();
        self.open = false;
    }

    pub(super) fn recycle(&mut self, c: Column) {
        self.spare.push(c.v);
        self.spare.push(c.w);
        self.spare.push(c.dots);
    }

    pub(super) fn vector(&mut self) -> Vec<f64> {
        let mut v = self.spare.pop().unwrap_or_default();
        v.clear();
        v
    }

    /// Starts a new (current) step with no columns.
    pub(super) fn open_step(&mut self) {
        self.per_step.push_front(0);
        self.open = true;
    }

    /// Drops the current step's columns, if a step is open.
    pub(super) fn drop_current(&mut self) {
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
    pub(super) fn close_step(&mut self, keep: usize) {
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
    pub(super) fn rescale(&mut self, scale: &[f64]) {
        if self.scale.as_slice() == scale {
            return;
        }
        self.scale.clear();
        self.scale.extend_from_slice(scale);
        let cols: Vec<&Vec<f64>> = self.columns.iter().map(|c| &c.v).collect();
        let fresh: Vec<(f64, Vec<f64>)> = (0..cols.len())
            .map(|p| {
                let mut dots = Vec::with_capacity(cols.len() - p - 1);
                let older = cols[p + 1..].iter().map(|q| q.as_slice());
                scaled_dots(cols[p], older, scale, &mut dots);
                (scaled_dot(cols[p], cols[p], scale), dots)
            })
            .collect();
        for (c, (norm2, dots)) in self.columns.iter_mut().zip(fresh) {
            c.norm2 = norm2;
            c.dots = dots;
        }
    }

    /// Adds the newest column `(v, w)` of the current step (`scale` as in [`Window::rescale`]).
    pub(super) fn push(&mut self, v: Vec<f64>, w: Vec<f64>, scale: &[f64]) {
        self.rescale(scale);
        let mut dots = self.vector();
        scaled_dots(
            &v,
            self.columns.iter().map(|c| c.v.as_slice()),
            scale,
            &mut dots,
        );
        let norm2 = scaled_dot(&v, &v, scale);
        self.columns.push_front(Column { v, w, norm2, dots });
        *self.per_step.front_mut().expect("a step is open") += 1;
    }

    /// `Gₚ_q` for `p < q`.
    pub(super) fn gram(&self, p: usize, q: usize) -> f64 {
        self.columns[p].dots[q - p - 1]
    }
}

/// Least squares `min ‖A c − b‖₂` over the columns `A = [a₀, a₁, …]` (each of length `n = b.len()`)
/// that pass a QR2 filter, taken in the given order: column `j` is dropped when the norm of its
/// part orthogonal to the columns kept so far is `≤ limit · ‖aⱼ‖` (or when it is zero or not
/// finite; `limit` is raised to 1e-6, see the module documentation), and at most `n` columns are
/// kept. Solved by the normal equations as in [`IqnIls`](super::iqn_ils::IqnIls). Returns `c` with `cⱼ = 0` for dropped
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
pub(super) struct Cholesky {
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
    pub(super) fn solve(
        &mut self,
        m: usize,
        n: usize,
        diag: impl Fn(usize) -> f64,
        gram: impl Fn(usize, usize) -> f64,
        rhs: &[f64],
        limit: f64,
        c: &mut Vec<f64>,
    ) {
        self.factor(m, n, diag, gram, limit);
        self.solve_factored(m, rhs, c);
    }

    /// Factorises `G` over the columns `0..m` that pass the filter (see [`Cholesky::solve`]).
    fn factor(
        &mut self,
        m: usize,
        n: usize,
        diag: impl Fn(usize) -> f64,
        gram: impl Fn(usize, usize) -> f64,
        limit: f64,
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
    }

    /// `G c = rhs` with the last factor (`rhs` and `c` indexed by column, `m` of them).
    fn solve_factored(&mut self, m: usize, rhs: &[f64], c: &mut Vec<f64>) {
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
}
