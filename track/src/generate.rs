//! Seeded samples of a spectrum by the spectral representation method.
//!
//! See the crate documentation for the mathematics; the choices made here:
//!
//! * Band `[Ω_lo, Ω_hi]` with `Ω_lo = 2π/λ_max`, split into `N` bins of width `ΔΩ`; term `k`
//!   sits at the bin mid-point `Ω_k = Ω_lo + (k + ½) ΔΩ` with amplitude `√(2 G(Ω_k) ΔΩ)` and
//!   phase `φ_k` uniform in `[0, 2π)`.
//! * `ΔΩ = Ω_lo / (m − ½)` for an integer `m ≥ 1`. Then every `Ω_k = (m + k) ΔΩ` is a whole
//!   multiple of `ΔΩ` and the sample is exactly periodic with period `P = 2π/ΔΩ = (m − ½) λ_max`.
//!   `m` is the smallest integer with `P ≥ x_end − x_start` and `N ≥ min_terms`, where
//!   `N = round((λ_max/λ_min − 1)(m − ½))`; so the line never sees a repetition. The upper
//!   band edge `Ω_hi = Ω_lo + N ΔΩ` is within `ΔΩ/2` of `2π/λ_min` (relative difference at most
//!   `λ_min / (2P)`, e.g. 0.02 % for `λ_min = 1 m`, `P = 2500 m`).
//! * Grid: `M = ⌈P / grid_spacing_m⌉` nodes per period, actual spacing `h = P/M`
//!   (at most the requested spacing), nodes `x_j = x_start + (j P)/M`, `j = 0 … M` (node `M`
//!   closes the period and repeats node 0). Since `Ω_k h = 2π (m + k)/M`, the values and the
//!   exact derivatives `r′(x_j) = −Σ Ω_k a_k sin(Ω_k x_j + φ_k)` at all nodes are one inverse
//!   DFT of length `M` (the two real sequences are packed as real and imaginary part), i.e.
//!   `O(M log M)` instead of `O(N M)`.
//! * Random numbers: ChaCha8 seeded with `seed` via `seed_from_u64`, stream 0/1/2 for
//!   lateral/vertical/cross-level (independent components), phases drawn in order of `k`.
//!   Samples are reproducible for a given build and machine; FFT round-off may differ in the
//!   last bits between CPUs, so use a record file ([`crate::Irregularity::to_record_csv`]) to
//!   carry a sample bit-exactly.

use std::f64::consts::TAU;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use serde::Serialize;

use crate::profile::Profile;
use crate::spectrum::DEFAULT_CONTACT_DISTANCE_M;
use crate::{Component, RailIrregularity, Spectrum, TrackError};

/// Default shortest wavelength, m.
pub const DEFAULT_LAMBDA_MIN_M: f64 = 1.0;
/// Default longest wavelength, m.
pub const DEFAULT_LAMBDA_MAX_M: f64 = 80.0;
/// Default (largest) grid spacing, m.
pub const DEFAULT_GRID_SPACING_M: f64 = 0.1;
/// Default seed.
pub const DEFAULT_SEED: u64 = 1;
/// Largest number of grid nodes per period that [`GeneratedSpec::generate`] accepts
/// (about 0.8 GB of interpolation table).
pub const MAX_GRID_NODES: usize = 1 << 23;

/// Parameters of a generated irregularity sample.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GeneratedSpec {
    /// Spectrum to sample. Required.
    pub spectrum: Spectrum,
    /// Seed of the phase generator. Default [`DEFAULT_SEED`] (1).
    pub seed: u64,
    /// Shortest wavelength of the band, m (> 0). Default 1.0 m.
    pub lambda_min_m: f64,
    /// Longest wavelength of the band, m (> `lambda_min_m`). Default 80.0 m.
    pub lambda_max_m: f64,
    /// Largest spacing of the interpolation grid, m (≤ `lambda_min_m / 4`; the actual spacing
    /// divides the period and may be slightly smaller). Default 0.1 m.
    pub grid_spacing_m: f64,
    /// Minimum number of spectral terms per component `N`; 0 lets the line length decide.
    /// Default 0.
    pub min_terms: usize,
    /// Lateral distance `2b` between the wheel–rail contact points used to turn a cross-level
    /// height difference into an angle, m (> 0). Default 1.5 m.
    pub contact_distance_m: f64,
}

/// One term `a cos(Ω x + φ)` of a generated sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralTerm {
    /// Circular spatial frequency `Ω_k`, rad/m.
    pub omega_rad_m: f64,
    /// Amplitude `a_k = √(2 G(Ω_k) ΔΩ)`, m (rad for cross-level).
    pub amplitude: f64,
    /// Phase `φ_k`, rad, in `[0, 2π)`.
    pub phase_rad: f64,
}

