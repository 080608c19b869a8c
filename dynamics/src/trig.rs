//! `sin θ` and `cos θ` of a few angles at once, for the angles of the sine mode shapes
//! (`θ = π (x − x₀)/L` of a position on the deck, `0 ≤ θ ≤ π`), without a library call per
//! angle: the same arithmetic in every lane, so the four lanes of one call compile to
//! four-wide vector instructions and one lane gives bit for bit what that lane gives among
//! four.
//!
//! The mathematics (as in the fdlibm kernels, whose polynomial coefficients these are):
//!
//! * **Reduction.** `n = round(2θ/π)`, `r = θ − n π/2` with `|r| ≤ π/4`. `π/2` is split into
//!   `P₁ + P₂ + P₃ + P₃ₜ`, the first three of 33 significant bits each, so that `n Pᵢ` is
//!   exact for `n ≤ 2`; `θ − n P₁` is exact (the two are within a factor two of each
//!   other), the next two subtractions are carried as exact sums (`two_sum`), and `r` is
//!   left as a head and a tail `r = r_h + r_l`, off by about 10⁻³² of `|r|` (the rounding of
//!   the tail) plus 10⁻⁴⁷ (what the four parts miss of `π/2`), so even the angle nearest to
//!   `π/2` (`r` about 6·10⁻¹⁷) keeps every bit of `cos θ`.
//! * **Kernels** on `|r| ≤ π/4`, `z = r_h²`:
//!   `sin r = r_h + r_h z (S₁ + z (S₂ + …)) + (1 − z/2) r_l` (degree 13) and
//!   `cos r = 1 − z/2 + z² (C₁ + z (C₂ + …)) − r_h r_l` (degree 14); fdlibm bounds each
//!   polynomial's error by about 2⁻⁵⁸ and orders the sums so that the result is within one
//!   unit in the last place.
//! * **Quadrant.** `n = 0`: `(sin r, cos r)`; `n = 1`: `(cos r, −sin r)`; `n = 2`:
//!   `(−sin r, −cos r)`.
//!
//! Angles outside `[−0.7, 3.9]` (where `n` would exceed 2) and non-finite ones go to the
//! standard library, lane by lane. Tested against the standard library: within one unit in
//! the last place over `[0, π]` (2²⁰ angles and the neighbours of the multiples of `π/4`),
//! and equal to it at 0, `π/2` and `π`.
//!
//! The polynomial coefficients are those of fdlibm (`k_sin.c`, `k_cos.c`):
//! Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved. Developed at SunPro, a
//! Sun Microsystems, Inc. business. Permission to use, copy, modify, and distribute this
//! software is freely granted, provided that this notice is preserved.

/// The first 33 bits of π/2.
const P1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// The next 33 bits of π/2.
const P2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000);
/// The next 33 bits of π/2.
const P3: f64 = f64::from_bits(0x3BA3_198A_2E00_0000);
/// The rest of π/2, π/2 − P1 − P2 − P3 to double precision.
const P3T: f64 = f64::from_bits(0x397B_839A_2520_49C1);

const S1: f64 = -0.16666666666666632;
const S2: f64 = 0.00833333333332249;
const S3: f64 = -0.0001984126982985795;
const S4: f64 = 2.7557313707070068e-06;
const S5: f64 = -2.5050760253406863e-08;
const S6: f64 = 1.58969099521155e-10;

const C1: f64 = 0.0416666666666666;
const C2: f64 = -0.001388888888887411;
const C3: f64 = 2.480158728947673e-05;
const C4: f64 = -2.7557314351390663e-07;
const C5: f64 = 2.087572321298175e-09;
const C6: f64 = -1.1359647557788195e-11;

/// The angles the polynomial path takes (`n = round(2θ/π) ≤ 2`, `θ − n P₁` exact).
const LOW: f64 = -0.7;
const HIGH: f64 = 3.9;

