//! The reduced bridge system of a step, `A q₁ = b_q` with `A = D̂ + Σᵢ Uᵢᵀ Sᵢ Uᵢ` (see
//! [`super`]), never assembled for the iterations: its product with a vector in rail-space
//! form ([`Reduced::apply`]), its assembly for the preconditioner and the direct solve
//! ([`Reduced::assemble`]), and the products with a vehicle's `U` and one wheelset's `Ψ`
//! that the step takes.

use super::geometry::Blocks;
use super::vehicle_cache::VehicleCache;
use nalgebra::{DMatrix, DVector, Vector3};
use std::sync::Arc;

/// The reduced matrix `A = D̂ + Σ Uᵀ S U` of one step: `D̂ = diag(a0 + a1 2ζω + ω²)` and, of
/// each of `vehicles` that couples to the modes ([`Reduced::couples`]), its `U` at the
/// step's geometry (`blocks`) with its rail-space `S` (`cache`).
pub(super) struct Reduced<'a> {
    pub(super) blocks: Blocks<'a>,
    /// Per vehicle, its constant blocks.
    pub(super) cache: &'a [Arc<VehicleCache>],
    pub(super) dhat: &'a DVector<f64>,
    /// The vehicles the step visits, ascending.
    pub(super) vehicles: &'a [usize],
    /// Per vehicle: a wheelset of it on the deck.
    pub(super) live: &'a [bool],
}

impl Reduced<'_> {
    /// Whether vehicle `i` adds `Uᵀ S U` to the reduced matrix: it has DOFs (a rail-space
    /// `S`) and a wheelset on the deck (`live`).
    fn couples(&self, i: usize) -> bool {
        self.live[i] && !self.cache[i].s_dense.is_empty()
    }

    /// Whether any of the vehicles couples to the modes (else `A = D̂`).
    pub(super) fn coupled(&self) -> bool {
        self.vehicles.iter().any(|&i| self.couples(i))
    }

    /// `y = A x` with `A = D̂ + Σ Uᵀ S U` (rail-space form, never assembled): per vehicle
    /// `U x` as one sum over the modes of its mode-major `U` ([`Blocks::block`]; each
    /// rail value summed over the modes in order, as one wheelset's `Ψ q` sums them),
    /// `S (U x)` with the dense `S` (column order), and `Uᵀ` of that as one product over the
    /// vehicle's rows of `psi_t` ([`Blocks::block_t`], [`block_tr_add`]). Two vehicles' `U x`
    /// and `S (U x)` go side by side ([`crate::simd::mul_columns_pair`]: each of these short
    /// sums is a chain of dependent additions, which the other's fills), the same values bit
    /// for bit; their `Uᵀ` into `y` one vehicle after the other, in order. `ux`, `sx`: scratch
    /// of two vehicles' rail DOFs.
    pub(super) fn apply(&self, x: &[f64], y: &mut [f64], ux: &mut [f64], sx: &mut [f64]) {
        let (dhat, b) = (self.dhat, &self.blocks);
        let nb = x.len();
        for n in 0..nb {
            y[n] = dhat[n] * x[n];
        }
        // two vehicles at a time: their U x and S (U x) side by side, then Uᵀ of each in
        // order (the sums into y as one vehicle after the other)
        let mut coupled = self.vehicles.iter().copied().filter(|&i| self.couples(i));
        let rows = |i: usize| 3 * b.train.vehicles[i].model.wheelsets.len();
        while let Some(i) = coupled.next() {
            let ri = rows(i);
            let Some(k) = coupled.next() else {
                let (ux, sx) = (&mut ux[..ri], &mut sx[..ri]);
                block_mul(b.block(i), x, ux);
                crate::simd::mul_columns(sx, ux, &self.cache[i].s_dense);
                block_tr_add(b.block_t(i), sx, y);
                break;
            };
            let rk = rows(k);
            let (ux_i, ux_k) = ux[..ri + rk].split_at_mut(ri);
            let (sx_i, sx_k) = sx[..ri + rk].split_at_mut(ri);
            let (ci, ck) = (&self.cache[i].s_dense, &self.cache[k].s_dense);
            crate::simd::mul_columns_pair(ux_i, x, b.block(i), ux_k, x, b.block(k));
            crate::simd::mul_columns_pair(sx_i, ux_i, ci, sx_k, ux_k, ck);
            block_tr_add(b.block_t(i), sx_i, y);
            block_tr_add(b.block_t(k), sx_k, y);
        }
    }

    /// Assemble `A = D̂ + Σ Uᵀ S U` and solve `A q = b` by Cholesky.
    pub(super) fn solve_direct(&self, b: &DVector<f64>) -> DVector<f64> {
        self.assemble()
            .cholesky()
            .expect("reduced bridge matrix is positive definite")
            .solve(b)
    }

    /// `A = D̂ + Σ Uᵀ S U` at the current wheelset positions, from each busy vehicle's `U`
    /// in its two layouts ([`Blocks::block`] and [`Blocks::block_t`]): column `n` of
    /// `S U` is `S` times column `n` of `U` (the mode-major block's `n`-th run), and the upper
    /// part (rows `0..=n`) of column `n` of
    /// `Uᵀ (S U)` is the rail-major rows' first `n + 1` values taken with those, each a
    /// product over whole columns; the upper triangle is then mirrored below, so that `A` is
    /// symmetric bit for bit (off-deck wheelsets have zero shapes and add exact zeros).
    pub(super) fn assemble(&self) -> DMatrix<f64> {
        let dhat = self.dhat;
        let nb = dhat.len();
        let mut a = vec![0.0; nb * nb];
        for n in 0..nb {
            a[n * nb + n] = dhat[n];
        }
        let mut su = Vec::new();
        for &i in self.vehicles {
            if !self.couples(i) {
                continue;
            }
            let s = &self.cache[i].s_dense;
            let u = self.blocks.block(i);
            let m = u.len() / nb;
            su.resize(m, 0.0);
            let ut = self.blocks.block_t(i);
            for (n, (col, un)) in a.chunks_exact_mut(nb).zip(u.chunks_exact(m)).enumerate() {
                crate::simd::mul_columns(&mut su, un, s);
                crate::simd::axpy_columns_strided(&mut col[..=n], &su, ut, nb);
            }
        }
        for j in 0..nb {
            for i in 0..j {
                a[i * nb + j] = a[j * nb + i];
            }
        }
        DMatrix::from_vec(nb, nb, a)
    }
}

