//! `tbi run`: simulate a scenario with the monolithic solver or by co-simulation of the two
//! FMUs, and write `summary.json`, `history.csv` and plots into the output folder.

use crate::model::{build, Limits, Model};
use crate::outdir::{NamedFile, OutputDir};
use crate::scenario::{Scenario, SolverKind};
use crate::summary::Summary;
use std::path::{Path, PathBuf};
use std::time::Instant;
use tbi_dynamics::response::{Layout, Recorder};
use tbi_dynamics::solver::sample::ProbeShapes;
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
    /// Mean wind speed on the deck, m/s (the `[wind]` table's, or with the suspension
    /// preset's deck coefficients when the scenario has none).
    #[arg(long = "wind-speed", allow_negative_numbers = true)]
    pub wind_speed: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Run even when the estimated steps, history.csv size or memory pass the limits.
    #[arg(long)]
    pub allow_large: bool,
    /// Print the whole `summary.json` on standard output instead of the short summary.
    #[arg(long)]
    pub json: bool,
}

pub fn main(args: RunArgs) -> Result<(), Box<dyn std::error::Error>> {
    let mut scenario = crate::scenario::load(
        args.scenario.as_deref(),
        args.solver.as_deref(),
        args.speed_kmh,
    )?;
    if let Some(u) = args.wind_speed {
        scenario
            .set_wind_speed(u)
            .map_err(|e| format!("--wind-speed: {e}"))?;
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("tbi-out").join(&scenario.name));
    let limits = if args.allow_large {
        Limits::none()
    } else {
        Limits::default()
    };
    let summary = run_scenario(&scenario, &out, !args.quiet, &limits)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        eprintln!("tbi: results in {}", out.display());
    } else {
        println!("{}", crate::summary::text(&summary, &out));
    }
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
                (
                    m.wheelsets[w.local].reference_load_n(),
                    m.contact_distance_m,
                )
            })
            .collect(),
    }
}

/// Run a scenario into `out` (co-simulation keeps its FMUs in `out/fmus`); returns the
/// summary (also written as `summary.json`). The folder is claimed for the run
/// ([`OutputDir`]) and the run's cost checked against `limits` before any step.
pub fn run_scenario(
    scenario: &Scenario,
    out: &Path,
    show_progress: bool,
    limits: &Limits,
) -> Result<Summary, Box<dyn std::error::Error>> {
    let model = build(scenario)?;
    limits.check(scenario, &model.estimate())?;
    let claim = OutputDir::claim(out)?;
    let out = claim.path();
    let history = out.join("history.csv");
    let mut rec = Recorder::new(
        layout(&model),
        &model.probes.iter().map(|p| p.1).collect::<Vec<_>>(),
        Some(NamedFile::create(&history)?),
    )?;
    let start = Instant::now();
    let result = match scenario.run.solver {
        SolverKind::Monolithic => run_monolithic(&model, &mut rec, show_progress).map(|_| None),
        SolverKind::Cosim => crate::cosim::run_cosim(
            &scenario.coupling,
            &model,
            &out.join("fmus"),
            &mut rec,
            show_progress,
        )
        .map(Some),
    };
    let wall = start.elapsed().as_secs_f64();
    rec.finish()?;
    let mut summary = Summary::new(scenario, &model, &rec, wall);
    // The plots come before the summary, so that `"status": "ok"` is only ever written for
    // a run that succeeded as a whole.
    let result = result.and_then(|coupling| {
        crate::plots::write_run_plots(
            out,
            &model,
            &history,
            &format!(
                "{}, {} km/h",
                scenario.name,
                crate::model::num(scenario.run.speed_kmh)
            ),
        )
        .map_err(|e| format!("plots in {}: {e}", out.display()))?;
        Ok(coupling)
    });
    match result {
        Ok(coupling) => {
            summary.coupling = coupling;
            summary.write(out)?;
            Ok(summary)
        }
        Err(e) => {
            summary.status = "failed".into();
            summary.error = Some(e.to_string());
            summary.write(out)?;
            Err(format!(
                "{e} (partial results up to the failure are in {})",
                out.display()
            )
            .into())
        }
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
    let probe_x: Vec<f64> = model.probes.iter().map(|p| p.1).collect();
    let shapes = ProbeShapes::new(&model.bridge, &probe_x);
    let mut sample = sol.sample(&shapes);
    rec.record(&sample, true)?;
    let pb = crate::progress::bar(model.steps, show_progress);
    for k in 1..=model.steps {
        crate::interrupt::check(sol.t)?;
        sol.step();
        if !sol.q.iter().all(|v| v.is_finite()) {
            return Err(format!(
                "monolithic solver: non-finite bridge response at t = {} s",
                sol.t
            )
            .into());
        }
        sol.sample_into(&shapes, &mut sample);
        rec.record(&sample, k % model.output_every == 0 || k == model.steps)?;
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(())
}
