//! `summary.json`: what a run reports, as one type that `tbi run` writes and `tbi sweep`,
//! `tbi bench` and the tests read back.
//!
//! Maxima are of absolute values over the whole run (every step, not only the rows written
//! to `history.csv`); units are in the key names (SI).

use crate::model::Model;
use crate::scenario::Scenario;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use tbi_dynamics::response::{ProbeMax, Recorder, SafetyMax, VehicleMax};

/// The content of `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub name: String,
    /// `"ok"` or `"failed"` (then `error` says why; the maxima cover the steps done).
    pub status: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    pub speed_kmh: f64,
    /// `"monolithic"` or `"cosim"`.
    pub solver: String,
    pub dt_s: f64,
    pub steps: usize,
    pub simulated_time_s: f64,
    pub wall_time_s: f64,
    pub bridge: BridgeSummary,
    pub train: TrainSummary,
    /// Per probe, by name.
    pub probes: BTreeMap<String, ProbeMax>,
    pub vehicles: VehicleMax,
    pub safety: SafetyMax,
    /// Co-simulation only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coupling: Option<CouplingSummary>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BridgeSummary {
    pub kind: String,
    pub modes: usize,
    pub frequencies_hz: Vec<f64>,
    pub labels: Vec<String>,
    pub length_m: f64,
    /// The damping rule and the ratio it gave, when the scenario chose one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<crate::scenario::DampingRule>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainSummary {
    pub vehicles: usize,
    pub wheelsets: usize,
    pub length_m: f64,
}

/// How the co-simulation converged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CouplingSummary {
    pub scheme: String,
    pub acceleration: String,
    pub iterations_mean: f64,
    pub iterations_max: usize,
    pub steps: usize,
    pub accepted_unconverged: usize,
    pub rejected: usize,
    pub max_residual: f64,
    /// The FMUs that ran.
    pub bridge_fmu: String,
    pub train_fmu: String,
}

impl Summary {
    /// The summary of a run of `model` (from scenario `s`) whose recorder is `rec`.
    pub fn new<W: std::io::Write>(
        s: &Scenario,
        model: &Model,
        rec: &Recorder<W>,
        wall: f64,
    ) -> Summary {
        Summary {
            name: s.name.clone(),
            status: "ok".into(),
            error: None,
            speed_kmh: s.run.speed_kmh,
            solver: s.run.solver.as_str().into(),
            dt_s: model.dt,
            steps: model.steps,
            simulated_time_s: model.t_end(),
            wall_time_s: wall,
            bridge: BridgeSummary {
                kind: s.bridge.kind().into(),
                modes: model.bridge.n_modes(),
                frequencies_hz: model.bridge.frequencies_hz.clone(),
                labels: model.bridge.labels.clone(),
                length_m: model.bridge.length_m(),
                damping: s.damping_rule.clone(),
            },
            train: TrainSummary {
                vehicles: model.train.vehicles.len(),
                wheelsets: model.train.n_wheelsets(),
                length_m: model.train.length_m(),
            },
            probes: model
                .probes
                .iter()
                .zip(&rec.probes)
                .map(|((name, _), m)| (name.clone(), m.clone()))
                .collect(),
            vehicles: rec.vehicles.clone(),
            safety: rec.safety.clone(),
            coupling: None,
        }
    }

    /// Read `summary.json`.
    pub fn read(path: &Path) -> Result<Summary, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Write `summary.json` into `out` (through a temporary file and a rename).
    pub fn write(&self, out: &Path) -> Result<(), String> {
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        crate::outdir::write_atomically(&out.join("summary.json"), text.as_bytes())
    }
}