/// `Ψ q` of one wheelset, the modes summed in order (the reference of the block products).
#[cfg(test)]
fn psi_mul(psi: &[[f64; 3]], q: &[f64]) -> Vector3<f64> {
    let mut u = Vector3::zeros();
    for (p, qn) in psi.iter().zip(q.iter()) {
        u.x += p[0] * qn;
        u.y += p[1] * qn;
        u.z += p[2] * qn;
    }
    u
}

/// `y += Uᵀ s` for a vehicle's `U` rail DOF after rail DOF (`ut[(3l + k) N_b + n]`, its
/// wheelsets' rows of [`super::geometry::Geometry::psi_t`]): the rail DOFs' columns added in order (`s`
/// finite: the zero rows of wheelsets off the deck add exact zeros).
pub(super) fn block_tr_add(ut: &[f64], s: &[f64], y: &mut [f64]) {
    crate::simd::axpy_columns(y, s, ut);
}

/// `out = U x` for a mode-major block `u` ([`super::geometry::Geometry::blocks`]): each value summed over
/// the modes in order, from zero (as one wheelset's `Ψ q` sums them).
pub(super) fn block_mul(u: &[f64], x: &[f64], out: &mut [f64]) {
    crate::simd::mul_columns(out, x, u);
}

/// `Ψ a`, `Ψ b`, `Ψ c` in one pass over Ψ (each sum over the modes in order).
pub(super) fn psi_mul3(psi: &[[f64; 3]], a: &[f64], b: &[f64], c: &[f64]) -> [Vector3<f64>; 3] {
    let mut r = [Vector3::zeros(); 3];
    for (n, p) in psi.iter().enumerate() {
        let (an, bn, cn) = (a[n], b[n], c[n]);
        for k in 0..3 {
            r[0][k] += p[k] * an;
            r[1][k] += p[k] * bn;
            r[2][k] += p[k] * cn;
        }
    }
    r
}

