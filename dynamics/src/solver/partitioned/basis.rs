//! The shapes' own basis at the wheelsets, through which the bridge side forms `Σ Ψᵀ f` and
//! `Ψ (q, q̇, q̈)` ([`super`]): the Lagrange stencils of nodal shapes or `sin(k θ)` of sine
//! shapes at each wheelset's recent positions, with the irregularity there ([`ShapeCache`]);
//! the sums per basis function ([`BasisScratch`]); and the sums over the half-wave numbers of
//! sine shapes, in AVX2 registers where the processor has them ([`sine_forces`],
//! [`sine_motions`]: the same products in the same order, bit for bit the same).

use super::interface::WheelInput;
use crate::bridge::{ModalBridge, SHAPE_LANES};
use crate::track::RailProfile;
use tbi_track::RailIrregularity;

/// `h[k] ← Σ_w sin(k θ_w) g_w` from zero, over the wheelsets `w` in turn (`(at, g)`: the
/// sines of its position for `k = 0 ..` from `sines[at]` on, and its force on the deck): the
/// forces gathered per half-wave number. With AVX2 and at most twelve half-wave numbers the sums stay in registers, the
/// half-wave numbers side by side, instead of being loaded and stored for every wheelset;
/// each `h[k][c]` takes the same products in the same order (bit for bit the same).
pub(super) fn sine_forces(h: &mut [[f64; 3]], sines: &[f64], wheelsets: &[(usize, [f64; 3])]) {
    #[cfg(target_arch = "x86_64")]
    if h.len() <= 12 && std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe {
            match h.len().div_ceil(4) {
                0 => {}
                1 => sine_forces_avx2::<1>(h, sines, wheelsets),
                2 => sine_forces_avx2::<2>(h, sines, wheelsets),
                _ => sine_forces_avx2::<3>(h, sines, wheelsets),
            }
        }
        return;
    }
    sine_forces_body(h, sines, wheelsets)
}

fn sine_forces_body(h: &mut [[f64; 3]], sines: &[f64], wheelsets: &[(usize, [f64; 3])]) {
    h.fill([0.0; 3]);
    let n = h.len();
    for &(at, g) in wheelsets {
        for (hk, &sk) in h.iter_mut().zip(&sines[at..at + n]) {
            for (hc, gc) in hk.iter_mut().zip(g) {
                *hc += sk * gc;
            }
        }
    }
}

/// [`sine_forces`] with `h.len() ≤ 4 V` half-wave numbers in `V` vectors per component.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sine_forces_avx2<const V: usize>(
    h: &mut [[f64; 3]],
    sines: &[f64],
    wheelsets: &[(usize, [f64; 3])],
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_setzero_pd, _mm256_storeu_pd,
    };
    let n = h.len();
    let last = n - 4 * (V - 1); // 1..=4 values in the last vector
                                // SAFETY: AVX2, as this function
    let mask = unsafe { crate::simd::first_lanes(last) };
    let mut acc = [[_mm256_setzero_pd(); V]; 3];
    for &(at, g) in wheelsets {
        let sines = &sines[at..at + n];
        let p = sines.as_ptr();
        let gv = [
            _mm256_set1_pd(g[0]),
            _mm256_set1_pd(g[1]),
            _mm256_set1_pd(g[2]),
        ];
        for v in 0..V {
            // SAFETY: values 4 v .. 4 v + 4 of `sines` (n of them), the last vector's lanes
            // past n masked off
            let sv = unsafe {
                if v + 1 < V || last == 4 {
                    _mm256_loadu_pd(p.add(4 * v))
                } else {
                    _mm256_maskload_pd(p.add(4 * v), mask)
                }
            };
            for (ac, gc) in acc.iter_mut().zip(gv) {
                ac[v] = _mm256_add_pd(ac[v], _mm256_mul_pd(sv, gc));
            }
        }
    }
    let mut out = [[0.0; 12]; 3];
    for (o, ac) in out.iter_mut().zip(acc) {
        for (v, a) in ac.into_iter().enumerate() {
            // SAFETY: 4 values from 4 v < 12 of a 12-value array
            unsafe { _mm256_storeu_pd(o.as_mut_ptr().add(4 * v), a) };
        }
    }
    for (k, hk) in h.iter_mut().enumerate() {
        *hk = [out[0][k], out[1][k], out[2][k]];
    }
}

