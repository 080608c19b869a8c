//! The convergence measure of the interface iteration.
//!
//! For the guess `x ∈ ℝⁿ` of the interface values and the values `x̃ = H(x)` that one sweep
//! returns, the measure is the weighted root mean square of the change
//!
//! ```text
//!            ┌  1   n   ⎛      x̃ᵢ − xᵢ       ⎞² ┐ ½
//! ‖x̃ − x‖ = │ ───  Σ   ⎜ ────────────────── ⎟  │
//!            └  n  i=1  ⎝ rtol·|x̃ᵢ| + atol  ⎠  ┘
//! ```
//!
//! and the iteration has converged when `‖x̃ − x‖ ≤ 1`. Each value is thus compared with its
//! own magnitude, so positions (~1e3 m), displacements (~1e-3 m) and forces (~1e5 N) can share
//! one interface. With `n = 0` (no feedback) the measure is 0.
//!
//! **Groups** ([`WeightedRms::evaluate_grouped`]). A value that passes through zero (a lateral
//! force, a roll moment) would be held to `atol` alone, down at the rounding level of its
//! computation, where the iteration may stall. Values of one physical quantity (the same
//! source and unit, e.g. all wheel forces in N) therefore form a group `g`, and each value is
//! compared with the largest magnitude in its group:
//!
//! ```text
//!            ┌  1   n   ⎛         x̃ᵢ − xᵢ          ⎞² ┐ ½
//! ‖x̃ − x‖ = │ ───  Σ   ⎜ ───────────────────────── ⎟  │ ,   X_g = max |x̃ⱼ| over j ∈ g .
//!            └  n  i=1  ⎝ rtol·X_g(i) + atol        ⎠  ┘
//! ```
//!
//! A group of one value is the plain measure above.

/// The groups of the grouped measure: the group of each value, scratch for the group
/// maxima, and the largest magnitude each group has had ([`WeightedRms::evaluate_lag`]).
#[derive(Debug, Clone, Default)]
pub struct Groups {
    of: Vec<usize>,
    /// The values of each group, in order.
    members: Members,
    max: Vec<f64>,
    /// `rtol·max + atol` of each group (scratch of [`WeightedRms::evaluate_in`]).
    denominator: Vec<f64>,
    peak: Vec<f64>,
}

impl Groups {
    /// Values with equal keys share a group (numbered in order of first appearance).
    pub fn by_key<K: PartialEq>(keys: impl Iterator<Item = K>) -> Self {
        let (of, n) = number_by_key(keys);
        Self {
            members: members_of(&of, n),
            of,
            max: vec![0.0; n],
            denominator: Vec::with_capacity(n),
            peak: vec![0.0; n],
        }
    }

    /// The group of each value.
    pub fn of(&self) -> &[usize] {
        &self.of
    }

    /// Number of values grouped.
    pub fn len(&self) -> usize {
        self.of.len()
    }

    pub fn is_empty(&self) -> bool {
        self.of.is_empty()
    }
}

/// Number the keys by equality, in order of first appearance; returns the numbers and how
/// many distinct keys there are.
pub(crate) fn number_by_key<K: PartialEq>(keys: impl Iterator<Item = K>) -> (Vec<usize>, usize) {
    let mut seen: Vec<K> = Vec::new();
    let numbers = keys
        .map(|k| match seen.iter().position(|s| *s == k) {
            Some(n) => n,
            None => {
                seen.push(k);
                seen.len() - 1
            }
        })
        .collect();
    (numbers, seen.len())
}

/// The members of each group, and, where the groups repeat with a short period (the
/// position, speed, forces and moment of one wheelset after another), the group of each
/// place in a period.
#[derive(Debug, Clone, Default)]
pub(crate) struct Members {
    lists: Vec<Vec<usize>>,
    /// `Some(lanes)`: item `i` is in group `lanes[i mod p]`, `p = lanes.len() ≤ MAX_PERIOD`
    /// dividing the number of items.
    lanes: Option<Vec<usize>>,
}

/// The longest period [`max_abs_into`] takes item by item.
const MAX_PERIOD: usize = 8;

