//! `tbi sweep`: one scenario at several speeds (a list, or `start:stop:step` in km/h), run
//! in parallel on every core.
//!
//! * Without `--trains`: summarised in the layout of the paper's Table 2 (maximum responses of
//!   bridge and vehicles) beside the paper's values (`table.md`, `table.csv`).
//! * With `--trains hslm-a` (the ten EN 1991-2 HSLM-A trains) or a list such as `A1,A4`: every
//!   train at every speed as moving forces on the scenario's bridge, with one progress bar;
//!   `envelope.csv` has one row per train and speed (the largest deck vertical acceleration
//!   and displacement over the probes), and the governing train and speed are printed.

use crate::run::run_scenario;
use crate::summary::Summary;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;
use tbi_dynamics::response::ProbeMax;

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

/// One row of Table 2: name, unit, scale from SI, extractor, paper values at 20/40/70/120 km/h.
pub struct Row {
    pub name: &'static str,
    pub unit: &'static str,
    pub paper: [f64; 4],
    pub value: fn(&Summary) -> f64,
}

/// The largest value of one maximum over the probes.
fn probe_max(s: &Summary, key: fn(&ProbeMax) -> f64) -> f64 {
    s.probes.values().map(key).fold(0.0, f64::max)
}

/// The paper's speeds, km/h.
pub const PAPER_SPEEDS: [f64; 4] = [20.0, 40.0, 70.0, 120.0];

/// Table 2 of Xia, Xu & Chan (2000) and how each row is read from a summary.
pub const TABLE2: [Row; 8] = [
    Row {
        name: "Deck vertical displacement",
        unit: "cm",
        paper: [49.39, 49.52, 51.29, 54.04],
        value: |s| 100.0 * probe_max(s, |p| p.vertical_displacement_max_m),
    },
    Row {
        name: "Deck vertical acceleration",
        unit: "cm/s²",
        paper: [0.0845, 0.332, 0.878, 3.156],
        value: |s| 100.0 * probe_max(s, |p| p.vertical_acceleration_max_m_s2),
    },
    Row {
        name: "Deck lateral displacement",
        unit: "mm",
        paper: [15.07, 10.83, 8.058, 4.686],
        value: |s| 1000.0 * probe_max(s, |p| p.lateral_displacement_max_m),
    },
    Row {
        name: "Deck lateral acceleration",
        unit: "cm/s²",
        paper: [0.931, 1.097, 1.298, 2.234],
        value: |s| 100.0 * probe_max(s, |p| p.lateral_acceleration_max_m_s2),
    },
    Row {
        name: "Vehicle vertical acceleration",
        unit: "cm/s²",
        paper: [12.96, 31.85, 48.29, 74.31],
        value: |s| {
            s.vehicles
                .as_ref()
                .map_or(f64::NAN, |v| 100.0 * v.vertical_acceleration_max_m_s2)
        },
    },
    Row {
        name: "Vehicle lateral acceleration",
        unit: "cm/s²",
        paper: [19.01, 38.19, 40.05, 51.92],
        value: |s| {
            s.vehicles
                .as_ref()
                .map_or(f64::NAN, |v| 100.0 * v.lateral_acceleration_max_m_s2)
        },
    },
    Row {
        name: "Derail factor",
        unit: "Q/P",
        paper: [0.247, 0.287, 0.306, 0.413],
        value: |s| s.safety.as_ref().map_or(f64::NAN, |f| f.derail_factor_max),
    },
    Row {
        name: "Offload factor",
        unit: "ΔP/P",
        paper: [0.380, 0.381, 0.393, 0.410],
        value: |s| s.safety.as_ref().map_or(f64::NAN, |f| f.offload_factor_max),
    },
];

/// The speeds of `--speeds`: numbers, or `start:stop:step` ranges (stop included when it
/// is a whole number of steps from the start, to 1e-9 of a step); a speed given twice is
/// refused.
pub fn parse_speeds(items: &[String]) -> Result<Vec<f64>, String> {
    parse_range(items, "--speeds", "km/h")
}

/// Values of option `flag` (in `unit`): comma-separated items, each a number or
/// `start:stop:step` (stop included); each value once.
pub fn parse_range(items: &[String], flag: &str, unit: &str) -> Result<Vec<f64>, String> {
    let number = |t: &str| -> Result<f64, String> {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{flag}: \"{}\" is not a number", t.trim()))
    };
    let mut speeds = Vec::new();
    for item in items {
        let parts: Vec<&str> = item.split(':').collect();
        match parts.as_slice() {
            [v] => speeds.push(number(v)?),
            [a, b, c] => {
                let (start, stop, step) = (number(a)?, number(b)?, number(c)?);
                if step <= 0.0 || stop < start {
                    return Err(format!(
                        "{flag} {item}: expected start:stop:step with stop ≥ start and step > 0"
                    ));
                }
                let n = ((stop - start) / step + 1e-9).floor();
                if n > 100_000.0 {
                    return Err(format!("{flag} {item}: {n} values, more than 100000"));
                }
                speeds.extend((0..=n as usize).map(|k| start + k as f64 * step));
            }
            _ => {
                return Err(format!(
                    "{flag} {item}: expected a number or start:stop:step"
                ))
            }
        }
    }
    if speeds.is_empty() {
        return Err(format!("{flag}: give at least one value"));
    }
    for (i, v) in speeds.iter().enumerate() {
        if speeds[..i].contains(v) {
            return Err(format!(
                "{flag}: {} {unit} is given twice",
                crate::model::num(*v)
            ));
        }
    }
    Ok(speeds)
}

