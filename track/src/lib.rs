//! Track irregularities and wheel hunting for train–bridge interaction (Xia, Xu & Chan 2000,
//! eq. (7)–(8)).
//!
//! # Conventions
//!
//! SI units; `x` along the track in the direction of travel, `y` lateral (+ right looking in
//! +x), `z` vertical (+ down), roll about +x (right side down +). An irregularity is the
//! rail's deviation from the ideal geometry: lateral (alignment) `Y_s(x)` in m, vertical
//! (profile) `Z_s(x)` in m, cross-level as an angle `θ_s(x)` in rad. A cross-level height
//! difference `Δh` becomes the angle `Δh / (2b)`, `2b` the distance between the wheel–rail
//! contact points (default 1.5 m).
//!
//! The caller-facing type is [`Irregularity`]: [`Irregularity::at`] returns value, first and
//! second derivative along `x` of the three components ([`RailIrregularity`]). A wheel at
//! speed `v` and acceleration `a` sees `ṙ = v r′`, `r̈ = v² r″ + a r′`.
//!
//! # Spectra
//!
//! [`Spectrum::psd`] is the one-sided PSD `G(Ω)` in the spatial circular frequency `Ω`
//! (rad/m, wavelength `λ = 2π/Ω`), normalised so that `σ² = ∫₀^∞ G(Ω) dΩ`; units m²/(rad/m),
//! or rad²/(rad/m) for cross-level. Formulas and unit conversions: [`spectrum`].
//! A spectrum `S(f)` in cycles/m converts as `G(Ω) = S(Ω/2π)/(2π)` (same variance).
//!
//! # Sample generation (spectral representation)
//!
//! ```text
//! r(x) = Σ_{k=0}^{N-1} a_k cos(Ω_k x + φ_k),   a_k = √(2 G(Ω_k) ΔΩ),
//! Ω_k = Ω_lo + (k + ½) ΔΩ,   Ω_lo = 2π/λ_max,   Ω_hi = Ω_lo + N ΔΩ ≈ 2π/λ_min,
//! ```
//!
//! with phases `φ_k` independent and uniform in `[0, 2π)`. Each term has mean square
//! `a_k²/2 = G(Ω_k) ΔΩ`, so the variance is `σ² = Σ G(Ω_k) ΔΩ`, the mid-point rule for
//! `∫_{Ω_lo}^{Ω_hi} G dΩ`. The exact derivatives are `r′ = −Σ a_k Ω_k sin(…)`,
//! `r″ = −Σ a_k Ω_k² cos(…)`.
//!
//! `ΔΩ` is chosen so that every `Ω_k` is a whole multiple of `ΔΩ`; the sample is then exactly
//! periodic with period `P = 2π/ΔΩ`, and `N` is chosen so that `P` exceeds the line length
//! (or so that `N` reaches a caller-given minimum). Over one period the cross terms average to
//! zero and the sample variance equals `Σ a_k²/2` exactly. Details: [`generate`].
//!
//! # Evaluation
//!
//! The exact `r` and `r′` are computed on a uniform grid covering one period (default
//! spacing 0.1 m) with one inverse FFT, and evaluated at any `x` by cubic Hermite
//! interpolation ([`Profile`]): value and slope are matched at every node, so the interpolant
//! is C¹ and reproduces `r` with error at most `h⁴/384 · max|r⁗|`, `r′` within
//! `√3/216 · h³ max|r⁗|` and `r″` within `h²/12 · max|r⁗|` (here `max|r⁗| ≤ Σ a_k Ω_k⁴`).
//! For the shortest wavelength `λ_min`, `r″` is thus accurate to `(2π h/λ_min)²/12`
//! relative, 3.3 % at `h = λ_min/10`; choose a finer grid if the highest frequencies matter.
//! Beyond one period the generated profile repeats.
//!
//! Records ([`record`]) use the same interpolation; without slope columns the slopes come
//! from parabolic finite differences, and beyond their ends the end values are held (value
//! of the end node, zero derivatives) unless the record is declared periodic. A generated
//! sample written with [`Irregularity::to_record_csv`] carries its slopes and the periodic
//! declaration, so read back it evaluates bit for bit like the original at every `x`.
//!
//! # Wheel hunting
//!
//! [`hunting`]: `Y_h(s) = A_h sin(2π s/L_h + φ_i)` in the distance travelled `s`, with seeded
//! per-wheelset phases.

pub mod error;
pub mod generate;
pub mod hunting;
pub mod profile;
pub mod record;
mod record_format;
pub mod spec;
pub mod spectrum;

use std::fs;
use std::path::Path;

pub use error::{RecordProblem, TrackError};
pub use generate::{GeneratedSample, GeneratedSpec, SpectralTerm};
pub use hunting::{HuntingParams, WheelHunting};
pub use profile::Profile;
pub use record::Record;
pub use spec::{IrregularitySpec, RecordSpec};
pub use spectrum::{Component, Spectrum, DEFAULT_CONTACT_DISTANCE_M};

