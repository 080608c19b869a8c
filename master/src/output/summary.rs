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
    /// Monolithic runs: the steps whose geometry a second core made ahead
    /// ([`tbi_dynamics::solver::Monolithic::run_ahead`], chosen by timing while the run goes
    /// on; the values are the same either way).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps_ahead: Option<usize>,
    pub bridge: BridgeSummary,
    pub train: TrainSummary,
    /// Per probe, by name.
    pub probes: BTreeMap<String, ProbeMax>,
    /// Car-body maxima and Sperling indices: only when a vehicle has a car body (not for
    /// moving forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vehicles: Option<VehicleMax>,
    /// Wheel–rail safety maxima: only when the wheel loads vary (not for moving forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety: Option<SafetyMax>,
    /// Several trains: each train's run and results (the maxima above are over all).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub trains: Vec<super::trains::TrainResult>,
    /// Several trains: where and when trains running towards each other meet on the deck.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub meetings: Vec<super::trains::Meeting>,
    /// Co-simulation only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coupling: Option<CouplingSummary>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BridgeSummary {
    pub kind: String,
    pub modes: usize,
    /// `bridge.modes_rule`: `"en1990"` (the modes up to max(30 Hz, 1.5 f₁, f₃)) or `"all"`.
    #[serde(default = "default_modes_rule")]
    pub modes_rule: String,
    pub frequencies_hz: Vec<f64>,
    pub labels: Vec<String>,
    pub length_m: f64,
    /// The damping rule and the ratio it gave, when the scenario chose one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<crate::scenario::DampingRule>,
    /// The mean wind on the deck, when the scenario has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindSummary>,
}

fn default_modes_rule() -> String {
    "all".into()
}

/// The mean wind of a run and the steady deck load it gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindSummary {
    pub mean_speed_m_s: f64,
    pub air_density_kg_m3: f64,
    pub deck: crate::scenario::DeckAero,
    /// Steady deck load per unit length at the shear centre: lateral N/m (+y), vertical N/m
    /// (+ down), torque N·m/m.
    pub deck_load: [f64; 3],
    /// The turbulence buffeting the deck, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turbulence: Option<tbi_wind::Turbulence>,
    /// Deck points of the turbulence.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deck_points: Option<usize>,
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
    /// Steps by their number of sweeps: entry `k` counts the steps that took `k + 1`.
    #[serde(default)]
    pub steps_by_iterations: Vec<usize>,
    pub steps: usize,
    pub accepted_unconverged: usize,
    pub rejected: usize,
    pub max_residual: f64,
    /// FMU steps spent on step Jacobians (finite differences through rollback; 0 unless the
    /// acceleration is `newton`).
    #[serde(default)]
    pub jacobian_probes: usize,
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
                modes_rule: s.modes_rule.as_str().into(),
                frequencies_hz: model.bridge.frequencies_hz.clone(),
                labels: model.bridge.labels.clone(),
                length_m: model.bridge.length_m(),
                damping: s.damping_rule.clone(),
                wind: s.wind.as_ref().map(|w| WindSummary {
                    mean_speed_m_s: w.mean_speed_m_s,
                    air_density_kg_m3: w.air_density_kg_m3,
                    deck: w.deck(),
                    deck_load: w.deck_load(),
                    turbulence: w.turbulence.clone(),
                    deck_points: w.turbulence.as_ref().map(|_| w.deck_points),
                }),
            },
            train: TrainSummary {
                vehicles: model.train.vehicles.len(),
                wheelsets: model.train.n_wheelsets(),
                length_m: model.train.length_m(0),
            },
            probes: model
                .probes
                .iter()
                .zip(&rec.probes)
                .map(|((name, _), m)| (name.clone(), m.clone()))
                .collect(),
            vehicles: rec
                .layout
                .vehicles
                .iter()
                .any(|[lateral, vertical]| *lateral || *vertical)
                .then(|| rec.vehicles.clone()),
            safety: (!matches!(s.train.spec, tbi_dynamics::train::TrainSpec::MovingForce(_)))
                .then(|| rec.safety.clone()),
            trains: super::trains::results(model, rec),
            meetings: super::trains::meetings(model),
            coupling: None,
            steps_ahead: None,
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
        crate::output::outdir::write_atomically(&out.join("summary.json"), text.as_bytes())
    }
}

