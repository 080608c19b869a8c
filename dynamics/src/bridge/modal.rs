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
//!
//! Ψ at several positions at once, as the monolithic step reads it, is made in `lanes`
//! ([`ModalBridge::rail_shapes_lanes`], [`ModalBridge::sines_lanes`]).

use serde::{Deserialize, Serialize};

/// Sine shapes' half-wave number and deck amplitudes of each mode, and the largest half-wave
/// number ([`ModalBridge::sine_modes`]).
pub type SineModes<'a> = (&'a [u32], &'a [[f64; 3]], usize);

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
    /// Further tracks on the deck (a double-track deck), each `[e, h4]`, m: track `k ≥ 1` is
    /// `other_tracks[k − 1]`, track 0 is `(e_m, h4_m)`. Empty: one track.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub other_tracks: Vec<[f64; 2]>,
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
        if let Some(k) = (self.other_tracks.iter()).position(|t| !t.iter().all(|v| v.is_finite())) {
            return Some(format!("track {}: {:?}", k + 2, self.other_tracks[k]));
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
        self.rail_shapes_on(0, x, out)
    }

    /// [`Self::rail_shapes`] of track `k`.
    pub fn rail_shapes_on(&self, k: usize, x: f64, out: &mut [[f64; 3]]) -> bool {
        let on = self.deck_shapes(x, out);
        if on {
            self.deck_to_rail(k, out);
        }
        on
    }

    /// `(φ_h, φ_v, φ_θ)` → `(φ_h + h4 φ_θ, φ_θ, φ_v + e φ_θ)` (eq. 8): deck motion at the
    /// shear centre to rail motion, on the first track.
    #[inline]
    pub fn rail_of(&self, v: [f64; 3]) -> [f64; 3] {
        self.rail_of_on(0, v)
    }

    /// The transpose of [`Self::rail_of`]: a force on the rail `(F_y, M_x, F_z)` as the
    /// deck's generalised force per unit shape `(F_y, F_z, M_x + h4 F_y + e F_z)`, so that
    /// `Ψᵀ f = Σ φᵀ (rail_ofᵀ f)`; on the first track.
    #[inline]
    pub fn deck_force_of(&self, f: [f64; 3]) -> [f64; 3] {
        self.deck_force_of_on(0, f)
    }

    /// How many tracks the deck carries.
    pub fn n_tracks(&self) -> usize {
        1 + self.other_tracks.len()
    }

    /// Track `k`'s `[h4, e]`, m (k < [`Self::n_tracks`]).
    #[inline]
    pub fn track_place(&self, k: usize) -> [f64; 2] {
        match k {
            0 => [self.h4_m, self.e_m],
            _ => {
                let [e, h4] = self.other_tracks[k - 1];
                [h4, e]
            }
        }
    }

    /// [`Self::rail_of`] on track `k`.
    #[inline]
    pub fn rail_of_on(&self, k: usize, [h, v, t]: [f64; 3]) -> [f64; 3] {
        let [h4, e] = self.track_place(k);
        [h + h4 * t, t, v + e * t]
    }

    /// [`Self::deck_force_of`] on track `k`.
    #[inline]
    pub fn deck_force_of_on(&self, k: usize, [fy, mx, fz]: [f64; 3]) -> [f64; 3] {
        let [h4, e] = self.track_place(k);
        [fy, fz, mx + h4 * fy + e * fz]
    }

    /// Per mode, which components of its deck shape `(φ_h, φ_v, φ_θ)` and of its rail shape
    /// ([`Self::rail_of`]) are not zero everywhere on the deck: `(deck, rail)`.
    pub fn nonzero_components(&self) -> (Vec<[bool; 3]>, Vec<[bool; 3]>) {
        let nb = self.n_modes();
        let (mut deck, mut rail) = (vec![[false; 3]; nb], vec![[false; 3]; nb]);
        let mut mark = |n: usize, v: [f64; 3]| {
            for k in 0..self.n_tracks() {
                let r = self.rail_of_on(k, v);
                for c in 0..3 {
                    deck[n][c] |= v[c] != 0.0;
                    rail[n][c] |= r[c] != 0.0;
                }
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
    fn deck_to_rail(&self, k: usize, out: &mut [[f64; 3]]) {
        for o in out.iter_mut() {
            *o = self.rail_of_on(k, *o);
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
        self.rail_shape_slopes_on(0, x, out)
    }

    /// [`Self::rail_shape_slopes`] of track `k`.
    pub fn rail_shape_slopes_on(&self, k: usize, x: f64, out: &mut [[f64; 3]]) -> bool {
        let on = self.deck_shape_slopes(x, out);
        if on {
            self.deck_to_rail(k, out);
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
pub(super) fn chebyshev_sines<const L: usize>(sin1: [f64; L], c2: [f64; L], s: &mut [[f64; L]]) {
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
            other_tracks: Vec::new(),
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
            other_tracks: Vec::new(),
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
