//! The iterative solve of the reduced bridge system of a step, `A q₁ = b_q` ([`super`]):
//! preconditioned conjugate gradients to round-off ([`ReducedSolver::solve`]), the
//! preconditioner chosen by the sizes ([`Costs`]: the lagged inverse of
//! [`super::lagged`], or `D̂`), started from the correction extrapolated from the last
//! solves' ([`Corrections`]).

use super::lagged::{dense_mul, Lagged};
use super::reduced::Reduced;
use crate::train::Train;
use nalgebra::{DMatrix, DVector};

/// What the iterative solve keeps from solve to solve, and its vectors.
#[derive(Default)]
pub(super) struct ReducedSolver {
    /// The preconditioner: the inverse of the reduced matrix of an earlier step, carried
    /// forward ([`Lagged`]; None: assemble at the next solve; a product with it is a run of
    /// independent multiply-adds, where the two triangular solves of its Cholesky factor are
    /// chains), the solves made with it since its assembly and their iterations.
    pre: Option<Lagged>,
    pre_solves: usize,
    pre_iterations: usize,
    /// The last (up to two) assembled reduced matrices, oldest first, with the solve each
    /// was assembled at; the solves so far (with the lagged preconditioner) and the
    /// preconditioner of this solve ([`Lagged::at`]).
    assembled: Vec<(DMatrix<f64>, usize)>,
    solves: usize,
    pre_now: DMatrix<f64>,
    costs: Costs,
    /// The corrections `q − M⁻¹ b` of the last solves (the initial guess of the next).
    corrections: Corrections,
    /// `M⁻¹ b` of the current solve.
    cg_base: DVector<f64>,
    /// The conjugate-gradient vectors (N_b); `cg_x` holds the solution.
    pub(super) cg_x: DVector<f64>,
    cg_r: DVector<f64>,
    cg_z: DVector<f64>,
    cg_p: DVector<f64>,
    cg_ap: DVector<f64>,
    cg_t: DVector<f64>,
}

impl ReducedSolver {
    /// For `nb` modes under `train`.
    pub(super) fn new(nb: usize, train: &Train) -> Self {
        ReducedSolver {
            pre: None,
            pre_solves: 0,
            pre_iterations: 0,
            assembled: Vec::new(),
            solves: 0,
            pre_now: DMatrix::zeros(nb, nb),
            costs: Costs::of(nb, train),
            corrections: Corrections::new(nb),
            cg_base: DVector::zeros(nb),
            cg_x: DVector::zeros(nb),
            cg_r: DVector::zeros(nb),
            cg_z: DVector::zeros(nb),
            cg_p: DVector::zeros(nb),
            cg_ap: DVector::zeros(nb),
            cg_t: DVector::zeros(nb),
        }
    }

    /// How the reduced system is preconditioned: None by `D̂`, else by an earlier step's
    /// inverse carried forward to this order ([`Lagged::order`]).
    pub(super) fn order(&self) -> Option<usize> {
        if !self.costs.lagged() {
            return None;
        }
        Some(self.pre.as_ref()?.order())
    }

