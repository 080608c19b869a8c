//! `tbi run`: simulate a scenario with the monolithic solver or by co-simulation of the two
//! FMUs, and write `summary.json`, `history.csv` and plots into the output folder.

use crate::model::{build, Model};
use crate::scenario::{Scenario, SolverKind};
use serde_json::json;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tbi_dynamics::response::{Layout, Recorder, Sample};
use tbi_dynamics::solver::partitioned::ProbeValues;
use tbi_dynamics::solver::Monolithic;

/// Command-line arguments of `tbi run`.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case (`tbi scenario show`).
    pub scenario: Option<PathBuf>,
    /// Solver: `monolithic` or `cosim` (default: the scenario's `run.solver`).
    #[arg(long)]
    pub solver: Option<String>,
    /// Output folder. Default: `tbi-out/<scenario name>`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override the scenario's speed, km/h.
    #[arg(long = "speed-kmh", allow_negative_numbers = true)]
    pub speed_kmh: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Load the scenario named on the command line (or the embedded one) with overrides.
pub fn load_scenario(
    path: Option<&Path>,
    solver: Option<&str>,
    speed_kmh: Option<f64>,
) -> Result<Scenario, String> {
    let mut s = match path {
        Some(p) => Scenario::from_path(p).map_err(|e| e.to_string())?,
        None => Scenario::default_case(),
    };
    if let Some(sv) = solver {
        s.run.solver = match sv {
            "monolithic" => SolverKind::Monolithic,
            "cosim" => SolverKind::Cosim,
            other => {
                return Err(format!(
                    "--solver {other}: expected \"monolithic\" or \"cosim\""
                ))
            }
        };
    }
    if let Some(v) = speed_kmh {
        s.run.speed_kmh = v;
        s.validate().map_err(|e| format!("--speed-kmh: {e}"))?;
    }
    Ok(s)
}

pub fn main(args: RunArgs) -> Result<(), Box<dyn std::error::Error>> {
    let scenario = load_scenario(
        args.scenario.as_deref(),
        args.solver.as_deref(),
        args.speed_kmh,
    )?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("tbi-out").join(&scenario.name));
    let summary = run_scenario(&scenario, &out, !args.quiet)?;
    println!("{}", serde_json::to_string_pretty(&summary)?);
    eprintln!("tbi: results in {}", out.display());
    Ok(())
}

/// The record layout of a model.
pub fn layout(model: &Model) -> Layout {
    Layout {
        probe_names: model.probes.iter().map(|p| p.0.clone()).collect(),
        vehicles: model
            .train
            .vehicles
            .iter()
            .map(|v| {
                [
                    v.model.body.lateral.is_some(),
                    v.model.body.vertical.is_some(),
                ]
            })
            .collect(),
        wheelsets: model
            .train
            .wheelsets()
            .iter()
            .map(|w| {
                let m = &model.train.vehicles[w.vehicle].model;
                (m.wheelsets[w.local].p0.z, m.contact_distance_m)
            })
            .collect(),
    }
}

/// A progress bar on stderr for runs that take more than about a second.
pub fn progress(steps: usize, enabled: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !enabled || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new(steps as u64);
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:40}] {pos}/{len} steps ({per_sec}, eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    pb
}

/// Run a scenario into `out`; returns the summary (also written as `summary.json`).
pub fn run_scenario(
    scenario: &Scenario,
    out: &Path,
    show_progress: bool,
) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create output folder: {e}", out.display()))?;
    let model = build(scenario)?;
    let history = out.join("history.csv");
    let file = File::create(&history).map_err(|e| format!("{}: {e}", history.display()))?;
    let mut rec = Recorder::new(
        layout(&model),
        &model.probes.iter().map(|p| p.1).collect::<Vec<_>>(),
        Some(BufWriter::new(file)),
    )?;
    let start = Instant::now();
    let result = match scenario.run.solver {
        SolverKind::Monolithic => run_monolithic(&model, &mut rec, show_progress).map(|_| None),
        SolverKind::Cosim => {
            let mut s = scenario.clone();
            s.fmu_dir = Some(s.fmu_dir.clone().unwrap_or_else(|| out.join("fmus")));
            crate::cosim::run_cosim(&s, &model, &mut rec, show_progress).map(Some)
        }
    };
    let wall = start.elapsed().as_secs_f64();
    rec.finish()?;
    let mut summary = summary_json(scenario, &model, &rec, wall);
    match result {
        Ok(coupling) => {
            if let Some(c) = coupling {
                summary["coupling"] = c;
            }
            write_summary(out, &summary)?;
            crate::plots::write_run_plots(out, &model, &history)
                .map_err(|e| format!("plots in {}: {e}", out.display()))?;
            Ok(summary)
        }
        Err(e) => {
            summary["status"] = json!("failed");
            summary["error"] = json!(e.to_string());
            write_summary(out, &summary)?;
            Err(format!(
                "{e} (partial results up to the failure are in {})",
                out.display()
            )
            .into())
        }
    }
}

