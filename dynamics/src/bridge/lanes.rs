//! The rail shapes `Ψ` (and the sines of sine shapes) at up to [`SHAPE_LANES`] positions at
//! once, the same values bit for bit as one position at a time ([`ModalBridge::rail_shapes`]):
//! the positions' Chebyshev recurrences interleaved, the rail map applied as each value is
//! made, and with AVX2 the four lanes in one vector; written in the two layouts the
//! monolithic step reads.

use super::modal::{chebyshev_sines, ModalBridge, Shapes};

/// How many positions [`ModalBridge::rail_shapes_lanes`] takes at once.
pub const SHAPE_LANES: usize = 4;

/// Scratch of [`ModalBridge::rail_shapes_lanes`]: the sines of the lanes' positions, and one
/// lane's nodal shapes. It only grows.
#[derive(Debug, Clone, Default)]
pub struct LaneScratch {
    sines: Vec<[f64; SHAPE_LANES]>,
    shapes: Vec<[f64; 3]>,
}

impl ModalBridge {
    /// [`Self::rail_shapes`] at up to [`SHAPE_LANES`] positions at once, the same values bit
    /// for bit, in two layouts: mode after mode into `block`, lane `j`'s mode `n` at
    /// `block[start + n · stride ..][..3]` with `(start, stride) = at[j]` (a vehicle's `U` of
    /// the monolithic step, its wheelsets side by side within a mode), and as three rows of
    /// the modes' values, component after component, into `rows[j]`
    /// (`rows[j][k N + n] = Ψ(xs[j])[n][k]`); `on[j]` whether `xs[j]` is on the deck (zeros
    /// off it); lane `j` lies on track `tracks[j]` ([`Self::rail_shapes_on`]). For sine shapes the Chebyshev recurrences of the positions run interleaved
    /// (one position's recurrence is a chain of dependent multiplies and subtractions, which
    /// leaves the processor waiting), and the rail map is applied as each value is made
    /// instead of in a second pass; with AVX2 and four lanes, the four lanes go through the
    /// modes in one vector and are stored as vectors (`rail_lanes_avx2`). `scratch` keeps
    /// the sines and a lane's nodal shapes (it only grows, so repeated calls do not
    /// allocate).
    #[allow(clippy::too_many_arguments)]
    pub fn rail_shapes_lanes(
        &self,
        xs: &[f64],
        tracks: &[usize],
        block: &mut [f64],
        at: &[(usize, usize)],
        rows: &mut [&mut [f64]],
        on: &mut [bool],
        scratch: &mut LaneScratch,
    ) {
        let m = xs.len();
        let nb = self.n_modes();
        assert!(m <= SHAPE_LANES && at.len() >= m && on.len() >= m && rows.len() >= m);
        assert!(tracks.len() >= m);
        let Shapes::Sine {
            span_m,
            half_waves,
            amplitudes,
        } = &self.shapes
        else {
            scratch.shapes.resize(nb, [0.0; 3]);
            for j in 0..m {
                on[j] = self.rail_shapes_on(tracks[j], xs[j], &mut scratch.shapes);
                for (c, p) in lane(block, at[j], nb).zip(&scratch.shapes) {
                    *c = *p;
                }
                components_into(&scratch.shapes, rows[j]);
            }
            return;
        };
        let s = self.lane_sines(*span_m, half_waves, xs, on, &mut scratch.sines);
        #[cfg(target_arch = "x86_64")]
        if m == SHAPE_LANES && std::arch::is_x86_feature_detected!("avx2") {
            let mut lanes = [(std::ptr::null_mut(), 0); SHAPE_LANES];
            let mut row_ptrs = [std::ptr::null_mut(); SHAPE_LANES];
            let (mut h4, mut e) = ([0.0; SHAPE_LANES], [0.0; SHAPE_LANES]);
            for j in 0..m {
                [h4[j], e[j]] = self.track_place(tracks[j]);
                check_lane(block.len(), at[j], nb);
                lanes[j] = (block[at[j].0..].as_mut_ptr(), at[j].1);
                row_ptrs[j] = rows[j][..3 * nb].as_mut_ptr();
            }
            // SAFETY: the processor has AVX2 (checked above); each lane's nb runs of three
            // from its start, stride ≥ 3 apart, lie inside `block` and each row's 3 nb values
            // inside `rows[j]` (checked above); `s` holds every half-wave number's sines
            unsafe {
                rail_lanes_avx2(
                    s,
                    &half_waves[..nb],
                    &amplitudes[..nb],
                    [h4, e],
                    lanes,
                    row_ptrs,
                    nb,
                )
            };
            for j in (0..m).filter(|&j| !on[j]) {
                lane(block, at[j], nb).for_each(|c| *c = [0.0; 3]);
                rows[j][..3 * nb].fill(0.0);
            }
            return;
        }
        for j in 0..m {
            let r = &mut rows[j][..3 * nb];
            if !on[j] {
                lane(block, at[j], nb).for_each(|c| *c = [0.0; 3]);
                r.fill(0.0);
                continue;
            }
            let (r0, r12) = r.split_at_mut(nb);
            let (r1, r2) = r12.split_at_mut(nb);
            let rows = r0.iter_mut().zip(r1.iter_mut()).zip(r2.iter_mut());
            let modes = lane(block, at[j], nb)
                .zip(half_waves)
                .zip(amplitudes)
                .zip(rows);
            for (((c, &k), a), ((r0, r1), r2)) in modes {
                let sk = s[k as usize][j];
                let v = self.rail_of_on(tracks[j], [a[0] * sk, a[1] * sk, a[2] * sk]);
                *c = v;
                (*r0, *r1, *r2) = (v[0], v[1], v[2]);
            }
        }
    }