/// The members of each of `n` groups, in order, from the group of each item; the shortest
/// period of the groups up to [`MAX_PERIOD`].
pub(crate) fn members_of(of: &[usize], n: usize) -> Members {
    let mut lists = vec![Vec::new(); n];
    for (i, &g) in of.iter().enumerate() {
        lists[g].push(i);
    }
    let lanes = (1..=MAX_PERIOD.min(of.len()))
        .find(|&p| of.len().is_multiple_of(p) && (p..of.len()).all(|i| of[i] == of[i - p]))
        .map(|p| of[..p].to_vec());
    Members { lists, lanes }
}

/// `out[g] ← max(out[g], |vᵢ|)` over the members `i` of each group `g` (`out` holds no NaN).
///
/// Four running maxima per group instead of one chain through `out[g]` (the groups of an
/// interface interleave: position, speed, force, moment of each wheelset); a maximum is exact
/// in any order, so the result equals the element-by-element update bit for bit. The larger
/// of two magnitudes is taken by one comparison, which is `f64::max` where neither is NaN
/// and, as `f64::max`, passes over a NaN `|vᵢ|`.
///
/// Groups that repeat with a period ([`Members`]) are read in order, one running maximum per
/// place of the period (a maximum is exact in any order, so bit for bit the same again).
pub(crate) fn max_abs_into(members: &Members, values: &[f64], out: &mut [f64]) {
    if let Some(lanes) = &members.lanes {
        match lanes.len() {
            1 => return max_abs_periodic::<1>(lanes, values, out),
            2 => return max_abs_periodic::<2>(lanes, values, out),
            3 => return max_abs_periodic::<3>(lanes, values, out),
            4 => return max_abs_periodic::<4>(lanes, values, out),
            5 => return max_abs_periodic::<5>(lanes, values, out),
            6 => return max_abs_periodic::<6>(lanes, values, out),
            7 => return max_abs_periodic::<7>(lanes, values, out),
            8 => return max_abs_periodic::<8>(lanes, values, out),
            _ => {}
        }
    }
    for (list, o) in members.lists.iter().zip(out.iter_mut()) {
        let mut m = [*o; 4];
        let chunks = list.chunks_exact(4);
        let rest = chunks.remainder();
        for c in chunks {
            for (mk, &i) in m.iter_mut().zip(c) {
                *mk = larger(*mk, values[i].abs());
            }
        }
        for (mk, &i) in m.iter_mut().zip(rest) {
            *mk = larger(*mk, values[i].abs());
        }
        *o = larger(larger(m[0], m[1]), larger(m[2], m[3]));
    }
}

/// The larger of two magnitudes by one comparison (`f64::max` where neither is NaN; passes
/// over a NaN `a`).
#[inline(always)]
fn larger(m: f64, a: f64) -> f64 {
    if a > m {
        a
    } else {
        m
    }
}

/// [`max_abs_into`] of groups with period `P` (`lanes`: the group of each place).
fn max_abs_periodic<const P: usize>(lanes: &[usize], values: &[f64], out: &mut [f64]) {
    let mut m: [f64; P] = std::array::from_fn(|k| out[lanes[k]]);
    for chunk in values.chunks_exact(P) {
        for (mk, &v) in m.iter_mut().zip(chunk) {
            *mk = larger(*mk, v.abs());
        }
    }
    for (&g, mk) in lanes.iter().zip(m) {
        out[g] = larger(out[g], mk);
    }
}

/// Weighted RMS of the interface change with relative and absolute tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WeightedRms {
    /// Relative tolerance (dimensionless).
    pub rtol: f64,
    /// Absolute tolerance, in the units of the interface values; must be > 0.
    pub atol: f64,
}

impl WeightedRms {
    pub fn new(rtol: f64, atol: f64) -> Self {
        Self { rtol, atol }
    }

    /// `‖x̃ − x‖` as defined in the module documentation.
    pub fn evaluate(&self, x: &[f64], x_tilde: &[f64]) -> f64 {
        self.rms(x, x_tilde, |_, t| t.abs())
    }