/// `out += Ψᵀ f` (one wheelset's generalised forces).
pub(super) fn psi_tr_add(psi: &[[f64; 3]], f: &Vector3<f64>, out: &mut [f64]) {
    crate::simd::project_force(out, psi, [f.x, f.y, f.z]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vehicle's mode-major block gives each wheelset's `Ψ q` bit for bit as one
    /// [`psi_mul`] per wheelset does, for one to nine wheelsets, and zeros for a wheelset off
    /// the deck; its rows rail DOF after rail DOF (a zero row for a wheelset off the deck)
    /// give `Σ Ψᵀ f` of the wheelsets on the deck as one projection per wheelset does, to
    /// round-off of the terms' magnitudes.
    #[test]
    fn a_vehicles_blocks_give_each_wheelsets_products() {
        let nb = 23;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let q: Vec<f64> = (0..nb)
            .map(|n| next() * 10f64.powi(n as i32 % 7 - 3))
            .collect();
        for nw in 1..=9 {
            let psi: Vec<[f64; 3]> = (0..nw * nb).map(|_| [next(), next(), next()]).collect();
            // the block as the step keeps it, mode after mode; wheelset 1 is off the deck
            let r = 3 * nw;
            let mut u = vec![0.0; nb * r];
            for l in (0..nw).filter(|&l| l != 1) {
                for n in 0..nb {
                    u[n * r + 3 * l..n * r + 3 * l + 3].copy_from_slice(&psi[l * nb + n]);
                }
            }
            let mut out = vec![f64::NAN; 3 * nw];
            block_mul(&u, &q, &mut out);
            for l in 0..nw {
                let one = if l == 1 {
                    Vector3::zeros()
                } else {
                    psi_mul(&psi[l * nb..(l + 1) * nb], &q)
                };
                for k in 0..3 {
                    assert_eq!(out[3 * l + k].to_bits(), one[k].to_bits(), "{nw} wheelsets");
                }
            }
            let mut ut = vec![0.0; 3 * nw * nb];
            for l in (0..nw).filter(|&l| l != 1) {
                for k in 0..3 {
                    for n in 0..nb {
                        ut[(3 * l + k) * nb + n] = psi[l * nb + n][k];
                    }
                }
            }
            let f: Vec<f64> = (0..3 * nw).map(|_| next() * 1e5).collect();
            let y0: Vec<f64> = (0..nb).map(|_| next()).collect();
            let mut got = y0.clone();
            block_tr_add(&ut, &f, &mut got);
            let (mut want, mut scale) =
                (y0.clone(), y0.iter().map(|v| v.abs()).collect::<Vec<_>>());
            for l in (0..nw).filter(|&l| l != 1) {
                let shapes = &psi[l * nb..(l + 1) * nb];
                crate::simd::project_force(
                    &mut want,
                    shapes,
                    [f[3 * l], f[3 * l + 1], f[3 * l + 2]],
                );
                for (s, p) in scale.iter_mut().zip(shapes) {
                    *s += (0..3).map(|k| (p[k] * f[3 * l + k]).abs()).sum::<f64>();
                }
            }
            for n in 0..nb {
                let tol = 4.0 * f64::EPSILON * scale[n];
                assert!((got[n] - want[n]).abs() <= tol, "{nw} wheelsets, mode {n}");
            }
            // and nothing but the wheelsets on the deck: with all of them off, y is unchanged
            ut.fill(0.0);
            let mut none = y0.clone();
            block_tr_add(&ut, &f, &mut none);
            assert_eq!(none, y0);
        }
    }
}