/// `out[i] ← Σₖ sin(k θᵢ) b[k]` from zero, `k = 0, 1, …` in turn, for the wheelsets `i` on
/// the deck (`starts[i]`: where their sines start in `sines`): the deck motion under
/// each, `b[k]` the deck motion of half-wave number `k` (deck components × `(u, u̇, ü, 0)`).
/// With AVX2 a component's four values are one vector; each value takes the same products
/// in the same order as the scalar loop (bit for bit the same).
pub(super) fn sine_motions(
    out: &mut Vec<[[f64; 4]; 3]>,
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    out.clear();
    out.resize(starts.len(), [[0.0; 4]; 3]);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe { sine_motions_avx2(out, b, sines, starts) };
        return;
    }
    sine_motions_body(out, b, sines, starts)
}

fn sine_motions_body(
    out: &mut [[[f64; 4]; 3]],
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    for (acc, &at) in out.iter_mut().zip(starts) {
        for (sk, bk) in sines[at..at + b.len()].iter().zip(b) {
            for (ac, bc) in acc.iter_mut().zip(bk) {
                for (v, bv) in ac.iter_mut().zip(bc) {
                    *v += sk * bv;
                }
            }
        }
    }
}

/// [`sine_motions`] with a component's `(u, u̇, ü, 0)` in one vector.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sine_motions_avx2(
    out: &mut [[[f64; 4]; 3]],
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_setzero_pd,
        _mm256_storeu_pd,
    };
    for (o, &at) in out.iter_mut().zip(starts) {
        let mut acc = [_mm256_setzero_pd(); 3];
        for (&sk, bk) in sines[at..at + b.len()].iter().zip(b) {
            let s = _mm256_set1_pd(sk);
            for (ac, bc) in acc.iter_mut().zip(bk) {
                // SAFETY: four values of a four-value array
                let bv = unsafe { _mm256_loadu_pd(bc.as_ptr()) };
                *ac = _mm256_add_pd(*ac, _mm256_mul_pd(s, bv));
            }
        }
        for (oc, ac) in o.iter_mut().zip(acc) {
            // SAFETY: four values of a four-value array
            unsafe { _mm256_storeu_pd(oc.as_mut_ptr(), ac) };
        }
    }
}

/// A Lagrange stencil of nodal shapes: `φ(x) = Σⱼ w[j] φ(node start + j)`, `j < k`.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Stencil {
    pub(super) start: usize,
    pub(super) w: [f64; 8],
    pub(super) k: usize,
}

/// Scratch of [`super::BridgeSide`]'s sums over the wheelsets (its generalised forces and [`super::BridgeSide::rails`]): per basis function
/// (node, or half-wave number) the wheelsets' forces gathered there (deck components) and
/// the deck motion `(φ q, φ q̇, φ q̈)` there, and the nodes in use, ascending once sorted.
#[derive(Debug, Default)]
pub(super) struct BasisScratch {
    pub(super) force: Vec<[f64; 3]>,
    pub(super) motion: Vec<[[f64; 4]; 3]>,
    used: Vec<bool>,
    pub(super) nodes: Vec<usize>,
    /// Sine shapes: the wheelsets on the deck, as the start of their sines in the shape
    /// cache and their force on the deck ([`sine_forces`]).
    pub(super) on_deck: Vec<(usize, [f64; 3])>,
    /// Sine shapes: where the sines of each wheelset on the deck start in the shape cache,
    /// and the deck motion under it ([`sine_motions`]).
    pub(super) starts: Vec<usize>,
    pub(super) deck: Vec<[[f64; 4]; 3]>,
}

impl BasisScratch {
    /// No node in use, room for `n` nodes.
    pub(super) fn begin(&mut self, n: usize) {
        for &i in &self.nodes {
            self.used[i] = false;
        }
        self.nodes.clear();
        if self.used.len() < n {
            self.used.resize(n, false);
            self.force.resize(n, [0.0; 3]);
            self.motion.resize(n, [[0.0; 4]; 3]);
        }
    }

