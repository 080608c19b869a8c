//! Analytic modes of a simply supported, uniform Euler–Bernoulli span with St-Venant torsion.
//!
//! For span `L`, mass per length `μ`, polar mass moment per length `I_m`:
//!
//! ```text
//! vertical:  ωₙ = (nπ/L)² √(E I_v / μ),   φ_v = √(2/(μL)) sin(nπx/L)
//! lateral:   ωₙ = (nπ/L)² √(E I_h / μ),   φ_h = √(2/(μL)) sin(nπx/L)
//! torsion:   ωₙ = (nπ/L) √(G J / I_m),    φ_θ = √(2/(I_m L)) sin(nπx/L)
//! ```
//!
//! all mass-normalised (∫ μ φ² dx = 1). The lowest `modes` of the families that are defined
//! (vertical always; lateral and torsion when their properties are given) are kept, sorted
//! by frequency. Labels: `V-S-1` for the first symmetric vertical mode (odd n), `V-A-1` for the
//! first antisymmetric (even n), likewise `L-` and `T-`.

use super::modal::{ModalBridge, Shapes};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Section and span data of a simply supported bridge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimplySupported {
    /// Span length L, m.
    pub span_m: f64,
    /// Young's modulus E, Pa.
    pub youngs_modulus_pa: f64,
    /// Second moment of area for vertical bending I_v, m⁴.
    pub inertia_vertical_m4: f64,
    /// Second moment of area for lateral bending I_h, m⁴ (None: no lateral modes).
    pub inertia_lateral_m4: Option<f64>,
    /// Shear modulus G, Pa (torsion needs G, J and I_m).
    pub shear_modulus_pa: Option<f64>,
    /// St-Venant torsion constant J, m⁴.
    pub torsion_constant_m4: Option<f64>,
    /// Polar mass moment of inertia per length I_m, kg·m²/m.
    pub polar_inertia_kg_m: Option<f64>,
    /// Mass per length μ, kg/m.
    pub mass_per_length_kg_m: f64,
    /// Number of modes kept.
    pub modes: usize,
    /// Damping ratio of bending modes, –.
    pub damping_ratio: f64,
    /// Damping ratio of torsional modes, –.
    pub damping_ratio_torsional: f64,
    /// Track offset e, m; height h4, m; deck start, m.
    pub e_m: f64,
    pub h4_m: f64,
    pub x_start_m: f64,
}

impl SimplySupported {
    /// A 60 m concrete girder with vertical, lateral and torsional modes (the lowest 10
    /// kept, damping ratios 0.02 in bending and 0.01 in torsion), its track 2.05 m beside and
    /// 1.25 m above the shear centre, the deck starting at x = 0: the bridge of the examples
    /// and tests, to be adapted with struct update syntax.
    pub fn example() -> Self {
        SimplySupported {
            span_m: 60.0,
            youngs_modulus_pa: 3.0e10,
            inertia_vertical_m4: 8.0,
            inertia_lateral_m4: Some(40.0),
            shear_modulus_pa: Some(1.2e10),
            torsion_constant_m4: Some(12.0),
            polar_inertia_kg_m: Some(3.0e5),
            mass_per_length_kg_m: 2.0e4,
            modes: 10,
            damping_ratio: 0.02,
            damping_ratio_torsional: 0.01,
            e_m: 2.05,
            h4_m: 1.25,
            x_start_m: 0.0,
        }
    }

    pub fn modal(&self) -> ModalBridge {
        let l = self.span_m;
        let mu = self.mass_per_length_kg_m;
        let mut cands: Vec<(f64, char, u32, [f64; 3])> = Vec::new();
        let amp_b = (2.0 / (mu * l)).sqrt();
        for n in 1..=self.modes as u32 {
            let k = n as f64 * PI / l;
            let wv = k * k * (self.youngs_modulus_pa * self.inertia_vertical_m4 / mu).sqrt();
            cands.push((wv, 'V', n, [0.0, amp_b, 0.0]));
            if let Some(ih) = self.inertia_lateral_m4 {
                let wh = k * k * (self.youngs_modulus_pa * ih / mu).sqrt();
                cands.push((wh, 'L', n, [amp_b, 0.0, 0.0]));
            }
            if let (Some(g), Some(j), Some(im)) = (
                self.shear_modulus_pa,
                self.torsion_constant_m4,
                self.polar_inertia_kg_m,
            ) {
                let wt = k * (g * j / im).sqrt();
                cands.push((wt, 'T', n, [0.0, 0.0, (2.0 / (im * l)).sqrt()]));
            }
        }
        cands.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        cands.truncate(self.modes);
        let mut counters = std::collections::HashMap::new();
        let mut labels = Vec::new();
        for c in &cands {
            let sym = if c.2 % 2 == 1 { 'S' } else { 'A' };
            let e = counters.entry((c.1, sym)).or_insert(0);
            *e += 1;
            labels.push(format!("{}-{}-{}", c.1, sym, e));
        }
        ModalBridge {
            x_start_m: self.x_start_m,
            x_end_m: self.x_start_m + l,
            frequencies_hz: cands.iter().map(|c| c.0 / (2.0 * PI)).collect(),
            damping: cands
                .iter()
                .map(|c| {
                    if c.1 == 'T' {
                        self.damping_ratio_torsional
                    } else {
                        self.damping_ratio
                    }
                })
                .collect(),
            labels,
            e_m: self.e_m,
            h4_m: self.h4_m,
            other_tracks: Vec::new(),
            shapes: Shapes::Sine {
                span_m: l,
                half_waves: cands.iter().map(|c| c.2).collect(),
                amplitudes: cands.iter().map(|c| c.3).collect(),
            },
            steady_modal_force: Vec::new(),
            buffeting: None,
        }
    }
}
