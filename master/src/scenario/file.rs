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
    pub(super) train: FileTrain,
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
    pub(super) speed_kmh: f64,
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
