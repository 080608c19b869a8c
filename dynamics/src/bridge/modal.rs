//! The modal bridge: frequencies, damping ratios and mass-normalised deck mode shapes, and
//! the map from modal coordinates to the motion of the rail under a wheelset.
//!
//! Deck motion at the shear centre (eq. 9): `Y_b = Σ φ_hⁿ qₙ`, `Z_b = Σ φ_vⁿ qₙ`,
//! `θ_b = Σ φ_θⁿ qₙ`. The track lies at lateral offset `e` (+y) and height `h4` above the
//! shear centre, so a rigid cross-section rotation moves it by `(h4 θ, e θ)` and the rail
//! DOFs of a wheelset at `x` are (eq. 13, deck part)
//!
//! ```text
//! u(x) = Ψ(x) q,   Ψ(x) row-wise = [ φ_h + h4 φ_θ ;  φ_θ ;  φ_v + e φ_θ ]   (3 × N_b)
//! ```
//!
//! By virtual work the generalised force of a wheelset force `f = (F_y, M_x, F_z)` is
//! `Ψ(x)ᵀ f` (eq. 12), which contains the torque `M_x + h4 F_y + e F_z` about the shear centre.
//! Each mode obeys `q̈ₙ + 2ζₙωₙ q̇ₙ + ωₙ² qₙ = Fₙ + Sₙ` (eq. 10), `Sₙ` the generalised force
//! of steady loads on the deck (the mean wind, [`ModalBridge::uniform_load`]); the bridge
//! starts at its static response `qₙ = Sₙ / ωₙ²` to them.
//!
//! Shapes are either analytic sine series (simply supported spans, exact at every x) or
//! nodal values interpolated with Lagrange polynomials through the `order` nearest nodes
//! (the paper's choice). Off the deck (`x` outside `[x_start, x_end]`) `Ψ = 0`: rigid ground.

use serde::{Deserialize, Serialize};

/// Sine shapes' half-wave number and deck amplitudes of each mode, and the largest half-wave
/// number ([`ModalBridge::sine_modes`]).
pub type SineModes<'a> = (&'a [u32], &'a [[f64; 3]], usize);

/// How many positions [`ModalBridge::rail_shapes_lanes`] takes at once.
pub const SHAPE_LANES: usize = 4;

/// Scratch of [`ModalBridge::rail_shapes_lanes`]: the sines of the lanes' positions, and one
/// lane's nodal shapes. It only grows.
#[derive(Debug, Clone, Default)]
pub struct LaneScratch {
    sines: Vec<[f64; SHAPE_LANES]>,
    shapes: Vec<[f64; 3]>,
}

/// How the mode shapes are represented.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shapes {
    /// `φ(x) = a · sin(k π (x − x_start) / span)` per component, exact.
    Sine {
        span_m: f64,
        /// Half-wave number k of each mode.
        half_waves: Vec<u32>,
        /// Amplitudes (lateral, vertical, torsion) of each mode.
        amplitudes: Vec<[f64; 3]>,
    },
    /// Values at nodes, interpolated by Lagrange polynomials through `order` nodes.
    Nodal {
        x_m: Vec<f64>,
        /// Node-major: `values[node * n_modes + mode] = (lateral, vertical, torsion)`.
        values: Vec<[f64; 3]>,
        order: usize,
    },
}

/// A bridge reduced to its lowest modes (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalBridge {
    /// Position of the deck start along the track, m.
    pub x_start_m: f64,
    /// Position of the deck end along the track, m.
    pub x_end_m: f64,
    /// Natural frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Modal damping ratios, –.
    pub damping: Vec<f64>,
    /// Mode labels (e.g. `V-S-1`).
    pub labels: Vec<String>,
    /// Track lateral offset from the shear centre `e`, m (+y).
    pub e_m: f64,
    /// Height of the wheelset reference point above the shear centre `h4`, m.
    pub h4_m: f64,
    pub shapes: Shapes,
    /// Generalised force `Sₙ` of steady deck loads per mode (empty: none), N·m/√kg with the
    /// mass-normalised shapes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steady_modal_force: Vec<f64>,
    /// Buffeting of the deck by a turbulent wind (None: none), generated when a solver starts
    /// ([`super::buffeting`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub buffeting: Option<super::buffeting::BuffetingSpec>,
}

