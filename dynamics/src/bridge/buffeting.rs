//! Buffeting of the deck: the quasi-steady forces of the turbulent wind ([`tbi_wind`]) at
//! points along the deck, projected on the modes.
//!
//! Per unit length at the shear centre, with the mean wind U towards +y, the turbulence `u`
//! (along wind) and `w` (+ up), the deck width B and its steady coefficients and their slopes
//! with the angle of attack (per rad):
//!
//! ```text
//! drag (+y)                  D_b = ½ρU²B [2 C_D u/U + C_D′ w/U]
//! lift (upward)              L_b = ½ρU²B [2 C_L u/U + (C_L′ + C_D) w/U]
//! moment (leeward side down) M_b = ½ρU²B² [2 C_M u/U + C_M′ w/U]
//! ```
//!
//! in the quasi-steady limit, or with Davenport's aerodynamic admittance
//! `|χ(f)|² = (2/λ²)(λ − 1 + e^(−λ))`, `λ = c f B / U` (`admittance = c`, about 7 for a
//! bridge deck), which weighs down the turbulence that is short against the deck's width:
//! the forces then see the field with every harmonic's amplitude times `|χ(f)|` (generated
//! from the same phases; the car bodies still see the field itself). The deck points `x_j` are equally
//! spaced over the deck with trapezoidal weights `Δx_j`; the generalised force of mode n is
//! `Fₙ(t) = Σ_j Δx_j (φ_h D_b − φ_v L_b + φ_θ M_b)(x_j, t)` (z down: lift enters with −).
//! The field is generated from its seed when a solver starts ([`DeckBuffeting::new`]), so the
//! monolithic solver and the bridge FMU see the same wind. The forces are linear in `(u, w)`
//! and the field is linear in time between its samples `t_k`, so between two samples
//! `Fₙ(t) = Fₙ(t_k) + a (Fₙ(t_{k+1}) − Fₙ(t_k))` with the field's own weight `a`: a solver
//! stepping through the field projects the deck points once per sample, not once per step
//! ([`DeckBuffeting::add_modal_force`]).

use super::ModalBridge;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use tbi_wind::{Turbulence, WindField};

/// What the buffeting of a deck needs (kept in the modal bridge; the field itself is
/// generated from it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BuffetingSpec {
    /// Mean wind speed U, m/s (> 0).
    pub mean_speed_m_s: f64,
    /// Air density ρ, kg/m³.
    pub air_density_kg_m3: f64,
    /// Deck width B, m.
    pub width_m: f64,
    /// Steady coefficients (C_D, C_L, C_M) on B.
    pub coefficients: [f64; 3],
    /// Their slopes (C_D′, C_L′, C_M′) with the angle of attack, per rad.
    pub slopes: [f64; 3],
    /// The turbulence, generated from its seed (unless `record` is given).
    pub turbulence: Turbulence,
    /// A measured record of the turbulence, used instead of `turbulence` (not serialised:
    /// the bridge FMU takes the wind at its deck points as inputs).
    #[serde(skip)]
    pub record: Option<Arc<WindField>>,
    /// Number of deck points (≥ 2), equally spaced from deck start to end.
    pub points: usize,
    /// Davenport's admittance constant c (None: the quasi-steady limit, χ = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admittance: Option<f64>,
    /// Duration the field must cover, s (it repeats beyond).
    pub duration_s: f64,
}

/// The buffeting forces of one run (see the module docs).
#[derive(Debug, Clone)]
pub struct DeckBuffeting {
    /// The field at the deck points; None when the wind comes from outside (the bridge FMU's
    /// inputs, [`Self::add_modal_force_from`]).
    field: Option<WindField>,
    /// The same field through the admittance, which the forces see (None: the field itself).
    admitted: Option<WindField>,
    /// The deck points, m.
    x_m: Vec<f64>,
    /// Per point: Δx_j times the shapes of every mode, as three rows of the modes' values
    /// (lateral, vertical, torsion; `weighted_shapes[(3 j + c) N + n]`), point after point.
    weighted_shapes: Vec<f64>,
    n_modes: usize,
    /// ½ρU²B, N/m.
    q_b: f64,
    spec: BuffetingSpec,
    /// The generalised forces of the last two field samples used, `(sample, forces)`
    /// ([`Self::add_modal_force`]; `usize::MAX`: none yet).
    samples: Samples,
}

