//! The lagged preconditioner of the reduced system: the inverse of the reduced matrix of an
//! earlier step, carried forward in time to second order ([`Lagged`]), by Gauss–Jordan
//! sweeps ([`spd_inverse`]) and applied as a dense product ([`dense_mul`]).

use nalgebra::DMatrix;

/// The lagged preconditioner: the inverse `P = A_k⁻¹` of the reduced matrix assembled at
/// solve `k`, carried forward in time to second order.
///
/// The reduced matrix changes only as the wheelsets move along the shapes, smoothly in time:
/// `A(k + τ) = A_k + τ A₁ + τ² A₂ + O(τ³)` (τ in solves, i.e. steps), so that
///
/// ```text
/// A(k + τ)⁻¹ = P − τ P A₁ P + τ² P (A₁ P A₁ − A₂) P + O(τ³) .
/// ```
///
/// `A₁` and `A₂` are the first and half the second derivative at `k` of the parabola through
/// the last three assembled matrices (`A_k` and the two before it, whatever solves apart);
/// with only two, the secant's slope and no second-order term; with none, `P` alone. The
/// preconditioner of solve `k + τ`, `P − τ B₁ + τ² B₂`, is formed once per solve (`N_b²`
/// multiply-adds) so that each iteration still takes one product with it. It is a
/// preconditioner only: the iteration's residual is always that of the true `A`, so a poor
/// extrapolation (a jump in the matrix's history) costs iterations, never accuracy, and one
/// that is no longer positive definite hands the step to the direct solver and a new
/// assembly. On the bench case it takes 3.1 applications of `A` a step against 4.3 for `P`
/// alone (3.3 to first order), with an assembly every 38 steps against 23.5.
#[derive(Debug, Clone)]
pub(super) struct Lagged {
    inverse: DMatrix<f64>,
    /// `B₁ = P A₁ P` and `B₂ = P (A₁ P A₁ − A₂) P`, per solve and per solve squared; None
    /// without enough earlier assemblies.
    slope: Option<DMatrix<f64>>,
    curvature: Option<DMatrix<f64>>,
    /// The solve `k` of the assembly.
    made_at: usize,
}

impl Lagged {
    /// From the matrix `a` assembled at solve `k` and the earlier ones `before` (oldest
    /// first, at most two used, each at a solve before `k`); None if `a` is not positive
    /// definite.
    pub(super) fn new(
        a: &DMatrix<f64>,
        k: usize,
        before: &[(DMatrix<f64>, usize)],
    ) -> Option<Lagged> {
        let inverse = spd_inverse(a.clone())?;
        let at = |j: usize| j as f64 - k as f64;
        // A₁ and A₂ of the interpolating polynomial in τ through the nodes (Lagrange's
        // weights' first and half their second derivatives at τ = 0)
        let (a1, a2) = match before {
            [.., (m2, k2), (m1, k1)] => {
                let (t1, t2) = (at(*k1), at(*k2));
                let d = [
                    -(1.0 / t1 + 1.0 / t2),
                    -t2 / (t1 * (t1 - t2)),
                    -t1 / (t2 * (t2 - t1)),
                ];
                let h = [
                    1.0 / (t1 * t2),
                    1.0 / (t1 * (t1 - t2)),
                    1.0 / (t2 * (t2 - t1)),
                ];
                (
                    Some(a * d[0] + m1 * d[1] + m2 * d[2]),
                    Some(a * h[0] + m1 * h[1] + m2 * h[2]),
                )
            }
            [(m1, k1)] => (Some((a - m1) / -at(*k1)), None),
            [] => (None, None),
        };
        let pa1 = a1.as_ref().map(|a1| &inverse * a1);
        let slope = pa1.as_ref().map(|x| x * &inverse);
        let curvature = match (&a1, &a2, &pa1) {
            (Some(a1), Some(a2), Some(pa1)) => Some(&inverse * (a1 * pa1 - a2) * &inverse),
            _ => None,
        };
        Some(Lagged {
            inverse,
            slope,
            curvature,
            made_at: k,
        })
    }

