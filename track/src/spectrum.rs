//! One-sided power spectral densities of track irregularities.
//!
//! All functions return the one-sided PSD `G(Ω)` in the spatial circular frequency
//! `Ω` (rad/m), normalised so that the variance is `σ² = ∫₀^∞ G(Ω) dΩ`:
//!
//! * lateral (alignment) and vertical (profile): m²/(rad/m);
//! * cross-level, as an angle: rad²/(rad/m).
//!
//! Cross-level is published as a height difference `Δh` between the rails (FRA, Chinese) or
//! already as an angle with `b = 0.75 m` (German). It is converted to the angle
//! `θ = Δh / (2b)`, where `2b` is the lateral distance between the wheel–rail contact points
//! (default [`DEFAULT_CONTACT_DISTANCE_M`]), so `G_θ = G_Δh / (2b)²`. The German formula
//! `(A_v/b²) …` equals `4 A_v … / (2b)²`, i.e. the height-difference spectrum `4 A_v …`
//! divided by `(2b)²`, and is scaled the same way when another contact distance is used.
//!
//! Formulas (constants in the private tables below):
//!
//! * German low/high interference (`Ω_c = 0.8246`, `Ω_r = 0.0206`, `Ω_s = 0.4380` rad/m):
//!   `G_v = A_v Ω_c² / ((Ω²+Ω_r²)(Ω²+Ω_c²))`, `G_a` the same with `A_a`,
//!   `G_Δh = 4 A_v Ω_c² Ω² / ((Ω²+Ω_r²)(Ω²+Ω_c²)(Ω²+Ω_s²))`.
//! * US FRA classes 1–6 (`k = 0.25`, `Ω_c = 0.8245` rad/m, `A` in cm²·rad/m, result in
//!   cm²/(rad/m), multiplied by 10⁻⁴ to get m²):
//!   `G_v = k A_v Ω_c² / (Ω²(Ω²+Ω_c²))`, `G_a` the same with `A_a`,
//!   `G_Δh = 4 k A_v Ω_c² / ((Ω²+Ω_c²)(Ω²+Ω_s²))`.
//! * Chinese main-line, given in `f = Ω/(2π)` cycles/m and mm²/(1/m):
//!   `S(f) = A (f² + B f + C) / (f⁴ + D f³ + E f² + F f + G)`. Converted with
//!   `G(Ω) = 10⁻⁶ S(Ω/2π) / (2π)` (so that `∫ G dΩ = 10⁻⁶ ∫ S df`). The model carries a
//!   single vertical and a single lateral profile, so the left and right rail spectra are
//!   averaged: `G_v = (G_left + G_right)/2` (same for alignment). The cross-level spectrum is a
//!   height difference in mm.

use std::f64::consts::TAU;
use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::TrackError;

/// Default lateral distance between the wheel–rail contact points of a wheelset, `2b`, m.
pub const DEFAULT_CONTACT_DISTANCE_M: f64 = 1.5;

/// An irregularity component.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Component {
    /// Lateral (alignment) deviation `Y_s`, m, + to the right looking in +x.
    Lateral,
    /// Vertical (profile) deviation `Z_s`, m, + downward.
    Vertical,
    /// Cross-level as an angle `θ_s`, rad, right side down positive.
    CrossLevel,
}

impl Component {
    /// The three components in storage order (lateral, vertical, cross-level).
    pub const ALL: [Component; 3] = [
        Component::Lateral,
        Component::Vertical,
        Component::CrossLevel,
    ];

    /// Storage index: lateral 0, vertical 1, cross-level 2.
    pub fn index(self) -> usize {
        match self {
            Component::Lateral => 0,
            Component::Vertical => 1,
            Component::CrossLevel => 2,
        }
    }
}

/// A standard track irregularity spectrum.
///
/// Names (for [`FromStr`], [`fmt::Display`] and serde): `german-low`, `german-high`,
/// `fra-1` … `fra-6`, `chinese-main-line` (also accepted on input: `china`, `chinese`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum Spectrum {
    /// German spectrum, low interference (high-speed lines).
    GermanLow,
    /// German spectrum, high interference.
    GermanHigh,
    /// US FRA track class 1 … 6 (6 is the best). The class must be in `1..=6`;
    /// [`Spectrum::psd`] panics otherwise (names and scenario files are validated).
    Fra(u8),
    /// Chinese main-line spectrum (mean of the left and right rail spectra).
    ChineseMainLine,
}

