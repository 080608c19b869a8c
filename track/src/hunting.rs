//! Wheel hunting, eq. (7) of Xia, Xu & Chan (2000).
//!
//! The paper adds to the lateral displacement of each wheelset a sinusoid
//! `Y_h(t) = A_h sin(2π U t / L_h + φ_i)` with a random phase `φ_i ∈ [0, 2π)` per wheelset.
//! Written in the distance travelled by the train `s` (`s = U t` at constant speed):
//!
//! ```text
//! Y_h(s)   =  A_h sin(κ s + φ_i),      κ = 2π / L_h
//! Y_h′(s)  =  A_h κ cos(κ s + φ_i)
//! Y_h″(s)  = −A_h κ² sin(κ s + φ_i)
//! ```
//!
//! Time derivatives follow from `ṡ = v`, `s̈ = a`: `Ẏ_h = v Y_h′`, `Ÿ_h = v² Y_h″ + a Y_h′`.
//!
//! # Default wavelength
//!
//! The kinematic (Klingel) hunting wavelength of a wheelset with wheel radius `r₀`, half
//! distance between the contact points `b` and effective conicity `λ_e` is
//! `L_h = 2π √(r₀ b / λ_e)` ([`klingel_wavelength_m`]). With `b = 0.75 m` (the default
//! contact-point distance `2b = 1.5 m`), the classic 1:20 conical tread (`λ_e = 0.05`) and
//! `r₀ = 0.42 m` (840 mm wheels) it is 15.77 m, the default ([`DEFAULT_HUNTING_WAVELENGTH_M`]);
//! `r₀ = 0.4575 m` (915 mm wheels) gives 16.5 m. Worn treads have a higher effective conicity
//! and a shorter wavelength (11.2 m at `λ_e = 0.1`, `r₀ = 0.42 m`). The paper found hunting
//! negligible and left it out
//! of its case study, hence the default amplitude 0 (off).

use std::f64::consts::TAU;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::TrackError;

/// ChaCha8 stream used for the hunting phases (the irregularity components use streams 0–2,
/// so the same seed may be used for both without correlation).
pub const HUNTING_STREAM: u64 = 3;

/// Default hunting wavelength, m: [`klingel_wavelength_m`]`(0.42, 0.75, 0.05)` (see the module
/// docs).
pub const DEFAULT_HUNTING_WAVELENGTH_M: f64 = 15.77;

/// Kinematic (Klingel) hunting wavelength `2π √(r₀ b / λ_e)`, m, for wheel radius
/// `wheel_radius_m` (m), half the distance between the contact points `half_contact_distance_m`
/// (m) and effective conicity `effective_conicity` (–).
pub fn klingel_wavelength_m(
    wheel_radius_m: f64,
    half_contact_distance_m: f64,
    effective_conicity: f64,
) -> f64 {
    TAU * (wheel_radius_m * half_contact_distance_m / effective_conicity).sqrt()
}

/// Hunting parameters (scenario table; every field optional).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HuntingParams {
    /// Amplitude `A_h`, m (≥ 0). Default 0 (hunting off).
    pub amplitude_m: f64,
    /// Wavelength `L_h`, m (> 0). Default [`DEFAULT_HUNTING_WAVELENGTH_M`] (15.77 m).
    pub wavelength_m: f64,
    /// Seed of the per-wheelset phases. Default 1.
    pub seed: u64,
}

impl Default for HuntingParams {
    fn default() -> Self {
        HuntingParams {
            amplitude_m: 0.0,
            wavelength_m: DEFAULT_HUNTING_WAVELENGTH_M,
            seed: 1,
        }
    }
}

impl HuntingParams {
    /// Checks the ranges documented on the fields.
    pub fn validate(&self) -> Result<(), TrackError> {
        if !(self.amplitude_m.is_finite() && self.amplitude_m >= 0.0) {
            return Err(TrackError::Invalid {
                field: "amplitude_m",
                value: self.amplitude_m.to_string(),
                reason: "must be a finite number >= 0".into(),
            });
        }
        if !(self.wavelength_m.is_finite() && self.wavelength_m > 0.0) {
            return Err(TrackError::Invalid {
                field: "wavelength_m",
                value: self.wavelength_m.to_string(),
                reason: "must be a finite number > 0".into(),
            });
        }
        Ok(())
    }
}

/// Per-wheelset phases `φ_i`, rad, uniform in `[0, 2π)`: ChaCha8 seeded with `seed`
/// (`seed_from_u64`), stream [`HUNTING_STREAM`], drawn in wheelset order — so the phases of
/// the first `n` wheelsets do not depend on how many wheelsets follow.
pub fn phases(seed: u64, n_wheelsets: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(HUNTING_STREAM);
    (0..n_wheelsets)
        .map(|_| TAU * rng.random::<f64>())
        .collect()
}

/// Hunting displacements of the wheelsets of a train.
#[derive(Clone, Debug, PartialEq)]
pub struct WheelHunting {
    amplitude_m: f64,
    wavenumber_rad_m: f64,
    phases: Vec<f64>,
}

impl WheelHunting {
    /// Validates `params` and draws the phases of `n_wheelsets` wheelsets.
    pub fn new(params: &HuntingParams, n_wheelsets: usize) -> Result<WheelHunting, TrackError> {
        params.validate()?;
        Ok(WheelHunting {
            amplitude_m: params.amplitude_m,
            wavenumber_rad_m: TAU / params.wavelength_m,
            phases: phases(params.seed, n_wheelsets),
        })
    }

    /// `(Y_h, dY_h/ds, d²Y_h/ds²)` of wheelset `wheelset` (0-based) after the train has
    /// travelled `s_m` (m); units m, m/m, 1/m. Panics if `wheelset` is out of range.
    #[inline]
    pub fn lateral(&self, wheelset: usize, s_m: f64) -> [f64; 3] {
        let k = self.wavenumber_rad_m;
        let (sin, cos) = (k * s_m + self.phases[wheelset]).sin_cos();
        let a = self.amplitude_m;
        [a * sin, a * k * cos, -a * k * k * sin]
    }

    /// Whether the amplitude is non-zero.
    pub fn is_active(&self) -> bool {
        self.amplitude_m != 0.0
    }

    /// The phases `φ_i`, rad.
    pub fn phases(&self) -> &[f64] {
        &self.phases
    }
}