    /// Every basis function `0..n` zero (the half-wave numbers of sine shapes, all in use);
    /// the forces.
    pub(super) fn zeroed(&mut self, n: usize) -> &mut [[f64; 3]] {
        self.force.clear();
        self.force.resize(n, [0.0; 3]);
        self.motion.clear();
        self.motion.resize(n, [[0.0; 4]; 3]);
        self.used.clear();
        self.nodes.clear();
        &mut self.force
    }

    /// Node `i` in use (its force and motion zero when it is new).
    pub(super) fn touch(&mut self, i: usize) {
        if !self.used[i] {
            self.used[i] = true;
            self.nodes.push(i);
            self.force[i] = [0.0; 3];
            self.motion[i] = [[0.0; 4]; 3];
        }
    }

    /// The deck motion of every node in use from the node values and `modal` (`(q, q̇, q̈, 0)`
    /// of each mode), two nodes at a time; sorts the nodes.
    pub(super) fn node_motions(&mut self, values: &[[f64; 3]], nb: usize, modal: &[[f64; 4]]) {
        self.nodes.sort_unstable();
        let of = |i: usize| &values[i * nb..(i + 1) * nb];
        for pair in self.nodes.chunks(2) {
            if let [a, b] = *pair {
                let mut acc = [self.motion[a], self.motion[b]];
                crate::simd::rail_accumulate_pair(&mut acc, [of(a), of(b)], modal);
                [self.motion[a], self.motion[b]] = acc;
            } else {
                crate::simd::rail_accumulate(&mut self.motion[pair[0]], of(pair[0]), modal);
            }
        }
    }

    /// The deck motion `(u, u̇, ü)` (deck components) at a stencil from the node motions.
    pub(super) fn deck_motion(&self, st: &Stencil) -> [[f64; 3]; 3] {
        let mut d = [[0.0; 3]; 3];
        for j in 0..st.k {
            let m = &self.motion[st.start + j];
            for (dd, out) in d.iter_mut().enumerate() {
                for (c, o) in out.iter_mut().enumerate() {
                    *o += st.w[j] * m[c][dd];
                }
            }
        }
        d
    }
}

/// The shapes' basis and the track irregularity at the last two positions of each wheelset
/// slot (the positions at the start and at the end of the current step are what an iterating
/// master asks for): for nodal shapes the Lagrange stencil, for sine shapes `sin(k θ)`.
#[derive(Debug, Default)]
pub(super) struct ShapeCache {
    /// Per slot: two entries (x bits, on deck); entry `2 w + slot`.
    keys: Vec<[(u64, bool); 2]>,
    /// Per entry, for nodal shapes: the stencil ([`ModalBridge::nodal_stencil`]).
    stencils: Vec<Stencil>,
    /// Per entry, for sine shapes: `sin(k θ)`, `k = 0 ..= kmax` (`stride = kmax + 1` values).
    pub(super) sines: Vec<f64>,
    stride: usize,
    /// Per slot and entry: the irregularity at that position.
    irregularity: Vec<[RailIrregularity; 2]>,
    next: Vec<usize>,
    /// Deck shapes at the probe positions asked for (x bits, shapes).
    probes: Vec<(u64, Vec<[f64; 3]>)>,
    /// Scratch of [`ModalBridge::sines_lanes`].
    lanes: Vec<[f64; SHAPE_LANES]>,
}

impl ShapeCache {
    /// The deck shapes at probe position `x`.
    pub(super) fn probe(&mut self, bridge: &ModalBridge, nb: usize, x: f64) -> &[[f64; 3]] {
        let bits = x.to_bits();
        let i = match self.probes.iter().position(|p| p.0 == bits) {
            Some(i) => i,
            None => {
                let mut shapes = vec![[0.0; 3]; nb];
                bridge.deck_shapes(x, &mut shapes);
                self.probes.push((bits, shapes));
                self.probes.len() - 1
            }
        };
        &self.probes[i].1
    }

    /// Room for wheelset slots `0..n`.
    pub(super) fn reserve(&mut self, n: usize) {
        if self.keys.len() < n {
            self.keys.resize(n, [(f64::NAN.to_bits(), false); 2]);
            self.next.resize(n, 0);
            self.stencils.resize(2 * n, Stencil::default());
            self.irregularity
                .resize(n, [RailIrregularity::default(); 2]);
        }
    }

