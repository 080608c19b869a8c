//! The seeded turbulence field at points along the deck (the mathematics is in the crate
//! docs): random-phase spectral representation with the phases chained along the deck so
//! that two points have Davenport's coherence `exp(−C f Δx / U)`, one inverse FFT per point
//! and component.

use crate::spectrum::{Component, Spectrum};
use crate::WindError;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustfft::{num_complex::Complex, FftPlanner};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// The turbulence of the wind (the mean speed is given separately). Defaults are documented
/// assumptions for a long-span deck in strong wind, not measurements of a particular site.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Turbulence {
    /// Spectrum family of u and w. Default von Kármán.
    pub spectrum: Spectrum,
    /// Turbulence intensity of u, σ_u / U, –, in [0, 1]. Default 0.12.
    pub intensity_u: f64,
    /// Turbulence intensity of w, σ_w / U, –, in [0, 1]. Default 0.06 (half of u's).
    pub intensity_w: f64,
    /// Integral length scale of u, m (Kaimal, von Kármán). Default 150.
    pub length_scale_u_m: f64,
    /// Integral length scale of w, m (Kaimal, von Kármán). Default 30.
    pub length_scale_w_m: f64,
    /// Height of the deck above ground or sea, m (Simiu–Scanlan). Default 60.
    pub height_m: f64,
    /// Davenport decay coefficient C of u for separations along the deck, –. Default 16
    /// (horizontal separation normal to the wind; Simiu & Scanlan).
    pub coherence_u: f64,
    /// Davenport decay coefficient C of w along the deck, –. Default 8.
    pub coherence_w: f64,
    /// Seed of the random phases. Default 1.
    pub seed: u64,
    /// Time step of the generated field, s (its Nyquist frequency bounds the spectrum).
    /// Default 0.05.
    pub dt_s: f64,
}

impl Default for Turbulence {
    fn default() -> Self {
        Turbulence {
            spectrum: Spectrum::VonKarman,
            intensity_u: 0.12,
            intensity_w: 0.06,
            length_scale_u_m: 150.0,
            length_scale_w_m: 30.0,
            height_m: 60.0,
            coherence_u: 16.0,
            coherence_w: 8.0,
            seed: 1,
            dt_s: 0.05,
        }
    }
}

/// At most this many samples (points × times × components) in a generated field.
pub const MAX_SAMPLES: usize = 1 << 27;

impl Turbulence {
    /// Check every field, naming the first bad one.
    pub fn validate(&self) -> Result<(), WindError> {
        let unit = |field: &'static str, v: f64| {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(WindError::invalid(field, v, "must lie in [0, 1]"));
            }
            Ok(())
        };
        let positive = |field: &'static str, v: f64| {
            if !(v.is_finite() && v > 0.0) {
                return Err(WindError::invalid(
                    field,
                    v,
                    "must be a positive finite number",
                ));
            }
            Ok(())
        };
        let non_negative = |field: &'static str, v: f64| {
            if !(v.is_finite() && v >= 0.0) {
                return Err(WindError::invalid(field, v, "must be a finite number ≥ 0"));
            }
            Ok(())
        };
        unit("intensity_u", self.intensity_u)?;
        unit("intensity_w", self.intensity_w)?;
        positive("length_scale_u_m", self.length_scale_u_m)?;
        positive("length_scale_w_m", self.length_scale_w_m)?;
        positive("height_m", self.height_m)?;
        non_negative("coherence_u", self.coherence_u)?;
        non_negative("coherence_w", self.coherence_w)?;
        positive("dt_s", self.dt_s)?;
        Ok(())
    }

    /// σ of a component, m/s.
    pub fn sigma(&self, c: Component, mean_speed: f64) -> f64 {
        mean_speed
            * match c {
                Component::U => self.intensity_u,
                Component::W => self.intensity_w,
            }
    }

    /// The scale the spectrum is reduced with: the length scale or the height, m.
    pub fn scale(&self, c: Component) -> f64 {
        match (self.spectrum, c) {
            (Spectrum::SimiuScanlan, _) => self.height_m,
            (_, Component::U) => self.length_scale_u_m,
            (_, Component::W) => self.length_scale_w_m,
        }
    }

    /// `S(f)` of a component in the mean wind `mean_speed`, (m/s)²/Hz.
    pub fn psd(&self, c: Component, f: f64, mean_speed: f64) -> f64 {
        self.spectrum
            .psd(c, f, self.sigma(c, mean_speed), mean_speed, self.scale(c))
    }

    fn coherence(&self, c: Component) -> f64 {
        match c {
            Component::U => self.coherence_u,
            Component::W => self.coherence_w,
        }
    }
}