    /// The grouped measure (module docs): `group_of[i]` is the group of value i, and
    /// `group_max` (one entry per group) is scratch space.
    pub fn evaluate_grouped(
        &self,
        x: &[f64],
        x_tilde: &[f64],
        group_of: &[usize],
        group_max: &mut [f64],
    ) -> f64 {
        assert_eq!(x.len(), group_of.len(), "one group per interface value");
        group_max.iter_mut().for_each(|m| *m = 0.0);
        for (&g, &v) in group_of.iter().zip(x_tilde) {
            group_max[g] = group_max[g].max(v.abs());
        }
        self.rms(x, x_tilde, |i, _| group_max[group_of[i]])
    }

    /// The grouped measure over [`Groups`].
    pub fn evaluate_in(&self, x: &[f64], x_tilde: &[f64], groups: &mut Groups) -> f64 {
        let Groups {
            of,
            members,
            max,
            denominator,
            ..
        } = groups;
        assert_eq!(x.len(), of.len(), "one group per interface value");
        max.fill(0.0);
        max_abs_into(members, x_tilde, max);
        // each group's denominator once (the same operations as per value: bit for bit)
        denominator.clear();
        denominator.extend(max.iter().map(|&m| self.rtol * m + self.atol));
        self.rms_by(x, x_tilde, |i, _| denominator[of[i]])
    }