mod german {
    pub const OMEGA_C: f64 = 0.8246;
    pub const OMEGA_R: f64 = 0.0206;
    pub const OMEGA_S: f64 = 0.4380;
    /// (A_v, A_a) in m·rad, low interference.
    pub const LOW: (f64, f64) = (4.032e-7, 2.119e-7);
    /// (A_v, A_a) in m·rad, high interference.
    pub const HIGH: (f64, f64) = (1.080e-6, 6.125e-7);
}

mod fra {
    pub const K: f64 = 0.25;
    pub const OMEGA_C: f64 = 0.8245;
    /// A_v, cm²·rad/m, classes 1..=6.
    pub const A_V: [f64; 6] = [1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339];
    /// A_a, cm²·rad/m, classes 1..=6.
    pub const A_A: [f64; 6] = [3.3634, 1.2107, 0.4128, 0.3027, 0.0762, 0.0339];
    /// Ω_s, rad/m, classes 1..=6.
    pub const OMEGA_S: [f64; 6] = [0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380];
    /// cm² → m².
    pub const CM2: f64 = 1e-4;
}

mod chinese {
    /// (A, B, C, D, E, F, G) of S(f) = A (f² + B f + C) / (f⁴ + D f³ + E f² + F f + G),
    /// f in 1/m, S in mm²/(1/m).
    pub type Coefficients = [f64; 7];
    pub const LEFT_VERTICAL: Coefficients =
        [1.1029, -1.4709, 0.5941, 0.8480, 3.8016, -0.2500, 0.0112];
    pub const RIGHT_VERTICAL: Coefficients =
        [0.8581, -1.4607, 0.5848, 0.0407, 2.8428, -0.1989, 0.0094];
    pub const LEFT_ALIGNMENT: Coefficients =
        [0.2244, -1.5746, 0.6683, -2.1466, 1.7665, -0.1506, 0.0052];
    pub const RIGHT_ALIGNMENT: Coefficients =
        [0.3743, -1.5894, 0.7265, 0.4353, 0.9101, -0.0270, 0.0031];
    pub const CROSS_LEVEL: Coefficients =
        [0.1214, -2.1603, 2.0214, 4.5089, 2.2227, -0.0396, 0.0073];
    /// mm² → m².
    pub const MM2: f64 = 1e-6;

    /// S(f) in mm²/(1/m).
    pub fn s(c: &Coefficients, f: f64) -> f64 {
        let [a, b, cc, d, e, ff, g] = *c;
        a * (f * f + b * f + cc) / ((((f + d) * f + e) * f + ff) * f + g)
    }
}

impl Spectrum {
    /// Every valid canonical name.
    pub const NAMES: [&'static str; 9] = [
        "german-low",
        "german-high",
        "fra-1",
        "fra-2",
        "fra-3",
        "fra-4",
        "fra-5",
        "fra-6",
        "chinese-main-line",
    ];

    /// Every spectrum, in the order of [`Spectrum::NAMES`].
    pub const ALL: [Spectrum; 9] = [
        Spectrum::GermanLow,
        Spectrum::GermanHigh,
        Spectrum::Fra(1),
        Spectrum::Fra(2),
        Spectrum::Fra(3),
        Spectrum::Fra(4),
        Spectrum::Fra(5),
        Spectrum::Fra(6),
        Spectrum::ChineseMainLine,
    ];

    /// Whether the spectrum is a valid one (FRA class in `1..=6`).
    pub fn is_valid(&self) -> bool {
        !matches!(self, Spectrum::Fra(c) if !(1..=6).contains(c))
    }