/// A generated sample: the spectral terms and their interpolation table over one period.
#[derive(Clone, Debug)]
pub struct GeneratedSample {
    spec: GeneratedSpec,
    line_m: (f64, f64),
    first_harmonic: usize,
    delta_omega: f64,
    terms: [Vec<SpectralTerm>; 3],
    profile: Profile,
}

fn invalid(field: &'static str, value: impl ToString, reason: impl Into<String>) -> TrackError {
    TrackError::Invalid {
        field,
        value: value.to_string(),
        reason: reason.into(),
    }
}

impl GeneratedSpec {
    /// A spec with the given spectrum and seed and every other field at its default.
    pub fn new(spectrum: Spectrum, seed: u64) -> GeneratedSpec {
        GeneratedSpec {
            spectrum,
            seed,
            lambda_min_m: DEFAULT_LAMBDA_MIN_M,
            lambda_max_m: DEFAULT_LAMBDA_MAX_M,
            grid_spacing_m: DEFAULT_GRID_SPACING_M,
            min_terms: 0,
            contact_distance_m: DEFAULT_CONTACT_DISTANCE_M,
        }
    }

    /// Checks the ranges documented on the fields.
    pub fn validate(&self) -> Result<(), TrackError> {
        if !self.spectrum.is_valid() {
            return Err(invalid(
                "spectrum",
                self.spectrum,
                format!("valid names: {}", Spectrum::NAMES.join(", ")),
            ));
        }
        let positive = |field, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(invalid(field, v, "must be a finite number > 0"))
            }
        };
        positive("lambda_min_m", self.lambda_min_m)?;
        positive("lambda_max_m", self.lambda_max_m)?;
        positive("grid_spacing_m", self.grid_spacing_m)?;
        positive("contact_distance_m", self.contact_distance_m)?;
        if self.lambda_max_m <= self.lambda_min_m {
            return Err(invalid(
                "lambda_max_m",
                self.lambda_max_m,
                format!("must be greater than lambda_min_m = {}", self.lambda_min_m),
            ));
        }
        if self.grid_spacing_m > self.lambda_min_m / 4.0 {
            return Err(invalid(
                "grid_spacing_m",
                self.grid_spacing_m,
                format!(
                    "must be at most lambda_min_m / 4 = {} (4 nodes per shortest wavelength)",
                    self.lambda_min_m / 4.0
                ),
            ));
        }
        Ok(())
    }

    /// Generates the sample for the line `[x_start_m, x_end_m]` (m). The sample is defined
    /// for every `x` (it is periodic with a period of at least the line length).
    pub fn generate(&self, x_start_m: f64, x_end_m: f64) -> Result<GeneratedSample, TrackError> {
        self.validate()?;
        if !x_start_m.is_finite() {
            return Err(invalid("x_start_m", x_start_m, "must be finite"));
        }
        if !(x_end_m.is_finite() && x_end_m > x_start_m) {
            return Err(invalid(
                "x_end_m",
                x_end_m,
                format!("must be finite and greater than x_start_m = {x_start_m}"),
            ));
        }
        let length = x_end_m - x_start_m;
        let (lambda_min, lambda_max) = (self.lambda_min_m, self.lambda_max_m);
        let ratio = lambda_max / lambda_min;
        let n_req = self.min_terms.max(1) as f64;
        let terms_for = |m: f64| ((ratio - 1.0) * (m - 0.5)).round();
        // Smallest m with (m − ½) λ_max ≥ length and N(m) ≥ n_req; the closed forms give it up
        // to rounding, the loop settles the last step.
        let mut m = 1f64
            .max((length / lambda_max + 0.5).ceil())
            .max(((n_req - 0.5) / (ratio - 1.0) + 0.5).ceil());
        let grid_nodes = |m: f64| {
            let exact = (m - 0.5) * lambda_max / self.grid_spacing_m;
            if (exact - exact.round()).abs() <= 1e-9 * exact {
                exact.round()
            } else {
                exact.ceil()
            }
        };
        let too_many = |m: f64| {
            let period = (m - 0.5) * lambda_max;
            invalid(
                "grid_spacing_m",
                self.grid_spacing_m,
                format!(
                    "the period of {period} m (line length {length} m, min_terms {}) needs \
                     {} grid nodes, more than the limit {MAX_GRID_NODES}",
                    self.min_terms,
                    grid_nodes(m)
                ),
            )
        };
        if grid_nodes(m) > MAX_GRID_NODES as f64 {
            return Err(too_many(m));
        }
        while (m - 0.5) * lambda_max < length || terms_for(m) < n_req {
            m += 1.0;
        }
        let nodes = grid_nodes(m);
        if nodes > MAX_GRID_NODES as f64 {
            return Err(too_many(m));
        }
        let period = (m - 0.5) * lambda_max;
        let nodes = nodes as usize;
        let first_harmonic = m as usize;
        let n_terms = terms_for(m) as usize;
        assert!(
            2 * (first_harmonic + n_terms) < nodes,
            "grid too coarse for the band"
        );
        let delta_omega = TAU / period;
        let mut x = Vec::with_capacity(nodes + 1);
        x.extend((0..=nodes).map(|j| x_start_m + j as f64 * period / nodes as f64));

        let fft = FftPlanner::<f64>::new().plan_fft_inverse(nodes);
        let mut terms: [Vec<SpectralTerm>; 3] = Default::default();
        let mut values: [Vec<f64>; 3] = Default::default();
        let mut slopes: [Vec<f64>; 3] = Default::default();
        for comp in Component::ALL {
            let c = comp.index();
            let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
            rng.set_stream(c as u64);
            terms[c] = (0..n_terms)
                .map(|k| {
                    let omega = (first_harmonic + k) as f64 * delta_omega;
                    let g = self.spectrum.psd_with_contact_distance(
                        comp,
                        omega,
                        self.contact_distance_m,
                    );
                    SpectralTerm {
                        omega_rad_m: omega,
                        amplitude: (2.0 * g * delta_omega).sqrt(),
                        phase_rad: TAU * rng.random::<f64>(),
                    }
                })
                .collect();
            // With c_k = a_k e^{i(φ_k + Ω_k x_start)} and θ = 2π b j / M:
            // r_j = Re Σ c_k e^{iθ}, r′_j = Re Σ iΩ_k c_k e^{iθ}. A real sequence Re Σ c e^{iθ}
            // is the inverse DFT of c/2 at bin b plus conj(c)/2 at bin M − b; packing the
            // second sequence as imaginary part gives bin b: (c + i·iΩc)/2 = c(1 − Ω)/2 and
            // bin M − b: (c̄ + i·conj(iΩc))/2 = c̄(1 + Ω)/2.
            let mut buf = vec![Complex::new(0.0, 0.0); nodes];
            for (k, t) in terms[c].iter().enumerate() {
                let b = first_harmonic + k;
                let z = Complex::from_polar(t.amplitude, t.phase_rad + t.omega_rad_m * x_start_m);
                buf[b] += z * (0.5 * (1.0 - t.omega_rad_m));
                buf[nodes - b] += z.conj() * (0.5 * (1.0 + t.omega_rad_m));
            }
            fft.process(&mut buf);
            values[c] = buf.iter().map(|z| z.re).chain([buf[0].re]).collect();
            slopes[c] = buf.iter().map(|z| z.im).chain([buf[0].im]).collect();
        }
        let profile = Profile::from_validated(
            x,
            values.each_ref().map(Vec::as_slice),
            slopes.each_ref().map(Vec::as_slice),
            true,
        );
        Ok(GeneratedSample {
            spec: self.clone(),
            line_m: (x_start_m, x_end_m),
            first_harmonic,
            delta_omega,
            terms,
            profile,
        })
    }
}

