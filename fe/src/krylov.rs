//! Lowest eigenpairs of `K φ = ω² M φ` by a block Krylov subspace of the shift-invert operator
//! `K⁻¹ M`, for the large sparse models (thousands of DOFs, tens of modes wanted).
//!
//! # Method
//!
//! `K = L Lᵀ` by a sparse Cholesky factorisation (faer, fill-reducing ordering). From a block of
//! `b` pseudo-random vectors (fixed seed: the result is deterministic) the basis `V`, M-orthonormal
//! (`Vᵀ M V = I`), is extended block by block with `K⁻¹ M` applied to the newest block; every
//! new vector is M-orthogonalised against all earlier ones twice (Gram–Schmidt with
//! reorthogonalisation). After `j` blocks `V` spans the block Krylov space
//! `span{X₀, (K⁻¹M) X₀, …, (K⁻¹M)ʲ⁻¹ X₀}`, in which the largest eigenvalues `1/ω²` of `K⁻¹M`
//! (the lowest modes) converge first. Rayleigh–Ritz: the pairs `(λ, y)` of `(Vᵀ K V) y = λ y`,
//! ascending, give `φ = V y` with `φᵀ M φ = 1`. The lowest `n` pairs are accepted when every one
//! has
//!
//! ```text
//! ‖λ K⁻¹ M φ − φ‖_M ≤ 1e-12
//! ```
//!
//! (formed with one more solve, without the cancellation of `K φ − λ M φ`):
//!
//! `φ` is an eigenvector of `K⁻¹M` to a relative residual of 1e-12, and `λ` is accurate to
//! about the square of that. A block of `b = 8` resolves eigenvalues of multiplicity up to 8
//! (the identical cables of a symmetric bridge give pairs), which a single-vector Lanczos
//! process would not.
//!
//! # Cost
//!
//! A sparse factorisation, one sparse solve per basis vector and `O(N k²)` for orthogonalising
//! `k` basis vectors of length `N` (`k` ≈ 2–3 × the modes wanted), instead of the `O(N³)` of the
//! dense reduction. Returns `None` (the caller falls back to the dense solution) when `K` is not
//! positive definite or the basis would exhaust the space.

use crate::sparse::SparseMatrix;
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatRef, Par, Side};

/// Block size.
const BLOCK: usize = 8;
/// Accepted shift-invert residual of a pair (see the module documentation).
const TOLERANCE: f64 = 1e-12;

/// `aᵀ b`, summed in four interleaved partial sums (element `i` into sum `i mod 4`), then
/// `(s₀ + s₁) + (s₂ + s₃)`: a fixed order, independent of the machine, that lets the
/// compiler keep the sums in vector registers.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut s = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail = ca.remainder().iter().zip(cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    for (k, (x, y)) in tail.enumerate() {
        s[k] += x * y;
    }
    (s[0] + s[1]) + (s[2] + s[3])
}

/// The M-orthonormal basis with `M V` beside it, column after column (column-major `N × k`).
struct Basis {
    n: usize,
    v: Vec<f64>,
    mv: Vec<f64>,
}

impl Basis {
    fn len(&self) -> usize {
        self.v.len() / self.n
    }

