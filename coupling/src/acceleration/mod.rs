//! Acceleration of the interface fixed-point iteration (preCICE: *acceleration*; FSI
//! literature: relaxation / quasi-Newton coupling).
//!
//! Within a step the implicit scheme iterates `x̃ₖ = H(xₖ)` with residual `rₖ = x̃ₖ − xₖ`. An
//! [`Acceleration`] turns `(xₖ, x̃ₖ)` into the next guess `xₖ₊₁`:
//!
//! | method | update |
//! |---|---|
//! | [`ConstantRelaxation`] | `xₖ₊₁ = xₖ + ω rₖ` |
//! | [`Aitken`] | `xₖ₊₁ = xₖ + ωₖ rₖ`, `ωₖ = −ωₖ₋₁ (rₖ₋₁ᵀ D² Δrₖ) / ‖D Δrₖ‖²`, `Δrₖ = rₖ − rₖ₋₁` |
//! | [`IqnIls`] | `xₖ₊₁ = x̃ₖ + W c`, `c = argmin ‖D (V c + rₖ)‖₂` |
//! | [`Newton`] | `xₖ₊₁ = xₖ + (I − J)⁻¹ rₖ`, `J = ∂H/∂x` by finite differences through rollback |
//!
//! `D = diag(sᵢ)` is a per-variable scaling, positive and constant within a step, that makes
//! variables of very different magnitude (forces ~1e5 N next to displacements ~1e-3 m)
//! contribute alike; the implicit scheme derives it from the tolerances and the magnitude of
//! each block of interface values (see [`Implicit`](crate::Implicit)).
//! [`ConstantRelaxation`] ignores it.
//!
//! Call sequence per step: [`Acceleration::begin_step`], then [`Acceleration::perform`] once per
//! non-converged sweep, [`Acceleration::converged`] with a converged sweep after the first,
//! then [`Acceleration::end_step`].

mod aitken;
mod constant;
mod iqn_ils;
mod newton;
mod secant;

pub use aitken::Aitken;
pub use constant::ConstantRelaxation;
pub use iqn_ils::IqnIls;
pub use newton::Newton;
pub use secant::filtered_least_squares;

/// One acceleration method for the interface iteration.
pub trait Acceleration {
    /// Short name as in the configuration, e.g. `"iqn-ils"`.
    fn name(&self) -> &str;

    /// Sets the interface size `n` and forgets all history.
    fn initialize(&mut self, n: usize);

    /// A step of size `h` starts (also when a step is retried): forget the iterates of any
    /// unfinished step. Methods that keep information across steps may drop it when `h`
    /// changes.
    fn begin_step(&mut self, h: f64);

    /// Computes the next guess `next` from the guess `x`, the sweep result `x_tilde = H(x)` and
    /// the per-variable scaling `scale` (positive, constant within the step).
    fn perform(&mut self, x: &[f64], x_tilde: &[f64], scale: &[f64], next: &mut [f64]);

    /// The sweep `x_tilde = H(x)` met the convergence criterion (called before
    /// [`Acceleration::end_step`]): methods that learn from the sweeps may keep what this one
    /// adds. Default: ignored.
    fn converged(&mut self, _x: &[f64], _x_tilde: &[f64], _scale: &[f64]) {}

    /// The step ends; `converged` tells whether the convergence criterion was met.
    fn end_step(&mut self, converged: bool);

    /// Whether the next [`Acceleration::perform`] needs the interface Jacobian `J = ∂H/∂x`
    /// of this step; the implicit scheme then computes it after the first sweep and hands it
    /// over with [`Acceleration::set_jacobian`]. Default: never.
    fn needs_jacobian(&self) -> bool {
        false
    }

    /// `J = ∂H/∂x` (n × n) of the current step. Default: ignored.
    fn set_jacobian(&mut self, _j: nalgebra::DMatrix<f64>) {}
}

/// `Σ (sᵢ aᵢ)(sᵢ bᵢ)`, summed in four interleaved partial sums (term `i` into sum `i mod 4`),
/// then `(S₀ + S₁) + (S₂ + S₃)`: a fixed order, independent of the machine, whose four
/// independent chains of additions the processor overlaps (one chain waits on each addition).
fn scaled_dot(a: &[f64], b: &[f64], s: &[f64]) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { scaled_dot_avx2(a, b, s) };
    }
    scaled_dot_body(a, b, s)
}