/// `(a + b)` as the rounded sum and its exact error.
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The reduction and kernels of one angle inside `[LOW, HIGH]` (see the module
/// documentation); [`sin_cos4_avx2`] makes the same operations in the same order.
#[inline(always)]
fn sin_cos_inside(t: f64) -> (f64, f64) {
    let n = (t * std::f64::consts::FRAC_2_PI + ROUND) - ROUND;
    let a = t - n * P1;
    let (r, e1) = two_sum(a, -(n * P2));
    let (r, e2) = two_sum(r, -(n * P3));
    let lo = (e1 + e2) - n * P3T;
    let x = r + lo;
    let y = (r - x) + lo;
    let z = x * x;
    let w = z * z;
    let rs = (S2 + z * (S3 + z * S4)) + (z * w) * (S5 + z * S6);
    let v = z * x;
    let s = x - ((z * (0.5 * y - v * rs) - y) - v * S1);
    let rc = z * (C1 + z * (C2 + z * C3)) + (w * w) * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = w + (((1.0 - w) - hz) + (z * rc - x * y));
    let (ps, pc) = if n == 1.0 { (c, -s) } else { (s, c) };
    if n == 2.0 {
        (-ps, -pc)
    } else {
        (ps, pc)
    }
}

/// 1.5·2⁵²: adding and taking it off rounds to the nearest integer.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// Whether the polynomial path takes `t` (NaN fails both comparisons).
#[inline(always)]
fn inside(t: f64) -> bool {
    (LOW..=HIGH).contains(&t)
}

/// `(sin θ, cos θ)` of one angle, bit for bit as a lane of [`sin_cos4`].
#[inline]
pub fn sin_cos(theta: f64) -> (f64, f64) {
    if inside(theta) {
        sin_cos_inside(theta)
    } else {
        theta.sin_cos()
    }
}

/// `(sin θⱼ, cos θⱼ)` of four angles, with AVX2 where the processor has it (the same values).
#[inline]
pub fn sin_cos4(theta: [f64; 4]) -> ([f64; 4], [f64; 4]) {
    #[cfg(target_arch = "x86_64")]
    if theta.iter().all(|&t| inside(t)) && std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { sin_cos4_avx2(theta) };
    }
    let (mut s, mut c) = ([0.0; 4], [0.0; 4]);
    for j in 0..4 {
        (s[j], c[j]) = sin_cos(theta[j]);
    }
    (s, c)
}