/// The few lines `tbi run` prints for a person: the case, the run, the governing maxima
/// (displacements in mm, accelerations in m/s², as in `tbi sweep --trains`' outputs) against
/// their limits with PASS/FAIL, and where the files are; and whether every check passed.
///
/// Limits: deck vertical acceleration 3.5 m/s² (EN 1990 A2.4.4.2.1, ballasted track);
/// car-body vertical acceleration against the comfort levels of EN 1990 Table A2.9 (1.0 very
/// good, 1.3 good, 2.0 m/s² acceptable); derail factor 0.8 and offload factor 0.6 (the
/// paper's Chinese code limits); Sperling W < 2.5 excellent, < 2.75 good, < 3.0 acceptable.
pub fn text(s: &Summary, out: &Path) -> (String, bool) {
    use std::fmt::Write as _;
    let pass = |ok: bool| if ok { "PASS" } else { "FAIL" };
    let mut t = String::new();
    let mut checks: Vec<bool> = Vec::new();
    let _ = writeln!(
        t,
        "{}: {} at {} km/h, {} steps ({:.3} s simulated) in {:.2} s wall{}",
        s.name,
        s.solver,
        crate::text::num(s.speed_kmh),
        s.steps,
        s.simulated_time_s,
        s.wall_time_s,
        if s.status == "ok" {
            String::new()
        } else {
            format!(" — {}", s.status.to_uppercase())
        }
    );
    if let Some(w) = &s.bridge.wind {
        let _ = writeln!(t, "{}", wind_line(w));
    }
    let _ = writeln!(
        t,
        "  bridge: {} modes up to {:.1} Hz (modes_rule = \"{}\")",
        s.bridge.modes,
        s.bridge.frequencies_hz.iter().copied().fold(0.0, f64::max),
        s.bridge.modes_rule
    );
    let probe_max = |f: fn(&ProbeMax) -> f64| {
        s.probes
            .iter()
            .max_by(|a, b| f(a.1).total_cmp(&f(b.1)))
            .map(|(n, p)| (n.clone(), f(p)))
    };
    if let (Some((nz, z)), Some((na, a))) = (
        probe_max(|p| p.vertical_displacement_max_m),
        probe_max(|p| p.vertical_acceleration_max_m_s2),
    ) {
        checks.push(a <= 3.5);
        let _ = writeln!(
            t,
            "  deck: vertical displacement {:.3} mm ({nz}); vertical acceleration {a:.4} m/s² ({na}), limit 3.5 m/s² (EN 1990 A2.4.4.2.1, ballasted): {}",
            1000.0 * z,
            pass(a <= 3.5)
        );
    }
    if let (Some((ny, y)), Some((nl, l))) = (
        probe_max(|p| p.lateral_displacement_max_m),
        probe_max(|p| p.lateral_acceleration_max_m_s2),
    ) {
        let torsion = probe_max(|p| p.torsion_max_rad).filter(|(_, r)| *r > 0.0);
        let torsion = match torsion {
            Some((nr, r)) => format!("; torsion {:.4} mrad ({nr})", 1000.0 * r),
            None => String::new(),
        };
        if y > 0.0 || l > 0.0 || !torsion.is_empty() {
            let _ = writeln!(
                t,
                "        lateral displacement {:.3} mm ({ny}); lateral acceleration {l:.4} m/s² ({nl}){torsion}",
                1000.0 * y,
            );
        }
    }
    let _ = writeln!(t, "{}", car_body_line(s.vehicles.as_ref()));
    if let Some(f) = &s.safety {
        let lateral = s
            .vehicles
            .as_ref()
            .is_some_and(|v| v.sperling_lateral.iter().any(Option::is_some))
            || f.lateral_force_max_n > 0.0;
        checks.push(f.offload_factor_max <= 0.6);
        let offload = format!(
            "offload factor {:.3} (limit 0.6: {})",
            f.offload_factor_max,
            pass(f.offload_factor_max <= 0.6)
        );
        if lateral {
            checks.push(f.derail_factor_max <= 0.8);
            let _ = writeln!(
                t,
                "  safety: derail factor {:.3} (limit 0.8: {}), {offload}",
                f.derail_factor_max,
                pass(f.derail_factor_max <= 0.8),
            );
        } else {
            let _ = writeln!(t, "  safety: {offload} (no lateral wheel forces modelled)");
        }
    }
    for line in train_lines(s) {
        let _ = writeln!(t, "{line}");
    }
    if let Some(c) = &s.coupling {
        let _ = writeln!(
            t,
            "  coupling: {} ({}), {:.2} iterations per step (max {})",
            c.scheme, c.acceleration, c.iterations_mean, c.iterations_max
        );
        if c.jacobian_probes > 0 {
            let _ = writeln!(
                t,
                "            {:.1} FMU steps per step for the step Jacobians",
                c.jacobian_probes as f64 / c.steps.max(1) as f64
            );
        }
    }
    let _ = write!(
        t,
        "  files: {} (summary.json, history.csv, plots)",
        out.display()
    );
    (t, checks.iter().all(|&ok| ok))
}

