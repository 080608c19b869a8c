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
/// are finite. Eight running sums, one per lane, which the compiler keeps in vector
/// registers: the body is compiled twice, for AVX2 (two four-wide registers) where the
/// processor has it and for the baseline (four two-wide SSE2 registers on x86-64).
fn all_finite(values: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { all_finite_avx2(values) };
    }
    all_finite_body(values)
}

#[inline(always)]
fn all_finite_body(values: &[f64]) -> bool {
    let chunks = values.chunks_exact(8);
    let rest = chunks.remainder();
    let mut lanes = [0.0; 8];
    #[allow(clippy::eq_op)] // v − v is the point: 0, or NaN for a non-finite v
    for c in chunks {
        for (l, &v) in lanes.iter_mut().zip(c) {
            *l += v - v;
        }
    }
    #[allow(clippy::eq_op)]
    let sum = rest
        .iter()
        .fold(lanes.iter().sum::<f64>(), |s, &v| s + (v - v));
    sum == 0.0
}

/// [`all_finite_body`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn all_finite_avx2(values: &[f64]) -> bool {
    all_finite_body(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_nan_or_infinity_is_found_wherever_it_is() {
        assert_eq!(first_non_finite(&[]), None);
        let finite = [0.0, -0.0, f64::MAX, f64::MIN_POSITIVE, 5e-324, -1.5];
        assert_eq!(first_non_finite(&finite), None);
        // every position of a longer vector, through the eight-value steps and their tails,
        // in both builds of the all-finite pass
        for n in [1, 3, 4, 5, 7, 8, 9, 15, 16, 17, 160, 163] {
            let ok: Vec<f64> = (0..n).map(|i| 1e300 * (i as f64 - 2.5)).collect();
            assert_eq!(first_non_finite(&ok), None, "n = {n}");
            assert!(all_finite_body(&ok), "n = {n}");
            for at in 0..n {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut v = ok.clone();
                    v[at] = bad;
                    assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
                    assert!(!all_finite_body(&v), "{bad} at {at} of {n}");
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
