//! Wind at a bridge deck for train–bridge interaction: the mean wind normal to the bridge and
//! its turbulence as a seeded, stationary, Gaussian field at points along the deck, or a
//! measured record.
//!
//! # Conventions
//!
//! SI units. The mean wind `U` (m/s) blows horizontally, normal to the bridge, towards **+y**
//! (the lateral axis of the tool: to the right looking along +x). Turbulence: `u` along the
//! mean wind (+y), `w` vertical, **positive upward** (so that an upward gust lifts; the
//! tool's `z` points down, and a force from `w` enters with that sign). The deck points are
//! positions `x` along the track. The wind at a moving vehicle is the field at its position
//! ([`WindField::at`]).
//!
//! # Spectra ([`spectrum`])
//!
//! One-sided auto-spectra `S(f)` in (m/s)²/Hz of the frequency `f` in Hz, normalised so that
//! `σ² = ∫₀^∞ S(f) df`, `σ_u = I_u U`, `σ_w = I_w U`:
//!
//! ```text
//! Kaimal (EN 1991-1-4 Annex B)   f S/σ² = 6.8 n / (1 + 10.2 n)^{5/3},              n = f L / U
//! von Kármán, u                  f S/σ² = 4 n / (1 + 70.8 n²)^{5/6},               n = f L / U
//! von Kármán, w                  f S/σ² = 4 n (1 + 755.2 n²) / (1 + 283.2 n²)^{11/6}
//! Simiu–Scanlan, u               f S/u*² = 200 n / (1 + 50 n)^{5/3},               n = f z / U
//! Simiu–Scanlan (Lumley–Panofsky), w   f S/u*² = 3.36 n / (1 + 10 n^{5/3})
//! ```
//!
//! with `L` the integral length scale of the component and `z` the height above ground.
//! The first three integrate to 1 (Kaimal exactly, von Kármán to 2e-4 with its rounded
//! published constants); the Simiu–Scanlan forms are scaled by their
//! integrals (6 and 3.36 · 10^{−3/5} π / (5/3 · sin(3π/5)) = 1.6732) so that they too give the
//! σ asked for.
//!
//! # The field ([`field`])
//!
//! At sorted deck points `x₀ < x₁ < … < x_{P−1}` and times `t_n = n Δt`, `n < N` (`N` a power
//! of two, `N Δt ≥` the duration), each component is
//!
//! ```text
//! u_j(t) = Σ_{k=1}^{K} a_k cos(2π f_k t + φ_{jk}),   a_k = √(2 S(f_k) Δf),   f_k = k Δf,  Δf = 1/(N Δt)
//! ```
//!
//! up to the Nyquist frequency, with the phases chosen along the deck as a Markov chain: `φ_{0k}`
//! uniform in [0, 2π); for `j ≥ 1`, `φ_{jk} = φ_{j−1,k}` with probability
//! `ρ_{jk} = exp(−C f_k (x_j − x_{j−1}) / U)`, else a fresh uniform phase. Then
//! `E[e^{i(φ_{jk} − φ_{lk})}] = Π ρ = exp(−C f_k |x_j − x_l| / U)`: the cross-spectrum of two
//! points is `S(f) exp(−C f Δx / U)`, Davenport's coherence, exactly in the ensemble, and every
//! point's variance over the period is `Σ a_k²/2 = Σ S(f_k) Δf` exactly (the mid-point rule of
//! the spectrum's integral over the band). Each point is a sum of `K` cosines of independent
//! uniform phases, Gaussian to the central limit. `u` and `w` are independent (their
//! co-spectrum is neglected, as usual in buffeting analysis). One inverse FFT per point and
//! component gives the whole run; beyond one period the field repeats.
//!
//! # Records ([`record`])
//!
//! A measured field as CSV, header `time_s,x_m,u_m_s,w_m_s`, one line per time and point;
//! every time must carry the same points.

pub mod error;
pub mod field;
pub mod record;
pub mod spectrum;

pub use error::WindError;
pub use field::{Turbulence, WindField};
pub use spectrum::{Component, Spectrum};
