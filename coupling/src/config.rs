//! Coupling configuration as written in a scenario, and the scheme factory.
//!
//! ```toml
//! scheme = "implicit"          # "implicit" | "gauss-seidel" | "jacobi"
//! acceleration = "iqn-ils"     # "aitken" | "iqn-ils" | "newton" | "constant"
//! relaxation = 0.5
//! rtol = 1e-10
//! atol = 1e-12
//! max_iterations = 50
//! ```
//!
//! Every key is optional; unknown keys and out-of-range values are errors that name the key and
//! the value.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer};

use super::acceleration::{Acceleration, Aitken, ConstantRelaxation, IqnIls, Newton};
use super::advance::OnNonConvergence;
use super::convergence::WeightedRms;
use super::gauss_seidel::GaussSeidel;
use super::implicit::{Implicit, Predictor};
use super::jacobi::Jacobi;
use super::scheme::CouplingScheme;
use super::system::CouplingError;

/// Coupling algorithm (`scheme`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SchemeKind {
    /// Iterated Gauss–Seidel with rollback and acceleration: [`Implicit`].
    #[default]
    Implicit,
    /// One Gauss–Seidel sweep per step: [`GaussSeidel`].
    GaussSeidel,
    /// Gauss–Jacobi, all inputs from the start of the step: [`Jacobi`].
    Jacobi,
}

/// Acceleration of the implicit iteration (`acceleration`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AccelerationKind {
    /// [`Aitken`] dynamic relaxation.
    #[default]
    Aitken,
    /// [`IqnIls`] quasi-Newton.
    IqnIls,
    /// [`Newton`] with finite-difference interface Jacobians.
    Newton,
    /// [`ConstantRelaxation`].
    Constant,
}

/// Policy for steps that do not converge (`on_non_convergence`); see [`OnNonConvergence`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NonConvergenceAction {
    #[default]
    Stop,
    Retry,
    Accept,
}

/// Implements `as_str`, `Display`, `FromStr` and `Deserialize` (from the keyword, with an error
/// naming the configuration key) for a keyword enum.
macro_rules! keywords {
    ($ty:ident, $key:literal, { $($variant:ident => $text:literal),+ $(,)? }) => {
        impl $ty {
            /// The keyword as written in the configuration.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($ty::$variant => $text),+
                }
            }
        }

        impl fmt::Display for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }

        impl FromStr for $ty {
            type Err = CouplingError;

            fn from_str(s: &str) -> Result<Self, CouplingError> {
                match s {
                    $($text => Ok($ty::$variant),)+
                    other => {
                        let expected: Vec<String> =
                            [$($text),+].iter().map(|t| format!("\"{t}\"")).collect();
                        Err(CouplingError::Keyword {
                            key: $key,
                            value: other.to_owned(),
                            expected: expected.join(", "),
                        })
                    }
                }
            }
        }

        impl<'de> Deserialize<'de> for $ty {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = String::deserialize(d)?;
                s.parse().map_err(serde::de::Error::custom)
            }
        }
    };
}

keywords!(SchemeKind, "scheme", {
    Implicit => "implicit",
    GaussSeidel => "gauss-seidel",
    Jacobi => "jacobi",
});
keywords!(AccelerationKind, "acceleration", {
    Aitken => "aitken",
    IqnIls => "iqn-ils",
    Newton => "newton",
    Constant => "constant",
});
keywords!(Predictor, "predictor", {
    Linear => "linear",
    Quadratic => "quadratic",
    Constant => "constant",
});
keywords!(NonConvergenceAction, "on_non_convergence", {
    Stop => "stop",
    Retry => "retry",
    Accept => "accept",
});

/// Coupling parameters. Every field documents its default and unit.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(try_from = "RawCouplingConfig")]
pub struct CouplingConfig {
    /// Coupling algorithm. Default `"implicit"`.
    pub scheme: SchemeKind,
    /// Acceleration of the implicit iteration; unused by explicit schemes. Default
    /// `"iqn-ils"`.
    pub acceleration: AccelerationKind,
    /// Relaxation factor ω ∈ (0, 1] (dimensionless): the constant factor, Aitken's initial
    /// factor and the factor of IQN-ILS's first iteration. Default 0.5.
    pub relaxation: f64,
    /// Relative tolerance of the interface iteration (dimensionless, ≥ 0), relative to the
    /// largest value of the same unit from the same participant. Default 1e-10.
    pub rtol: f64,
    /// Absolute tolerance, in the units of the interface values (> 0). Default 1e-12.
    pub atol: f64,
    /// Maximum sweeps per step (≥ 1). Default 50.
    pub max_iterations: usize,
    /// First guess of each step: `"quadratic"` or `"linear"` extrapolation of the accepted
    /// values, or `"constant"`. Default `"quadratic"`.
    pub predictor: Predictor,
    /// IQN-ILS: previous converged steps whose columns are reused. Default 8.
    pub reuse_steps: usize,
    /// What to do when a step does not converge: `"stop"`, `"retry"` (halve the step) or
    /// `"accept"` (keep it and report it). Default `"stop"`.
    pub on_non_convergence: NonConvergenceAction,
    /// Smallest step of `"retry"` (s, > 0). Default: the macro step / 16.
    pub min_step: Option<f64>,
}

impl Default for CouplingConfig {
    fn default() -> Self {
        Self {
            scheme: SchemeKind::Implicit,
            acceleration: AccelerationKind::IqnIls,
            relaxation: 0.5,
            rtol: 1e-10,
            atol: 1e-12,
            max_iterations: 50,
            predictor: Predictor::Quadratic,
            reuse_steps: 8,
            on_non_convergence: NonConvergenceAction::Stop,
            min_step: None,
        }
    }
}

