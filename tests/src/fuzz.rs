//! A seeded mutation fuzzer for the project's parsers, run as ordinary tests.
//!
//! [`Mutator`] derives inputs from a few valid seeds by byte flips, insertions, deletions,
//! duplications of a slice, splices of two seeds, and "interesting" tokens (numbers at the
//! edges of f64 and usize, `nan`, `inf`, empty strings, deep nesting, long lines). [`run`]
//! feeds `cases` of them to a parser inside `catch_unwind` and fails on the first panic,
//! printing the input (and keeping it under `target/tmp/fuzz-failures/`) so that it can be
//! added to the regression corpus of the test. The generator is a fixed-seed xorshift, so a
//! run is reproducible.

use std::panic::{catch_unwind, AssertUnwindSafe};

/// Tokens that often break parsers.
const TOKENS: &[&str] = &[
    "0",
    "-0",
    "1e-300",
    "1e300",
    "5e-324",
    "1.7976931348623157e308",
    "-1",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "18446744073709551616",
    "\"\"",
    "\"",
    "[",
    "]",
    "{",
    "}",
    "[[",
    "]]",
    "=",
    ",",
    "\n",
    "\r\n",
    "\t",
    "\0",
    "#",
    "'",
    "\\",
    "\u{feff}",
    "é",
    "∞",
    "true",
    "null",
    "[]",
    "{}",
    "..",
    "/",
    "%",
    "-1e-308",
];

/// A fixed-seed mutator over a set of seed inputs.
pub struct Mutator {
    state: u64,
    seeds: Vec<Vec<u8>>,
}

impl Mutator {
    pub fn new(seed: u64, seeds: &[&[u8]]) -> Mutator {
        assert!(!seeds.is_empty());
        Mutator {
            state: seed | 1,
            seeds: seeds.iter().map(|s| s.to_vec()).collect(),
        }
    }

    fn next(&mut self) -> u64 {
        // xorshift64*
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }

    /// The next input: a seed with one to eight mutations.
    pub fn input(&mut self) -> Vec<u8> {
        let k = self.below(self.seeds.len());
        let mut v = self.seeds[k].clone();
        for _ in 0..1 + self.below(8) {
            let at = self.below(v.len() + 1);
            match self.below(7) {
                0 if !v.is_empty() => {
                    let i = self.below(v.len());
                    v[i] ^= 1 << self.below(8);
                }
                1 => {
                    let b = self.next() as u8;
                    v.insert(at, b);
                }
                2 if !v.is_empty() => {
                    let n = 1 + self.below(16.min(v.len()));
                    let from = self.below(v.len() - n + 1);
                    v.drain(from..from + n);
                }
                3 if !v.is_empty() => {
                    let n = 1 + self.below(32.min(v.len()));
                    let from = self.below(v.len() - n + 1);
                    let piece: Vec<u8> = v[from..from + n].to_vec();
                    v.splice(at..at, piece);
                }
                4 => {
                    let k = self.below(self.seeds.len());
                    let other = self.seeds[k].clone();
                    let cut = self.below(other.len() + 1);
                    v.truncate(at);
                    v.extend_from_slice(&other[cut..]);
                }
                5 => {
                    // replace a number-like run by an interesting token
                    let t = TOKENS[self.below(TOKENS.len())].as_bytes();
                    let end = (at..v.len())
                        .find(|&i| !(v[i].is_ascii_alphanumeric() || b".+-".contains(&v[i])))
                        .unwrap_or(v.len());
                    v.splice(at..end, t.iter().copied());
                }
                _ => {
                    let t = TOKENS[self.below(TOKENS.len())].as_bytes();
                    v.splice(at..at, t.iter().copied());
                }
            }
        }
        v
    }
}

/// Feed `cases` mutated inputs to `parse`; panics (failing the test) on the first input
/// that makes `parse` panic, after writing it to `target/tmp/fuzz-failures/<name>-<n>`.
/// Returns how many inputs `parse` accepted (`Ok`), to show the fuzzer reaches past the
/// first error.
pub fn run(
    name: &str,
    seed: u64,
    seeds: &[&[u8]],
    cases: usize,
    parse: impl Fn(&[u8]) -> bool,
) -> usize {
    let mut m = Mutator::new(seed, seeds);
    let mut accepted = 0;
    for n in 0..cases {
        let input = m.input();
        match catch_unwind(AssertUnwindSafe(|| parse(&input))) {
            Ok(true) => accepted += 1,
            Ok(false) => {}
            Err(_) => {
                let dir = crate::paths::target_tmp_dir().join("fuzz-failures");
                let _ = std::fs::create_dir_all(&dir);
                let file = dir.join(format!("{name}-{n}"));
                let _ = std::fs::write(&file, &input);
                panic!(
                    "{name}: case {n} panicked; input kept in {}:\n{}",
                    file.display(),
                    String::from_utf8_lossy(&input)
                );
            }
        }
    }
    accepted
}

/// Run `parse` on every input of a regression corpus (inputs that once failed).
pub fn corpus(name: &str, inputs: &[&[u8]], parse: impl Fn(&[u8]) -> bool) {
    for (i, input) in inputs.iter().enumerate() {
        if catch_unwind(AssertUnwindSafe(|| parse(input))).is_err() {
            panic!("{name}: corpus input {i} panics again");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mutator_is_reproducible_and_the_runner_catches_panics() {
        let a: Vec<Vec<u8>> = {
            let mut m = Mutator::new(7, &[b"speed = 1.0"]);
            (0..50).map(|_| m.input()).collect()
        };
        let b: Vec<Vec<u8>> = {
            let mut m = Mutator::new(7, &[b"speed = 1.0"]);
            (0..50).map(|_| m.input()).collect()
        };
        assert_eq!(a, b);
        assert!(a.iter().any(|v| v != b"speed = 1.0"));
        let caught = catch_unwind(|| {
            run("selftest", 1, &[b"x"], 100, |i| {
                assert!(i.len() < 3, "long input");
                true
            })
        });
        assert!(caught.is_err());
    }
}
