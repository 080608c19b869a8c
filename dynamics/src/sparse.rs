//! The small constant vehicle matrices in compressed sparse rows, for the hot paths of both
//! solvers.
//!
//! A vehicle's blocks are mostly structural zeros: the 15 free DOFs of the 27-DOF coach have a
//! diagonal `M`, 53 of 225 entries of `C` and `K`, 6 of 45 of each `K_vw`, `C_vw`, and the
//! Cholesky factor `L` of `a0 M + a1 C + K` keeps 39 of its 120. Products skip exactly the
//! zero entries, so they give the dense products' values up to the order of summation.
//!
//! [`Csr::mul_add`] is `y ← y + α A x`, [`Csr::tr_mul_add`] `y ← y + α Aᵀ x`, and
//! [`SparseCholesky::solve_mut`] solves `L Lᵀ x = b` by one forward and one backward sweep.

use nalgebra::{Cholesky, DMatrix, Dyn};

/// A matrix in compressed sparse rows (the exact non-zeros).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Csr {
    /// Row `i` holds the entries `start[i]..start[i + 1]`.
    start: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
}

impl Csr {
    /// The non-zero entries of `m`.
    pub fn of(m: &DMatrix<f64>) -> Csr {
        let mut c = Csr {
            start: vec![0],
            ..Default::default()
        };
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                let v = m[(i, j)];
                if v != 0.0 {
                    c.col.push(j);
                    c.val.push(v);
                }
            }
            c.start.push(c.col.len());
        }
        c
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// `y ← y + α A x`.
    #[inline]
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate().take(self.start.len() - 1) {
            let mut s = 0.0;
            for e in self.start[i]..self.start[i + 1] {
                s += self.val[e] * x[self.col[e]];
            }
            *yi += alpha * s;
        }
    }

    /// `y ← y + α Aᵀ x`.
    #[inline]
    pub fn tr_mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        for (i, &xi) in x.iter().enumerate().take(self.start.len() - 1) {
            let a = alpha * xi;
            for e in self.start[i]..self.start[i + 1] {
                y[self.col[e]] += self.val[e] * a;
            }
        }
    }
}

/// A Cholesky factor `L` (lower) kept as the sparse rows of `L` below its diagonal, and of
/// `Lᵀ` above it, with the diagonal apart.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseCholesky {
    lower: Csr,
    upper: Csr,
    diagonal: Vec<f64>,
}

impl SparseCholesky {
    pub fn of(chol: &Cholesky<f64, Dyn>) -> SparseCholesky {
        let l = chol.l();
        let n = l.nrows();
        let strict_lower = DMatrix::from_fn(n, n, |i, j| if j < i { l[(i, j)] } else { 0.0 });
        SparseCholesky {
            upper: Csr::of(&strict_lower.transpose()),
            lower: Csr::of(&strict_lower),
            diagonal: (0..n).map(|i| l[(i, i)]).collect(),
        }
    }

    /// Overwrite `b` with the solution of `L Lᵀ x = b`.
    pub fn solve_mut(&self, b: &mut [f64]) {
        let n = self.diagonal.len();
        for i in 0..n {
            let mut s = b[i];
            for e in self.lower.start[i]..self.lower.start[i + 1] {
                s -= self.lower.val[e] * b[self.lower.col[e]];
            }
            b[i] = s / self.diagonal[i];
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for e in self.upper.start[i]..self.upper.start[i + 1] {
                s -= self.upper.val[e] * b[self.upper.col[e]];
            }
            b[i] = s / self.diagonal[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// Against nalgebra's dense products and solve on a matrix with structural zeros.
    #[test]
    fn sparse_products_and_solve_equal_the_dense_ones() {
        let n = 7;
        let a = DMatrix::from_fn(n, n, |i, j| {
            if (i + 2 * j) % 3 == 0 || i == j {
                1.0 + (i * n + j) as f64 * 0.37
            } else {
                0.0
            }
        });
        let spd = &a * a.transpose() + DMatrix::identity(n, n) * 3.0;
        let x = DVector::from_fn(n, |i, _| (i as f64 * 1.3).sin());
        let c = Csr::of(&a);
        assert!(c.nnz() < n * n);
        let mut y = DVector::from_element(n, 0.5);
        c.mul_add(-2.0, x.as_slice(), y.as_mut_slice());
        let dense = DVector::from_element(n, 0.5) - 2.0 * &a * &x;
        assert!((y - dense).amax() < 1e-12);
        let mut y = DVector::from_element(n, 0.5);
        c.tr_mul_add(3.0, x.as_slice(), y.as_mut_slice());
        let dense = DVector::from_element(n, 0.5) + 3.0 * a.transpose() * &x;
        assert!((y - dense).amax() < 1e-12);
        let chol = spd.clone().cholesky().unwrap();
        let mut b = x.clone();
        SparseCholesky::of(&chol).solve_mut(b.as_mut_slice());
        assert!((&spd * b - x).amax() < 1e-10);
    }
}