/// The irregularity seen at one position: for each component `[r, dr/dx, d²r/dx²]`.
/// `Default` is all zero (ideal track).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RailIrregularity {
    /// Alignment `Y_s` (m, + right), `dY_s/dx` (m/m), `d²Y_s/dx²` (1/m).
    pub lateral: [f64; 3],
    /// Profile `Z_s` (m, + down), `dZ_s/dx` (m/m), `d²Z_s/dx²` (1/m).
    pub vertical: [f64; 3],
    /// Cross-level angle `θ_s` (rad, right side down +), `dθ_s/dx` (rad/m),
    /// `d²θ_s/dx²` (rad/m²).
    pub cross_level: [f64; 3],
}

impl RailIrregularity {
    /// The triple of one component.
    pub fn component(&self, component: Component) -> [f64; 3] {
        match component {
            Component::Lateral => self.lateral,
            Component::Vertical => self.vertical,
            Component::CrossLevel => self.cross_level,
        }
    }
}

/// The track irregularity used by a simulation.
///
/// Cheap to evaluate ([`Irregularity::at`]: an interval lookup and three cubic polynomials),
/// `Clone + Send + Sync`. To carry it elsewhere, either keep its [`IrregularitySpec`] and the
/// line and rebuild it, or write it as a record ([`Irregularity::to_record_csv`]) and read
/// that back ([`Record::parse`], [`Record::read`]), which reproduces it bit for bit.
#[derive(Clone, Debug, Default)]
pub enum Irregularity {
    /// Ideal track: everything zero.
    #[default]
    None,
    /// A generated sample.
    Generated(Box<GeneratedSample>),
    /// A record (measured, or an exported sample).
    Record(Record),
}

impl From<GeneratedSample> for Irregularity {
    fn from(g: GeneratedSample) -> Self {
        Irregularity::Generated(Box::new(g))
    }
}

impl From<Record> for Irregularity {
    fn from(r: Record) -> Self {
        Irregularity::Record(r)
    }
}

impl Irregularity {
    /// Value, first and second derivative along `x` of all components at `x` (m).
    #[inline]
    pub fn at(&self, x: f64) -> RailIrregularity {
        match self {
            Irregularity::None => RailIrregularity::default(),
            Irregularity::Generated(g) => g.at(x),
            Irregularity::Record(r) => r.at(x),
        }
    }

    /// A hint that [`Self::at`] at `x` follows soon ([`Profile::prefetch`]).
    #[inline]
    pub fn prefetch(&self, x: f64) {
        if let Some(p) = self.profile() {
            p.prefetch(x);
        }
    }

    /// The interpolation table, if any.
    pub fn profile(&self) -> Option<&Profile> {
        match self {
            Irregularity::None => None,
            Irregularity::Generated(g) => Some(g.profile()),
            Irregularity::Record(r) => Some(r.profile()),
        }
    }

    /// The table in the record format (with slope columns; `None` for the ideal track, which
    /// is described by `irregularity = "none"`).
    pub fn to_record_csv(&self) -> Option<String> {
        let comments = self.record_comments()?;
        let mut out = Vec::new();
        self.profile()?
            .write_csv(&mut out, &comments)
            .expect("writing to memory cannot fail");
        Some(String::from_utf8(out).expect("the record format is ASCII"))
    }

    /// [`Profile::identity_bytes`] of the table (`None` for the ideal track): what identifies
    /// [`Irregularity::to_record_csv`]'s record apart from its comments, without writing it.
    pub fn record_identity(&self) -> Option<Vec<u8>> {
        self.profile().map(Profile::identity_bytes)
    }

    /// The leading comment lines of the record (`None` for the ideal track).
    fn record_comments(&self) -> Option<Vec<String>> {
        Some(match self {
            Irregularity::None => return None,
            Irregularity::Generated(g) => {
                let s = g.spec();
                vec![
                    "track irregularity sample (tbi-track)".to_owned(),
                    format!(
                        "spectrum = {}, seed = {}, lambda_min_m = {}, lambda_max_m = {}, \
                         contact_distance_m = {}",
                        s.spectrum, s.seed, s.lambda_min_m, s.lambda_max_m, s.contact_distance_m
                    ),
                    format!(
                        "terms = {}, period_m = {}, grid_spacing_m = {}",
                        g.n_terms(),
                        g.period_m(),
                        g.grid_spacing_m()
                    ),
                ]
            }
            Irregularity::Record(r) => {
                vec![format!("track irregularity record from {}", r.source())]
            }
        })
    }

    /// Writes [`Irregularity::to_record_csv`] to `path` (nothing is written for
    /// [`Irregularity::None`], which returns an error naming the field).
    pub fn write_record_file(&self, path: impl AsRef<Path>) -> Result<(), TrackError> {
        let path = path.as_ref();
        let text = self.to_record_csv().ok_or_else(|| TrackError::Invalid {
            field: "irregularity",
            value: "none".into(),
            reason: "the ideal track has no record".into(),
        })?;
        fs::write(path, text).map_err(|source| TrackError::Io {
            file: path.display().to_string(),
            source,
        })
    }

    /// Reads a record file (see [`record`]).
    pub fn read_record(path: impl AsRef<Path>) -> Result<Irregularity, TrackError> {
        Record::read(path).map(Irregularity::Record)
    }
}