    /// Preconditioned conjugate gradients on the reduced bridge system, to round-off.
    ///
    /// Two preconditioners, chosen once by the sizes ([`Costs`]): where a product with an
    /// `N_b × N_b` matrix is cheap against an application of `A` (few modes under many
    /// wheelsets), the inverse of the reduced matrix of an earlier step, `A_k = D̂ + Σ Uᵀ S U` at
    /// the wheelset positions of step k, carried forward in time to second order
    /// ([`Lagged`]: the matrix changes only as the wheelsets move, smoothly, so a few
    /// iterations suffice); otherwise `D̂`. Either preconditioner `M⁻¹` starts the iteration
    /// from `M⁻¹ b` plus the extrapolated correction ([`Corrections`]): the corrections
    /// `q − M⁻¹ b` of the last solves vary smoothly, as `q` and the matrices do, so a cubic
    /// through the last four predicts the next one. From such a start (a non-zero
    /// correction added) at least one iteration is made: the start may already pass the
    /// test below, within 10⁻¹⁴ of its terms, and the step's accelerations, `4/h²` times its
    /// displacements, would keep that error (on the default case the deck's vertical
    /// acceleration then moved by 2.8·10⁻⁷ of its largest value); one iteration takes it far
    /// below, as the iterations from `M⁻¹ b` do (2.9·10⁻⁸ from the co-simulation there,
    /// against 7.1·10⁻⁸ before).
    ///
    /// Where no vehicle on the deck is coupled to the modes (moving forces, or no vehicle
    /// there), `A = D̂` and `q = D̂⁻¹ b` is taken at once: no iteration, nothing assembled.
    ///
    /// The lagged inverse is renewed (assembled at the next step) when a solve's
    /// iterations, at the cost `c` of one each, pass the average cost per solve since its
    /// assembly, the assembly's cost `C` included: after the `k`-th solve with `iₖ`
    /// iterations, when `iₖ c > (C + c Σⱼ≤ₖ iⱼ) / k`. The iterations grow as the
    /// preconditioner ages, and renewing where the running cost reaches the average is what
    /// keeps the average least (the rule for replacing an item whose running cost grows with
    /// age). The step of the assembly itself needs none and does not count.
    ///
    /// Measured on the bench case (20 modes under 32 wheelsets, 22 378 steps): 2.11
    /// iterations per solve and 584 assemblies from `M⁻¹ b` alone with the earlier rule
    /// (renew when the iterations beyond the fewest since the assembly have cost an
    /// assembly), 1.15 and 163 with the extrapolation, 1.02 and 220 with both (and at least
    /// one iteration from an extrapolated start): 2.02 applications of `A` a step against
    /// 3.11. On the default case (65 059 steps) 1.28 iterations per solve and 1000
    /// assemblies, 0.81 and 1505, and with both 338 assemblies and 1.85 applications a step
    /// against 2.28.
    ///
    /// The solution is left in `cg_x`; returns false when it has not reached round-off
    /// level within [`MAX_CG_ITERATIONS`] (or the carried-forward preconditioner has stopped
    /// being positive definite), so that the direct solver takes over.
    ///
    /// `ux`, `sx`: rail-space scratch of [`Reduced::apply`].
    pub(super) fn solve(
        &mut self,
        a: &Reduced<'_>,
        bq: &DVector<f64>,
        ux: &mut [f64],
        sx: &mut [f64],
    ) -> bool {
        let nb = bq.len();
        let lagged = self.costs.lagged();
        // the preconditioner made at this step's own positions (its iterations count for
        // nothing: the steps after it are what a lagged one is judged by)
        let fresh = lagged && self.pre.is_none();
        if lagged {
            self.solves += 1;
        }
        // No vehicle on the deck is coupled to the modes (moving forces, or none there):
        // `A = D̂`, solved exactly, with no iteration and nothing to assemble.
        if !a.coupled() {
            for n in 0..nb {
                self.cg_x[n] = bq[n] / a.dhat[n];
            }
            self.corrections.clear();
            return true;
        }
        if fresh {
            let m = a.assemble();
            // None (not positive definite) leaves the step to the direct solver
            let Some(lagged) = Lagged::new(&m, self.solves, &self.assembled) else {
                return false;
            };
            self.pre = Some(lagged);
            if self.assembled.len() == 2 {
                self.assembled.remove(0);
            }
            self.assembled.push((m, self.solves));
            self.pre_solves = 0;
            self.pre_iterations = 0;
        }
        if let Some(p) = self.pre.as_ref().filter(|_| lagged) {
            p.at(self.solves, &mut self.pre_now);
        }
        if fresh {
            // a new preconditioner: the corrections of the old one do not continue
            self.corrections.clear();
        }
        self.iterate(a, bq, (lagged, fresh), ux, sx)
    }

