//! The FMI 2.0 Co-Simulation C binding, written once for the exporter (`fmi-export`), the
//! importer (`fmi-import`) and the misuse harness.
//!
//! | module | what |
//! |---|---|
//! | [`types`] (re-exported here) | the `fmi2…` C types and constants, [`Status`] |
//! | [`functions`] | the 34 functions listed once: [`Function`], the `fmi2…TYPE` typedefs, the pointer table [`Functions`] (loaded with feature `load`) |
//! | [`uri`] | `fmuResourceLocation` ↔ path |
//! | `logger` (feature `logger`) | the variadic `fmi2CallbackLogger` as a C shim forwarding text to a Rust [`LogReceiver`](logger::LogReceiver) |
//! | [`first_non_finite`] | the check of the Reals crossing the C ABI, on both sides (`fmi2SetReal` in an FMU, `fmi2GetReal` in the importer) |

#![deny(unsafe_op_in_unsafe_fn)]

pub mod functions;
#[cfg(feature = "logger")]
pub mod logger;
pub mod types;
pub mod uri;

pub use functions::{Function, Functions};
pub use types::*;

/// The index of the first NaN or infinite value, if any. The common all-finite case is one
/// pass without branches (`all_finite`); the index search only runs when that pass failed.
pub fn first_non_finite(values: &[f64]) -> Option<usize> {
    if all_finite(values) {
        None
    } else {
        values.iter().position(|v| !v.is_finite())
    }
}

/// Whether every value is finite: `v − v` is 0 for a finite `v` and NaN for NaN and ±∞, and
/// a NaN stays NaN through any sum, so the sum of all `v − v` is 0 exactly when they all
/// are finite (summed in vector registers: eight values per step in two four-wide registers
/// where the processor has AVX2, four in two two-wide ones otherwise).
fn all_finite(values: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { all_finite_avx2(values) };
    }
    all_finite_baseline(values)
}

/// [`all_finite`] on any x86-64 (SSE2), four values per step; elsewhere value by value.
fn all_finite_baseline(values: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    let (sum, rest) = {
        use std::arch::x86_64::{
            _mm_add_pd, _mm_loadu_pd, _mm_setzero_pd, _mm_storeu_pd, _mm_sub_pd,
        };
        let chunks = values.chunks_exact(4);
        let rest = chunks.remainder();
        let mut lanes = [0.0; 2];
        // SAFETY: SSE2 is part of x86-64; each chunk has four values to load.
        unsafe {
            let (mut a, mut b) = (_mm_setzero_pd(), _mm_setzero_pd());
            for c in chunks {
                let (x, y) = (_mm_loadu_pd(c.as_ptr()), _mm_loadu_pd(c.as_ptr().add(2)));
                a = _mm_add_pd(a, _mm_sub_pd(x, x));
                b = _mm_add_pd(b, _mm_sub_pd(y, y));
            }
            _mm_storeu_pd(lanes.as_mut_ptr(), _mm_add_pd(a, b));
        }
        (lanes[0] + lanes[1], rest)
    };
    #[cfg(not(target_arch = "x86_64"))]
    let (sum, rest) = (0.0, values);
    #[allow(clippy::eq_op)] // v − v is the point: 0, or NaN for a non-finite v
    let sum = rest.iter().fold(sum, |s, &v| s + (v - v));
    sum == 0.0
}

/// [`all_finite`] eight values per step.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn all_finite_avx2(values: &[f64]) -> bool {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd,
    };
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    let mut lanes = [0.0; 4];
    // SAFETY: each chunk has eight values to load.
    unsafe {
        let (mut a, mut b) = (_mm256_setzero_pd(), _mm256_setzero_pd());
        for c in chunks {
            let (x, y) = (
                _mm256_loadu_pd(c.as_ptr()),
                _mm256_loadu_pd(c.as_ptr().add(4)),
            );
            a = _mm256_add_pd(a, _mm256_sub_pd(x, x));
            b = _mm256_add_pd(b, _mm256_sub_pd(y, y));
        }
        _mm256_storeu_pd(lanes.as_mut_ptr(), _mm256_add_pd(a, b));
    }
    #[allow(clippy::eq_op)] // v − v is the point: 0, or NaN for a non-finite v
    let sum = rest
        .iter()
        .fold(lanes.iter().sum::<f64>(), |s, &v| s + (v - v));
    sum == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_nan_or_infinity_is_found_wherever_it_is() {
        assert_eq!(first_non_finite(&[]), None);
        let finite = [0.0, -0.0, f64::MAX, f64::MIN_POSITIVE, 5e-324, -1.5];
        assert_eq!(first_non_finite(&finite), None);
        // every position of a longer vector, through the four- and eight-value steps and
        // their tails, in both builds of the all-finite pass
        for n in [1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 160, 163] {
            let ok: Vec<f64> = (0..n).map(|i| 1e300 * (i as f64 - 2.5)).collect();
            assert_eq!(first_non_finite(&ok), None, "n = {n}");
            assert!(all_finite_baseline(&ok), "n = {n}");
            for at in 0..n {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut v = ok.clone();
                    v[at] = bad;
                    assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
                    assert!(!all_finite_baseline(&v), "{bad} at {at} of {n}");
                    #[cfg(target_arch = "x86_64")]
                    if std::arch::is_x86_feature_detected!("avx2") {
                        // SAFETY: the processor has AVX2.
                        assert!(!unsafe { all_finite_avx2(&v) }, "{bad} at {at} of {n}");
                        assert!(unsafe { all_finite_avx2(&ok) }, "n = {n}");
                    }
                }
            }
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in 0..finite.len() {
                let mut v = finite.to_vec();
                v[at] = bad;
                v.push(bad);
                assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at}");
            }
        }
    }
}
