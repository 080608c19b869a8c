//! EN 1991-2 rules for the dynamic analysis of railway bridges (see also [`crate::hslm`]):
//! damping, the modes considered, the dynamic factors Φ₂, Φ₃ and φ'', the determinant
//! length and LM71's classification factors.
//!
//! **Damping** (§6.4.6.3.1, Table 6.6): the lower limit of the damping ratio for design, in
//! percent, by structure type and span L (m):
//!
//! | structure | L < 20 m | L ≥ 20 m |
//! |---|---|---|
//! | steel and composite | ζ = 0.5 + 0.125 (20 − L) | ζ = 0.5 |
//! | prestressed concrete | ζ = 1.0 + 0.07 (20 − L) | ζ = 1.0 |
//! | filler beam and reinforced concrete | ζ = 1.5 + 0.07 (20 − L) | ζ = 1.5 |
//!
//! and, for spans under 30 m analysed with moving forces (vehicle–bridge interaction not
//! modelled), the additional damping of eq. (6.13), in percent:
//!
//! ```text
//! Δζ = (0.0187 L − 0.00064 L²) / (1 − 0.0441 L − 0.0044 L² + 0.000255 L³)
//! ```

use std::str::FromStr;

/// Structure type of EN 1991-2 Table 6.6.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Structure {
    SteelComposite,
    PrestressedConcrete,
    ReinforcedConcrete,
}

impl FromStr for Structure {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "steel_composite" => Ok(Structure::SteelComposite),
            "prestressed_concrete" => Ok(Structure::PrestressedConcrete),
            "reinforced_concrete" | "filler_beam" => Ok(Structure::ReinforcedConcrete),
            _ => Err(format!(
                "\"{s}\" is not a structure type of EN 1991-2 Table 6.6 (steel_composite, prestressed_concrete, reinforced_concrete, filler_beam)"
            )),
        }
    }
}

impl Structure {
    /// Table 6.6: the lower limit of the damping ratio for span `l_m`, percent.
    pub fn minimum_damping_percent(self, l_m: f64) -> f64 {
        let (base, slope) = match self {
            Structure::SteelComposite => (0.5, 0.125),
            Structure::PrestressedConcrete => (1.0, 0.07),
            Structure::ReinforcedConcrete => (1.5, 0.07),
        };
        if l_m < 20.0 {
            base + slope * (20.0 - l_m)
        } else {
            base
        }
    }
}

/// Eq. (6.13): the additional damping for span `l_m` < 30 m, percent (0 from 30 m).
pub fn additional_damping_percent(l_m: f64) -> f64 {
    if l_m >= 30.0 {
        return 0.0;
    }
    (0.0187 * l_m - 0.00064 * l_m * l_m)
        / (1.0 - 0.0441 * l_m - 0.0044 * l_m * l_m + 0.000255 * l_m.powi(3))
}

/// EN 1990 A2.4.4.2.1: the frequency up to which the modes are considered,
/// max(30 Hz, 1.5 f₁, f₃), and the number of the lowest of `frequencies_hz` (ascending) up
/// to it (at least one).
pub fn modes_considered(frequencies_hz: &[f64]) -> (usize, f64) {
    let f = frequencies_hz;
    let needed = 30.0_f64
        .max(1.5 * f.first().copied().unwrap_or(0.0))
        .max(f.get(2).copied().unwrap_or(0.0));
    (
        f.iter().take_while(|&&x| x <= needed).count().max(1),
        needed,
    )
}

/// §6.4.5.2 eq. (6.4): the dynamic factor Φ₂ for carefully maintained track,
/// 1.44 / (√L_Φ − 0.2) + 0.82, bounded to [1.00, 1.67]; `l_phi_m` the determinant length, m.
pub fn phi2(l_phi_m: f64) -> f64 {
    (1.44 / (l_phi_m.sqrt() - 0.2) + 0.82).clamp(1.0, 1.67)
}

/// §6.4.5.2 eq. (6.5): the dynamic factor Φ₃ for standard maintenance,
/// 2.16 / (√L_Φ − 0.2) + 0.73, bounded to [1.00, 2.00].
pub fn phi3(l_phi_m: f64) -> f64 {
    (2.16 / (l_phi_m.sqrt() - 0.2) + 0.73).clamp(1.0, 2.0)
}

/// Annex C eq. (C.4), the allowance for track irregularities of real trains:
/// φ'' = (a/100)·[56 e^(−(L_Φ/10)²) + 50 (L_Φ n₀/80 − 1) e^(−(L_Φ/20)²)], a = v/22 for
/// v ≤ 22 m/s and 1 above, φ'' ≥ 0; `n0_hz` the first bending frequency of the loaded
/// bridge, `v_m_s` the speed.
pub fn phi_double_prime(l_phi_m: f64, n0_hz: f64, v_m_s: f64) -> f64 {
    let a = (v_m_s / 22.0).min(1.0);
    let l = l_phi_m;
    let value = a / 100.0
        * (56.0 * (-(l / 10.0).powi(2)).exp()
            + 50.0 * (l * n0_hz / 80.0 - 1.0) * (-(l / 20.0).powi(2)).exp());
    value.max(0.0)
}

/// §6.4.5.3 Table 6.2 (cases 5.1 and 5.2): the determinant length L_Φ of a beam's main girder
/// over `spans_m`: the span for a simply supported girder (or each span of a chain of them),
/// k·L_m for a girder continuous over n spans (L_m their mean, k = 1.2, 1.3, 1.4, 1.5 for
/// n = 2, 3, 4, ≥ 5).
pub fn determinant_length(spans_m: &[f64], continuous: bool, span: usize) -> f64 {
    let n = spans_m.len();
    if !continuous || n == 1 {
        return spans_m[span];
    }
    let k = match n {
        2 => 1.2,
        3 => 1.3,
        4 => 1.4,
        _ => 1.5,
    };
    k * spans_m.iter().sum::<f64>() / n as f64
}