    /// `sin(k θⱼ)` for `k = 0 ..= kmax` (the largest of `half_waves`) of up to
    /// [`SHAPE_LANES`] positions `xs`, `θⱼ = π (xⱼ − x_start)/span`, by lanes in `scratch`
    /// (`s[k][j]`; zero off the deck), the positions' Chebyshev recurrences interleaved;
    /// `on[j]` whether `xs[j]` is on the deck.
    fn lane_sines<'s>(
        &self,
        span_m: f64,
        half_waves: &[u32],
        xs: &[f64],
        on: &mut [bool],
        scratch: &'s mut Vec<[f64; SHAPE_LANES]>,
    ) -> &'s [[f64; SHAPE_LANES]] {
        let kmax = half_waves.iter().copied().max().unwrap_or(0) as usize;
        scratch.resize(scratch.len().max(kmax + 1), [0.0; SHAPE_LANES]);
        let s = &mut scratch[..=kmax];
        s[0] = [0.0; SHAPE_LANES];
        // the angles of the lanes on the deck (0 for the others, whose sines stay zero)
        let mut theta = [0.0; SHAPE_LANES];
        for (j, &x) in xs.iter().enumerate() {
            on[j] = self.on_deck(x);
            if on[j] {
                theta[j] = std::f64::consts::PI * (x - self.x_start_m) / span_m;
            }
        }
        if kmax >= 1 {
            let (sin, cos) = crate::trig::sin_cos4(theta);
            let (mut sin1, mut c2) = ([0.0; SHAPE_LANES], [0.0; SHAPE_LANES]);
            for j in 0..xs.len() {
                if on[j] {
                    sin1[j] = sin[j];
                    c2[j] = 2.0 * cos[j];
                }
            }
            chebyshev_sines(sin1, c2, s);
        }
        s
    }

    /// Sine shapes at up to [`SHAPE_LANES`] positions: `outs[j][k] = sin(k θⱼ)` for
    /// `k = 0 ..= kmax` ([`Self::sine_modes`]), `θⱼ = π (xs[j] − x_start)/span`, the values
    /// [`Self::rail_shapes_lanes`] combines (bit for bit); `on[j]` whether `xs[j]` is on the
    /// deck (zeros off it). `scratch` as there.
    pub fn sines_lanes(
        &self,
        xs: &[f64],
        outs: &mut [&mut [f64]],
        on: &mut [bool],
        scratch: &mut Vec<[f64; SHAPE_LANES]>,
    ) {
        let m = xs.len();
        assert!(m <= SHAPE_LANES && outs.len() >= m && on.len() >= m);
        let Shapes::Sine {
            span_m, half_waves, ..
        } = &self.shapes
        else {
            panic!("sines of nodal shapes");
        };
        let s = self.lane_sines(*span_m, half_waves, xs, on, scratch);
        for j in 0..m {
            let out = &mut outs[j][..s.len()];
            if on[j] {
                for (o, sk) in out.iter_mut().zip(s.iter()) {
                    *o = sk[j];
                }
            } else {
                out.fill(0.0);
            }
        }
    }
}