/// Two field samples and their generalised forces, `(sample, forces)`.
type SampleForces = [(usize, Vec<f64>); 2];

/// [`DeckBuffeting::add_modal_force`]'s two samples (derived data: a clone starts without).
#[derive(Debug)]
struct Samples(std::sync::Mutex<SampleForces>);

impl Samples {
    fn new() -> Self {
        Samples(std::sync::Mutex::new([
            (usize::MAX, Vec::new()),
            (usize::MAX, Vec::new()),
        ]))
    }

    fn lock(&self) -> std::sync::LockResult<std::sync::MutexGuard<'_, SampleForces>> {
        self.0.lock()
    }
}

impl Clone for Samples {
    fn clone(&self) -> Self {
        Samples::new()
    }
}

impl DeckBuffeting {
    /// Generate the field at the deck points and tabulate the weighted shapes.
    pub fn new(bridge: &ModalBridge, spec: &BuffetingSpec) -> Result<DeckBuffeting, String> {
        let mut b = Self::without_field(bridge, spec);
        let (field, admitted) = spec.generate_pair(&b.x_m)?;
        b.field = Some(field);
        b.admitted = admitted;
        Ok(b)
    }

    /// The forces of a wind given from outside at the deck points ([`BuffetingSpec::points`]),
    /// without generating the field.
    pub fn without_field(bridge: &ModalBridge, spec: &BuffetingSpec) -> DeckBuffeting {
        let (x, dx) = deck_points(bridge, spec);
        let p = x.len();
        let (a, b) = (bridge.x_start_m, bridge.x_end_m);
        let n = bridge.n_modes();
        let mut weighted_shapes = vec![0.0; 3 * p * n];
        let mut phi = vec![[0.0; 3]; n];
        for (j, &xj) in x.iter().enumerate() {
            let w = if j == 0 || j == p - 1 { 0.5 * dx } else { dx };
            bridge.deck_shapes(xj.clamp(a, b), &mut phi);
            for m in 0..n {
                for c in 0..3 {
                    weighted_shapes[(3 * j + c) * n + m] = w * phi[m][c];
                }
            }
        }
        DeckBuffeting {
            field: None,
            admitted: None,
            x_m: x,
            weighted_shapes,
            n_modes: n,
            q_b: 0.5 * spec.air_density_kg_m3 * spec.mean_speed_m_s.powi(2) * spec.width_m,
            spec: spec.clone(),
            samples: Samples::new(),
        }
    }

    /// Check what [`Self::new`] would need, without generating the field.
    pub fn check(bridge: &ModalBridge, spec: &BuffetingSpec) -> Result<(), String> {
        if spec.record.is_some() {
            return Ok(());
        }
        let (x, _) = deck_points(bridge, spec);
        WindField::check(&spec.turbulence, spec.mean_speed_m_s, &x, spec.duration_s)
            .map(drop)
            .map_err(|e| format!("wind.turbulence: {e}"))
    }

    /// The deck points' field (None when the wind comes from outside).
    pub fn field(&self) -> Option<&WindField> {
        self.field.as_ref()
    }

    /// The deck points, m.
    pub fn points(&self) -> &[f64] {
        &self.x_m
    }

