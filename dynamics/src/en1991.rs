//! EN 1991-2 rules for the dynamic analysis of railway bridges (see also [`crate::hslm`]).
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
}