/// The loop of [`ModalBridge::rail_shapes_lanes`] over the modes with the four lanes in one
/// vector: mode `n`'s rail shape `rail_of_on(track_j, a_n · sin(k_n θⱼ))` of lane `j` (its
/// track's `h4` and `e` in `[h4, e]`, lane by lane), the same
/// operations in the same order as the loop over one lane (bit for bit the same values),
/// written to `lanes[j].0 + n · lanes[j].1` (three values) and to `rows[j] + c · nb + n`.
/// Four modes at a time, each component's values are transposed to four modes of a lane and
/// stored as one vector into its row; where the lanes lie side by side in the block (lane
/// `j` from `3 j` after the first, one stride), a mode's twelve values are three vectors.
/// Storing values one by one would make the loop wait on the stores.
///
/// # Safety
/// AVX2; every `s[half_waves[n]]` exists; for each lane the runs `n · stride .. + 3` from
/// its pointer and the `3 nb` values from its row pointer are valid for writes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn rail_lanes_avx2(
    s: &[[f64; SHAPE_LANES]],
    half_waves: &[u32],
    amplitudes: &[[f64; 3]],
    [h4, e]: [[f64; SHAPE_LANES]; 2],
    lanes: [(*mut f64, usize); SHAPE_LANES],
    rows: [*mut f64; SHAPE_LANES],
    nb: usize,
) {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_loadu_pd, _mm256_mul_pd,
        _mm256_permute2f128_pd, _mm256_permute4x64_pd, _mm256_permute_pd, _mm256_set1_pd,
        _mm256_storeu_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd,
    };
    let (vh4, ve) = (_mm256_loadu_pd(h4.as_ptr()), _mm256_loadu_pd(e.as_ptr()));
    // mode n's rail shape, component after component, each over the lanes
    let shape = |n: usize| -> [__m256d; 3] {
        let a = &amplitudes[n];
        let sk = _mm256_loadu_pd(s[half_waves[n] as usize].as_ptr());
        let h = _mm256_mul_pd(_mm256_set1_pd(a[0]), sk);
        let v = _mm256_mul_pd(_mm256_set1_pd(a[1]), sk);
        let t = _mm256_mul_pd(_mm256_set1_pd(a[2]), sk);
        // rail_of: (h + h4 t, t, v + e t)
        [
            _mm256_add_pd(h, _mm256_mul_pd(vh4, t)),
            t,
            _mm256_add_pd(v, _mm256_mul_pd(ve, t)),
        ]
    };
    let (base0, stride0) = lanes[0];
    let side_by_side = (1..SHAPE_LANES)
        .all(|j| lanes[j].1 == stride0 && std::ptr::eq(lanes[j].0, base0.wrapping_add(3 * j)));
    // mode n into the block, lane by lane or as three vectors
    let to_block = |n: usize, r: &[__m256d; 3]| {
        if side_by_side {
            // (a0 b0 c0 a1) (b1 c1 a2 b2) (c2 a3 b3 c3) from a = r[0], b = r[1], c = r[2]
            let pa = _mm256_permute4x64_pd(r[0], 0b01_10_11_00); // a0 a3 a2 a1
            let pb = _mm256_permute_pd(r[1], 0b0101); // b1 b0 b3 b2
            let pc = _mm256_permute4x64_pd(r[2], 0b11_00_01_10); // c2 c1 c0 c3
            let v0 = _mm256_blend_pd(_mm256_blend_pd(pa, pb, 0b0010), pc, 0b0100);
            let v1 = _mm256_blend_pd(_mm256_blend_pd(pb, pc, 0b0010), pa, 0b0100);
            let v2 = _mm256_blend_pd(_mm256_blend_pd(pc, pa, 0b0010), pb, 0b0100);
            let b = base0.add(n * stride0);
            _mm256_storeu_pd(b, v0);
            _mm256_storeu_pd(b.add(4), v1);
            _mm256_storeu_pd(b.add(8), v2);
        } else {
            for (c, &rc) in r.iter().enumerate() {
                store_lanes(rc, |j| lanes[j].0.add(n * lanes[j].1 + c));
            }
        }
    };
    let whole = nb - nb % 4;
    for n0 in (0..whole).step_by(4) {
        let r = [shape(n0), shape(n0 + 1), shape(n0 + 2), shape(n0 + 3)];
        for (m, rm) in r.iter().enumerate() {
            to_block(n0 + m, rm);
        }
        for c in 0..3 {
            // rows: modes, columns: lanes → rows: lanes, columns: modes
            let t0 = _mm256_unpacklo_pd(r[0][c], r[1][c]);
            let t1 = _mm256_unpackhi_pd(r[0][c], r[1][c]);
            let t2 = _mm256_unpacklo_pd(r[2][c], r[3][c]);
            let t3 = _mm256_unpackhi_pd(r[2][c], r[3][c]);
            let by_lane = [
                _mm256_permute2f128_pd(t0, t2, 0x20),
                _mm256_permute2f128_pd(t1, t3, 0x20),
                _mm256_permute2f128_pd(t0, t2, 0x31),
                _mm256_permute2f128_pd(t1, t3, 0x31),
            ];
            for (&row, v) in rows.iter().zip(by_lane) {
                _mm256_storeu_pd(row.add(c * nb + n0), v);
            }
        }
    }
    for n in whole..nb {
        let r = shape(n);
        to_block(n, &r);
        for (c, &rc) in r.iter().enumerate() {
            store_lanes(rc, |j| rows[j].add(c * nb + n));
        }
    }
}