/// The short summary's wind line.
fn wind_line(w: &WindSummary) -> String {
    format!(
        "  wind: mean {} m/s on the deck (steady drag {:.0} N/m, lift {:.0} N/m, moment {:.0} N·m/m){}; the bridge starts in its static response",
        crate::text::num(w.mean_speed_m_s),
        w.deck_load[0],
        -w.deck_load[1],
        w.deck_load[2],
        match &w.turbulence {
            Some(t) => format!(
                ", buffeting by {} turbulence (I_u {}, I_w {}) at {} deck points",
                t.spectrum.name(),
                t.intensity_u,
                t.intensity_w,
                w.deck_points.unwrap_or(0)
            ),
            None => String::new(),
        }
    )
}

/// The short summary's car-body line: the largest accelerations against EN 1990 Table A2.9.
fn car_body_line(vehicles: Option<&VehicleMax>) -> String {
    let Some(v) = vehicles else {
        return "  car bodies: none modelled (moving forces)".to_string();
    };
    let bv = v.vertical_acceleration_max_m_s2;
    let comfort = if bv <= 1.0 {
        "very good"
    } else if bv <= 1.3 {
        "good"
    } else if bv <= 2.0 {
        "acceptable"
    } else {
        "beyond acceptable"
    };
    let sperling = v
        .sperling_vertical
        .iter()
        .flatten()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    format!(
        "  car bodies: vertical acceleration {bv:.4} m/s² (EN 1990 Table A2.9: {comfort}); lateral {:.4} m/s²{}",
        v.lateral_acceleration_max_m_s2,
        if sperling.is_finite() {
            format!("; Sperling W (vertical) up to {sperling:.2}")
        } else {
            String::new()
        }
    )
}

/// The short summary's lines of each train and meeting (none for one train).
fn train_lines(s: &Summary) -> Vec<String> {
    let mut out = Vec::new();
    for r in &s.trains {
        let mut line = format!(
            "  train {}: track {}, {} at {} km/h",
            r.train,
            r.track,
            r.direction.as_str(),
            crate::text::num(r.speed_kmh)
        );
        if let Some(c) = &r.speed_change {
            line += &format!(
                ", {} at {} m/s² from x = {} m to {} km/h",
                if c.rate_m_s2 < 0.0 {
                    "braking"
                } else {
                    "accelerating"
                },
                crate::text::num(c.rate_m_s2.abs()),
                crate::text::num(c.from_x_m),
                crate::text::num(c.to_speed_m_s * 3.6)
            );
        }
        if let Some(c) = &r.car_bodies {
            line += &format!(
                "; car bodies {:.4} m/s² vertical, {:.4} m/s² lateral",
                c.vertical_acceleration_max_m_s2, c.lateral_acceleration_max_m_s2
            );
        }
        if let Some(f) = &r.safety {
            line += &format!(
                "; derail factor {:.3}, offload factor {:.3}",
                f.derail_factor_max, f.offload_factor_max
            );
        }
        out.push(line);
    }
    for m in &s.meetings {
        out.push(format!(
            "  trains {} and {} meet at x = {:.1} m, t = {:.3} s",
            m.trains[0], m.trains[1], m.x_m, m.time_s
        ));
    }
    out
}