    /// The preconditioner of solve `k + τ`, `P − τ B₁ + τ² B₂`, into `out`.
    pub(super) fn at(&self, solve: usize, out: &mut DMatrix<f64>) {
        let tau = solve.saturating_sub(self.made_at) as f64;
        let o = out.as_mut_slice();
        o.copy_from_slice(self.inverse.as_slice());
        if tau > 0.0 {
            // (P − τ B₁) + τ² B₂, each a product then a sum per entry
            if let Some(b1) = &self.slope {
                crate::simd::axpy(o, -tau, b1.as_slice());
            }
            if let Some(b2) = &self.curvature {
                crate::simd::axpy(o, tau * tau, b2.as_slice());
            }
        }
    }

    /// The order it is carried forward to: 0 with no earlier assembly, 1 with one, 2 with
    /// two.
    pub(super) fn order(&self) -> usize {
        usize::from(self.slope.is_some()) + usize::from(self.curvature.is_some())
    }
}

/// The inverse of a symmetric positive definite matrix by Gauss–Jordan sweeps in place (the
/// pivots of such a matrix are positive, so none is exchanged): for each k, row k is divided
/// by the pivot `d = a_kk`, every other column j loses `a_kj` times column k, and column k
/// becomes `−a_ik / d` with `1/d` on the diagonal. Each sweep is a run of contiguous
/// multiply-adds over the columns, `N³` in all. None if a pivot is not positive and finite.
fn spd_inverse(mut a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let mut ck = vec![0.0; n];
    for k in 0..n {
        let d = a[(k, k)];
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        ck.copy_from_slice(a.column(k).as_slice());
        let data = a.as_mut_slice();
        for (j, col) in data.chunks_exact_mut(n).enumerate() {
            if j == k {
                continue;
            }
            let f = col[k] / d;
            crate::simd::axpy(col, -f, &ck);
            col[k] = f;
        }
        let col = &mut data[k * n..(k + 1) * n];
        for (o, &c) in col.iter_mut().zip(&ck) {
            *o = -c / d;
        }
        col[k] = 1.0 / d;
    }
    Some(a)
}