impl ModalBridge {
    /// The first number of the model that is not finite (NaN or ±∞), named; `None` when
    /// every number is finite. Such a model cannot be integrated or written to JSON.
    pub fn first_non_finite(&self) -> Option<String> {
        let scalars = [
            ("x_start_m", self.x_start_m),
            ("x_end_m", self.x_end_m),
            ("e_m", self.e_m),
            ("h4_m", self.h4_m),
        ];
        if let Some((name, v)) = scalars.iter().find(|(_, v)| !v.is_finite()) {
            return Some(format!("{name} = {v}"));
        }
        for (n, (f, z)) in self.frequencies_hz.iter().zip(&self.damping).enumerate() {
            if !(f.is_finite() && z.is_finite()) {
                return Some(format!("mode {}: frequency {f} Hz, damping {z}", n + 1));
            }
        }
        let bad = |v: &[[f64; 3]]| v.iter().position(|c| !c.iter().all(|x| x.is_finite()));
        match &self.shapes {
            Shapes::Sine {
                span_m, amplitudes, ..
            } => {
                if !span_m.is_finite() {
                    return Some(format!("span {span_m} m"));
                }
                bad(amplitudes)
                    .map(|n| format!("mode {}: shape amplitude {:?}", n + 1, amplitudes[n]))
            }
            Shapes::Nodal { x_m, values, .. } => {
                if let Some(j) = x_m.iter().position(|x| !x.is_finite()) {
                    return Some(format!("node {}: x = {}", j + 1, x_m[j]));
                }
                bad(values).map(|i| format!("shape value {} = {:?}", i + 1, values[i]))
            }
        }
    }

    pub fn n_modes(&self) -> usize {
        self.frequencies_hz.len()
    }

    /// The steady generalised force `Sₙ` of mode `n` (0 without steady loads).
    pub fn steady(&self, n: usize) -> f64 {
        self.steady_modal_force.get(n).copied().unwrap_or(0.0)
    }

    /// The static modal response to the steady loads, `qₙ = Sₙ / ωₙ²`.
    pub fn steady_response(&self) -> Vec<f64> {
        self.omegas()
            .iter()
            .enumerate()
            .map(|(n, w)| self.steady(n) / (w * w))
            .collect()
    }