impl CouplingConfig {
    /// Every option as `(key, value)` text, the keys of a scenario's `[coupling]` table (what
    /// the SSP annotation of this project carries).
    pub fn attributes(&self) -> Vec<(&'static str, String)> {
        let mut a = vec![
            ("scheme", self.scheme.as_str().to_owned()),
            ("acceleration", self.acceleration.as_str().to_owned()),
            ("relaxation", self.relaxation.to_string()),
            ("rtol", format!("{:e}", self.rtol)),
            ("atol", format!("{:e}", self.atol)),
            ("max_iterations", self.max_iterations.to_string()),
            ("predictor", self.predictor.as_str().to_owned()),
            ("reuse_steps", self.reuse_steps.to_string()),
            (
                "on_non_convergence",
                self.on_non_convergence.as_str().to_owned(),
            ),
        ];
        if let Some(m) = self.min_step {
            a.push(("min_step", format!("{m:e}")));
        }
        a
    }

    /// Checks the ranges of all fields; the error names the key and the value.
    pub fn validate(&self) -> Result<(), CouplingError> {
        let bad = |key: &str, value: &dyn fmt::Display, rule: &str| {
            Err(CouplingError::Config {
                key: key.to_owned(),
                value: value.to_string(),
                rule: rule.to_owned(),
            })
        };
        if !(self.relaxation > 0.0 && self.relaxation <= 1.0) {
            return bad("relaxation", &self.relaxation, "must be in (0, 1]");
        }
        if !(self.rtol >= 0.0 && self.rtol.is_finite()) {
            return bad("rtol", &self.rtol, "must be finite and ≥ 0");
        }
        if !(self.atol > 0.0 && self.atol.is_finite()) {
            return bad("atol", &self.atol, "must be finite and > 0");
        }
        if self.max_iterations == 0 {
            return bad("max_iterations", &self.max_iterations, "must be ≥ 1");
        }
        if let Some(m) = self.min_step {
            if !(m > 0.0 && m.is_finite()) {
                return bad("min_step", &m, "must be finite and > 0");
            }
            if self.on_non_convergence != NonConvergenceAction::Retry {
                return bad(
                    "min_step",
                    &m,
                    "only applies with on_non_convergence = \"retry\"",
                );
            }
        }
        Ok(())
    }

    /// The convergence measure.
    pub fn measure(&self) -> WeightedRms {
        WeightedRms::new(self.rtol, self.atol)
    }

    /// The non-convergence policy for macro steps of size `h` (s).
    pub fn policy(&self, h: f64) -> OnNonConvergence {
        match self.on_non_convergence {
            NonConvergenceAction::Stop => OnNonConvergence::Stop,
            NonConvergenceAction::Accept => OnNonConvergence::Accept,
            NonConvergenceAction::Retry => OnNonConvergence::Retry {
                min_step: self.min_step.unwrap_or(h / 16.0),
            },
        }
    }
}

/// The configuration as read, before validation.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
struct RawCouplingConfig {
    scheme: SchemeKind,
    acceleration: AccelerationKind,
    relaxation: f64,
    rtol: f64,
    atol: f64,
    max_iterations: usize,
    predictor: Predictor,
    reuse_steps: usize,
    on_non_convergence: NonConvergenceAction,
    min_step: Option<f64>,
}

impl Default for RawCouplingConfig {
    fn default() -> Self {
        let c = CouplingConfig::default();
        Self {
            scheme: c.scheme,
            acceleration: c.acceleration,
            relaxation: c.relaxation,
            rtol: c.rtol,
            atol: c.atol,
            max_iterations: c.max_iterations,
            predictor: c.predictor,
            reuse_steps: c.reuse_steps,
            on_non_convergence: c.on_non_convergence,
            min_step: c.min_step,
        }
    }
}

impl TryFrom<RawCouplingConfig> for CouplingConfig {
    type Error = CouplingError;

    fn try_from(r: RawCouplingConfig) -> Result<Self, CouplingError> {
        let c = CouplingConfig {
            scheme: r.scheme,
            acceleration: r.acceleration,
            relaxation: r.relaxation,
            rtol: r.rtol,
            atol: r.atol,
            max_iterations: r.max_iterations,
            predictor: r.predictor,
            reuse_steps: r.reuse_steps,
            on_non_convergence: r.on_non_convergence,
            min_step: r.min_step,
        };
        c.validate()?;
        Ok(c)
    }
}

/// The acceleration selected by `config`.
pub fn build_acceleration(config: &CouplingConfig) -> Box<dyn Acceleration> {
    match config.acceleration {
        AccelerationKind::Constant => Box::new(ConstantRelaxation::new(config.relaxation)),
        AccelerationKind::Aitken => Box::new(Aitken::new(config.relaxation)),
        AccelerationKind::IqnIls => Box::new(IqnIls::new(config.relaxation, config.reuse_steps)),
        AccelerationKind::Newton => Box::new(Newton::new()),
    }
}

/// The coupling scheme selected by `config`, or the error of [`CouplingConfig::validate`]
/// (deserialized configurations are validated already).
pub fn build_scheme(config: &CouplingConfig) -> Result<Box<dyn CouplingScheme>, CouplingError> {
    config.validate()?;
    Ok(match config.scheme {
        SchemeKind::Jacobi => Box::new(Jacobi::new(config.measure())),
        SchemeKind::GaussSeidel => Box::new(GaussSeidel::new(config.measure())),
        SchemeKind::Implicit => Box::new(
            Implicit::new(
                build_acceleration(config),
                config.measure(),
                config.max_iterations,
            )
            .with_predictor(config.predictor),
        ),
    })
}