/// The wind along the deck: the mean speed and the turbulence `u`, `w` at the points
/// `x_m` every `dt_s`, periodic in time (generated) or held at the ends (a record).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindField {
    /// Mean wind speed U, m/s (towards +y).
    pub mean_speed_m_s: f64,
    /// Deck points along the track, m, strictly increasing.
    pub x_m: Vec<f64>,
    /// Time of the first sample, s.
    pub t0_s: f64,
    /// Time step, s.
    pub dt_s: f64,
    /// Along-wind turbulence u at point j and time n: `u[j][n]`, m/s.
    pub u: Vec<Vec<f64>>,
    /// Vertical turbulence w (+ up), `w[j][n]`, m/s.
    pub w: Vec<Vec<f64>>,
    /// The samples repeat with period `n_times · dt_s` (generated fields).
    pub periodic: bool,
}

impl WindField {
    /// A steady wind: `U` everywhere, no turbulence.
    pub fn steady(mean_speed_m_s: f64) -> WindField {
        WindField {
            mean_speed_m_s,
            x_m: vec![0.0],
            t0_s: 0.0,
            dt_s: 1.0,
            u: vec![vec![0.0]],
            w: vec![vec![0.0]],
            periodic: true,
        }
    }

    /// Generate the turbulence at the points `x_m` for at least `duration_s` (see the crate
    /// docs): `N` = the power of two with `N Δt ≥ duration_s`.
    pub fn generate(
        turbulence: &Turbulence,
        mean_speed_m_s: f64,
        x_m: &[f64],
        duration_s: f64,
    ) -> Result<WindField, WindError> {
        Self::generate_pair(
            turbulence,
            mean_speed_m_s,
            x_m,
            duration_s,
            None::<fn(f64) -> f64>,
        )
        .map(|(raw, _)| raw)
    }

