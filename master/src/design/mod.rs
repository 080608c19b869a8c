//! Design checks over many runs of one scenario, in parallel on every core:
//!
//! * [`table2`]: the scenario at several speeds, tabulated like the paper's Table 2;
//! * [`hslm`]: the EN 1991-2 dynamic check with the HSLM trains;
//! * [`wind_curve`]: the characteristic wind curve of a train on the bridge.
//!
//! [`run`] chooses among them as `tbi sweep` does; [`speeds`] reads the speeds.

pub mod hslm;
pub mod speeds;
pub mod table2;
pub mod wind_curve;

use std::path::PathBuf;

/// What a sweep runs: the options of `tbi sweep` (and of `tbi.sweep` in Python), with the
/// defaults of [`SweepOptions::default`].
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Speeds, km/h: comma separated, or `start:stop:step` (stop included). Default: the
    /// paper's 20,40,70,120; with `--trains`, EN 1991-2 §6.4.6: from 40 m/s (144 km/h) to
    /// 1.2 × the scenario's speed (its line speed) in 2.5 km/h steps.
    pub speeds: Vec<String>,
    /// Trains replacing the scenario's: `hslm-a` (A1–A10) or names such as `A1,A4`.
    pub trains: Vec<String>,
    /// With `--trains`: the track for the deck acceleration limit, `ballasted` (3.5 m/s²)
    /// or `direct` (fastening, 5 m/s²).
    pub track: String,
    /// With `--trains`: the comfort level of EN 1990 Table A2.9 the car-body vertical
    /// acceleration is checked against when the trains carry vehicles (`train.vehicle`):
    /// `very-good` (1.0 m/s²), `good` (1.3 m/s²) or `acceptable` (2.0 m/s²).
    pub comfort: String,
    /// With `--trains`: keep every mode of the bridge (`bridge.modes_rule = "all"` in every
    /// case), not only those up to max(30 Hz, 1.5 f₁, f₃) that EN 1990 A2.4.4.2.1 considers.
    pub all_modes: bool,
    /// With `--trains`: write `history.csv` and plots for every case, not only for each
    /// train's case of largest deck acceleration and each check's governing case.
    pub keep_histories: bool,
    /// With `--trains`: LM71's classification factor α (EN 1991-2 §6.3.2(3)): 0.75, 0.83,
    /// 0.91, 1.00, 1.10, 1.21, 1.33 or 1.46.
    pub alpha: f64,
    /// With `--trains`: track maintenance for the LM71 comparison: `careful` (Φ₂ and φ''/2)
    /// or `standard` (Φ₃ and φ''), EN 1991-2 §6.4.5.2.
    pub maintenance: String,
    /// Mean wind speeds, m/s (a list or `start:stop:step`): every train speed in every wind;
    /// `wind_curve.csv` gives per train speed the largest wind that keeps the wheel unloading
    /// ΔQ/Q₀ within `--wheel-unloading-limit` (the characteristic wind curve).
    pub wind_speeds: Vec<String>,
    /// With `--wind-speeds`: the limit of the wheel unloading ΔQ/Q₀ (EN 14067-6).
    pub wheel_unloading_limit: f64,
    /// Solver (default: the scenario's).
    pub solver: Option<String>,
    /// Output folder: table.md, table.csv and one run folder per speed.
    pub out: PathBuf,
    /// Run even when a case's estimated cost, or a design check's estimated disk use,
    /// passes the limits (see `tbi run`).
    pub allow_large: bool,
}

impl Default for SweepOptions {
    fn default() -> Self {
        Self {
            scenario: None,
            speeds: Vec::new(),
            trains: Vec::new(),
            track: "ballasted".into(),
            comfort: "very-good".into(),
            all_modes: false,
            keep_histories: false,
            alpha: 1.0,
            maintenance: "careful".into(),
            wind_speeds: Vec::new(),
            wheel_unloading_limit: 0.9,
            solver: None,
            out: PathBuf::from("tbi-out/sweep"),
            allow_large: false,
        }
    }
}

/// Runs the sweep `o` asks for: the HSLM check with `trains`, the wind curve with
/// `wind_speeds`, else the speeds tabulated like Table 2.
pub fn run(o: &SweepOptions) -> Result<(), Box<dyn std::error::Error>> {
    let base = crate::scenario::load(o.scenario.as_deref(), o.solver.as_deref(), None)?;
    let speeds = speeds::of(o, &base)?;
    if !o.trains.is_empty() {
        return hslm::main(o, &speeds);
    }
    if !o.wind_speeds.is_empty() {
        return wind_curve::main(o, &base, &speeds);
    }
    table2::main(o, &base, &speeds)
}
