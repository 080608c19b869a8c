//! Self-excited (motion-dependent) wind forces on the deck from Scanlan's flutter
//! derivatives, mode by mode.
//!
//! Per unit length, with the deck's vertical displacement `h` (+ down), torsion `α` (leeward
//! side down, i.e. nose up for the wind towards +y) and lateral displacement `p` (+y, along
//! the wind), `K = B ω / U` and the derivatives functions of the reduced velocity
//! `U_r = U / (f B)` (Scanlan's convention, h and L downward):
//!
//! ```text
//! L_se = ½ρU²B  [K H₁* ḣ/U + K H₂* B α̇/U + K² H₃* α + K² H₄* h/B]     (+ down)
//! M_se = ½ρU²B² [K A₁* ḣ/U + K A₂* B α̇/U + K² A₃* α + K² A₄* h/B]     (leeward side down)
//! D_se = ½ρU²B  [K P₁* ṗ/U + K² P₄* p/B]                               (+y)
//! ```
//!
//! Mode by mode (each mode at its own still-air frequency ωₙ, Kₙ = B ωₙ / U; no aerodynamic
//! coupling between modes, so no coupled flutter), these are a damping and a stiffness of the
//! mode: with mass-normalised shapes the modal equation becomes
//! `q̈ + (2ζω − dₙ) q̇ + (ω² − sₙ) q = …` with
//!
//! ```text
//! dₙ = ½ρB²ωₙ  [H₁* I_vv + P₁* I_hh + B (H₂* + A₁*) I_vθ + B² A₂* I_θθ]
//! sₙ = ½ρB²ωₙ² [H₄* I_vv + P₄* I_hh + B (H₃* + A₄*) I_vθ + B² A₃* I_θθ]
//! ```
//!
//! `I_ab = ∫ φ_a φ_b dx` over the deck, i.e. an aerodynamic damping ratio `ζ_ae = −dₙ/(2ωₙ)`
//! (positive for the usual H₁* < 0) and the frequency `√(ωₙ² − sₙ)`. [`apply`] folds them into
//! the modal bridge's damping ratios and frequencies, so both solvers and the bridge FMU
//! carry them.

use super::ModalBridge;
use serde::{Deserialize, Serialize};

/// Flutter derivatives against the reduced velocity (missing ones are zero).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlutterDerivatives {
    /// Reduced velocities U / (f B), ascending, > 0.
    pub reduced_velocity: Vec<f64>,
    #[serde(default)]
    pub h1: Vec<f64>,
    #[serde(default)]
    pub h2: Vec<f64>,
    #[serde(default)]
    pub h3: Vec<f64>,
    #[serde(default)]
    pub h4: Vec<f64>,
    #[serde(default)]
    pub a1: Vec<f64>,
    #[serde(default)]
    pub a2: Vec<f64>,
    #[serde(default)]
    pub a3: Vec<f64>,
    #[serde(default)]
    pub a4: Vec<f64>,
    #[serde(default)]
    pub p1: Vec<f64>,
    #[serde(default)]
    pub p4: Vec<f64>,
}

/// What the self-excited forces did to one mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeChange {
    pub label: String,
    /// Reduced velocity U / (f B) of the mode, –.
    pub reduced_velocity: f64,
    /// Aerodynamic damping ratio ζ_ae, –.
    pub aerodynamic_damping_ratio: f64,
    /// Frequency in still air and in the wind, Hz.
    pub frequency_still_hz: f64,
    pub frequency_wind_hz: f64,
}