/// Lane `j` of `v` to `to(j)`, for the four lanes.
///
/// # Safety
/// AVX2; each `to(j)` valid for a write.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn store_lanes(v: std::arch::x86_64::__m256d, to: impl Fn(usize) -> *mut f64) {
    use std::arch::x86_64::{
        _mm256_castpd256_pd128, _mm256_extractf128_pd, _mm_storeh_pd, _mm_storel_pd,
    };
    let (low, high) = (_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    // SAFETY: the pointers the caller vouches for
    unsafe {
        _mm_storel_pd(to(0), low);
        _mm_storeh_pd(to(1), low);
        _mm_storel_pd(to(2), high);
        _mm_storeh_pd(to(3), high);
    }
}

/// Lane `(start, stride)` of a block of [`ModalBridge::rail_shapes_lanes`]: its `nb` modes,
/// three values each from `start`, `stride ≥ 3` apart, the bounds checked once (a checked
/// slice per mode cost a fifth of the shapes' loop). Panics unless `block` holds them.
fn lane(
    block: &mut [f64],
    (start, stride): (usize, usize),
    nb: usize,
) -> impl Iterator<Item = &mut [f64; 3]> {
    check_lane(block.len(), (start, stride), nb);
    let base = block[start..].as_mut_ptr();
    // SAFETY: the nb runs start + n · stride .. + 3 lie inside `block` (checked above) and
    // are disjoint (stride ≥ 3); the iterator borrows `block` mutably for as long as they
    // are used
    (0..nb).map(move |n| unsafe { &mut *base.add(n * stride).cast::<[f64; 3]>() })
}

/// Panics unless the `nb` runs of three values `start + n · stride ..` of a lane are disjoint
/// (`stride ≥ 3`) and inside a block of `len` values.
fn check_lane(len: usize, (start, stride): (usize, usize), nb: usize) {
    assert!(stride >= 3, "stride {stride} < 3");
    assert!(
        nb == 0 || len >= start + (nb - 1) * stride + 3,
        "a block of {len} values holds no {nb} modes from {start}, {stride} apart"
    );
}