/// [`scaled_dot`] with the four partial sums as the lanes of one AVX2 register: the same
/// products and sums (multiplications and additions, never fused), four per instruction.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn scaled_dot_avx2(a: &[f64], b: &[f64], s: &[f64]) -> f64 {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd, _mm256_storeu_pd,
    };
    let n = a.len().min(b.len()).min(s.len());
    let body = n - n % 4;
    let mut acc = _mm256_setzero_pd();
    for i in (0..body).step_by(4) {
        // SAFETY: i + 4 ≤ body ≤ the length of each slice.
        let (a4, b4, s4) = unsafe {
            (
                _mm256_loadu_pd(a.as_ptr().add(i)),
                _mm256_loadu_pd(b.as_ptr().add(i)),
                _mm256_loadu_pd(s.as_ptr().add(i)),
            )
        };
        acc = _mm256_add_pd(
            acc,
            _mm256_mul_pd(_mm256_mul_pd(s4, a4), _mm256_mul_pd(s4, b4)),
        );
    }
    let mut sum = [0.0; 4];
    // SAFETY: `sum` has room for the four lanes.
    unsafe { _mm256_storeu_pd(sum.as_mut_ptr(), acc) };
    for (k, i) in (body..n).enumerate() {
        sum[k] += (s[i] * a[i]) * (s[i] * b[i]);
    }
    (sum[0] + sum[1]) + (sum[2] + sum[3])
}

/// [`scaled_dot`] of `x` with each of `columns`, in order, appended to `out`: bit for bit
/// one call per column. With AVX2 the sums of up to four columns go through the values side
/// by side (one chain of dependent additions each, which the others' fill), instead of one
/// column's chain after the other's.
fn scaled_dots<'a>(
    x: &[f64],
    columns: impl Iterator<Item = &'a [f64]>,
    s: &[f64],
    out: &mut Vec<f64>,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        let mut columns = columns.peekable();
        while columns.peek().is_some() {
            let mut group: [&[f64]; 4] = [&[]; 4];
            let mut g = 0;
            for c in columns.by_ref().take(4) {
                group[g] = c;
                g += 1;
            }
            // SAFETY: the processor has AVX2 (checked just above).
            unsafe {
                match g {
                    1 => out.extend(scaled_dots_avx2::<1>(x, &group[..1], s)),
                    2 => out.extend(scaled_dots_avx2::<2>(x, &group[..2], s)),
                    3 => out.extend(scaled_dots_avx2::<3>(x, &group[..3], s)),
                    _ => out.extend(scaled_dots_avx2::<4>(x, &group[..4], s)),
                }
            }
        }
        return;
    }
    out.extend(columns.map(|c| scaled_dot_body(x, c, s)));
}

/// [`scaled_dot`] of `x` with `G` columns side by side: each column's four partial sums in
/// the lanes of its own register, the same products `(s x)(s c)` and sums as
/// [`scaled_dot_avx2`] (a product's factors in either order round alike).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn scaled_dots_avx2<const G: usize>(x: &[f64], columns: &[&[f64]], s: &[f64]) -> [f64; G] {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_setzero_pd, _mm256_storeu_pd,
    };
    let mut n = x.len().min(s.len());
    for c in &columns[..G] {
        n = n.min(c.len());
    }
    let body = n - n % 4;
    let mut acc = [_mm256_setzero_pd(); G];
    for i in (0..body).step_by(4) {
        // SAFETY: i + 4 ≤ body ≤ the length of each slice.
        let sx = unsafe {
            let s4 = _mm256_loadu_pd(s.as_ptr().add(i));
            (s4, _mm256_mul_pd(s4, _mm256_loadu_pd(x.as_ptr().add(i))))
        };
        for (a, c) in acc.iter_mut().zip(columns) {
            // SAFETY: as above.
            let c4 = unsafe { _mm256_loadu_pd(c.as_ptr().add(i)) };
            *a = _mm256_add_pd(*a, _mm256_mul_pd(sx.1, _mm256_mul_pd(sx.0, c4)));
        }
    }
    let mut dots = [0.0; G];
    for ((d, a), c) in dots.iter_mut().zip(acc).zip(columns) {
        let mut sum = [0.0; 4];
        // SAFETY: `sum` has room for the four lanes.
        unsafe { _mm256_storeu_pd(sum.as_mut_ptr(), a) };
        for (k, i) in (body..n).enumerate() {
            sum[k] += (s[i] * x[i]) * (s[i] * c[i]);
        }
        *d = (sum[0] + sum[1]) + (sum[2] + sum[3]);
    }
    dots
}