    /// Columns `range` of `V`.
    fn v(&self, range: std::ops::Range<usize>) -> MatRef<'_, f64> {
        MatRef::from_column_major_slice(
            &self.v[range.start * self.n..range.end * self.n],
            self.n,
            range.len(),
        )
    }

    /// Columns `range` of `M V`.
    fn mv(&self, range: std::ops::Range<usize>) -> MatRef<'_, f64> {
        MatRef::from_column_major_slice(
            &self.mv[range.start * self.n..range.end * self.n],
            self.n,
            range.len(),
        )
    }

    /// Appends the columns of `block` M-orthonormalised: first twice projected off the basis
    /// as a block (`W ← W − V (M V)ᵀ W`, matrix products), then each column off the columns
    /// appended before it, twice, and normalised. A column of which less than 1e-8 of its
    /// M-norm is left (nothing independent) is replaced by `fresh()`, orthogonalised in
    /// the same way on its own.
    fn append_block(
        &mut self,
        mut block: Mat<f64>,
        m: &SparseMatrix,
        mut fresh: impl FnMut() -> Vec<f64>,
    ) {
        let n = self.n;
        let mut mw = vec![0.0; n];
        let norms0: Vec<f64> = (0..block.ncols())
            .map(|j| {
                m.mul(
                    block
                        .col(j)
                        .try_as_col_major()
                        .expect("contiguous")
                        .as_slice(),
                    &mut mw,
                );
                dot(
                    block
                        .col(j)
                        .try_as_col_major()
                        .expect("contiguous")
                        .as_slice(),
                    &mw,
                )
                .max(0.0)
                .sqrt()
            })
            .collect();
        self.project_out(&mut block, 0..self.len());
        let first = self.len();
        for (j, &norm0) in norms0.iter().enumerate() {
            let w: Vec<f64> = block.col(j).iter().copied().collect();
            if !self.append_from(w, norm0, first, m) {
                // an invariant subspace was reached: continue from a fresh direction
                let mut w = Mat::from_fn(n, 1, {
                    let f = fresh();
                    move |i, _| f[i]
                });
                m.mul(
                    w.col(0).try_as_col_major().expect("contiguous").as_slice(),
                    &mut mw,
                );
                let norm0 = dot(
                    w.col(0).try_as_col_major().expect("contiguous").as_slice(),
                    &mw,
                )
                .max(0.0)
                .sqrt();
                self.project_out(&mut w, 0..first);
                self.append_from(w.col(0).iter().copied().collect(), norm0, first, m);
            }
        }
    }

    /// `W ← W − V (M V)ᵀ W` twice, over the basis columns `range`.
    fn project_out(&self, w: &mut Mat<f64>, range: std::ops::Range<usize>) {
        if range.is_empty() {
            return;
        }
        let mut c = Mat::<f64>::zeros(range.len(), w.ncols());
        for _pass in 0..2 {
            matmul(
                c.as_mut(),
                Accum::Replace,
                self.mv(range.clone()).transpose(),
                w.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                w.as_mut(),
                Accum::Add,
                self.v(range.clone()),
                c.as_ref(),
                -1.0,
                Par::Seq,
            );
        }
    }

    /// M-orthogonalises `w` (M-norm `norm0` before any projection) against the basis columns
    /// from `first` on (twice) and appends it normalised; false when nothing independent is
    /// left of it.
    fn append_from(&mut self, mut w: Vec<f64>, norm0: f64, first: usize, m: &SparseMatrix) -> bool {
        let n = self.n;
        if !(norm0 > 0.0 && norm0.is_finite()) {
            return false;
        }
        for _pass in 0..2 {
            for j in first..self.len() {
                let c = dot(&self.mv[j * n..(j + 1) * n], &w);
                w.iter_mut()
                    .zip(&self.v[j * n..(j + 1) * n])
                    .for_each(|(w, &v)| *w -= c * v);
            }
        }
        let mut mw = vec![0.0; n];
        m.mul(&w, &mut mw);
        let norm = dot(&w, &mw).max(0.0).sqrt();
        if norm.is_nan() || norm <= 1e-8 * norm0 {
            return false;
        }
        w.iter_mut().for_each(|w| *w /= norm);
        mw.iter_mut().for_each(|w| *w /= norm);
        self.v.extend(w);
        self.mv.extend(mw);
        true
    }
}

/// Pseudo-random values in [−1, 1) (xorshift64*, fixed seed).
struct Random(u64);