/// Shapes `(a, b, c)` of each mode as three rows of the modes' values, one component after
/// the other: `rows[k · N + n] = shapes[n][k]` (`N` = `shapes.len()`).
fn components_into(shapes: &[[f64; 3]], rows: &mut [f64]) {
    let nb = shapes.len();
    for (k, row) in rows[..3 * nb].chunks_exact_mut(nb.max(1)).enumerate() {
        for (o, p) in row.iter_mut().zip(shapes) {
            *o = p[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`ModalBridge::rail_shapes_lanes`] gives [`ModalBridge::rail_shapes`] bit for bit, into
    /// its lanes of a mode-major block (and nowhere else in it) and into its rows by
    /// component: sine shapes of many half-waves (and none),
    /// nodal shapes, one to four lanes, positions on and off the deck, lanes on different
    /// tracks, one scratch shared by bridges of different sizes.
    #[test]
    fn rail_shapes_lanes_equal_rail_shapes_bit_for_bit() {
        let sine = |half_waves: Vec<u32>| {
            let n = half_waves.len();
            let amplitudes = (0..n)
                .map(|i| {
                    let v = |c: f64| ((i as f64 + c) * 0.618_033_988_7).sin() * 0.37;
                    [v(0.1), v(1.3), -v(2.9)]
                })
                .collect();
            ModalBridge {
                x_start_m: 12.5,
                x_end_m: 812.5,
                frequencies_hz: (1..=n).map(|i| i as f64).collect(),
                damping: vec![0.01; n],
                labels: vec![String::new(); n],
                e_m: 2.05,
                h4_m: 1.25,
                other_tracks: vec![[-2.05, 1.25], [0.3, -0.7]],
                shapes: Shapes::Sine {
                    span_m: 800.0,
                    half_waves,
                    amplitudes,
                },
                steady_modal_force: Vec::new(),
                buffeting: None,
            }
        };
        let mut nodal = sine(vec![1, 2, 3]);
        let x_m: Vec<f64> = (0..=40).map(|i| 12.5 + 20.0 * i as f64).collect();
        let values = (0..x_m.len() * 3)
            .map(|i| {
                [
                    (i as f64 * 0.3).sin(),
                    (i as f64 * 0.7).cos(),
                    0.01 * i as f64,
                ]
            })
            .collect();
        nodal.shapes = Shapes::Nodal {
            x_m,
            values,
            order: 4,
        };
        let bridges = [
            sine((0..120).map(|i| (i * 37 % 97 + 1) as u32).collect()),
            sine(vec![3, 1, 2]),
            sine(vec![5, 1, 2, 9, 4, 4, 7]),
            sine(vec![0, 0]),
            nodal,
        ];
        let xs = [
            12.5,
            100.123_456_789,
            0.0,
            812.5,
            444.4,
            1000.0,
            812.500_000_001,
            13.0,
        ];
        let mut scratch = LaneScratch::default();
        for b in &bridges {
            let n = b.n_modes();
            for (lanes, reversed) in (1..=SHAPE_LANES).flat_map(|l| [(l, false), (l, true)]) {
                for start in 0..xs.len() - lanes {
                    let x = &xs[start..start + lanes];
                    // the lanes side by side within a mode, as a vehicle's U (or in the
                    // reverse order), with one value between them that no lane writes
                    let stride = 3 * lanes + 1;
                    let mut block = vec![f64::NAN; n * stride];
                    let slot = |j: usize| if reversed { lanes - 1 - j } else { j };
                    let at: Vec<(usize, usize)> =
                        (0..lanes).map(|j| (3 * slot(j), stride)).collect();
                    let mut rows = vec![vec![f64::NAN; 3 * n]; lanes];
                    let mut rows_of: Vec<&mut [f64]> =
                        rows.iter_mut().map(|r| r.as_mut_slice()).collect();
                    let mut on = [true; SHAPE_LANES];
                    let tracks: Vec<usize> = (0..lanes).map(|j| (start + 2 * j) % 3).collect();
                    b.rail_shapes_lanes(
                        x,
                        &tracks,
                        &mut block,
                        &at,
                        &mut rows_of,
                        &mut on,
                        &mut scratch,
                    );
                    let bufs: Vec<Vec<[f64; 3]>> = (0..lanes)
                        .map(|j| {
                            let at = |i: usize, k: usize| block[i * stride + 3 * slot(j) + k];
                            (0..n).map(|i| [at(i, 0), at(i, 1), at(i, 2)]).collect()
                        })
                        .collect();
                    assert!((0..n).all(|i| block[i * stride + 3 * lanes].is_nan()));
                    // the rows are the shapes' components, bit for bit
                    for j in 0..lanes {
                        for (i, p) in bufs[j].iter().enumerate() {
                            for k in 0..3 {
                                assert_eq!(rows[j][k * n + i].to_bits(), p[k].to_bits());
                            }
                        }
                    }
                    for j in 0..lanes {
                        let mut want = vec![[0.0; 3]; n];
                        let want_on = b.rail_shapes_on(tracks[j], x[j], &mut want);
                        assert_eq!(on[j], want_on, "x = {}", x[j]);
                        let bits = |v: &[[f64; 3]]| -> Vec<u64> {
                            v.iter().flatten().map(|f| f.to_bits()).collect()
                        };
                        assert_eq!(bits(&bufs[j]), bits(&want), "x = {}", x[j]);
                    }
                }
            }
        }
    }
}