    /// As [`Self::generate`], and with `gain` also the same field with every harmonic's
    /// amplitude multiplied by `gain(f)` (a zero-phase filter, e.g. an aerodynamic
    /// admittance `|χ(f)|`), from the same phases.
    pub fn generate_pair(
        turbulence: &Turbulence,
        mean_speed_m_s: f64,
        x_m: &[f64],
        duration_s: f64,
        gain: Option<impl Fn(f64) -> f64>,
    ) -> Result<(WindField, Option<WindField>), WindError> {
        let n = Self::check(turbulence, mean_speed_m_s, x_m, duration_s)?;
        let dt = turbulence.dt_s;
        let df = 1.0 / (n as f64 * dt);
        let bins = n / 2 - 1;
        let ifft = FftPlanner::<f64>::new().plan_fft_inverse(n);
        let mut out = [Vec::new(), Vec::new()];
        let mut filtered = [Vec::new(), Vec::new()];
        let gains: Option<Vec<f64>> = gain
            .as_ref()
            .map(|g| (1..=bins).map(|k| g(k as f64 * df)).collect());
        for (ci, c) in Component::ALL.into_iter().enumerate() {
            let amp: Vec<f64> = (1..=bins)
                .map(|k| (2.0 * turbulence.psd(c, k as f64 * df, mean_speed_m_s) * df).sqrt())
                .collect();
            let mut rng = ChaCha8Rng::seed_from_u64(turbulence.seed);
            rng.set_stream(ci as u64);
            let mut phase: Vec<f64> = (0..bins).map(|_| TAU * rng.random::<f64>()).collect();
            let decay = turbulence.coherence(c) / mean_speed_m_s;
            let mut series = Vec::with_capacity(x_m.len());
            let mut buf = vec![Complex::new(0.0, 0.0); n];
            for j in 0..x_m.len() {
                if j > 0 {
                    let dx = x_m[j] - x_m[j - 1];
                    for (k, p) in phase.iter_mut().enumerate() {
                        let rho = (-decay * (k + 1) as f64 * df * dx).exp();
                        let keep = rng.random::<f64>() < rho;
                        let fresh = TAU * rng.random::<f64>();
                        if !keep {
                            *p = fresh;
                        }
                    }
                }
                buf.iter_mut().for_each(|b| *b = Complex::new(0.0, 0.0));
                for k in 0..bins {
                    buf[k + 1] = Complex::from_polar(amp[k], phase[k]);
                }
                ifft.process(&mut buf);
                series.push(buf.iter().map(|z| z.re).collect::<Vec<f64>>());
                if let Some(g) = &gains {
                    buf.iter_mut().for_each(|b| *b = Complex::new(0.0, 0.0));
                    for k in 0..bins {
                        buf[k + 1] = Complex::from_polar(amp[k] * g[k], phase[k]);
                    }
                    ifft.process(&mut buf);
                    filtered[ci].push(buf.iter().map(|z| z.re).collect::<Vec<f64>>());
                }
            }
            out[ci] = series;
        }
        let field = |[u, w]: [Vec<Vec<f64>>; 2]| WindField {
            mean_speed_m_s,
            x_m: x_m.to_vec(),
            t0_s: 0.0,
            dt_s: dt,
            u,
            w,
            periodic: true,
        };
        let with_gain = gains.is_some().then(|| field(filtered));
        Ok((field(out), with_gain))
    }

    /// Everything [`Self::generate`] checks, without generating: the number of samples in
    /// time it would generate.
    pub fn check(
        turbulence: &Turbulence,
        mean_speed_m_s: f64,
        x_m: &[f64],
        duration_s: f64,
    ) -> Result<usize, WindError> {
        turbulence.validate()?;
        if !(mean_speed_m_s.is_finite() && mean_speed_m_s > 0.0) {
            return Err(WindError::invalid(
                "mean_speed_m_s",
                mean_speed_m_s,
                "must be positive for a turbulent wind",
            ));
        }
        if !(duration_s.is_finite() && duration_s > 0.0) {
            return Err(WindError::invalid(
                "duration_s",
                duration_s,
                "must be positive",
            ));
        }
        check_points(x_m)?;
        let dt = turbulence.dt_s;
        let n = ((duration_s / dt).ceil() as usize)
            .max(16)
            .next_power_of_two();
        if n.saturating_mul(x_m.len()).saturating_mul(2) > MAX_SAMPLES {
            return Err(WindError::Invalid {
                field: "dt_s",
                value: format!("{dt}"),
                reason: format!(
                    "{} points × {n} times exceed {MAX_SAMPLES} samples; raise dt_s or use fewer points",
                    x_m.len()
                ),
            });
        }
        Ok(n)
    }

    /// Number of samples in time.
    pub fn n_times(&self) -> usize {
        self.u.first().map_or(0, Vec::len)
    }