/// `y = A x` for a square column-major `A`, column by column.
pub(super) fn dense_mul(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    crate::simd::mul_columns(y, x, a.as_slice());
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// The carried-forward preconditioner of a reduced matrix that moves as a parabola in
    /// time, `A(τ) = A₀ + τ A₁ + τ² A₂`, assembled at three solves unevenly apart: the
    /// parabola through three assemblies is `A(τ)` itself, so its terms are `P A₁ P` and
    /// `P (A₁ P A₁ − A₂) P`, and with `M₁ = P A₁`, `M₂ = P A₂` the preconditioner's defect
    /// `(P − τ P A₁ P + τ² P (A₁ P A₁ − A₂) P) A(τ) − I` is the closed form
    /// `τ³ (M₁³ − M₁ M₂ − M₂ M₁) + τ⁴ (M₁² M₂ − M₂²)` to round-off: third order in τ where
    /// `P` alone leaves `P A(τ) − I`, first order. With one earlier assembly the slope is the
    /// secant's and there is no second-order term; with none, `P` alone.
    #[test]
    fn the_lagged_inverse_is_carried_forward_to_second_order() {
        let n = 20;
        let sym = |seed: usize, scale: f64| {
            let b = DMatrix::from_fn(n, n, |i, j| {
                (((i * 7 + j * 13 + seed) % 11) as f64 - 5.0) / 5.0
            });
            (&b + b.transpose()) * scale
        };
        // modal scales over two decades, the matrix moving by ~1e-4 of itself a solve
        let d = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                10f64.powf(i as f64 / 10.0)
            } else {
                0.0
            }
        });
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 3 + j * 5) % 7) as f64 - 3.0);
        let a0 = &d * (b.transpose() * &b + DMatrix::identity(n, n) * n as f64) * &d;
        let (a1, a2) = (&d * sym(1, 1e-4) * &d, &d * sym(4, 1e-6) * &d);
        let at = |tau: f64| &a0 + &a1 * tau + &a2 * (tau * tau);
        // assembled at solves 3, 17 and 30; A₀ is the matrix of solve 30
        let before = [(at(-27.0), 3), (at(-13.0), 17)];
        let lagged = Lagged::new(&a0, 30, &before).expect("positive definite");
        let p = &lagged.inverse;
        let (m1, m2) = (p * &a1, p * &a2);
        let close = |got: &DMatrix<f64>, want: &DMatrix<f64>, what: &str| {
            let err = (got - want).amax();
            assert!(
                err <= 1e-9 * want.amax(),
                "{what}: off by {err:e} of {:e}",
                want.amax()
            );
        };
        let slope = lagged.slope.as_ref().expect("two earlier assemblies");
        close(slope, &(&m1 * p), "B₁");
        let curvature = lagged.curvature.as_ref().expect("two earlier assemblies");
        close(curvature, &((&m1 * &m1 - &m2) * p), "B₂");
        let mut now = DMatrix::zeros(n, n);
        let id = DMatrix::<f64>::identity(n, n);
        for tau in [1.0, 4.0, 11.0, 25.0] {
            lagged.at(30 + tau as usize, &mut now);
            let defect = &now * at(tau) - &id;
            let closed = (&m1 * &m1 * &m1 - &m1 * &m2 - &m2 * &m1) * tau.powi(3)
                + (&m1 * &m1 * &m2 - &m2 * &m2) * tau.powi(4);
            let err = (&defect - &closed).amax();
            assert!(
                err <= 1e-3 * closed.amax(),
                "τ = {tau}: defect off the closed form by {err:e} of {:e}",
                closed.amax()
            );
            let plain = p * at(tau) - &id;
            assert!(
                defect.amax() < 1e-3 * plain.amax(),
                "τ = {tau}: {:e} against {:e}",
                defect.amax(),
                plain.amax()
            );
        }
        // one earlier assembly: the secant, no second-order term; none: P alone
        let one = Lagged::new(&a0, 30, &before[1..]).expect("positive definite");
        let secant = p * ((&a0 - &before[1].0) / 13.0) * p;
        close(
            one.slope.as_ref().expect("one earlier assembly"),
            &secant,
            "secant",
        );
        assert!(one.curvature.is_none());
        let none = Lagged::new(&a0, 30, &[]).expect("positive definite");
        assert!(none.slope.is_none());
        none.at(41, &mut now);
        assert_eq!(now, none.inverse);
    }

    /// The sweeps give the inverse: `A A⁻¹ = I` to round-off on a symmetric positive
    /// definite matrix with a wide range of scales (a reduced matrix's diagonal spans ω² of
    /// the first and last modes), and None for an indefinite one.
    #[test]
    fn gauss_jordan_sweeps_invert_a_positive_definite_matrix() {
        let n = 20;
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 11) as f64 - 5.0);
        let scale = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                10f64.powf(i as f64 / 4.0)
            } else {
                0.0
            }
        });
        let a = &scale * (b.transpose() * &b + DMatrix::identity(n, n)) * &scale;
        let inv = spd_inverse(a.clone()).expect("positive definite");
        let err = (&a * &inv - DMatrix::<f64>::identity(n, n)).amax();
        let cond = {
            let e = a.clone().symmetric_eigenvalues();
            e.max() / e.min()
        };
        assert!(
            err <= 1e-15 * cond,
            "|A A⁻¹ − I| = {err:e}, condition {cond:e}"
        );
        let mut x = vec![0.0; n];
        let v: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        dense_mul(&inv, &v, &mut x);
        let direct = a.cholesky().unwrap().solve(&DVector::from_vec(v));
        for (p, q) in x.iter().zip(direct.iter()) {
            assert!((p - q).abs() <= 1e-15 * cond * q.abs().max(direct.amax()));
        }
        let indefinite = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(spd_inverse(indefinite).is_none());
    }
}
