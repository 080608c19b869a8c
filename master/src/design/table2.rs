//! The scenario at several speeds, summarised in the layout of the paper's Table 2 (maximum
//! responses of bridge and vehicles) beside the paper's values (`table.md`, `table.csv`).

use super::SweepOptions;
use crate::output::summary::Summary;
use crate::solve::run_scenario;
use rayon::prelude::*;
use std::fmt::Write as _;
use tbi_dynamics::response::ProbeMax;

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

/// Table 2 of Xia, Xu & Chan (2000) and how each row is read from a summary, in the units
/// of the short summary (displacements in mm, accelerations in m/s²; the paper's cm and
/// cm/s² converted).
pub const TABLE2: [Row; 8] = [
    Row {
        name: "Deck vertical displacement",
        unit: "mm",
        paper: [493.9, 495.2, 512.9, 540.4],
        value: |s| 1000.0 * probe_max(s, |p| p.vertical_displacement_max_m),
    },
    Row {
        name: "Deck vertical acceleration",
        unit: "m/s²",
        paper: [0.000845, 0.00332, 0.00878, 0.03156],
        value: |s| probe_max(s, |p| p.vertical_acceleration_max_m_s2),
    },
    Row {
        name: "Deck lateral displacement",
        unit: "mm",
        paper: [15.07, 10.83, 8.058, 4.686],
        value: |s| 1000.0 * probe_max(s, |p| p.lateral_displacement_max_m),
    },
    Row {
        name: "Deck lateral acceleration",
        unit: "m/s²",
        paper: [0.00931, 0.01097, 0.01298, 0.02234],
        value: |s| probe_max(s, |p| p.lateral_acceleration_max_m_s2),
    },
    Row {
        name: "Vehicle vertical acceleration",
        unit: "m/s²",
        paper: [0.1296, 0.3185, 0.4829, 0.7431],
        value: |s| {
            s.vehicles
                .as_ref()
                .map_or(f64::NAN, |v| v.vertical_acceleration_max_m_s2)
        },
    },
    Row {
        name: "Vehicle lateral acceleration",
        unit: "m/s²",
        paper: [0.1901, 0.3819, 0.4005, 0.5192],
        value: |s| {
            s.vehicles
                .as_ref()
                .map_or(f64::NAN, |v| v.lateral_acceleration_max_m_s2)
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

/// The scenario `base` at `speeds` (km/h) into `args.out`: one run folder per speed,
/// `table.md` and `table.csv` (printed).
pub fn main(
    args: &SweepOptions,
    base: &crate::scenario::Scenario,
    speeds: &[f64],
) -> Result<(), Box<dyn std::error::Error>> {
    let mut cases = Vec::with_capacity(speeds.len());
    for &v in speeds {
        let mut s = base.clone();
        s.set_speed_kmh(v).map_err(|e| format!("--speeds: {e}"))?;
        cases.push((v, s));
    }
    // the sweep owns its folder: a second sweep into it is refused before any case runs
    let _claim = crate::output::outdir::OutputDir::claim(&args.out)?;
    let limits = if args.allow_large {
        crate::model::Limits::none()
    } else {
        crate::model::Limits::default()
    };
    // The bridge model is shared: build it once before the parallel runs.
    crate::model::build_bridge(base)?;
    let results: Vec<Result<Summary, String>> = cases
        .par_iter()
        .map(|(v, s)| {
            let v = crate::text::num(*v);
            let dir = args.out.join(format!("v{v}"));
            run_scenario(s, &dir, false, &limits).map_err(|e| format!("{v} km/h: {e}"))
        })
        .collect();
    let mut summaries = Vec::new();
    for r in results {
        summaries.push(r?);
    }
    let (md, csv) = tables(speeds, &summaries);
    crate::output::outdir::write_atomically(&args.out.join("table.md"), md.as_bytes())?;
    crate::output::outdir::write_atomically(&args.out.join("table.csv"), csv.as_bytes())?;
    crate::say!("{md}");
    eprintln!(
        "tbi: table.md, table.csv and the runs in {}",
        args.out.display()
    );
    Ok(())
}

/// `x` to five significant digits (a value in mm and one in m/s² both keep their digits).
fn significant(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let decimals = (4 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{x:.decimals$}")
}

/// Table 2 as Markdown and CSV: ours, the paper's value at the same speed, and the ratio.
pub fn tables(speeds: &[f64], summaries: &[Summary]) -> (String, String) {
    let mut md = String::from("| Response | Unit |");
    let mut csv = String::from("response,unit");
    for v in speeds {
        let v = crate::text::num(*v);
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
                    let _ = write!(md, " {} | {p} | {:.2} |", significant(ours), ours / p);
                    let _ = write!(csv, ",{ours},{p},{}", ours / p);
                }
                None => {
                    let _ = write!(md, " {} | – | – |", significant(ours));
                    let _ = write!(csv, ",{ours},,");
                }
            }
        }
        md.push('\n');
        csv.push('\n');
    }
    (md, csv)
}
