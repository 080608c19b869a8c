//! Scenario-file description of an irregularity.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::generate::{
    DEFAULT_GRID_SPACING_M, DEFAULT_LAMBDA_MAX_M, DEFAULT_LAMBDA_MIN_M, DEFAULT_SEED,
};
use crate::spectrum::DEFAULT_CONTACT_DISTANCE_M;
use crate::{GeneratedSpec, Irregularity, Record, Spectrum, TrackError};

/// A record file to read.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecordSpec {
    /// Path of the CSV record (format: [`crate::record`]); a relative path is taken relative to
    /// the `base_dir` given to [`IrregularitySpec::build`]. Required.
    pub file: PathBuf,
}

/// How a scenario describes the irregularity. In TOML:
///
/// ```toml
/// irregularity = "none"
/// # or a generated sample (every key but `spectrum` optional, defaults shown):
/// irregularity = { spectrum = "german-low", seed = 1, lambda_min_m = 1.0, lambda_max_m = 80.0,
///                  grid_spacing_m = 0.1, min_terms = 0, contact_distance_m = 1.5 }
/// # or a record file:
/// irregularity = { file = "track.csv" }
/// ```
///
/// Deserialisation checks the names and ranges (errors name the field and the value).
#[derive(Clone, Debug, PartialEq, Default)]
pub enum IrregularitySpec {
    /// Ideal track.
    #[default]
    None,
    /// A sample generated from a spectrum.
    Generated(GeneratedSpec),
    /// A record file.
    Record(RecordSpec),
}

impl IrregularitySpec {
    /// Checks the parameters (see [`GeneratedSpec::validate`]; a record file name must not be
    /// empty).
    pub fn validate(&self) -> Result<(), TrackError> {
        match self {
            IrregularitySpec::None => Ok(()),
            IrregularitySpec::Generated(g) => g.validate(),
            IrregularitySpec::Record(r) if r.file.as_os_str().is_empty() => {
                Err(TrackError::Invalid {
                    field: "file",
                    value: "\"\"".into(),
                    reason: "must name a record file".into(),
                })
            }
            IrregularitySpec::Record(_) => Ok(()),
        }
    }

    /// Builds the irregularity for the line `[x_start_m, x_end_m]` (m; used by generated
    /// samples, which are then defined everywhere and do not repeat within the line). A record
    /// covers what its file covers. Relative record paths are resolved against `base_dir`.
    pub fn build(
        &self,
        x_start_m: f64,
        x_end_m: f64,
        base_dir: &Path,
    ) -> Result<Irregularity, TrackError> {
        self.validate()?;
        Ok(match self {
            IrregularitySpec::None => Irregularity::None,
            IrregularitySpec::Generated(g) => {
                Irregularity::Generated(Box::new(g.generate(x_start_m, x_end_m)?))
            }
            IrregularitySpec::Record(r) => {
                Irregularity::Record(Record::read(base_dir.join(&r.file))?)
            }
        })
    }
}

impl Serialize for IrregularitySpec {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            IrregularitySpec::None => s.serialize_str("none"),
            IrregularitySpec::Generated(g) => g.serialize(s),
            IrregularitySpec::Record(r) => r.serialize(s),
        }
    }
}

/// Union of the keys of both table forms.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTable {
    spectrum: Option<Spectrum>,
    seed: Option<u64>,
    lambda_min_m: Option<f64>,
    lambda_max_m: Option<f64>,
    grid_spacing_m: Option<f64>,
    min_terms: Option<usize>,
    contact_distance_m: Option<f64>,
    file: Option<PathBuf>,
}

const EXPECTING: &str =
    "\"none\", a table with `spectrum = ...` (generated sample) or a table with `file = ...`";

impl RawTable {
    fn into_spec(self) -> Result<IrregularitySpec, String> {
        let generation_keys = [
            ("spectrum", self.spectrum.is_some()),
            ("seed", self.seed.is_some()),
            ("lambda_min_m", self.lambda_min_m.is_some()),
            ("lambda_max_m", self.lambda_max_m.is_some()),
            ("grid_spacing_m", self.grid_spacing_m.is_some()),
            ("min_terms", self.min_terms.is_some()),
            ("contact_distance_m", self.contact_distance_m.is_some()),
        ];
        let spec = match (self.spectrum, self.file) {
            (None, Some(file)) => {
                if let Some((key, _)) = generation_keys.iter().find(|(_, set)| *set) {
                    return Err(format!(
                        "irregularity: `{key}` cannot be combined with `file` (a record file is \
                         used as it is)"
                    ));
                }
                IrregularitySpec::Record(RecordSpec { file })
            }
            (Some(spectrum), None) => IrregularitySpec::Generated(GeneratedSpec {
                spectrum,
                seed: self.seed.unwrap_or(DEFAULT_SEED),
                lambda_min_m: self.lambda_min_m.unwrap_or(DEFAULT_LAMBDA_MIN_M),
                lambda_max_m: self.lambda_max_m.unwrap_or(DEFAULT_LAMBDA_MAX_M),
                grid_spacing_m: self.grid_spacing_m.unwrap_or(DEFAULT_GRID_SPACING_M),
                min_terms: self.min_terms.unwrap_or(0),
                contact_distance_m: self
                    .contact_distance_m
                    .unwrap_or(DEFAULT_CONTACT_DISTANCE_M),
            }),
            (Some(_), Some(_)) => {
                return Err("irregularity: give either `spectrum` or `file`, not both".into())
            }
            (None, None) => return Err(format!("irregularity: expected {EXPECTING}")),
        };
        spec.validate().map_err(|e| format!("irregularity: {e}"))?;
        Ok(spec)
    }
}

impl<'de> Deserialize<'de> for IrregularitySpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct SpecVisitor;
        impl<'de> Visitor<'de> for SpecVisitor {
            type Value = IrregularitySpec;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(EXPECTING)
            }

            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                if v.trim().eq_ignore_ascii_case("none") {
                    Ok(IrregularitySpec::None)
                } else {
                    Err(E::custom(format!(
                        "irregularity = {v:?}: expected {EXPECTING}"
                    )))
                }
            }

            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                RawTable::deserialize(de::value::MapAccessDeserializer::new(map))?
                    .into_spec()
                    .map_err(de::Error::custom)
            }
        }
        d.deserialize_any(SpecVisitor)
    }
}