    /// The conjugate-gradient iterations of [`Self::solve`] with its preconditioner
    /// (`lagged`: the inverse carried forward, `pre_now`, else `D̂`; `fresh`: made at this
    /// step's own positions, so that its iterations do not count), from `M⁻¹ b` plus the
    /// extrapolated correction.
    fn iterate(
        &mut self,
        a: &Reduced<'_>,
        bq: &DVector<f64>,
        (lagged, fresh): (bool, bool),
        ux: &mut [f64],
        sx: &mut [f64],
    ) -> bool {
        let nb = bq.len();
        let ReducedSolver {
            pre_now,
            corrections,
            cg_base: base,
            cg_x: x,
            cg_r: r,
            cg_z: z,
            cg_p: p,
            cg_ap: ap,
            cg_t: tmp,
            ..
        } = self;
        let inverse = Some(&*pre_now).filter(|_| lagged);
        let dhat: &DVector<f64> = a.dhat;
        let mut precondition = |v: &mut DVector<f64>| match inverse {
            Some(a) => {
                dense_mul(a, v.as_slice(), tmp.as_mut_slice());
                v.copy_from(tmp);
            }
            None => v.component_div_assign(dhat),
        };
        if bq.amax() == 0.0 {
            x.fill(0.0);
            corrections.push(x, x);
            return true;
        }
        // x₀ = M⁻¹ b + the extrapolated correction
        base.copy_from(bq);
        precondition(base);
        x.copy_from(base);
        let extrapolated = corrections.extrapolate_into(x);
        a.apply(x.as_slice(), ap.as_mut_slice(), ux, sx);
        r.copy_from(bq);
        *r -= &*ap;
        z.copy_from(r);
        precondition(z);
        p.copy_from(z);
        let mut rz = r.dot(z);
        if rz < 0.0 {
            // a carried-forward preconditioner no longer positive definite
            self.pre = None;
            corrections.clear();
            return false;
        }
        let b = bq.as_slice();
        for it in 0..MAX_CG_ITERATIONS {
            // Converged when every mode's residual is at round-off level relative to its own
            // terms, so that small (e.g. lateral) modal coordinates are as exact as large ones.
            let converged = (it > 0 || !extrapolated)
                && (0..nb)
                    .all(|n| r[n].abs() <= CG_TOLERANCE * (b[n].abs() + dhat[n] * x[n].abs()));
            if converged {
                corrections.push(x, base);
                if lagged && !fresh {
                    self.pre_solves += 1;
                    self.pre_iterations += it;
                    let c = self.costs.iteration();
                    let (k, total) = (self.pre_solves as f64, self.pre_iterations as f64);
                    if it as f64 * c * k > self.costs.assembly + total * c {
                        self.pre = None;
                    }
                }
                return true;
            }
            a.apply(p.as_slice(), ap.as_mut_slice(), ux, sx);
            let pap = p.dot(ap);
            if pap <= 0.0 {
                self.pre = None;
                corrections.clear();
                return false;
            }
            let alpha = rz / pap;
            x.axpy(alpha, p, 1.0);
            r.axpy(-alpha, ap, 1.0);
            z.copy_from(r);
            precondition(z);
            let rz1 = r.dot(z);
            if rz1 < 0.0 {
                self.pre = None;
                corrections.clear();
                return false;
            }
            let beta = rz1 / rz;
            rz = rz1;
            p.axpy(1.0, z, beta);
        }
        self.pre = None;
        corrections.clear();
        false
    }
}

/// Iterations of the conjugate-gradient path before the direct solver takes over.
const MAX_CG_ITERATIONS: usize = 12;
/// Operation counts (multiply-adds) of the pieces of the iterative solve, from the sizes.
#[derive(Debug, Clone, Copy, Default)]
struct Costs {
    /// One application of `A`: `Ψ x`, `S`, `Ψᵀ` for every wheelset.
    apply: f64,
    /// One product with the `N_b × N_b` inverse of the preconditioner (counted as the two
    /// triangular solves with its factor, `2 N_b²`).
    inverse_product: f64,
    /// Assembling and inverting `A`, and carrying the inverse forward ([`Lagged`]).
    assembly: f64,
}