    /// One-sided PSD at `omega_rad_m` (rad/m) of `component`, with the default contact
    /// distance [`DEFAULT_CONTACT_DISTANCE_M`] for the cross-level angle.
    ///
    /// Units: m²/(rad/m) for lateral and vertical, rad²/(rad/m) for cross-level. Zero for
    /// `omega_rad_m ≤ 0` (one-sided spectrum). Panics on an FRA class outside `1..=6`.
    pub fn psd(&self, component: Component, omega_rad_m: f64) -> f64 {
        self.psd_with_contact_distance(component, omega_rad_m, DEFAULT_CONTACT_DISTANCE_M)
    }

    /// As [`Spectrum::psd`], converting the cross-level height difference to an angle with the
    /// contact-point distance `contact_distance_m` (`2b`, m).
    pub fn psd_with_contact_distance(
        &self,
        component: Component,
        omega_rad_m: f64,
        contact_distance_m: f64,
    ) -> f64 {
        if omega_rad_m <= 0.0 {
            return 0.0;
        }
        let w2 = omega_rad_m * omega_rad_m;
        let to_angle = 1.0 / (contact_distance_m * contact_distance_m);
        match *self {
            Spectrum::GermanLow | Spectrum::GermanHigh => {
                use german::*;
                let (a_v, a_a) = if *self == Spectrum::GermanLow {
                    LOW
                } else {
                    HIGH
                };
                let wc2 = OMEGA_C * OMEGA_C;
                let base = wc2 / ((w2 + OMEGA_R * OMEGA_R) * (w2 + wc2));
                match component {
                    Component::Vertical => a_v * base,
                    Component::Lateral => a_a * base,
                    Component::CrossLevel => {
                        4.0 * a_v * base * w2 / (w2 + OMEGA_S * OMEGA_S) * to_angle
                    }
                }
            }
            Spectrum::Fra(class) => {
                use fra::*;
                let i = usize::from(class)
                    .checked_sub(1)
                    .filter(|&i| i < 6)
                    .unwrap_or_else(|| panic!("FRA class {class} is not in 1..=6"));
                let wc2 = OMEGA_C * OMEGA_C;
                match component {
                    Component::Vertical => CM2 * K * A_V[i] * wc2 / (w2 * (w2 + wc2)),
                    Component::Lateral => CM2 * K * A_A[i] * wc2 / (w2 * (w2 + wc2)),
                    Component::CrossLevel => {
                        let ws2 = OMEGA_S[i] * OMEGA_S[i];
                        CM2 * 4.0 * K * A_V[i] * wc2 / ((w2 + wc2) * (w2 + ws2)) * to_angle
                    }
                }
            }
            Spectrum::ChineseMainLine => {
                use chinese::*;
                let f = omega_rad_m / TAU;
                let s_mm2 = match component {
                    Component::Vertical => 0.5 * (s(&LEFT_VERTICAL, f) + s(&RIGHT_VERTICAL, f)),
                    Component::Lateral => 0.5 * (s(&LEFT_ALIGNMENT, f) + s(&RIGHT_ALIGNMENT, f)),
                    Component::CrossLevel => s(&CROSS_LEVEL, f) * to_angle,
                };
                MM2 * s_mm2 / TAU
            }
        }
    }
}

impl fmt::Display for Spectrum {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Spectrum::GermanLow => f.write_str("german-low"),
            Spectrum::GermanHigh => f.write_str("german-high"),
            Spectrum::Fra(c) => write!(f, "fra-{c}"),
            Spectrum::ChineseMainLine => f.write_str("chinese-main-line"),
        }
    }
}

impl FromStr for Spectrum {
    type Err = TrackError;

    /// Parses a canonical name (case-insensitive, surrounding blanks ignored) or one of the
    /// aliases `china`, `chinese`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let key = s.trim().to_ascii_lowercase();
        if key == "china" || key == "chinese" {
            return Ok(Spectrum::ChineseMainLine);
        }
        Spectrum::NAMES
            .iter()
            .position(|&n| n == key)
            .map(|i| Spectrum::ALL[i])
            .ok_or_else(|| TrackError::UnknownSpectrum { name: s.to_owned() })
    }
}

impl TryFrom<String> for Spectrum {
    type Error = TrackError;
    fn try_from(s: String) -> Result<Self, Self::Error> {
        s.parse()
    }
}

impl From<Spectrum> for String {
    fn from(s: Spectrum) -> String {
        s.to_string()
    }
}
