//! `tbi run`: simulate a scenario with the monolithic solver or by co-simulation of the two
//! FMUs, and write `summary.json`, `history.csv` and plots into the output folder.

use crate::model::Limits;
use crate::solve::run_scenario;
use std::path::PathBuf;

/// Command-line arguments of `tbi run`.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case (`tbi scenario show`).
    pub scenario: Option<PathBuf>,
    /// Run the embedded meeting case instead: the Tsing Ma case with a second 8-coach train
    /// on the other track (e = ±2.05 m), the two meeting at mid main span.
    #[arg(long, conflicts_with = "scenario")]
    pub meeting: bool,
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
    /// With `--solver cosim`: FMI 2.0 (2) or FMI 3.0 (3) FMUs (default: the scenario's
    /// `run.fmi_version`, else 2).
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub fmi_version: Option<u8>,
}

pub fn main(args: RunArgs) -> Result<(), Box<dyn std::error::Error>> {
    let mut scenario = match args.meeting {
        true => crate::scenario::load_meeting(args.solver.as_deref(), args.speed_kmh)?,
        false => crate::scenario::load(
            args.scenario.as_deref(),
            args.solver.as_deref(),
            args.speed_kmh,
        )?,
    };
    if let Some(v) = args.fmi_version {
        if scenario.run.solver != crate::scenario::SolverKind::Cosim {
            return Err(format!(
                "--fmi-version {v} applies to --solver cosim (the FMUs); this run is monolithic"
            )
            .into());
        }
        scenario.run.fmi_version = v;
    }
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
    let (text, passed) = crate::output::summary::text(&summary, &out);
    if args.json {
        crate::say!("{}", serde_json::to_string_pretty(&summary)?);
        eprintln!("tbi: results in {}", out.display());
    } else {
        crate::say!("{text}");
    }
    if !passed {
        crate::output::console::check_failed();
    }
    Ok(())
}