/// [`sin_cos_inside`] of four angles in one vector each step.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sin_cos4_avx2(theta: [f64; 4]) -> ([f64; 4], [f64; 4]) {
    use std::arch::x86_64::*;
    let k = |v: f64| _mm256_set1_pd(v);
    let (add, sub, mul) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd);
    // SAFETY: unaligned loads and stores of four f64 from and into arrays of four.
    let t = unsafe { _mm256_loadu_pd(theta.as_ptr()) };
    let n = sub(
        add(mul(t, k(std::f64::consts::FRAC_2_PI)), k(ROUND)),
        k(ROUND),
    );
    let a = sub(t, mul(n, k(P1)));
    let two_sum = |a: __m256d, b: __m256d| {
        let s = add(a, b);
        let bb = sub(s, a);
        (s, add(sub(a, sub(s, bb)), sub(b, bb)))
    };
    let neg = |v: __m256d| _mm256_xor_pd(v, k(-0.0));
    let (r, e1) = two_sum(a, neg(mul(n, k(P2))));
    let (r, e2) = two_sum(r, neg(mul(n, k(P3))));
    let lo = sub(add(e1, e2), mul(n, k(P3T)));
    let x = add(r, lo);
    let y = add(sub(r, x), lo);
    let z = mul(x, x);
    let w = mul(z, z);
    let rs = add(
        add(k(S2), mul(z, add(k(S3), mul(z, k(S4))))),
        mul(mul(z, w), add(k(S5), mul(z, k(S6)))),
    );
    let v = mul(z, x);
    let s = sub(
        x,
        sub(
            sub(mul(z, sub(mul(k(0.5), y), mul(v, rs))), y),
            mul(v, k(S1)),
        ),
    );
    let rc = add(
        mul(z, add(k(C1), mul(z, add(k(C2), mul(z, k(C3)))))),
        mul(mul(w, w), add(k(C4), mul(z, add(k(C5), mul(z, k(C6)))))),
    );
    let hz = mul(k(0.5), z);
    let w = sub(k(1.0), hz);
    let c = add(w, add(sub(sub(k(1.0), w), hz), sub(mul(z, rc), mul(x, y))));
    let swap = _mm256_cmp_pd::<_CMP_EQ_OQ>(n, k(1.0));
    let negate = _mm256_and_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(n, k(2.0)), k(-0.0));
    let ps = _mm256_blendv_pd(s, c, swap);
    let pc = _mm256_blendv_pd(c, neg(s), swap);
    let (mut so, mut co) = ([0.0; 4], [0.0; 4]);
    // SAFETY: as the load above.
    unsafe {
        _mm256_storeu_pd(so.as_mut_ptr(), _mm256_xor_pd(ps, negate));
        _mm256_storeu_pd(co.as_mut_ptr(), _mm256_xor_pd(pc, negate));
    }
    (so, co)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// How many representable values lie between a and b.
    fn ulps(a: f64, b: f64) -> u64 {
        let key = |v: f64| {
            let i = v.to_bits() as i64;
            if i < 0 {
                i64::MIN - i
            } else {
                i
            }
        };
        key(a).abs_diff(key(b))
    }

    #[test]
    fn the_parts_of_half_pi_sum_to_it() {
        // π/2 − fl(π/2) = 6.123233995736766e-17 (the head's error, to double precision):
        // fl(π/2) − P1 and P2 − that are exact (each pair within a factor two)
        let d = std::f64::consts::FRAC_PI_2 - P1;
        let tail = ((P2 - d) + P3) + P3T;
        assert!((tail - 6.123_233_995_736_766e-17).abs() < 1e-32, "{tail:e}");
        assert_eq!(P1 + P2, std::f64::consts::FRAC_PI_2);
        // each of the first three has at most 33 significant bits (n·Pᵢ exact for n ≤ 2)
        for p in [P1, P2, P3] {
            assert_eq!(p.to_bits() & ((1 << 20) - 1), 0, "{p:e}");
        }
    }

    #[test]
    fn within_one_ulp_of_the_standard_library_over_the_deck() {
        let mut worst = (0, 0);
        let mut differ = 0usize;
        let n = 1 << 20;
        // a low-discrepancy walk over [0, π] plus its end points and the quadrant edges
        let mut angles: Vec<f64> = (0..n)
            .map(|i| PI * ((i as f64 * 0.618_033_988_749_894_9) % 1.0))
            .collect();
        for k in 0..=4 {
            let a = k as f64 * PI / 4.0;
            let mut b = a;
            for _ in 0..64 {
                angles.push(b);
                b = f64::from_bits(b.to_bits() + 1);
            }
            let mut b = a;
            for _ in 0..64 {
                if b > 0.0 {
                    b = f64::from_bits(b.to_bits() - 1);
                    angles.push(b);
                }
            }
        }
        angles.extend([1e-300, 1e-20, 1e-9, 0.6999, 3.8999, LOW, HIGH]);
        for chunk in angles.chunks(4) {
            let mut t = [0.0; 4];
            t[..chunk.len()].copy_from_slice(chunk);
            let (s4, c4) = sin_cos4(t);
            for (j, &a) in chunk.iter().enumerate() {
                let (s, c) = sin_cos(a);
                assert_eq!(
                    (s.to_bits(), c.to_bits()),
                    (s4[j].to_bits(), c4[j].to_bits())
                );
                let (ws, wc) = a.sin_cos();
                let (us, uc) = (ulps(s, ws), ulps(c, wc));
                differ += usize::from(us + uc > 0);
                worst = (worst.0.max(us), worst.1.max(uc));
            }
        }
        assert!(
            worst.0 <= 1 && worst.1 <= 1,
            "worst ulps (sin, cos): {worst:?}"
        );
        // most equal the library's (both round to within one unit; the library mostly to
        // the nearest): 6 % of these angles differ in one of the two
        assert!(
            differ * 10 < angles.len(),
            "{differ} of {} differ",
            angles.len()
        );
        // the exact points
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(PI / 2.0), (PI / 2.0).sin_cos());
        assert_eq!(sin_cos(PI), PI.sin_cos());
    }

    #[test]
    fn other_angles_go_to_the_standard_library() {
        for t in [-1.0, 4.0, 100.0, -1e9, f64::INFINITY] {
            let (s, c) = sin_cos(t);
            assert_eq!(
                (s.to_bits(), c.to_bits()),
                (t.sin().to_bits(), t.cos().to_bits())
            );
        }
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
        // a lane outside does not change the others
        let (s4, c4) = sin_cos4([1.0, 7.0, f64::NAN, 2.0]);
        assert_eq!((s4[0], c4[0]), sin_cos(1.0));
        assert_eq!((s4[1], c4[1]), 7.0f64.sin_cos());
        assert_eq!((s4[3], c4[3]), sin_cos(2.0));
    }
}