    /// Makes the entries of every wheelset slot `w` at `inputs[w].x` ([`Self::claim`]), the
    /// basis of the misses [`SHAPE_LANES`] at a time ([`Self::shapes_of`]).
    pub(super) fn fill(
        &mut self,
        bridge: &ModalBridge,
        track: &dyn RailProfile,
        inputs: &[WheelInput],
    ) {
        self.reserve(inputs.len());
        let mut pending = [(0usize, 0.0f64); SHAPE_LANES];
        let mut m = 0;
        for (w, wi) in inputs.iter().enumerate() {
            if let Some(p) = self.claim(track, w, wi.x) {
                pending[m] = p;
                m += 1;
                if m == SHAPE_LANES {
                    self.shapes_of(bridge, &pending);
                    m = 0;
                }
            }
        }
        if m > 0 {
            self.shapes_of(bridge, &pending[..m]);
        }
    }

    /// Unless slot `w` has an entry at `x`: takes its older entry for `x` with the
    /// irregularity there, and returns `(2 w + slot, x)`, whose shapes are still to be made
    /// ([`Self::shapes_of`]).
    #[inline]
    pub(super) fn claim(
        &mut self,
        track: &dyn RailProfile,
        w: usize,
        x: f64,
    ) -> Option<(usize, f64)> {
        let bits = x.to_bits();
        if self.keys[w].iter().any(|k| k.0 == bits) {
            return None;
        }
        let s = self.next[w];
        self.next[w] = 1 - s;
        self.keys[w][s] = (bits, false);
        self.irregularity[w][s] = track.at(x);
        Some((2 * w + s, x))
    }

    /// The basis of entries `(2 w + slot, x)` (ascending entries, at most [`SHAPE_LANES`])
    /// and their on-deck flags into `keys`.
    pub(super) fn shapes_of(&mut self, bridge: &ModalBridge, pending: &[(usize, f64)]) {
        if let Some((_, _, kmax)) = bridge.sine_modes() {
            let stride = kmax + 1;
            let need = 2 * self.keys.len() * stride;
            if self.stride != stride || self.sines.len() < need {
                self.stride = stride;
                self.sines.resize(need, 0.0);
            }
            let mut outs: [&mut [f64]; SHAPE_LANES] = Default::default();
            let mut xs = [0.0; SHAPE_LANES];
            let mut rest = &mut self.sines[..];
            let mut base = 0;
            for (j, &(entry, x)) in pending.iter().enumerate() {
                let tail = std::mem::take(&mut rest)
                    .split_at_mut((entry - base) * stride)
                    .1;
                let (this, tail) = tail.split_at_mut(stride);
                outs[j] = this;
                rest = tail;
                base = entry + 1;
                xs[j] = x;
            }
            let m = pending.len();
            let mut on = [false; SHAPE_LANES];
            bridge.sines_lanes(&xs[..m], &mut outs[..m], &mut on, &mut self.lanes);
            for (&(entry, _), on) in pending.iter().zip(on) {
                self.keys[entry / 2][entry % 2].1 = on;
            }
            return;
        }
        for &(entry, x) in pending {
            let st = bridge.nodal_stencil(x);
            self.keys[entry / 2][entry % 2].1 = st.is_some();
            self.stencils[entry] =
                st.map_or(Stencil::default(), |(start, w, k)| Stencil { start, w, k });
        }
    }

    /// The slot of wheelset `w`'s entry at `x` (made by [`Self::fill`] or [`Self::claim`]).
    #[inline]
    fn slot(&self, w: usize, x: f64) -> usize {
        let bits = x.to_bits();
        self.keys[w]
            .iter()
            .position(|k| k.0 == bits)
            .expect("the shape cache was filled for these positions")
    }

    /// For nodal shapes, the entry of wheelset slot `w` at `x`: its stencil (None off the
    /// deck) and the irregularity there.
    pub(super) fn stencil(&self, w: usize, x: f64) -> (Option<&Stencil>, &RailIrregularity) {
        let slot = self.slot(w, x);
        let on = self.keys[w][slot].1;
        (
            on.then(|| &self.stencils[2 * w + slot]),
            &self.irregularity[w][slot],
        )
    }