fn write_summary(
    out: &Path,
    summary: &serde_json::Value,
) -> Result<(), Box<dyn std::error::Error>> {
    let p = out.join("summary.json");
    std::fs::write(&p, serde_json::to_string_pretty(summary)?)
        .map_err(|e| format!("{}: {e}", p.display()))?;
    Ok(())
}

/// `summary.json` content.
pub fn summary_json<W: std::io::Write>(
    s: &Scenario,
    model: &Model,
    rec: &Recorder<W>,
    wall: f64,
) -> serde_json::Value {
    let mut probes = serde_json::Map::new();
    for ((name, _), m) in model.probes.iter().zip(&rec.probes) {
        probes.insert(name.clone(), serde_json::to_value(m).expect("serialisable"));
    }
    json!({
        "name": s.name,
        "status": "ok",
        "speed_kmh": s.run.speed_kmh,
        "solver": s.run.solver.as_str(),
        "dt_s": model.dt,
        "steps": model.steps,
        "simulated_time_s": model.t_end(),
        "wall_time_s": wall,
        "bridge": {
            "kind": s.bridge.kind,
            "modes": model.bridge.n_modes(),
            "frequencies_hz": model.bridge.frequencies_hz,
            "labels": model.bridge.labels,
            "length_m": model.bridge.length_m(),
        },
        "train": {
            "vehicles": model.train.vehicles.len(),
            "wheelsets": model.train.n_wheelsets(),
            "length_m": model.train.length_m(),
        },
        "probes": probes,
        "vehicles": rec.vehicles,
        "safety": rec.safety,
    })
}

/// Deck shapes at the probes (precomputed once).
pub struct ProbeShapes(Vec<Vec<[f64; 3]>>);

impl ProbeShapes {
    pub fn new(model: &Model) -> Self {
        ProbeShapes(
            model
                .probes
                .iter()
                .map(|(_, x)| {
                    let mut sh = vec![[0.0; 3]; model.bridge.n_modes()];
                    model.bridge.deck_shapes(*x, &mut sh);
                    sh
                })
                .collect(),
        )
    }

    pub fn values(&self, q: &[f64], qdd: &[f64]) -> Vec<ProbeValues> {
        self.0
            .iter()
            .map(|sh| ProbeValues::from_shapes(sh, q, qdd))
            .collect()
    }
}

/// The monolithic solver's sample at its current time.
pub fn monolithic_sample(sol: &Monolithic, shapes: &ProbeShapes) -> Sample {
    Sample {
        t: sol.t,
        probes: shapes.values(sol.q.as_slice(), sol.qdd.as_slice()),
        vehicles: sol
            .train
            .vehicles
            .iter()
            .zip(&sol.vehicles)
            .map(|(tv, s)| {
                [
                    tv.model.body.lateral.map(|i| s.vdd[i]),
                    tv.model.body.vertical.map(|i| s.vdd[i]),
                ]
            })
            .collect(),
        forces: sol.forces.clone(),
    }
}

/// Integrate the model with the monolithic solver of eq. (14).
pub fn run_monolithic<W: std::io::Write>(
    model: &Model,
    rec: &mut Recorder<W>,
    show_progress: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut sol = Monolithic::new(
        model.bridge.clone(),
        model.train.clone(),
        model.track.clone(),
        model.dt,
    );
    let shapes = ProbeShapes::new(model);
    rec.record(&monolithic_sample(&sol, &shapes), true)?;
    let pb = progress(model.steps, show_progress);
    for k in 1..=model.steps {
        sol.step();
        if !sol.q.iter().all(|v| v.is_finite()) {
            return Err(format!(
                "monolithic solver: non-finite bridge response at t = {} s",
                sol.t
            )
            .into());
        }
        rec.record(
            &monolithic_sample(&sol, &shapes),
            k % model.output_every == 0 || k == model.steps,
        )?;
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(())
}
