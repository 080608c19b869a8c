//! Turbulence spectra (formulas in the crate docs): `f S(f) / σ²` as a function of the
//! reduced frequency `n = f L / U` (or `f z / U` for Simiu–Scanlan), each integrating to 1
//! over `d(ln f)`, i.e. `∫₀^∞ S df = σ²`.

use crate::WindError;
use serde::{Deserialize, Serialize};

/// A turbulence component: `u` along the mean wind, `w` vertical (+ up).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Component {
    U,
    W,
}

impl Component {
    pub const ALL: [Component; 2] = [Component::U, Component::W];

    pub fn name(self) -> &'static str {
        match self {
            Component::U => "u",
            Component::W => "w",
        }
    }
}

/// The spectrum family of both components.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Spectrum {
    /// EN 1991-1-4 Annex B (Kaimal form), for u and, with its own length scale, for w.
    Kaimal,
    /// von Kármán, u and w.
    VonKarman,
    /// Simiu–Scanlan (u) and Lumley–Panofsky (w), in the height above ground.
    SimiuScanlan,
}

/// ∫₀^∞ 3.36/(1 + 10 n^{5/3}) dn = 3.36 · 10^{−3/5} · (3π/5)/sin(3π/5).
fn lumley_panofsky_integral() -> f64 {
    let p = 5.0 / 3.0;
    let pi = std::f64::consts::PI;
    3.36 * 10f64.powf(-0.6) * (pi / p) / (pi / p).sin()
}

impl Spectrum {
    pub const NAMES: [&'static str; 3] = ["kaimal", "von-karman", "simiu-scanlan"];

    pub fn parse(name: &str) -> Result<Spectrum, WindError> {
        match name {
            "kaimal" => Ok(Spectrum::Kaimal),
            "von-karman" => Ok(Spectrum::VonKarman),
            "simiu-scanlan" => Ok(Spectrum::SimiuScanlan),
            other => Err(WindError::UnknownSpectrum { name: other.into() }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Spectrum::Kaimal => "kaimal",
            Spectrum::VonKarman => "von-karman",
            Spectrum::SimiuScanlan => "simiu-scanlan",
        }
    }

    /// `f S(f) / σ²` at the reduced frequency `n` (≥ 0).
    pub fn reduced(self, c: Component, n: f64) -> f64 {
        match (self, c) {
            (Spectrum::Kaimal, _) => 6.8 * n / (1.0 + 10.2 * n).powf(5.0 / 3.0),
            (Spectrum::VonKarman, Component::U) => 4.0 * n / (1.0 + 70.8 * n * n).powf(5.0 / 6.0),
            (Spectrum::VonKarman, Component::W) => {
                4.0 * n * (1.0 + 755.2 * n * n) / (1.0 + 283.2 * n * n).powf(11.0 / 6.0)
            }
            (Spectrum::SimiuScanlan, Component::U) => {
                200.0 * n / (1.0 + 50.0 * n).powf(5.0 / 3.0) / 6.0
            }
            (Spectrum::SimiuScanlan, Component::W) => {
                3.36 * n / (1.0 + 10.0 * n.powf(5.0 / 3.0)) / lumley_panofsky_integral()
            }
        }
    }

    /// The one-sided spectrum `S(f)`, (m/s)²/Hz, of a component with standard deviation
    /// `sigma` (m/s) in a mean wind `mean_speed` (m/s, > 0), `scale` the integral length
    /// scale (Kaimal, von Kármán) or the height above ground (Simiu–Scanlan), m.
    pub fn psd(self, c: Component, f: f64, sigma: f64, mean_speed: f64, scale: f64) -> f64 {
        if f <= 0.0 {
            // the limit f → 0 of σ² reduced(n)/f = σ² (scale/U) reduced(n)/n
            let r0 = self.reduced(c, 1e-12) / 1e-12;
            return sigma * sigma * scale / mean_speed * r0;
        }
        let n = f * scale / mean_speed;
        sigma * sigma * self.reduced(c, n) / f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ reduced(n) d(ln n) = 1 for every spectrum and component, to 2e-4: the published
    /// constants are rounded (von Kármán's 70.8 gives 0.99986). A log-spaced trapezoid over
    /// 1e-9 … 1e9, accurate to 1e-6 here.
    #[test]
    fn every_spectrum_integrates_to_its_variance() {
        for s in [
            Spectrum::Kaimal,
            Spectrum::VonKarman,
            Spectrum::SimiuScanlan,
        ] {
            for c in Component::ALL {
                let (lo, hi, m) = (-9.0_f64, 9.0_f64, 200_000);
                let h = (hi - lo) / m as f64 * std::f64::consts::LN_10;
                let mut sum = 0.0;
                for i in 0..=m {
                    let n = 10f64.powf(lo + (hi - lo) * i as f64 / m as f64);
                    let w = if i == 0 || i == m { 0.5 } else { 1.0 };
                    sum += w * s.reduced(c, n) * h;
                }
                assert!((sum - 1.0).abs() < 2e-4, "{s:?} {c:?}: {sum}");
            }
        }
        assert!((lumley_panofsky_integral() - 1.6728).abs() < 1e-3);
    }

    #[test]
    fn psd_scales_with_sigma_and_names_parse() {
        let s = Spectrum::VonKarman;
        let a = s.psd(Component::U, 0.1, 2.0, 20.0, 100.0);
        let b = s.psd(Component::U, 0.1, 4.0, 20.0, 100.0);
        assert!((b / a - 4.0).abs() < 1e-12);
        for name in Spectrum::NAMES {
            assert_eq!(Spectrum::parse(name).unwrap().name(), name);
        }
        assert!(Spectrum::parse("davenport")
            .unwrap_err()
            .to_string()
            .contains("unknown spectrum \"davenport\""));
    }
}
