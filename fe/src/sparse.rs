//! The assembled matrices K and M in compressed columns.
//!
//! A bridge model has thousands of DOFs and a few dozen non-zeros per column, so K and M are
//! assembled as triplets `(i, j, a)` and compressed, never held dense: a dense pair of the
//! Tsing Ma model's ≈2 900 DOFs would be 135 MB.
//!
//! # Summation order
//!
//! Entry `(i, j)` is the sum of its contributions in the order they were added (element by
//! element), `((a₁ + a₂) + a₃) + …`, exactly as `A[(i, j)] += aₖ` into a zeroed dense matrix
//! would form it, and an entry whose sum is exactly zero is not stored. The compressed matrix
//! therefore holds bit for bit the non-zeros of the dense assembly, rows ascending in each
//! column.

use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

/// A square matrix in compressed columns: the rows and values of column `j` are
/// `row[ptr[j]..ptr[j + 1]]` and `val[…]`, rows ascending, no stored zeros.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseMatrix {
    n: usize,
    ptr: Vec<usize>,
    row: Vec<usize>,
    val: Vec<f64>,
}

impl SparseMatrix {
    /// The `n × n` matrix whose entry `(i, j)` is the sum, in the order given, of the
    /// triplets `(i, j, a)` (see the module documentation). Panics on an index `≥ n`.
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> Self {
        // Stable counting sort by column keeps the order of addition within each column.
        let mut ptr = vec![0usize; n + 1];
        for &(i, j, _) in triplets {
            assert!(
                i < n && j < n,
                "entry ({i}, {j}) outside a {n} × {n} matrix"
            );
            ptr[j + 1] += 1;
        }
        for j in 0..n {
            ptr[j + 1] += ptr[j];
        }
        let mut fill = ptr.clone();
        let mut by_col = vec![(0usize, 0.0f64); triplets.len()];
        for &(i, j, a) in triplets {
            by_col[fill[j]] = (i, a);
            fill[j] += 1;
        }
        let mut m = SparseMatrix {
            n,
            ptr: Vec::with_capacity(n + 1),
            row: Vec::new(),
            val: Vec::new(),
        };
        m.ptr.push(0);
        for j in 0..n {
            let col = &mut by_col[ptr[j]..ptr[j + 1]];
            // stable: equal rows stay in the order they were added
            col.sort_by_key(|&(i, _)| i);
            let mut k = 0;
            while k < col.len() {
                let i = col[k].0;
                let mut sum = col[k].1;
                k += 1;
                while k < col.len() && col[k].0 == i {
                    sum += col[k].1;
                    k += 1;
                }
                if sum != 0.0 {
                    m.row.push(i);
                    m.val.push(sum);
                }
            }
            m.ptr.push(m.row.len());
        }
        m
    }

    /// Number of rows (= columns).
    pub fn nrows(&self) -> usize {
        self.n
    }

    /// Number of stored non-zeros.
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// Entry `(i, j)` (0 when not stored).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (rows, vals) = self.column(j);
        rows.binary_search(&i).map_or(0.0, |k| vals[k])
    }

    /// Rows and values of column `j`.
    pub fn column(&self, j: usize) -> (&[usize], &[f64]) {
        let r = self.ptr[j]..self.ptr[j + 1];
        (&self.row[r.clone()], &self.val[r])
    }

    /// `y = A x`, column by column.
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        assert_eq!(x.len(), self.n, "x of the matrix's size");
        assert_eq!(y.len(), self.n, "y of the matrix's size");
        y.iter_mut().for_each(|y| *y = 0.0);
        for (j, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                let (rows, vals) = self.column(j);
                for (&i, &a) in rows.iter().zip(vals) {
                    y[i] += a * xj;
                }
            }
        }
    }

    /// `A X` for a dense `X` (columns by [`SparseMatrix::mul`]).
    pub fn mul_dense(&self, x: &Mat<f64>) -> Mat<f64> {
        let mut out = Mat::<f64>::zeros(self.n, x.ncols());
        let mut xc = vec![0.0; self.n];
        let mut yc = vec![0.0; self.n];
        for c in 0..x.ncols() {
            xc.iter_mut().enumerate().for_each(|(i, v)| *v = x[(i, c)]);
            self.mul(&xc, &mut yc);
            yc.iter().enumerate().for_each(|(i, &v)| out[(i, c)] = v);
        }
        out
    }

    /// The dense matrix (for the dense reference solutions of small models).
    pub fn to_dense(&self) -> Mat<f64> {
        let mut a = Mat::<f64>::zeros(self.n, self.n);
        for j in 0..self.n {
            let (rows, vals) = self.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                a[(i, j)] = v;
            }
        }
        a
    }

    /// The lower triangle (`i ≥ j`) as a faer sparse matrix, for a sparse Cholesky
    /// factorisation of a symmetric matrix (which reads only that triangle).
    pub fn lower(&self) -> Option<SparseColMat<usize, f64>> {
        let lower: Vec<Triplet<usize, usize, f64>> = (0..self.n)
            .flat_map(|j| {
                let (rows, vals) = self.column(j);
                rows.iter()
                    .zip(vals)
                    .filter(move |(&i, _)| i >= j)
                    .map(move |(&i, &v)| Triplet::new(i, j, v))
            })
            .collect();
        SparseColMat::<usize, f64>::try_new_from_triplets(self.n, self.n, &lower).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The compressed matrix holds bit for bit what `+=` into a zeroed dense matrix makes,
    /// in the same order of addition: repeated entries, sums that cancel to exactly zero
    /// (not stored; 1 + 1e-16 + 1e-16 − 1 is one in this order), contributions whose sum
    /// depends on the order (0.1 + 0.2 + 0.3 against 0.3 + 0.2 + 0.1).
    #[test]
    fn triplets_sum_like_dense_assembly_in_order() {
        let n = 5;
        let triplets = vec![
            (0, 0, 1.0),
            (3, 1, 2.5),
            (1, 3, 1e-16),
            (1, 3, 1.0),
            (1, 3, 1e-16),
            (1, 3, -1.0),
            (2, 2, 4.0),
            (2, 2, -4.0),
            (4, 1, -0.0),
            (0, 4, 0.1),
            (0, 4, 0.2),
            (0, 4, 0.3),
            (4, 4, 0.3),
            (4, 4, 0.2),
            (4, 4, 0.1),
            (3, 1, -7.0),
        ];
        let mut dense = Mat::<f64>::zeros(n, n);
        for &(i, j, a) in &triplets {
            dense[(i, j)] += a;
        }
        let s = SparseMatrix::from_triplets(n, &triplets);
        for i in 0..n {
            for j in 0..n {
                assert_eq!(s.get(i, j).to_bits(), dense[(i, j)].to_bits(), "({i}, {j})");
            }
        }
        // (0,0), (3,1), (0,4), (4,4); (1,3), (2,2) and (4,1) sum to exactly zero
        assert_eq!(s.nnz(), 4);
        assert_ne!(s.get(0, 4), s.get(4, 4), "the order of addition is kept");
        assert_eq!(s.to_dense(), dense);
        let x = [1.0, -2.0, 3.0, 0.5, 4.0];
        let mut y = [0.0; 5];
        s.mul(&x, &mut y);
        for (i, yi) in y.iter().enumerate() {
            let expect: f64 = (0..n).map(|j| dense[(i, j)] * x[j]).sum();
            assert!(
                (yi - expect).abs() <= 1e-15 * expect.abs().max(1.0),
                "row {i}"
            );
        }
    }
}