    /// The value with the largest weighted change in [`WeightedRms::evaluate_in`] (call that
    /// first: it uses the group maxima it left), and that weighted change.
    pub fn worst_in(&self, x: &[f64], x_tilde: &[f64], groups: &Groups) -> Option<(usize, f64)> {
        x.iter()
            .zip(x_tilde)
            .enumerate()
            .map(|(i, (&xi, &ti))| {
                let m = groups.max[groups.of[i]];
                (i, ((ti - xi) / (self.rtol * m + self.atol)).abs())
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// The interface defect of an explicit step: `x` the values the lagged inputs used
    /// (outputs at `t`), `x̃` the outputs they stand for (at `t + h`), each difference
    /// measured against the largest magnitude its group has had so far in the run (`x` and
    /// `x̃` included), `X_g = max |x̃ⱼ|` over j ∈ g and all earlier steps:
    ///
    /// ```text
    ///            ┌  1   n   ⎛        x̃ᵢ − xᵢ          ⎞² ┐ ½
    /// ‖x̃ − x‖ = │ ───  Σ   ⎜ ──────────────────────── ⎟  │ .
    ///            └  n  i=1  ⎝ rtol·X_g(i) + atol       ⎠  ┘
    /// ```
    ///
    /// So an oscillating value is judged against its amplitude, not against its value at a
    /// zero crossing, and on a smooth response the defect is proportional to h.
    pub fn evaluate_lag(&self, x: &[f64], x_tilde: &[f64], groups: &mut Groups) -> f64 {
        for ((&g, &a), &b) in groups.of.iter().zip(x).zip(x_tilde) {
            groups.peak[g] = groups.peak[g].max(a.abs()).max(b.abs());
        }
        let Groups { of, peak, .. } = groups;
        self.rms(x, x_tilde, |i, _| peak[of[i]])
    }

    /// Weighted RMS of `x̃ − x` with value i measured against `magnitude(i, x̃ᵢ)`.
    fn rms(&self, x: &[f64], x_tilde: &[f64], magnitude: impl Fn(usize, f64) -> f64) -> f64 {
        self.rms_by(x, x_tilde, |i, t| self.rtol * magnitude(i, t) + self.atol)
    }

    /// Weighted RMS of `x̃ − x` with value i divided by `denominator(i, x̃ᵢ)`.
    fn rms_by(&self, x: &[f64], x_tilde: &[f64], denominator: impl Fn(usize, f64) -> f64) -> f64 {
        assert_eq!(
            x.len(),
            x_tilde.len(),
            "interface vectors of different length"
        );
        if x.is_empty() {
            return 0.0;
        }
        // Σ eᵢ² in the order of i; the quotients of four values at a time are independent
        // (the divisions overlap), the sum is one chain as before: bit for bit the same.
        let term = |i: usize, xi: f64, ti: f64| {
            let e = (ti - xi) / denominator(i, ti);
            e * e
        };
        let mut sum = 0.0;
        let (xs, ts) = (x.chunks_exact(4), x_tilde.chunks_exact(4));
        let first_rest = x.len() - xs.remainder().len();
        for (k, (xc, tc)) in xs.zip(ts).enumerate() {
            let i = 4 * k;
            let e = [
                term(i, xc[0], tc[0]),
                term(i + 1, xc[1], tc[1]),
                term(i + 2, xc[2], tc[2]),
                term(i + 3, xc[3], tc[3]),
            ];
            for ek in e {
                sum += ek;
            }
        }
        for (i, (&xi, &ti)) in x.iter().zip(x_tilde).enumerate().skip(first_rest) {
            sum += term(i, xi, ti);
        }
        (sum / x.len() as f64).sqrt()
    }

    /// Whether `x̃` is converged with respect to `x`.
    pub fn converged(&self, x: &[f64], x_tilde: &[f64]) -> bool {
        self.evaluate(x, x_tilde) <= 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::{max_abs_into, members_of, Groups, Members, WeightedRms};

    /// Groups that repeat with a period are found (the shortest, up to eight places, dividing
    /// the number of values), and their maxima taken place by place equal those by member
    /// lists bit for bit: NaN passed over, −0.0 and the maxima already held included.
    #[test]
    fn periodic_group_maxima_equal_those_by_member_lists() {
        // (pattern, its shortest period if it is at most eight places)
        let patterns: [(&[usize], Option<usize>); 6] = [
            (&[0], Some(1)),
            (&[0, 1, 2, 3, 2], Some(5)),
            (&[0, 1, 0, 1], Some(2)),
            (&[0, 1, 2, 0, 1, 2, 3, 4], Some(8)),
            (&[0, 1, 2, 3, 4, 5, 6, 7, 8], None),
            (&[0, 1, 2, 0, 1, 2, 0, 1, 2, 3], None),
        ];
        for (pattern, period) in patterns {
            for repeats in 0..7 {
                let of: Vec<usize> = (0..pattern.len() * repeats)
                    .map(|i| pattern[i % pattern.len()])
                    .collect();
                let n_groups = pattern.iter().max().map_or(0, |g| g + 1);
                let members = members_of(&of, n_groups);
                assert_eq!(
                    members.lanes.as_ref().map(Vec::len),
                    period.filter(|_| repeats > 0),
                    "{pattern:?} × {repeats}"
                );
                let by_lists = Members {
                    lists: members.lists.clone(),
                    lanes: None,
                };
                let mut v: Vec<f64> = (0..of.len())
                    .map(|i| ((i as f64 + 0.2) * 2.1).sin() * 10f64.powi(i as i32 % 5))
                    .collect();
                if v.len() > 3 {
                    v[1] = f64::NAN;
                    v[3] = -0.0;
                }
                for start in [0.0, -0.0, 3.5] {
                    let (mut a, mut b) = (vec![start; n_groups], vec![start; n_groups]);
                    max_abs_into(&members, &v, &mut a);
                    max_abs_into(&by_lists, &v, &mut b);
                    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&a), bits(&b), "{pattern:?} × {repeats}, from {start}");
                }
            }
        }
    }

    /// Interleaved groups (as position, speed, force, moment of each wheelset), every length
    /// through the tail cases of the four running maxima: the maxima by member lists equal
    /// the element-by-element ones bit for bit, and so does the measure.
    #[test]
    fn group_maxima_by_members_equal_the_element_loop() {
        let m = WeightedRms::new(1e-10, 1e-12);
        for n in 0..23 {
            let keys: Vec<usize> = (0..n).map(|i| [0, 1, 2, 3, 2][i % 5]).collect();
            let x: Vec<f64> = (0..n)
                .map(|i| {
                    ((i as f64 + 0.3) * 0.618_033_988_749_895).sin() * 10f64.powi(i as i32 % 7)
                })
                .collect();
            let xt: Vec<f64> = x.iter().map(|v| v * (1.0 + 3e-11) - 1e-13).collect();
            let mut groups = Groups::by_key(keys.iter().copied());
            let mut scratch = vec![0.0; groups.max.len()];
            let a = m.evaluate_grouped(&x, &xt, &groups.of.clone(), &mut scratch);
            let b = m.evaluate_in(&x, &xt, &mut groups);
            assert_eq!(a.to_bits(), b.to_bits(), "n = {n}");
            assert!(
                scratch
                    .iter()
                    .zip(&groups.max)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "n = {n}"
            );
        }
    }

    /// The measure's four-at-a-time quotients sum in the order of a plain loop, and the group
    /// maxima by comparison equal `f64::max`'s, NaN (passed over) and zeros included: bit for
    /// bit, every length through the tails.
    #[test]
    fn measure_and_maxima_equal_the_plain_loops_bit_for_bit() {
        let m = WeightedRms::new(1e-10, 1e-12);
        for n in 1..23 {
            let x: Vec<f64> = (0..n)
                .map(|i| ((i as f64 + 0.7) * 1.3).sin() * 1e3)
                .collect();
            let xt: Vec<f64> = x.iter().map(|v| v * (1.0 + 7e-11) + 3e-12).collect();
            let d = |i: usize, t: f64| 1e-10 * (t.abs() + i as f64) + 1e-12;
            let plain = (0..n)
                .map(|i| {
                    let e = (xt[i] - x[i]) / d(i, xt[i]);
                    e * e
                })
                .fold(0.0, |s, v| s + v);
            let plain = (plain / n as f64).sqrt();
            assert_eq!(m.rms_by(&x, &xt, d).to_bits(), plain.to_bits(), "n = {n}");
            let mut v = x.clone();
            v[n / 2] = f64::NAN;
            v[0] = -0.0;
            let members = Members {
                lists: vec![(0..n).collect::<Vec<_>>(), (0..n).step_by(3).collect()],
                lanes: None,
            };
            let mut out = [0.0, 2.5];
            max_abs_into(&members, &v, &mut out);
            for (list, (o, start)) in members.lists.iter().zip(out.iter().zip([0.0, 2.5])) {
                let expected = list.iter().fold(start, |a: f64, &i| a.max(v[i].abs()));
                assert_eq!(o.to_bits(), expected.to_bits(), "n = {n}");
            }
        }
    }

    #[test]
    fn groups_of_one_value_give_the_plain_measure() {
        let m = WeightedRms::new(1e-6, 1e-9);
        let x = [1.0, -2.0e5, 3.0e-3, 0.0];
        let xt = [1.0 + 1e-6, -2.0e5 + 0.3, 3.0e-3 - 1e-9, 1e-10];
        let mut scratch = [0.0; 4];
        let plain = m.evaluate(&x, &xt);
        let grouped = m.evaluate_grouped(&x, &xt, &[0, 1, 2, 3], &mut scratch);
        assert!(
            (plain - grouped).abs() <= 1e-15 * plain,
            "{plain} vs {grouped}"
        );
    }

    /// A value crossing zero is judged against its group's largest value: with rtol = 1e-10
    /// and a tiny atol a change of 1e-7 N in a 1e-3 N lateral force fails on its own, but is
    /// converged beside a 1.6e5 N vertical force (threshold 1.6e-5 N).
    #[test]
    fn a_value_near_zero_is_measured_against_its_group() {
        let m = WeightedRms::new(1e-10, 1e-14);
        let x = [1.0e-3, 1.6e5];
        let xt = [1.0e-3 + 1e-7, 1.6e5];
        let mut scratch = [0.0; 2];
        assert!(m.evaluate_grouped(&x, &xt, &[0, 1], &mut scratch[..2]) > 1.0);
        let grouped = m.evaluate_grouped(&x, &xt, &[0, 0], &mut scratch[..1]);
        let expected = (0.5f64).sqrt() * 1e-7 / (1e-10 * 1.6e5 + 1e-14);
        assert!(
            (grouped / expected - 1.0).abs() < 1e-12,
            "{grouped} vs {expected}"
        );
        assert!(grouped <= 1.0);
    }
}
