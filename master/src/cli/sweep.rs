//! `tbi sweep`: one scenario at several speeds (a list, or `start:stop:step` in km/h), run
//! in parallel on every core.
//!
//! * Without `--trains`: summarised in the layout of the paper's Table 2 (maximum responses of
//!   bridge and vehicles) beside the paper's values (`table.md`, `table.csv`).
//! * With `--trains hslm-a` (the ten EN 1991-2 HSLM-A trains) or a list such as `A1,A4`: every
//!   train at every speed as moving forces on the scenario's bridge, with one progress bar;
//!   `envelope.csv` has one row per train and speed (the largest deck vertical acceleration
//!   and displacement over the probes), and the governing train and speed are printed.

use crate::design::SweepOptions;
use std::path::PathBuf;

/// Command-line arguments of `tbi sweep`.
#[derive(Debug, Clone, clap::Args)]
pub struct SweepArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Speeds, km/h: comma separated, or `start:stop:step` (stop included). Default: the
    /// paper's 20,40,70,120; with `--trains`, EN 1991-2 §6.4.6: from 40 m/s (144 km/h) to
    /// 1.2 × the scenario's speed (its line speed) in 2.5 km/h steps.
    #[arg(long, value_delimiter = ',')]
    pub speeds: Vec<String>,
    /// Trains replacing the scenario's: `hslm-a` (A1–A10) or names such as `A1,A4`.
    #[arg(long, value_delimiter = ',')]
    pub trains: Vec<String>,
    /// With `--trains`: the track for the deck acceleration limit, `ballasted` (3.5 m/s²)
    /// or `direct` (fastening, 5 m/s²).
    #[arg(long, default_value = "ballasted")]
    pub track: String,
    /// With `--trains`: the comfort level of EN 1990 Table A2.9 the car-body vertical
    /// acceleration is checked against when the trains carry vehicles (`train.vehicle`):
    /// `very-good` (1.0 m/s²), `good` (1.3 m/s²) or `acceptable` (2.0 m/s²).
    #[arg(long, default_value = "very-good")]
    pub comfort: String,
    /// With `--trains`: keep every mode of the bridge (`bridge.modes_rule = "all"` in every
    /// case), not only those up to max(30 Hz, 1.5 f₁, f₃) that EN 1990 A2.4.4.2.1 considers.
    #[arg(long)]
    pub all_modes: bool,
    /// With `--trains`: write `history.csv` and plots for every case, not only for each
    /// train's case of largest deck acceleration and each check's governing case.
    #[arg(long)]
    pub keep_histories: bool,
    /// With `--trains`: LM71's classification factor α (EN 1991-2 §6.3.2(3)): 0.75, 0.83,
    /// 0.91, 1.00, 1.10, 1.21, 1.33 or 1.46.
    #[arg(long, default_value_t = 1.0)]
    pub alpha: f64,
    /// With `--trains`: track maintenance for the LM71 comparison: `careful` (Φ₂ and φ''/2)
    /// or `standard` (Φ₃ and φ''), EN 1991-2 §6.4.5.2.
    #[arg(long, default_value = "careful")]
    pub maintenance: String,
    /// Mean wind speeds, m/s (a list or `start:stop:step`): every train speed in every wind;
    /// `wind_curve.csv` gives per train speed the largest wind that keeps the wheel unloading
    /// ΔQ/Q₀ within `--wheel-unloading-limit` (the characteristic wind curve).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub wind_speeds: Vec<String>,
    /// With `--wind-speeds`: the limit of the wheel unloading ΔQ/Q₀ (EN 14067-6).
    #[arg(long, default_value_t = 0.9)]
    pub wheel_unloading_limit: f64,
    /// Solver (default: the scenario's).
    #[arg(long)]
    pub solver: Option<String>,
    /// Output folder: table.md, table.csv and one run folder per speed.
    #[arg(long, default_value = "tbi-out/sweep")]
    pub out: PathBuf,
    /// Run even when a case's estimated cost, or a design check's estimated disk use,
    /// passes the limits (see `tbi run`).
    #[arg(long)]
    pub allow_large: bool,
}

impl From<SweepArgs> for SweepOptions {
    fn from(a: SweepArgs) -> Self {
        SweepOptions {
            scenario: a.scenario,
            speeds: a.speeds,
            trains: a.trains,
            track: a.track,
            comfort: a.comfort,
            all_modes: a.all_modes,
            keep_histories: a.keep_histories,
            alpha: a.alpha,
            maintenance: a.maintenance,
            wind_speeds: a.wind_speeds,
            wheel_unloading_limit: a.wheel_unloading_limit,
            solver: a.solver,
            out: a.out,
            allow_large: a.allow_large,
        }
    }
}

pub fn main(args: SweepArgs) -> Result<(), Box<dyn std::error::Error>> {
    crate::design::run(&args.into())
}