impl GeneratedSample {
    /// Value, first and second derivative of all components at `x` (m), by cubic Hermite
    /// interpolation of the exact values and slopes on the grid; periodic beyond one period.
    #[inline]
    pub fn at(&self, x: f64) -> RailIrregularity {
        self.profile.at(x)
    }

    /// The parameters the sample was generated with.
    pub fn spec(&self) -> &GeneratedSpec {
        &self.spec
    }

    /// The line `(x_start, x_end)` it was generated for, m.
    pub fn line_m(&self) -> (f64, f64) {
        self.line_m
    }

    /// Number of spectral terms per component, `N`.
    pub fn n_terms(&self) -> usize {
        self.terms[0].len()
    }

    /// Bin width `ΔΩ`, rad/m.
    pub fn delta_omega_rad_m(&self) -> f64 {
        self.delta_omega
    }

    /// Band actually sampled `(Ω_lo, Ω_hi) = ((m − ½) ΔΩ, (m − ½ + N) ΔΩ)`, rad/m.
    pub fn band_rad_m(&self) -> (f64, f64) {
        let lo = (self.first_harmonic as f64 - 0.5) * self.delta_omega;
        (lo, lo + self.n_terms() as f64 * self.delta_omega)
    }

    /// Period `P = 2π/ΔΩ`, m.
    pub fn period_m(&self) -> f64 {
        TAU / self.delta_omega
    }

    /// Actual grid spacing `h = P/M`, m.
    pub fn grid_spacing_m(&self) -> f64 {
        self.period_m() / (self.profile.nodes().len() - 1) as f64
    }

    /// The terms of one component: `r(x) = Σ_k a_k cos(Ω_k x + φ_k)`.
    pub fn terms(&self, component: Component) -> &[SpectralTerm] {
        &self.terms[component.index()]
    }

    /// The interpolation table (one period, periodic).
    pub fn profile(&self) -> &Profile {
        &self.profile
    }
}