    /// Add the generalised buffeting forces at time `t` to `out` (one per mode); nothing
    /// without a field.
    ///
    /// The forces are linear in the turbulence, and the field is linear in time between
    /// its samples, so they are those of the two samples around `t` with the field's own
    /// weight, `F(t) = F(t₀) + a (F(t₁) − F(t₀))` ([`WindField::time_index`]); the two
    /// samples' forces are kept (`samples`) while `t` stays between them (a sample lasts
    /// `dt_s` = 0.05 s by default, 25 steps of 2 ms). Each step then costs one product per
    /// mode instead of the projection of every deck point (200 points under 20 modes:
    /// 23·10³ instructions a step, a tenth of the Tsing Ma case's run in a turbulent wind).
    pub fn add_modal_force(&self, t: f64, out: &mut [f64]) {
        let Some(f) = self.admitted.as_ref().or(self.field.as_ref()) else {
            return;
        };
        if f.n_times() == 0 {
            return;
        }
        let n = self.n_modes;
        let (i0, i1, a) = f.time_index(t);
        let mut s = self.samples.lock().expect("buffeting samples");
        for i in [i0, i1] {
            if !s.iter().any(|(k, _)| *k == i) {
                // in place of one this step does not use
                let (k, forces) = s
                    .iter_mut()
                    .find(|(k, _)| *k != i0 && *k != i1)
                    .expect("two places, at most one of them in use");
                *k = i;
                forces.clear();
                forces.resize(n, 0.0);
                self.add_forces(|j| f.at_point(j, (i, i, 0.0)), forces);
            }
        }
        let of = |i: usize| &s.iter().find(|(k, _)| *k == i).expect("kept above").1;
        let (f0, f1) = (of(i0), of(i1));
        for ((o, a0), a1) in out[..n].iter_mut().zip(f0).zip(f1) {
            *o += a0 + a * (a1 - a0);
        }
    }

    /// Add the generalised buffeting forces of the turbulence `uw[j] = (u, w)` at the deck
    /// points to `out`.
    pub fn add_modal_force_from(&self, uw: &[[f64; 2]], out: &mut [f64]) {
        self.add_forces(|j| uw[j], out);
    }

    fn add_forces(&self, uw: impl Fn(usize) -> [f64; 2], out: &mut [f64]) {
        let s = &self.spec;
        let u_mean = s.mean_speed_m_s;
        let [cd, cl, cm] = s.coefficients;
        let [dcd, dcl, dcm] = s.slopes;
        let n = self.n_modes;
        // Per point its (D, −L, M), 64 points at a time, then φ_h Δx D − φ_v Δx L + φ_θ Δx M
        // of every mode summed over them in order, each mode's sum in a register through
        // the points (`project_rows_many`; the lift's product subtracted as the product
        // with −L added, the same rounding): 200 points under 20 modes took 46·10³
        // instructions a step one point after the other, a fifth of the Tsing Ma case's
        // run in a turbulent wind.
        let mut loads = [[0.0; 3]; 64];
        let points = self.x_m.len();
        for start in (0..points).step_by(loads.len()) {
            let m = loads.len().min(points - start);
            for (k, l) in loads[..m].iter_mut().enumerate() {
                let [u, w] = uw(start + k);
                let (ru, rw) = (u / u_mean, w / u_mean);
                let drag = self.q_b * (2.0 * cd * ru + dcd * rw);
                let lift = self.q_b * (2.0 * cl * ru + (dcl + cd) * rw);
                let moment = self.q_b * s.width_m * (2.0 * cm * ru + dcm * rw);
                *l = [drag, -lift, moment];
            }
            let rows = &self.weighted_shapes[3 * n * start..3 * n * (start + m)];
            crate::simd::project_rows_many(&mut out[..n], rows, &loads[..m]);
        }
    }
}

/// The deck points of a spec, equally spaced from deck start to end, and their spacing, m.
fn deck_points(bridge: &ModalBridge, spec: &BuffetingSpec) -> (Vec<f64>, f64) {
    spec.points_on(bridge.x_start_m, bridge.x_end_m)
}

impl BuffetingSpec {
    /// The deck points on a deck from `a` to `b`, equally spaced, and their spacing, m.
    pub fn points_on(&self, a: f64, b: f64) -> (Vec<f64>, f64) {
        let p = self.points.max(2);
        let dx = (b - a) / (p - 1) as f64;
        ((0..p).map(|j| a + j as f64 * dx).collect(), dx)
    }

    /// The field of this spec at the points `x`: the record's there (linear between its
    /// points), or generated from the seed.
    pub fn generate(&self, x: &[f64]) -> Result<WindField, String> {
        self.generate_pair(x).map(|(f, _)| f)
    }

    /// [`Self::generate`], and the field through the admittance when there is one (generated
    /// fields only: a record has no admittance).
    pub fn generate_pair(&self, x: &[f64]) -> Result<(WindField, Option<WindField>), String> {
        match &self.record {
            Some(r) => Ok((r.resample(x), None)),
            None => WindField::generate_pair(
                &self.turbulence,
                self.mean_speed_m_s,
                x,
                self.duration_s,
                self.admittance
                    .map(|c| admittance_gain(c, self.width_m, self.mean_speed_m_s)),
            )
            .map_err(|e| format!("wind.turbulence: {e}")),
        }
    }
}

