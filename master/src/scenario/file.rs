//! The scenario file as written: private structs that mirror the TOML, so that serde's
//! errors keep their line.

use super::{Probe, SolverKind, Wind};
use serde::Deserialize;
use std::path::PathBuf;
use tbi_coupling::CouplingConfig;
use tbi_track::{HuntingParams, IrregularitySpec};

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileScenario {
    #[serde(default = "default_name")]
    pub(super) name: String,
    pub(super) run: FileRun,
    pub(super) bridge: FileBridge,
    /// `[train]`, or `[[train]]` once per train.
    pub(super) train: OneOrMany<FileTrain>,
    #[serde(default)]
    pub(super) track: FileTrack,
    #[serde(default, rename = "probe")]
    pub(super) probes: Vec<Probe>,
    #[serde(default)]
    pub(super) coupling: CouplingConfig,
    pub(super) wind: Option<Wind>,
}

pub(super) fn default_name() -> String {
    "scenario".into()
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileRun {
    /// The trains' speed, unless each gives its own.
    pub(super) speed_kmh: Option<f64>,
    #[serde(default = "default_dt")]
    pub(super) dt_s: f64,
    #[serde(default)]
    pub(super) solver: SolverKind,
    #[serde(default = "default_free")]
    pub(super) free_vibration_s: f64,
    #[serde(default)]
    pub(super) start_x_m: Option<f64>,
    #[serde(default = "default_every")]
    pub(super) output_every: usize,
    #[serde(default = "default_fmi_version")]
    pub(super) fmi_version: u8,
}

pub(super) fn default_dt() -> f64 {
    0.001
}
pub(super) fn default_free() -> f64 {
    1.0
}
pub(super) fn default_every() -> usize {
    1
}
pub(super) fn default_fmi_version() -> u8 {
    2
}

/// `[bridge]`: one table for all kinds; keys that do not belong to the kind are refused.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileBridge {
    pub(super) kind: String,
    #[serde(default = "default_modes")]
    pub(super) modes: usize,
    #[serde(default)]
    pub(super) damping_ratio: f64,
    pub(super) damping_ratio_torsional: Option<f64>,
    pub(super) damping: Option<FileDamping>,
    /// `"en1990"` or `"all"` ([`ModesRule`]); default by the train's kind.
    pub(super) modes_rule: Option<String>,
    pub(super) track_eccentricity_m: Option<f64>,
    pub(super) track_height_m: Option<f64>,
    /// `[[bridge.track]]`: the tracks, instead of `track_eccentricity_m`/`track_height_m`.
    pub(super) track: Option<Vec<FileTrackPlace>>,
    // simply supported
    pub(super) span_m: Option<f64>,
    // beam
    pub(super) spans_m: Option<Vec<f64>>,
    /// `kind = "beam"`: one section per span, each key defaulting to the bridge's.
    pub(super) sections: Option<Vec<FileSection>>,
    /// `kind = "beam"`: `"continuous"` (default) or `"simply_supported"` (a chain of spans).
    pub(super) supports: Option<String>,
    pub(super) youngs_modulus_pa: Option<f64>,
    pub(super) inertia_vertical_m4: Option<f64>,
    pub(super) inertia_lateral_m4: Option<f64>,
    pub(super) shear_modulus_pa: Option<f64>,
    pub(super) torsion_constant_m4: Option<f64>,
    pub(super) polar_inertia_kg_m: Option<f64>,
    pub(super) mass_per_length_kg_m: Option<f64>,
    pub(super) x_start_m: Option<f64>,
    // modal file
    pub(super) path: Option<PathBuf>,
    pub(super) interpolation_points: Option<usize>,
    // suspension
    pub(super) preset: Option<String>,
}

pub(super) fn default_modes() -> usize {
    20
}

/// `[[bridge.track]]`: where a track lies on the deck.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileTrackPlace {
    pub(super) eccentricity_m: f64,
    pub(super) height_m: f64,
}