/// §6.3.2(3): the classification factors α of LM71 a national annex may choose.
pub const LM71_ALPHAS: [f64; 8] = [0.75, 0.83, 0.91, 1.00, 1.10, 1.21, 1.33, 1.46];

/// EN 1990 A2.4.4.2.2 Table A2.7: the limit of the deck twist over 3 m, m, for line speed
/// `v_kmh` (4.5 mm up to 120 km/h, 3.0 mm up to 200 km/h, 1.5 mm above).
pub fn twist_limit_m(v_kmh: f64) -> f64 {
    if v_kmh <= 120.0 {
        4.5e-3
    } else if v_kmh <= 200.0 {
        3.0e-3
    } else {
        1.5e-3
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 6.6 at its corners, and eq. (6.13) at values worked by hand.
    #[test]
    fn table_6_6_and_eq_6_13() {
        let pc = Structure::PrestressedConcrete;
        assert_eq!(pc.minimum_damping_percent(25.0), 1.0);
        assert!((pc.minimum_damping_percent(10.0) - 1.7).abs() < 1e-12);
        assert!((Structure::SteelComposite.minimum_damping_percent(12.0) - 1.5).abs() < 1e-12);
        assert_eq!(
            Structure::ReinforcedConcrete.minimum_damping_percent(40.0),
            1.5
        );
        // L = 10: (0.187 − 0.064) / (1 − 0.441 − 0.44 + 0.255) = 0.123 / 0.374
        assert!((additional_damping_percent(10.0) - 0.123 / 0.374).abs() < 1e-12);
        // L = 20: (0.374 − 0.256) / (1 − 0.882 − 1.76 + 2.04) = 0.118 / 0.398
        assert!((additional_damping_percent(20.0) - 0.118 / 0.398).abs() < 1e-12);
        assert_eq!(additional_damping_percent(30.0), 0.0);
        assert!("timber".parse::<Structure>().is_err());
    }

    /// Φ₂, Φ₃ (eqs. 6.4, 6.5) with their bounds and φ'' (eq. C.4) at several spans, worked
    /// from the formulas as written in the standard.
    #[test]
    fn dynamic_factors_at_several_spans() {
        for l in [3.0_f64, 4.0, 8.0, 12.5, 20.0, 25.0, 40.0, 100.0] {
            let p2 = (1.44 / (l.sqrt() - 0.2) + 0.82).clamp(1.0, 1.67);
            let p3 = (2.16 / (l.sqrt() - 0.2) + 0.73).clamp(1.0, 2.0);
            assert!((phi2(l) - p2).abs() < 1e-15, "Φ₂({l})");
            assert!((phi3(l) - p3).abs() < 1e-15, "Φ₃({l})");
        }
        // the bounds: short spans reach the upper, long spans the lower
        assert_eq!(phi2(3.0), 1.67);
        assert_eq!(phi3(3.0), 2.0);
        assert_eq!(phi2(1000.0), 1.0);
        assert_eq!(phi3(1000.0), 1.0);
        // worked values: L = 20 m, Φ₂ = 1.44/(4.472136 − 0.2) + 0.82 = 1.157068
        assert!((phi2(20.0) - 1.157_068).abs() < 1e-6);
        for (l, n0, v) in [
            (10.0, 8.0, 50.0),
            (20.0, 6.4, 80.0),
            (25.0, 5.5, 15.0),
            (40.0, 3.0, 60.0),
        ] {
            let a: f64 = if v <= 22.0 { v / 22.0 } else { 1.0 };
            let want = (a / 100.0
                * (56.0 * (-(l / 10.0_f64).powi(2)).exp()
                    + 50.0 * (l * n0 / 80.0 - 1.0) * (-(l / 20.0_f64).powi(2)).exp()))
            .max(0.0);
            assert!(
                (phi_double_prime(l, n0, v) - want).abs() < 1e-15,
                "φ''({l}, {n0}, {v})"
            );
        }
        // L = 20 m, n₀ = 6.4 Hz, fast: (56 e⁻⁴ + 50 · 0.6 · e⁻¹)/100
        assert!((phi_double_prime(20.0, 6.4, 80.0) - 0.120_621).abs() < 1e-6);
        // negative parts are cut to 0: a low frequency on a long span
        assert_eq!(phi_double_prime(40.0, 0.5, 80.0), 0.0);
    }

    /// Table 6.2: the span of a simple girder, k·L_m of a continuous one.
    #[test]
    fn determinant_lengths() {
        assert_eq!(determinant_length(&[25.0], true, 0), 25.0);
        assert_eq!(determinant_length(&[20.0, 15.0], false, 1), 15.0);
        assert!((determinant_length(&[20.0, 30.0], true, 0) - 30.0).abs() < 1e-12);
        assert!((determinant_length(&[20.0; 3], true, 2) - 26.0).abs() < 1e-12);
        assert!((determinant_length(&[20.0; 6], true, 2) - 30.0).abs() < 1e-12);
    }

    /// EN 1990 A2.4.4.2.1: the modes up to max(30 Hz, 1.5 f₁, f₃).
    #[test]
    fn the_modes_considered() {
        assert_eq!(modes_considered(&[5.0, 20.0, 45.0, 80.0]), (3, 45.0));
        assert_eq!(modes_considered(&[5.0, 20.0, 25.0, 31.0]), (3, 30.0));
        assert_eq!(modes_considered(&[25.0, 60.0]), (1, 37.5));
    }
}