    /// For sine shapes, where the entry of wheelset slot `w` at `x` starts in `sines` (None
    /// off the deck), and its slot.
    #[inline]
    fn sines_entry(&self, w: usize, x: f64) -> (Option<usize>, usize) {
        let slot = self.slot(w, x);
        let at = self.keys[w][slot].1.then(|| (2 * w + slot) * self.stride);
        (at, slot)
    }

    /// For sine shapes, where the entry of wheelset slot `w` at `x` starts in `sines` (None
    /// off the deck).
    #[inline]
    pub(super) fn sines_at(&self, w: usize, x: f64) -> Option<usize> {
        self.sines_entry(w, x).0
    }

    /// For sine shapes, the entry of wheelset slot `w` at `x`: `sin(k θ)` (None off the
    /// deck) and the irregularity there.
    #[inline]
    pub(super) fn sines(&self, w: usize, x: f64) -> (Option<&[f64]>, &RailIrregularity) {
        let (at, slot) = self.sines_entry(w, x);
        (
            at.map(|at| &self.sines[at..at + self.stride]),
            &self.irregularity[w][slot],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The forces gathered per half-wave number in registers equal the loop over the
    /// wheelsets bit for bit, for 1 to 13 half-wave numbers (13: the loop itself).
    #[test]
    fn sine_forces_equal_the_loop_bit_for_bit() {
        let v = |i: usize, c: f64| ((i as f64 + c) * 0.618_033_988_749_895).sin() * 1e3;
        for n in 1..=13 {
            let sines: Vec<Vec<f64>> = (0..7)
                .map(|w| (0..n).map(|k| v(k + 17 * w, 0.3)).collect())
                .collect();
            let g: Vec<[f64; 3]> = (0..7).map(|w| [v(w, 1.1), -v(w, 2.2), v(w, 3.3)]).collect();
            // the sines one after the other, a gap after each (as entries in the cache)
            let storage: Vec<f64> = sines
                .iter()
                .flat_map(|s| s.iter().copied().chain([9.9]))
                .collect();
            let items: Vec<(usize, [f64; 3])> = (0..7).map(|w| (w * (n + 1), g[w])).collect();
            let (mut a, mut b) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
            sine_forces(&mut a, &storage, &items);
            sine_forces_body(&mut b, &storage, &items);
            let bits =
                |h: &[[f64; 3]]| -> Vec<u64> { h.iter().flatten().map(|x| x.to_bits()).collect() };
            assert_eq!(bits(&a), bits(&b), "{n} half-wave numbers");
        }
    }

    /// The deck motions summed over the half-wave numbers a component at a time equal the
    /// scalar loop bit for bit, for 1 to 13 half-wave numbers, and are the sums they stand
    /// for (to round-off, summed in another order).
    #[test]
    fn sine_motions_equal_the_loop_bit_for_bit() {
        let v = |i: usize, c: f64| ((i as f64 + c) * 0.618_033_988_749_895).sin() * 1e3;
        for n in 1..=13 {
            let storage: Vec<f64> = (0..7 * (n + 1)).map(|i| v(i, 0.3)).collect();
            let b: Vec<[[f64; 4]; 3]> = (0..n)
                .map(|k| {
                    let m = |c: usize| [v(k, c as f64), -v(k, 1.5 + c as f64), v(k, 7.0), 0.0];
                    [m(0), m(1), m(2)]
                })
                .collect();
            let starts: Vec<usize> = (0..7).map(|w| w * (n + 1)).collect();
            let mut a = Vec::new();
            sine_motions(&mut a, &b, &storage, &starts);
            let mut s = vec![[[0.0; 4]; 3]; 7];
            sine_motions_body(&mut s, &b, &storage, &starts);
            let bits = |h: &[[[f64; 4]; 3]]| -> Vec<u64> {
                h.iter().flatten().flatten().map(|x| x.to_bits()).collect()
            };
            assert_eq!(bits(&a), bits(&s), "{n} half-wave numbers");
            for (w, aw) in a.iter().enumerate() {
                for c in 0..3 {
                    for d in 0..4 {
                        let sum: f64 = (0..n)
                            .rev()
                            .map(|k| storage[w * (n + 1) + k] * b[k][c][d])
                            .sum();
                        assert!((aw[c][d] - sum).abs() <= 1e-12 * 1e6 * n as f64);
                    }
                }
            }
        }
    }
}
