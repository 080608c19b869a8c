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
/// are finite (summed in vector registers, four values per step).
fn all_finite(values: &[f64]) -> bool {
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

#[cfg(test)]
mod tests {
    use super::first_non_finite;

    #[test]
    fn the_first_nan_or_infinity_is_found_wherever_it_is() {
        assert_eq!(first_non_finite(&[]), None);
        let finite = [0.0, -0.0, f64::MAX, f64::MIN_POSITIVE, 5e-324, -1.5];
        assert_eq!(first_non_finite(&finite), None);
        // every position of a longer vector, through the four-value steps and their tail
        for n in [1, 3, 4, 5, 8, 9, 160, 163] {
            let ok: Vec<f64> = (0..n).map(|i| 1e300 * (i as f64 - 2.5)).collect();
            assert_eq!(first_non_finite(&ok), None, "n = {n}");
            for at in 0..n {
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut v = ok.clone();
                    v[at] = bad;
                    assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
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