    /// The turbulence (u, w) at position `x` and time `t`, m/s: linear between the points
    /// (the end points' values beyond them) and between the samples (periodic, or the end
    /// samples held beyond a record).
    pub fn at(&self, x: f64, t: f64) -> [f64; 2] {
        if self.n_times() == 0 {
            return [0.0; 2];
        }
        let (i0, i1, a) = self.time_index(t);
        let p = self.x_m.partition_point(|&xi| xi <= x);
        let (j0, j1, b) = if p == 0 {
            (0, 0, 0.0)
        } else if p >= self.x_m.len() {
            let j = self.x_m.len() - 1;
            (j, j, 0.0)
        } else {
            let (xa, xb) = (self.x_m[p - 1], self.x_m[p]);
            (p - 1, p, (x - xa) / (xb - xa))
        };
        let f = |v: &[Vec<f64>]| {
            let at = |j: usize| v[j][i0] + a * (v[j][i1] - v[j][i0]);
            at(j0) + b * (at(j1) - at(j0))
        };
        [f(&self.u), f(&self.w)]
    }

    /// The same field at the points `x` (linear between this field's points, their end
    /// values beyond them), sample by sample.
    pub fn resample(&self, x: &[f64]) -> WindField {
        let n = self.n_times();
        let mut u = vec![vec![0.0; n]; x.len()];
        let mut w = vec![vec![0.0; n]; x.len()];
        for (j, &xj) in x.iter().enumerate() {
            let p = self.x_m.partition_point(|&xi| xi <= xj);
            let (j0, j1, b) = if p == 0 {
                (0, 0, 0.0)
            } else if p >= self.x_m.len() {
                (self.x_m.len() - 1, self.x_m.len() - 1, 0.0)
            } else {
                let (xa, xb) = (self.x_m[p - 1], self.x_m[p]);
                (p - 1, p, (xj - xa) / (xb - xa))
            };
            for i in 0..n {
                u[j][i] = self.u[j0][i] + b * (self.u[j1][i] - self.u[j0][i]);
                w[j][i] = self.w[j0][i] + b * (self.w[j1][i] - self.w[j0][i]);
            }
        }
        WindField {
            x_m: x.to_vec(),
            u,
            w,
            ..self.clone()
        }
    }

    /// The turbulence (u, w) at deck point `j` at the time of `index` ([`Self::time_index`]).
    pub fn at_point(&self, j: usize, (i0, i1, a): (usize, usize, f64)) -> [f64; 2] {
        let f = |v: &[Vec<f64>]| v[j][i0] + a * (v[j][i1] - v[j][i0]);
        [f(&self.u), f(&self.w)]
    }

    /// The samples around time `t` and the weight of the later one, `(i0, i1, a)`: a value is
    /// `v[i0] + a (v[i1] − v[i0])` (periodic, or the end samples held beyond a record). The
    /// field must hold at least one sample.
    pub fn time_index(&self, t: f64) -> (usize, usize, f64) {
        let nt = self.n_times();
        let s = (t - self.t0_s) / self.dt_s;
        if self.periodic {
            let period = nt as f64;
            let s = s.rem_euclid(period);
            let i0 = (s.floor() as usize).min(nt - 1);
            (i0, (i0 + 1) % nt, s - i0 as f64)
        } else if s <= 0.0 {
            (0, 0, 0.0)
        } else if s >= (nt - 1) as f64 {
            (nt - 1, nt - 1, 0.0)
        } else {
            let i0 = s.floor() as usize;
            (i0, i0 + 1, s - i0 as f64)
        }
    }
}

/// Deck points: finite, strictly increasing, at least one, at most 100 000.
pub(crate) fn check_points(x: &[f64]) -> Result<(), WindError> {
    if x.is_empty() || x.len() > 100_000 {
        return Err(WindError::Invalid {
            field: "points",
            value: format!("{}", x.len()),
            reason: "give between 1 and 100000 deck points".into(),
        });
    }
    for (i, w) in x.windows(2).enumerate() {
        if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
            return Err(WindError::Invalid {
                field: "points",
                value: format!("x[{i}] = {}, x[{}] = {}", w[0], i + 1, w[1]),
                reason: "deck points must be finite and strictly increasing".into(),
            });
        }
    }
    if !x[0].is_finite() {
        return Err(WindError::invalid("points", x[0], "must be finite"));
    }
    Ok(())
}