#[inline(always)]
fn scaled_dot_body(a: &[f64], b: &[f64], s: &[f64]) -> f64 {
    let n = a.len().min(b.len()).min(s.len());
    let (a, b, s) = (&a[..n], &b[..n], &s[..n]);
    let mut sum = [0.0; 4];
    let body = n - n % 4;
    for i in (0..body).step_by(4) {
        for k in 0..4 {
            sum[k] += (s[i + k] * a[i + k]) * (s[i + k] * b[i + k]);
        }
    }
    for (k, i) in (body..n).enumerate() {
        sum[k] += (s[i] * a[i]) * (s[i] * b[i]);
    }
    (sum[0] + sum[1]) + (sum[2] + sum[3])
}

#[cfg(test)]
mod tests {
    use super::scaled_dot;

    /// Lengths through the vector tails and past one AVX2 vector's multiples.
    const LENGTHS: [usize; 11] = [0, 1, 3, 4, 5, 8, 15, 16, 17, 160, 163];

    /// `n` values whose products and sums round (`seed` makes another vector).
    fn v(n: usize, seed: f64) -> Vec<f64> {
        (0..n)
            .map(|i| ((i as f64 + seed) * 0.618_033_988_749_895).sin() * 1e3 / (1.0 + i as f64))
            .collect()
    }

    /// Small integers are summed exactly in any order: every length through the tail cases.
    #[test]
    fn scaled_dot_equals_the_exact_sum() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| i as f64 - 4.0).collect();
            let b: Vec<f64> = (0..n).map(|i| (3 * i + 1) as f64).collect();
            let s: Vec<f64> = (0..n).map(|i| (i % 3 + 1) as f64).collect();
            let exact: i64 = (0..n as i64)
                .map(|i| (i - 4) * (3 * i + 1) * (i % 3 + 1).pow(2))
                .sum();
            assert_eq!(scaled_dot(&a, &b, &s), exact as f64, "n = {n}");
        }
    }

    /// The dots of one vector with many columns equal one call per column bit for bit, for
    /// every group size and tail (0 to 9 columns of lengths through the vector tails).
    #[test]
    fn scaled_dots_equal_one_call_per_column() {
        for n in LENGTHS {
            let (x, s) = (v(n, 0.3), v(n, 2.9));
            for m in 0..10 {
                let columns: Vec<Vec<f64>> = (0..m).map(|j| v(n, 1.7 + j as f64)).collect();
                let mut out = vec![-1.0];
                super::scaled_dots(&x, columns.iter().map(|c| c.as_slice()), &s, &mut out);
                let one_by_one: Vec<u64> = std::iter::once(-1.0f64)
                    .chain(columns.iter().map(|c| scaled_dot(c, &x, &s)))
                    .map(f64::to_bits)
                    .collect();
                let bits: Vec<u64> = out.iter().map(|d| d.to_bits()).collect();
                assert_eq!(bits, one_by_one, "n = {n}, m = {m}");
            }
        }
    }

    /// With values whose products and sums round, the kernel (vector lanes, and AVX2 where
    /// the processor has it) sums exactly in the documented order.
    #[test]
    fn scaled_dot_sums_in_the_documented_order() {
        for n in LENGTHS {
            let (a, b, s) = (v(n, 0.3), v(n, 1.7), v(n, 2.9));
            let mut sum = [0.0; 4];
            for i in 0..n {
                sum[i % 4] += (s[i] * a[i]) * (s[i] * b[i]);
            }
            let documented: f64 = (sum[0] + sum[1]) + (sum[2] + sum[3]);
            assert_eq!(
                scaled_dot(&a, &b, &s).to_bits(),
                documented.to_bits(),
                "n = {n}"
            );
            assert_eq!(
                super::scaled_dot_body(&a, &b, &s).to_bits(),
                documented.to_bits(),
                "n = {n}"
            );
        }
    }
}