impl FlutterDerivatives {
    fn columns(&self) -> [(&'static str, &Vec<f64>); 10] {
        [
            ("h1", &self.h1),
            ("h2", &self.h2),
            ("h3", &self.h3),
            ("h4", &self.h4),
            ("a1", &self.a1),
            ("a2", &self.a2),
            ("a3", &self.a3),
            ("a4", &self.a4),
            ("p1", &self.p1),
            ("p4", &self.p4),
        ]
    }

    /// Check the table; the first bad field and why.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let r = &self.reduced_velocity;
        if r.is_empty() {
            return Err((
                "reduced_velocity".into(),
                "give at least one reduced velocity".into(),
            ));
        }
        if let Some(i) = r.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err((
                format!("reduced_velocity[{i}]"),
                format!("{} must be a positive finite number", r[i]),
            ));
        }
        for i in 1..r.len() {
            if r[i] <= r[i - 1] {
                return Err((
                    format!("reduced_velocity[{i}]"),
                    format!(
                        "{} does not ascend from {} (the table is out of order)",
                        r[i],
                        r[i - 1]
                    ),
                ));
            }
        }
        for (name, c) in self.columns() {
            if !c.is_empty() && c.len() != r.len() {
                return Err((
                    name.into(),
                    format!("{} values for {} reduced velocities", c.len(), r.len()),
                ));
            }
            if let Some(i) = c.iter().position(|v| !v.is_finite()) {
                return Err((format!("{name}[{i}]"), format!("{} is not finite", c[i])));
            }
        }
        Ok(())
    }

    /// A derivative at the reduced velocity `ur`: linear between the table's points, the end
    /// values beyond them; 0 for a column not given.
    pub fn at(&self, column: &[f64], ur: f64) -> f64 {
        let r = &self.reduced_velocity;
        if column.is_empty() {
            return 0.0;
        }
        if ur <= r[0] {
            return column[0];
        }
        if ur >= r[r.len() - 1] {
            return column[r.len() - 1];
        }
        let k = r.partition_point(|&v| v <= ur);
        let (r0, r1) = (r[k - 1], r[k]);
        column[k - 1] + (ur - r0) / (r1 - r0) * (column[k] - column[k - 1])
    }
}

/// The integrals `(I_vv, I_hh, I_vθ, I_θθ)` of each mode's shapes over the deck (composite
/// Simpson over 4000 intervals).
fn shape_integrals(bridge: &ModalBridge) -> Vec<[f64; 4]> {
    let mut out = vec![[0.0; 4]; bridge.n_modes()];
    bridge.integrate_shapes(|w, phi| {
        for (o, p) in out.iter_mut().zip(phi) {
            o[0] += w * p[1] * p[1];
            o[1] += w * p[0] * p[0];
            o[2] += w * p[1] * p[2];
            o[3] += w * p[2] * p[2];
        }
    });
    out
}

/// Fold the self-excited forces of a mean wind `u` (m/s, > 0) on a deck of width `b` (m) in
/// air of density `rho` into the bridge's damping ratios and frequencies (module docs). Fails
/// when a mode would lose its stiffness (ω² − sₙ ≤ 0: divergence).
pub fn apply(
    bridge: &mut ModalBridge,
    table: &FlutterDerivatives,
    rho: f64,
    u: f64,
    b: f64,
) -> Result<Vec<ModeChange>, String> {
    let integrals = shape_integrals(bridge);
    let mut changes = Vec::with_capacity(bridge.n_modes());
    for (n, i) in integrals.iter().enumerate() {
        let f = bridge.frequencies_hz[n];
        let w = 2.0 * std::f64::consts::PI * f;
        let ur = u / (f * b);
        let d = |c: &[f64]| table.at(c, ur);
        let dn = 0.5
            * rho
            * b
            * b
            * w
            * (d(&table.h1) * i[0]
                + d(&table.p1) * i[1]
                + b * (d(&table.h2) + d(&table.a1)) * i[2]
                + b * b * d(&table.a2) * i[3]);
        let sn = 0.5
            * rho
            * b
            * b
            * w
            * w
            * (d(&table.h4) * i[0]
                + d(&table.p4) * i[1]
                + b * (d(&table.h3) + d(&table.a4)) * i[2]
                + b * b * d(&table.a3) * i[3]);
        let w2 = w * w - sn;
        if w2 <= 0.0 {
            return Err(format!(
                "mode {} ({}) loses its stiffness in the wind (ω² − s = {w2:.3e}): divergence",
                n + 1,
                bridge.labels[n]
            ));
        }
        let zeta_ae = -dn / (2.0 * w);
        let w_wind = w2.sqrt();
        // the damping term 2ζω − d keeps its value with the new frequency
        bridge.damping[n] = (2.0 * bridge.damping[n] * w - dn) / (2.0 * w_wind);
        bridge.frequencies_hz[n] = w_wind / (2.0 * std::f64::consts::PI);
        changes.push(ModeChange {
            label: bridge.labels[n].clone(),
            reduced_velocity: ur,
            aerodynamic_damping_ratio: zeta_ae,
            frequency_still_hz: f,
            frequency_wind_hz: bridge.frequencies_hz[n],
        });
    }
    Ok(changes)
}