impl Costs {
    fn of(nb: usize, train: &Train) -> Costs {
        let nb = nb as f64;
        // the inverse (N_b³) and the five products of Lagged's terms
        let (mut apply, mut assembly) = (0.0, 6.0 * nb * nb * nb);
        for tv in &train.vehicles {
            let r = 3.0 * tv.model.wheelsets.len() as f64;
            apply += 2.0 * r * nb + r * r;
            assembly += r * r * nb + r * nb * nb;
        }
        Costs {
            apply,
            inverse_product: 2.0 * nb * nb,
            assembly,
        }
    }

    /// Whether the inverse of an earlier step's matrix is the preconditioner: when a product
    /// with it costs at most a quarter of an application of `A` (measured: 20 modes under 32
    /// wheelsets, the bench case, 2.1 iterations per solve and an assembly every 38 steps;
    /// not 200 modes under 128 wheelsets, whose matrix costs as much as the application, and
    /// where `D̂` was measured faster).
    fn lagged(&self) -> bool {
        4.0 * self.inverse_product <= self.apply
    }

    /// One iteration with the factor.
    fn iteration(&self) -> f64 {
        self.apply + self.inverse_product
    }
}
/// Residual of each mode, relative to the size of its own terms, at which the iteration
/// counts as exact.
const CG_TOLERANCE: f64 = 1e-14;

/// The corrections `eₖ = qₖ − M⁻¹ bₖ` of the last solves of the reduced system with one
/// preconditioner `M⁻¹`, newest first, and their extrapolation to the next solve: the
/// polynomial of degree `m − 1` through the last `m ≤ 4` of them (consecutive solves of
/// steps of one size), `ê = Σⱼ (−1)ʲ C(m, j+1) eⱼ` (with four, `4e₀ − 6e₁ + 4e₂ − e₃`). The
/// start `M⁻¹ b + ê` changes how many iterations the conjugate gradients need, not the
/// tolerance their solution meets.
#[derive(Debug, Clone, Default)]
struct Corrections {
    /// A ring of the last corrections; `newest` indexes the newest.
    ring: [DVector<f64>; CORRECTIONS],
    newest: usize,
    /// How many of them are of consecutive solves since the last [`Corrections::clear`].
    count: usize,
}

/// How many past corrections the extrapolation goes through (a cubic; the weights are
/// spelt out up to four in [`Corrections::extrapolate_into`]). Measured with the earlier renewal
/// rule, iterations per solve through none and one to six: bench case (lagged inverse)
/// 2.11, 2.14, 1.81, 1.36, 1.15, 1.11, 1.10; default case 1.28, 1.17, 1.07, 0.94, 0.81,
/// 0.77, 0.88.
const CORRECTIONS: usize = 4;

impl Corrections {
    fn new(nb: usize) -> Self {
        Corrections {
            ring: std::array::from_fn(|_| DVector::zeros(nb)),
            newest: 0,
            count: 0,
        }
    }

    /// Forgets the corrections (a new preconditioner, or a solve that did not converge).
    fn clear(&mut self) {
        self.count = 0;
    }

    /// Records the correction `x − base` of a converged solve.
    fn push(&mut self, x: &DVector<f64>, base: &DVector<f64>) {
        self.newest = (self.newest + 1) % CORRECTIONS;
        let e = &mut self.ring[self.newest];
        for ((e, x), b) in e.iter_mut().zip(x.iter()).zip(base.iter()) {
            *e = x - b;
        }
        self.count = (self.count + 1).min(CORRECTIONS);
    }