/// Davenport's admittance `|χ(f)| = √((2/λ²)(λ − 1 + e^(−λ)))`, `λ = c f B / U`.
pub fn admittance_gain(c: f64, width_m: f64, mean_speed_m_s: f64) -> impl Fn(f64) -> f64 {
    move |f: f64| {
        let l = c * f * width_m / mean_speed_m_s;
        if l < 1e-4 {
            // the series 1 − λ/3 + λ²/12 (the closed form loses digits here)
            (1.0 - l / 3.0 + l * l / 12.0).sqrt()
        } else {
            (2.0 / (l * l) * (l - 1.0 + (-l).exp())).sqrt()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bridge::SimplySupported;

    /// The forces from the two field samples around `t` equal the projection of the field
    /// interpolated to `t` at every deck point ([`DeckBuffeting::add_modal_force_from`], the
    /// forces' definition) to round-off of the terms, at times inside a sample's interval,
    /// on samples, backwards and across the field's period; with and without the admittance;
    /// and a clone starts from the same forces.
    #[test]
    fn sampled_forces_equal_the_projection_of_the_interpolated_field() {
        let bridge = SimplySupported {
            span_m: 120.0,
            modes: 9,
            ..SimplySupported::example()
        }
        .modal();
        for admittance in [None, Some(7.0)] {
            let spec = BuffetingSpec {
                mean_speed_m_s: 25.0,
                air_density_kg_m3: 1.225,
                width_m: 12.0,
                coefficients: [1.5, 0.3, 0.1],
                slopes: [0.2, 3.0, 0.8],
                turbulence: Turbulence::default(),
                record: None,
                points: 70,
                admittance,
                duration_s: 4.0,
            };
            let b = DeckBuffeting::new(&bridge, &spec).unwrap();
            let f = b.admitted.as_ref().or(b.field.as_ref()).unwrap();
            let period = f.n_times() as f64 * f.dt_s;
            let n = bridge.n_modes();
            let times = (0..400).map(|k| 0.013 * k as f64).chain([
                0.0,
                f.dt_s,
                7.0 * f.dt_s,
                period - 1e-9,
                period + 0.031,
                2.5,
                0.4,
            ]);
            let copy = b.clone();
            for t in times {
                let mut sampled = vec![0.25; n];
                b.add_modal_force(t, &mut sampled);
                let when = f.time_index(t);
                let uw: Vec<[f64; 2]> = (0..b.x_m.len()).map(|j| f.at_point(j, when)).collect();
                let mut direct = vec![0.25; n];
                b.add_modal_force_from(&uw, &mut direct);
                // the terms' size: Σ_j Σ_c |Δx φ_c| |load_c|, each load's terms in absolute value
                let mut scale = vec![0.25; n];
                let ([cd, cl, cm], [dcd, dcl, dcm]) = (spec.coefficients, spec.slopes);
                for (j, v) in uw.iter().enumerate() {
                    let u_mean = spec.mean_speed_m_s;
                    let (u, w) = (v[0].abs() / u_mean, v[1].abs() / u_mean);
                    let loads = [
                        b.q_b * (2.0 * cd.abs() * u + dcd.abs() * w),
                        b.q_b * (2.0 * cl.abs() * u + (dcl.abs() + cd.abs()) * w),
                        b.q_b * spec.width_m * (2.0 * cm.abs() * u + dcm.abs() * w),
                    ];
                    for (c, load) in loads.iter().enumerate() {
                        for (m, s) in scale.iter_mut().enumerate() {
                            *s += b.weighted_shapes[(3 * j + c) * n + m].abs() * load;
                        }
                    }
                }
                for m in 0..n {
                    assert!(
                        (sampled[m] - direct[m]).abs() <= 1e-13 * scale[m],
                        "admittance {admittance:?}, t = {t}, mode {m}: {} against {}",
                        sampled[m],
                        direct[m]
                    );
                }
                let mut again = vec![0.25; n];
                copy.add_modal_force(t, &mut again);
                assert_eq!(again, sampled, "a clone, t = {t}");
            }
        }
    }
}