/// The speeds of a sweep: `--speeds`, or by default the paper's four, or with `--trains`
/// EN 1991-2 §6.4.6's 40 m/s (144 km/h) to 1.2 × the scenario's speed in 2.5 km/h steps.
pub fn speeds(
    args: &SweepArgs,
    base: &crate::scenario::Scenario,
) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    Ok(match (args.speeds.is_empty(), args.trains.is_empty()) {
        (false, _) => parse_speeds(&args.speeds)?,
        (true, true) => PAPER_SPEEDS.to_vec(),
        (true, false) => {
            let top = 1.2 * base.run.speed_kmh;
            if top < 144.0 {
                return Err(format!(
                    "--speeds: the default range 144 km/h to 1.2 × the scenario's {} km/h is empty; give --speeds",
                    crate::model::num(base.run.speed_kmh)
                )
                .into());
            }
            parse_speeds(&[format!("144:{top}:2.5")])?
        }
    })
}

pub fn main(args: SweepArgs) -> Result<(), Box<dyn std::error::Error>> {
    let base = crate::scenario::load(args.scenario.as_deref(), args.solver.as_deref(), None)?;
    let speeds = speeds(&args, &base)?;
    if !args.trains.is_empty() {
        return crate::design::main(&args, &speeds);
    }
    if !args.wind_speeds.is_empty() {
        return crate::wind_curve::main(&args, &base, &speeds);
    }
    let mut cases = Vec::with_capacity(speeds.len());
    for &v in &speeds {
        let mut s = base.clone();
        s.set_speed_kmh(v).map_err(|e| format!("--speeds: {e}"))?;
        cases.push((v, s));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let limits = if args.allow_large {
        crate::model::Limits::none()
    } else {
        crate::model::Limits::default()
    };
    // The bridge model is shared: build it once before the parallel runs.
    crate::model::build_bridge(&base)?;
    let results: Vec<Result<Summary, String>> = cases
        .par_iter()
        .map(|(v, s)| {
            let v = crate::model::num(*v);
            let dir = args.out.join(format!("v{v}"));
            run_scenario(s, &dir, false, &limits).map_err(|e| format!("{v} km/h: {e}"))
        })
        .collect();
    let mut summaries = Vec::new();
    for r in results {
        summaries.push(r?);
    }
    let (md, csv) = tables(&speeds, &summaries);
    std::fs::write(args.out.join("table.md"), &md)?;
    std::fs::write(args.out.join("table.csv"), &csv)?;
    crate::say!("{md}");
    eprintln!(
        "tbi: table.md, table.csv and the runs in {}",
        args.out.display()
    );
    Ok(())
}

/// Table 2 as Markdown and CSV: ours, the paper's value at the same speed, and the ratio.
pub fn tables(speeds: &[f64], summaries: &[Summary]) -> (String, String) {
    let mut md = String::from("| Response | Unit |");
    let mut csv = String::from("response,unit");
    for v in speeds {
        let v = crate::model::num(*v);
        let _ = write!(md, " {v} km/h: ours | paper | ratio |");
        let _ = write!(csv, ",ours_{v}_kmh,paper_{v}_kmh,ratio_{v}_kmh");
    }
    md.push_str("\n|---|---|");
    for _ in speeds {
        md.push_str("---:|---:|---:|");
    }
    md.push('\n');
    csv.push('\n');
    for row in &TABLE2 {
        let _ = write!(md, "| {} | {} |", row.name, row.unit);
        let _ = write!(csv, "{},{}", row.name, row.unit);
        for (v, s) in speeds.iter().zip(summaries) {
            let ours = (row.value)(s);
            let paper = PAPER_SPEEDS
                .iter()
                .position(|p| (p - v).abs() < 1e-9)
                .map(|i| row.paper[i]);
            match paper {
                Some(p) => {
                    let _ = write!(md, " {ours:.4} | {p} | {:.2} |", ours / p);
                    let _ = write!(csv, ",{ours},{p},{}", ours / p);
                }
                None => {
                    let _ = write!(md, " {ours:.4} | – | – |");
                    let _ = write!(csv, ",{ours},,");
                }
            }
        }
        md.push('\n');
        csv.push('\n');
    }
    (md, csv)
}