impl Random {
    fn vector(&mut self, n: usize) -> Vec<f64> {
        (0..n)
            .map(|_| {
                self.0 ^= self.0 >> 12;
                self.0 ^= self.0 << 25;
                self.0 ^= self.0 >> 27;
                let r = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
                (r >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect()
    }
}

/// The lowest `nev` eigenpairs `(ω², φ)` of `K φ = ω² M φ` (ascending, `φᵀ M φ = 1`), or None
/// (see the module documentation).
pub(crate) fn lowest(
    k: &SparseMatrix,
    m: &SparseMatrix,
    nev: usize,
) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = k.nrows();
    if nev == 0 || 3 * nev + 2 * BLOCK > n {
        return None;
    }
    let llt = k.lower()?.sp_cholesky(Side::Lower).ok()?;
    let solve = |cols: MatRef<'_, f64>| -> Mat<f64> {
        let mut x = cols.to_owned();
        llt.solve_in_place(x.as_mut());
        x
    };
    let mut basis = Basis {
        n,
        v: Vec::new(),
        mv: Vec::new(),
    };
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    let columns: Vec<Vec<f64>> = (0..BLOCK).map(|_| random.vector(n)).collect();
    let mut block = Mat::from_fn(n, BLOCK, |i, j| columns[j][i]);
    let mut next_check = 2 * nev + BLOCK;
    loop {
        let first = basis.len();
        basis.append_block(block, m, || random.vector(n));
        let size = basis.len();
        if size >= n / 2 || size == first {
            return None;
        }
        if size >= next_check {
            if let Some(pairs) = ritz(&basis, m, &solve, nev) {
                return Some(pairs);
            }
            next_check = size + BLOCK.max(size / 4);
        }
        block = solve(basis.mv(first..size));
    }
}

/// Rayleigh–Ritz of `K⁻¹M` in the basis, in the M-inner product: `H = (M V)ᵀ K⁻¹ (M V)`,
/// `H y = θ y`, `λ = 1/θ` (the largest θ first), `φ = V y`. Working with `K⁻¹` keeps the lowest
/// modes accurate to round-off relative to themselves; a projection of `K`, whose norm the stiff
/// cables and hangers make 10⁸ times the lowest eigenvalue, would not. The lowest `nev` pairs
/// if all meet the tolerance.
fn ritz(
    basis: &Basis,
    mc: &SparseMatrix,
    solve: &dyn Fn(MatRef<'_, f64>) -> Mat<f64>,
    nev: usize,
) -> Option<(Vec<f64>, Mat<f64>)> {
    let n = basis.n;
    let size = basis.len();
    let x = solve(basis.mv(0..size));
    let mvm = basis.mv(0..size);
    let mut h = Mat::<f64>::zeros(size, size);
    matmul(
        h.as_mut(),
        Accum::Replace,
        mvm.transpose(),
        x.as_ref(),
        1.0,
        Par::Seq,
    );
    // descending θ: the eigen-decomposition of −H is ascending
    let h = Mat::from_fn(size, size, |i, j| -0.5 * (h[(i, j)] + h[(j, i)]));
    let evd = h.self_adjoint_eigen(Side::Lower).ok()?;
    let s = evd.S().column_vector();
    let theta: Vec<f64> = (0..nev).map(|i| -s[i]).collect();
    if !theta.iter().all(|&t| t > 0.0 && t.is_finite()) {
        return None;
    }
    let lambda: Vec<f64> = theta.iter().map(|t| 1.0 / t).collect();
    let y = evd.U().subcols(0, nev);
    let v = basis.v(0..size);
    let mut phi = Mat::<f64>::zeros(n, nev);
    matmul(phi.as_mut(), Accum::Replace, v, y, 1.0, Par::Seq);
    let mut xphi = Mat::<f64>::zeros(n, nev);
    matmul(xphi.as_mut(), Accum::Replace, x.as_ref(), y, 1.0, Par::Seq);
    let mut zj = vec![0.0; n];
    let mut mz = vec![0.0; n];
    for j in 0..nev {
        for (i, z_i) in zj.iter_mut().enumerate() {
            *z_i = lambda[j] * xphi[(i, j)] - phi[(i, j)];
        }
        mc.mul(&zj, &mut mz);
        let err = dot(&zj, &mz).max(0.0).sqrt();
        if err.is_nan() || err > TOLERANCE {
            return None;
        }
    }
    Some((lambda, phi))
}

#[cfg(test)]
mod tests {
    use super::dot;

    /// Integers are summed exactly in any order: every length through the tail cases.
    #[test]
    fn dot_equals_the_exact_sum_of_products() {
        for n in 0..13 {
            let a: Vec<f64> = (0..n).map(|i| (i as f64) - 3.0).collect();
            let b: Vec<f64> = (0..n).map(|i| (2 * i + 1) as f64).collect();
            let exact: i64 = (0..n as i64).map(|i| (i - 3) * (2 * i + 1)).sum();
            assert_eq!(dot(&a, &b), exact as f64, "n = {n}");
        }
    }
}