/// `bridge.sections[i]` of `kind = "beam"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSection {
    pub(super) youngs_modulus_pa: Option<f64>,
    pub(super) inertia_vertical_m4: Option<f64>,
    pub(super) mass_per_length_kg_m: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileDamping {
    pub(super) rule: String,
    pub(super) structure: String,
    pub(super) additional: Option<bool>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileTrain {
    pub(super) kind: String,
    /// `kind = "hslm_a"`: the train's name, `A1` … `A10`.
    pub(super) name: Option<String>,
    /// `kind = "hslm_b"`: the number N of point forces of 170 kN.
    pub(super) forces: Option<usize>,
    /// `kind = "hslm_b"`: their uniform spacing d, m.
    pub(super) spacing_m: Option<f64>,
    /// `kind = "moving_force"`: a CSV of axles instead of `axles`.
    pub(super) file: Option<PathBuf>,
    #[serde(default)]
    pub(super) axles: Vec<toml::Table>,
    pub(super) preset: Option<String>,
    pub(super) vehicles: Option<usize>,
    pub(super) coach: Option<toml::Table>,
    pub(super) hunting: Option<HuntingParams>,
    /// `kind = "moving_force"` or `"hslm_a"`: a sprung mass under every axle.
    pub(super) vehicle: Option<toml::Table>,
    /// `"forward"` (+x, the default) or `"backward"` (−x).
    pub(super) direction: Option<String>,
    /// 1-based index into `[[bridge.track]]`. Default 1.
    pub(super) track: Option<usize>,
    /// Its speed at the start (else `run.speed_kmh`).
    pub(super) speed_kmh: Option<f64>,
    /// Its first axle's position at t = 0 (the first train: else `run.start_x_m`).
    pub(super) start_x_m: Option<f64>,
    /// The time its first axle enters the deck, s.
    pub(super) enter_time_s: Option<f64>,
    /// Where its front meets the first train's front, m.
    pub(super) meet_at_x_m: Option<f64>,
    pub(super) braking: Option<FileBraking>,
    pub(super) accelerating: Option<FileAccelerating>,
}

/// `train.braking`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileBraking {
    pub(super) from_x_m: f64,
    pub(super) deceleration_m_s2: f64,
    pub(super) to_speed_kmh: Option<f64>,
}

/// `train.accelerating`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileAccelerating {
    pub(super) from_x_m: f64,
    pub(super) acceleration_m_s2: f64,
    pub(super) to_speed_kmh: f64,
}

/// A table written once (`[x]`) or as an array of tables (`[[x]]`), serde's errors (and
/// their lines) kept either way.
#[derive(Debug)]
pub(super) enum OneOrMany<T> {
    One(T),
    Many(Vec<T>),
}

impl<T> OneOrMany<T> {
    /// The tables, and whether they were written as an array.
    pub(super) fn items(&self) -> (Vec<&T>, bool) {
        match self {
            OneOrMany::One(t) => (vec![t], false),
            OneOrMany::Many(v) => (v.iter().collect(), true),
        }
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for OneOrMany<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for Visit<T> {
            type Value = OneOrMany<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table or an array of tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Self::Value, A::Error> {
                T::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(OneOrMany::One)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Self::Value, A::Error> {
                Vec::<T>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(OneOrMany::Many)
            }
        }
        d.deserialize_any(Visit(std::marker::PhantomData))
    }
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct FileTrack {
    #[serde(default)]
    pub(super) irregularity: IrregularitySpec,
}

/// serde's "unknown field `x`, expected one of `a`, `b`" (or "unknown variant") with the
/// closest expected name: "…; did you mean `a`?" ([`crate::text::closest`]).
pub(super) fn with_suggestion(message: &str) -> String {
    let unknown = ["unknown field `", "unknown variant `"]
        .iter()
        .find_map(|p| message.strip_prefix(p))
        .and_then(|rest| rest.split('`').next());
    let Some(unknown) = unknown else {
        return message.to_string();
    };
    let expected = message
        .split_once("expected")
        .map(|(_, list)| list.split('`').skip(1).step_by(2));
    match expected.and_then(|names| crate::text::closest(unknown, names)) {
        Some(name) => format!("{message}; did you mean `{name}`?"),
        None => message.to_string(),
    }
}

/// A table on one line, `{ key = value, ... }`, for messages.
pub(super) fn inline_table(t: &toml::Table) -> String {
    let items: Vec<String> = t.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    format!("{{ {} }}", items.join(", "))
}