    /// `x += ê`, the extrapolated correction of the next solve; whether that moved `x` (false
    /// without corrections or with all of them zero).
    fn extrapolate_into(&self, x: &mut DVector<f64>) -> bool {
        let e = |j: usize| self.ring[(self.newest + CORRECTIONS - j) % CORRECTIONS].as_slice();
        let x = x.as_mut_slice();
        // whether any correction is non-zero (the solve at an assembly, exact from `M⁻¹ b`,
        // leaves a zero one)
        let mut moved = false;
        let mut add = |x: &mut f64, d: f64| {
            moved |= d != 0.0;
            *x += d;
        };
        match self.count {
            0 => {}
            1 => x.iter_mut().zip(e(0)).for_each(|(x, &a)| add(x, a)),
            2 => {
                for ((x, a), b) in x.iter_mut().zip(e(0)).zip(e(1)) {
                    add(x, 2.0 * a - b);
                }
            }
            3 => {
                for (((x, a), b), c) in x.iter_mut().zip(e(0)).zip(e(1)).zip(e(2)) {
                    add(x, 3.0 * (a - b) + c);
                }
            }
            _ => {
                for ((((x, a), b), c), d) in x.iter_mut().zip(e(0)).zip(e(1)).zip(e(2)).zip(e(3)) {
                    add(x, 4.0 * (a + c) - 6.0 * b - d);
                }
            }
        }
        moved
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extrapolation through the last m corrections is exact on polynomials of degree
    /// m − 1 (to round-off), takes the last four once there are more, starts from nothing,
    /// and forgets on `clear`; a correction is the solution less the base.
    #[test]
    fn corrections_extrapolate_polynomials_of_their_degree() {
        let nb = 3;
        // per component a polynomial in the solve number k: constant, linear, quadratic
        // and cubic parts scaled differently
        let p = |k: f64, c: usize| {
            let s = [1.0, -2.5e-3, 7.0e4][c];
            s * (0.3 + 1.7 * k - 0.45 * k * k + 0.021 * k * k * k)
        };
        let lower = |k: f64, c: usize, degree: usize| {
            let s = [1.0, -2.5e-3, 7.0e4][c];
            let terms = [0.3, 1.7 * k, -0.45 * k * k, 0.021 * k * k * k];
            s * terms[..=degree].iter().sum::<f64>()
        };
        let base = DVector::from_vec(vec![0.25, -4.0, 1.0e3]);
        // with m = 1, 2, 3 pushed values of a polynomial of degree m − 1: exact
        for degree in 0..3 {
            let mut c = Corrections::new(nb);
            let mut x = base.clone();
            assert!(!c.extrapolate_into(&mut x), "nothing to extrapolate from");
            assert_eq!(x, base);
            for k in 0..=degree {
                let e = DVector::from_fn(nb, |i, _| lower(k as f64, i, degree));
                c.push(&(&base + &e), &base);
            }
            let mut got = DVector::zeros(nb);
            assert!(c.extrapolate_into(&mut got));
            for i in 0..nb {
                let want = lower((degree + 1) as f64, i, degree);
                assert!(
                    (got[i] - want).abs() <= 1e-12 * want.abs().max(1e-300),
                    "degree {degree}, component {i}: {} against {want}",
                    got[i]
                );
            }
        }
        // a cubic through more than four values: the last four, exactly
        let mut c = Corrections::new(nb);
        for k in 0..9 {
            let e = DVector::from_fn(nb, |i, _| p(k as f64, i));
            c.push(&(&base + &e), &base);
        }
        let mut got = DVector::zeros(nb);
        assert!(c.extrapolate_into(&mut got));
        for i in 0..nb {
            let want = p(9.0, i);
            assert!(
                (got[i] - want).abs() <= 1e-11 * want.abs(),
                "cubic, component {i}: {} against {want}",
                got[i]
            );
        }
        // a polynomial of degree four is not: the cubic's error is the fourth difference
        let q = |k: f64| k.powi(4);
        let mut c = Corrections::new(1);
        for k in 0..4 {
            c.push(&DVector::from_element(1, q(k as f64)), &DVector::zeros(1));
        }
        let mut got = DVector::zeros(1);
        c.extrapolate_into(&mut got);
        assert_eq!(q(4.0) - got[0], 24.0, "Δ⁴ k⁴ = 4!");
        c.clear();
        let mut x = DVector::from_element(1, 2.0);
        assert!(!c.extrapolate_into(&mut x));
        assert_eq!(x[0], 2.0);
    }
}