    /// Generalised forces `Fₙ = ∫ (φ_h q_y + φ_v q_z + φ_θ m_x) dx` of a load per unit length
    /// `q = (q_y, q_z, m_x)` (N/m lateral +y, N/m vertical + down, N·m/m torque about +x at
    /// the shear centre) uniform over the whole deck: composite Simpson's rule over 4000
    /// intervals of the interpolated shapes.
    pub fn uniform_load(&self, q: [f64; 3]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_modes()];
        self.integrate_shapes(|w, phi| {
            for (o, p) in out.iter_mut().zip(phi) {
                *o += w * (p[0] * q[0] + p[1] * q[1] + p[2] * q[2]);
            }
        });
        out
    }

    /// Integrals over the deck of functions of the shapes: `f(weight, shapes at x)` at the
    /// nodes of the composite Simpson rule over 4000 intervals.
    pub fn integrate_shapes(&self, mut f: impl FnMut(f64, &[[f64; 3]])) {
        let m = 4000;
        let h = self.length_m() / m as f64;
        let mut phi = vec![[0.0; 3]; self.n_modes()];
        for i in 0..=m {
            let x = (self.x_start_m + i as f64 * h).min(self.x_end_m);
            let w = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            } * h
                / 3.0;
            self.deck_shapes(x, &mut phi);
            f(w, &phi);
        }
    }

    /// Circular frequencies ωₙ, rad/s.
    pub fn omegas(&self) -> Vec<f64> {
        self.frequencies_hz
            .iter()
            .map(|f| 2.0 * std::f64::consts::PI * f)
            .collect()
    }

    /// Deck length, m.
    pub fn length_m(&self) -> f64 {
        self.x_end_m - self.x_start_m
    }

    pub fn on_deck(&self, x: f64) -> bool {
        x >= self.x_start_m && x <= self.x_end_m
    }

    /// Deck shapes at the shear centre at `x`: `out[n] = (φ_h, φ_v, φ_θ)`. Returns false
    /// (and zeros) off the deck.
    pub fn deck_shapes(&self, x: f64, out: &mut [[f64; 3]]) -> bool {
        let n = self.n_modes();
        debug_assert_eq!(out.len(), n);
        if !self.on_deck(x) {
            out.iter_mut().for_each(|o| *o = [0.0; 3]);
            return false;
        }
        match &self.shapes {
            Shapes::Sine {
                span_m,
                half_waves,
                amplitudes,
            } => {
                let theta = std::f64::consts::PI * (x - self.x_start_m) / span_m;
                let kmax = half_waves.iter().copied().max().unwrap_or(0) as usize;
                // (a short array for the common few half-waves: zeroing costs by its length)
                let (mut few, mut many, mut owned);
                let s: &mut [[f64; 1]] = if kmax < 32 {
                    few = [[0.0f64]; 32];
                    &mut few[..=kmax]
                } else if kmax < 256 {
                    many = [[0.0f64]; 256];
                    &mut many[..=kmax]
                } else {
                    owned = vec![[0.0]; kmax + 1];
                    &mut owned[..]
                };
                if kmax >= 1 {
                    let (sin, cos) = crate::trig::sin_cos(theta);
                    chebyshev_sines([sin], [2.0 * cos], s);
                }
                for (i, o) in out.iter_mut().enumerate() {
                    let [sk] = s[half_waves[i] as usize];
                    let a = amplitudes[i];
                    *o = [a[0] * sk, a[1] * sk, a[2] * sk];
                }
            }
            Shapes::Nodal { x_m, values, order } => {
                let (start, w) = lagrange_weights(x_m, *order, x);
                let k = (*order).min(x_m.len()).min(w.len());
                nodal_combination(values, start, &w[..k], out);
            }
        }
        true
    }

    /// Rail shapes Ψ at `x`: `out[n] = (φ_h + h4 φ_θ, φ_θ, φ_v + e φ_θ)` — the lateral, roll and
    /// vertical rail motion per unit modal coordinate. Returns false (zeros) off the deck.
    pub fn rail_shapes(&self, x: f64, out: &mut [[f64; 3]]) -> bool {
        let on = self.deck_shapes(x, out);
        if on {
            self.deck_to_rail(out);
        }
        on
    }

    /// [`Self::rail_shapes`] at up to [`SHAPE_LANES`] positions at once, the same values bit
    /// for bit, in two layouts: mode after mode into `block`, lane `j`'s mode `n` at
    /// `block[start + n · stride ..][..3]` with `(start, stride) = at[j]` (a vehicle's `U` of
    /// the monolithic step, its wheelsets side by side within a mode), and as three rows of
    /// the modes' values, component after component, into `rows[j]`
    /// (`rows[j][k N + n] = Ψ(xs[j])[n][k]`); `on[j]` whether `xs[j]` is on the deck (zeros
    /// off it). For sine shapes the Chebyshev recurrences of the positions run interleaved
    /// (one position's recurrence is a chain of dependent multiplies and subtractions, which
    /// leaves the processor waiting), and the rail map is applied as each value is made
    /// instead of in a second pass; with AVX2 and four lanes, the four lanes go through the
    /// modes in one vector and are stored as vectors (`rail_lanes_avx2`). `scratch` keeps
    /// the sines and a lane's nodal shapes (it only grows, so repeated calls do not
    /// allocate).
    pub fn rail_shapes_lanes(
        &self,
        xs: &[f64],
        block: &mut [f64],
        at: &[(usize, usize)],
        rows: &mut [&mut [f64]],
        on: &mut [bool],
        scratch: &mut LaneScratch,
    ) {
        let m = xs.len();
        let nb = self.n_modes();
        assert!(m <= SHAPE_LANES && at.len() >= m && on.len() >= m && rows.len() >= m);
        let Shapes::Sine {
            span_m,
            half_waves,
            amplitudes,
        } = &self.shapes
        else {
            scratch.shapes.resize(nb, [0.0; 3]);
            for j in 0..m {
                on[j] = self.rail_shapes(xs[j], &mut scratch.shapes);
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
            for j in 0..m {
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
                    [self.h4_m, self.e_m],
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
                let v = self.rail_of([a[0] * sk, a[1] * sk, a[2] * sk]);
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

    /// `(φ_h, φ_v, φ_θ)` → `(φ_h + h4 φ_θ, φ_θ, φ_v + e φ_θ)` (eq. 8): deck motion at the
    /// shear centre to rail motion.
    #[inline]
    pub fn rail_of(&self, [h, v, t]: [f64; 3]) -> [f64; 3] {
        [h + self.h4_m * t, t, v + self.e_m * t]
    }

    /// The transpose of [`Self::rail_of`]: a force on the rail `(F_y, M_x, F_z)` as the
    /// deck's generalised force per unit shape `(F_y, F_z, M_x + h4 F_y + e F_z)`, so that
    /// `Ψᵀ f = Σ φᵀ (rail_ofᵀ f)`.
    #[inline]
    pub fn deck_force_of(&self, [fy, mx, fz]: [f64; 3]) -> [f64; 3] {
        [fy, fz, mx + self.h4_m * fy + self.e_m * fz]
    }

    /// Per mode, which components of its deck shape `(φ_h, φ_v, φ_θ)` and of its rail shape
    /// ([`Self::rail_of`]) are not zero everywhere on the deck: `(deck, rail)`.
    pub fn nonzero_components(&self) -> (Vec<[bool; 3]>, Vec<[bool; 3]>) {
        let nb = self.n_modes();
        let (mut deck, mut rail) = (vec![[false; 3]; nb], vec![[false; 3]; nb]);
        let mut mark = |n: usize, v: [f64; 3]| {
            let r = self.rail_of(v);
            for c in 0..3 {
                deck[n][c] |= v[c] != 0.0;
                rail[n][c] |= r[c] != 0.0;
            }
        };
        match &self.shapes {
            Shapes::Sine { amplitudes, .. } => {
                for (n, &a) in amplitudes.iter().enumerate() {
                    mark(n, a);
                }
            }
            Shapes::Nodal { values, .. } => {
                for (i, &v) in values.iter().enumerate() {
                    mark(i % nb.max(1), v);
                }
            }
        }
        (deck, rail)
    }

    /// Nodal shapes: the node values, node-major (`values[node * n_modes + mode]`, deck
    /// components), and the number of nodes. None for sine shapes.
    pub fn nodal_values(&self) -> Option<(&[[f64; 3]], usize)> {
        match &self.shapes {
            Shapes::Nodal { x_m, values, .. } => Some((values, x_m.len())),
            Shapes::Sine { .. } => None,
        }
    }

    /// Sine shapes: each mode's half-wave number `k` and deck amplitudes `a`
    /// (`φ(x) = a sin(k π (x − x_start)/span)`), and the largest `k`. None for nodal shapes.
    pub fn sine_modes(&self) -> Option<SineModes<'_>> {
        match &self.shapes {
            Shapes::Sine {
                half_waves,
                amplitudes,
                ..
            } => Some((
                half_waves,
                amplitudes,
                half_waves.iter().copied().max().unwrap_or(0) as usize,
            )),
            Shapes::Nodal { .. } => None,
        }
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

    /// Nodal shapes on the deck at `x`: the Lagrange stencil [`Self::deck_shapes`] combines
    /// the node values with, `φ(x) = Σⱼ wⱼ φ(node start + j)` for `j < count`, as
    /// `(start, w, count)`. None off the deck or for sine shapes.
    pub fn nodal_stencil(&self, x: f64) -> Option<(usize, [f64; 8], usize)> {
        match &self.shapes {
            Shapes::Nodal { x_m, order, .. } if self.on_deck(x) => {
                let (start, w) = lagrange_weights(x_m, *order, x);
                Some((start, w, (*order).min(x_m.len()).min(w.len())))
            }
            _ => None,
        }
    }

    /// [`Self::rail_of`] in place.
    fn deck_to_rail(&self, out: &mut [[f64; 3]]) {
        for o in out.iter_mut() {
            *o = self.rail_of(*o);
        }
    }

    /// Slopes of the deck shapes, `out[n] = d/dx (φ_h, φ_v, φ_θ)` at `x` (1/m per unit modal
    /// coordinate): for sine shapes `a k π/L cos(k π (x − x₀)/L)`; for nodal shapes the
    /// derivative of the Lagrange interpolant [`Self::deck_shapes`] uses (of the stencil to
    /// the right at a node, where the interpolant's slope may jump). Returns false (zeros)
    /// off the deck.
    pub fn deck_shape_slopes(&self, x: f64, out: &mut [[f64; 3]]) -> bool {
        let n = self.n_modes();
        debug_assert_eq!(out.len(), n);
        out.iter_mut().for_each(|o| *o = [0.0; 3]);
        if !self.on_deck(x) {
            return false;
        }
        match &self.shapes {
            Shapes::Sine {
                span_m,
                half_waves,
                amplitudes,
            } => {
                let theta = std::f64::consts::PI * (x - self.x_start_m) / span_m;
                let kmax = half_waves.iter().copied().max().unwrap_or(0) as usize;
                // cos(kθ) by the Chebyshev recurrence cos((k+1)θ) = 2 cos θ cos(kθ) − cos((k−1)θ)
                let mut c = vec![1.0; kmax + 1];
                if kmax >= 1 {
                    c[1] = theta.cos();
                    for k in 2..=kmax {
                        c[k] = 2.0 * c[1] * c[k - 1] - c[k - 2];
                    }
                }
                for (i, o) in out.iter_mut().enumerate() {
                    let k = half_waves[i] as usize;
                    let d = k as f64 * std::f64::consts::PI / span_m * c[k];
                    let a = amplitudes[i];
                    *o = [a[0] * d, a[1] * d, a[2] * d];
                }
            }
            Shapes::Nodal { x_m, values, order } => {
                let (start, w) = lagrange_weight_slopes(x_m, *order, x);
                let k = (*order).min(x_m.len()).min(w.len());
                nodal_combination(values, start, &w[..k], out);
            }
        }
        true
    }

    /// Slopes of the rail shapes, `dΨ/dx` at `x` ([`Self::deck_shape_slopes`] through eq. 8).
    /// Returns false (zeros) off the deck.
    pub fn rail_shape_slopes(&self, x: f64, out: &mut [[f64; 3]]) -> bool {
        let on = self.deck_shape_slopes(x, out);
        if on {
            self.deck_to_rail(out);
        }
        on
    }
}

/// `s[k] = sin(kθ)` of every lane for `k = 0 … s.len() − 1` (`s.len() ≥ 2`), by the
/// Chebyshev recurrence `sin((k+1)θ) = 2 cos θ sin(kθ) − sin((k−1)θ)` from `sin θ` and
/// `2 cos θ` of each lane. Each lane is a chain of dependent multiplies and subtractions, so
/// several lanes run side by side; the last two values stay in registers (the chain is one
/// multiply and one subtraction per k, not a store and reload of `s[k − 1]` as well).
#[inline]
fn chebyshev_sines<const L: usize>(sin1: [f64; L], c2: [f64; L], s: &mut [[f64; L]]) {
    s[0] = [0.0; L];
    s[1] = sin1;
    let (mut prev, mut cur) = (s[0], s[1]);
    for sk in &mut s[2..] {
        let mut next = [0.0; L];
        for j in 0..L {
            next[j] = c2[j] * cur[j] - prev[j];
        }
        *sk = next;
        (prev, cur) = (cur, next);
    }
}

/// The loop of [`ModalBridge::rail_shapes_lanes`] over the modes with the four lanes in one
/// vector: mode `n`'s rail shape `rail_of(a_n · sin(k_n θⱼ))` of lane `j`, the same
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
    [h4, e]: [f64; 2],
    lanes: [(*mut f64, usize); SHAPE_LANES],
    rows: [*mut f64; SHAPE_LANES],
    nb: usize,
) {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_loadu_pd, _mm256_mul_pd,
        _mm256_permute2f128_pd, _mm256_permute4x64_pd, _mm256_permute_pd, _mm256_set1_pd,
        _mm256_storeu_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd,
    };
    let (vh4, ve) = (_mm256_set1_pd(h4), _mm256_set1_pd(e));
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

/// The first node and the number of nodes of the Lagrange stencil around `x`.
fn lagrange_stencil(xs: &[f64], order: usize, x: f64) -> (usize, usize) {
    let n = xs.len();
    let p = order.clamp(2, 8).min(n);
    // interval i with xs[i] <= x < xs[i+1]
    let i = match xs.binary_search_by(|v| v.partial_cmp(&x).expect("finite node positions")) {
        Ok(i) => i.min(n - 2),
        Err(i) => i.saturating_sub(1).min(n - 2),
    };
    ((i + 1).saturating_sub(p / 2).min(n - p), p)
}

/// `out = Σⱼ wⱼ Φ(x_{start+j})`: the deck shapes (or their slopes) combined over the nodes of
/// a Lagrange stencil with weights `w`, the `n` shapes of a node contiguous (node-major).
fn nodal_combination(values: &[[f64; 3]], start: usize, w: &[f64], out: &mut [[f64; 3]]) {
    let n = out.len();
    let out = out.as_flattened_mut();
    out.fill(0.0);
    let rows = values[start * n..(start + w.len()) * n].as_flattened();
    crate::simd::axpy_columns(out, w, rows);
}

/// The derivatives `l_j′(x) = Σ_{k≠j} Π_{m≠j,k} (x − x_m) / Π_{m≠j} (x_j − x_m)` of the
/// weights of [`lagrange_weights`] (same stencil): the first node index and the slopes.
pub fn lagrange_weight_slopes(xs: &[f64], order: usize, x: f64) -> (usize, [f64; 8]) {
    let (start, p) = lagrange_stencil(xs, order, x);
    let mut w = [0.0; 8];
    for j in 0..p {
        let xj = xs[start + j];
        let mut den = 1.0;
        let mut sum = 0.0;
        for k in 0..p {
            if k == j {
                continue;
            }
            den *= xj - xs[start + k];
            let mut prod = 1.0;
            for m in 0..p {
                if m != j && m != k {
                    prod *= x - xs[start + m];
                }
            }
            sum += prod;
        }
        w[j] = sum / den;
    }
    (start, w)
}

/// Lagrange interpolation weights through `order` consecutive nodes around `x`.
/// Returns the first node index and the weights (up to 8 nodes).
pub fn lagrange_weights(xs: &[f64], order: usize, x: f64) -> (usize, [f64; 8]) {
    let (start, p) = lagrange_stencil(xs, order, x);
    // l_j = Π_{m≠j} (x − x_m) / Π_{m≠j} (x_j − x_m): one division per weight
    let mut w = [0.0; 8];
    for j in 0..p {
        let xj = xs[start + j];
        let (mut num, mut den) = (1.0, 1.0);
        for m in 0..p {
            if m != j {
                let xm = xs[start + m];
                num *= x - xm;
                den *= xj - xm;
            }
        }
        w[j] = num / den;
    }
    (start, w)
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

    /// Through `order` nodes the weights reproduce every polynomial of degree < order (here
    /// on uneven nodes, inside, at a node and at both ends).
    #[test]
    fn lagrange_weights_reproduce_polynomials_of_their_degree() {
        let xs = [0.0, 1.5, 2.0, 4.0, 7.0, 7.5, 11.0];
        for order in 2..=6 {
            for x in [0.0, 0.3, 2.0, 3.1, 6.9, 11.0] {
                let (start, w) = lagrange_weights(&xs, order, x);
                for degree in 0..order as i32 {
                    let value: f64 = (0..order).map(|j| w[j] * xs[start + j].powi(degree)).sum();
                    let exact = x.powi(degree);
                    assert!(
                        (value - exact).abs() <= 1e-12 * (1.0 + exact.abs()),
                        "order {order}, x {x}, degree {degree}: {value} vs {exact}"
                    );
                }
            }
        }
    }

    /// The weight slopes differentiate every polynomial of degree < order exactly: through
    /// `order` nodes, Σ l_j′(x) x_jᵈ = d xᵈ⁻¹ (same points as above).
    #[test]
    fn lagrange_weight_slopes_differentiate_polynomials_of_their_degree() {
        let xs = [0.0, 1.5, 2.0, 4.0, 7.0, 7.5, 11.0];
        for order in 2..=6 {
            for x in [0.0, 0.3, 2.0, 3.1, 6.9, 11.0] {
                let (start, w) = lagrange_weight_slopes(&xs, order, x);
                assert_eq!(start, lagrange_weights(&xs, order, x).0, "the same stencil");
                for degree in 0..order as i32 {
                    let value: f64 = (0..order).map(|j| w[j] * xs[start + j].powi(degree)).sum();
                    let exact = if degree == 0 {
                        0.0
                    } else {
                        degree as f64 * x.powi(degree - 1)
                    };
                    assert!(
                        (value - exact).abs() <= 1e-10 * (1.0 + exact.abs()),
                        "order {order}, x {x}, degree {degree}: {value} vs {exact}"
                    );
                }
            }
        }
    }

    /// Sine shape slopes equal the closed form a (kπ/L) cos(kπ(x − x₀)/L), through eq. 8.
    #[test]
    fn sine_shape_slopes_equal_the_closed_form() {
        let b = ModalBridge {
            x_start_m: 5.0,
            x_end_m: 35.0,
            frequencies_hz: vec![1.0, 2.0, 3.0],
            damping: vec![0.01; 3],
            labels: vec!["a".into(), "b".into(), "c".into()],
            e_m: 1.5,
            h4_m: 0.7,
            shapes: Shapes::Sine {
                span_m: 30.0,
                half_waves: vec![1, 5, 2],
                amplitudes: vec![[0.1, 0.2, 0.3], [0.0, 0.4, 0.0], [0.5, 0.0, -0.2]],
            },
            steady_modal_force: Vec::new(),
            buffeting: None,
        };
        let mut out = vec![[0.0; 3]; 3];
        for x in [5.0, 11.3, 20.0, 34.9] {
            assert!(b.rail_shape_slopes(x, &mut out));
            for (i, (k, a)) in [
                (1.0, [0.1, 0.2, 0.3]),
                (5.0, [0.0, 0.4, 0.0]),
                (2.0, [0.5, 0.0, -0.2]),
            ]
            .iter()
            .enumerate()
            {
                let d = k * std::f64::consts::PI / 30.0
                    * (k * std::f64::consts::PI * (x - 5.0) / 30.0).cos();
                let deck = [a[0] * d, a[1] * d, a[2] * d];
                let rail = [deck[0] + 0.7 * deck[2], deck[2], deck[1] + 1.5 * deck[2]];
                for c in 0..3 {
                    assert!(
                        (out[i][c] - rail[c]).abs() <= 1e-14,
                        "x {x} mode {i}: {:?} vs {rail:?}",
                        out[i]
                    );
                }
            }
        }
        assert!(!b.rail_shape_slopes(40.0, &mut out));
        assert_eq!(out, vec![[0.0; 3]; 3]);
    }

    /// [`ModalBridge::rail_shapes_lanes`] gives [`ModalBridge::rail_shapes`] bit for bit, into
    /// its lanes of a mode-major block (and nowhere else in it) and into its rows by
    /// component: sine shapes of many half-waves (and none),
    /// nodal shapes, one to four lanes, positions on and off the deck, one scratch shared by
    /// bridges of different sizes.
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
                    b.rail_shapes_lanes(x, &mut block, &at, &mut rows_of, &mut on, &mut scratch);
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
                        let want_on = b.rail_shapes(x[j], &mut want);
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

    #[test]
    fn the_first_non_finite_number_is_named() {
        let mut b = ModalBridge {
            x_start_m: 0.0,
            x_end_m: 10.0,
            frequencies_hz: vec![1.0, 2.0],
            damping: vec![0.01, 0.01],
            labels: vec!["V-S-1".into(), "V-A-1".into()],
            e_m: 0.0,
            h4_m: 0.0,
            shapes: Shapes::Sine {
                span_m: 10.0,
                half_waves: vec![1, 2],
                amplitudes: vec![[0.0, 0.1, 0.0], [0.0, 0.1, 0.0]],
            },
            steady_modal_force: Vec::new(),
            buffeting: None,
        };
        assert_eq!(b.first_non_finite(), None);
        b.frequencies_hz[1] = f64::INFINITY;
        assert_eq!(
            b.first_non_finite().unwrap(),
            "mode 2: frequency inf Hz, damping 0.01"
        );
        b.frequencies_hz[1] = 2.0;
        if let Shapes::Sine { amplitudes, .. } = &mut b.shapes {
            amplitudes[0][1] = f64::NAN;
        }
        assert!(b
            .first_non_finite()
            .unwrap()
            .starts_with("mode 1: shape amplitude"));
    }
}
