//! `tbi validate [SCENARIO.toml]`: run a scenario both ways — co-simulation of the FMUs and
//! the monolithic solver — and report how far apart they are.
//!
//! For every column of `history.csv` the difference is `max_t |co − mono| / max_t |mono|`
//! (the monolithic run is the reference; a column that is zero there and not in the
//! co-simulation counts as infinitely different). Columns are grouped into the deck (the
//! probes), the car bodies (`veh…`) and the wheelsets (`ws…`); for each group the worst
//! column is printed with the time of its largest difference. `validation.json` holds the
//! same, and `validation_worst.svg` overlays the worst column of both runs with their
//! difference. With `--tolerance`, a worst difference above it makes the command fail.

use crate::model::Limits;
use crate::output::plots::History;
use crate::scenario::SolverKind;
use crate::solve::compare::{differences, ColumnDifference};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use tbi_coupling::{AccelerationKind, SchemeKind};

/// Command-line arguments of `tbi validate`.
#[derive(Debug, Clone, clap::Args)]
pub struct ValidateArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Coupling scheme of the co-simulation (default: the scenario's).
    #[arg(long)]
    pub scheme: Option<String>,
    /// Acceleration of the implicit scheme (default: the scenario's).
    #[arg(long)]
    pub acceleration: Option<String>,
    /// Fail when the worst relative difference is above this.
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// Output folder (default `tbi-out/<name>-validate`): `monolithic/`, `cosim/`,
    /// `validation.json`, `validation_worst.svg`.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
}

/// The group of a `history.csv` column: a probe's (`mid.…`), a car body's (`veh3.…`, or
/// `train2.veh3.…` of a later train), or a wheelset's.
fn group_of(column: &str, probes: &[String]) -> &'static str {
    let of_train = match column.strip_prefix("train") {
        Some(rest) => rest.split_once('.').map_or(column, |(_, item)| item),
        None => column,
    };
    if probes.iter().any(|p| column.starts_with(&format!("{p}."))) {
        "deck"
    } else if of_train.starts_with("veh") {
        "car bodies"
    } else {
        "wheelsets"
    }
}

pub fn main(args: ValidateArgs) -> Result<(), Box<dyn std::error::Error>> {
    let mut s = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    if let Some(v) = &args.scheme {
        s.coupling.scheme = SchemeKind::from_str(v).map_err(|e| format!("--scheme {v}: {e}"))?;
    }
    if let Some(v) = &args.acceleration {
        s.coupling.acceleration =
            AccelerationKind::from_str(v).map_err(|e| format!("--acceleration {v}: {e}"))?;
    }
    if let Some(t) = args.tolerance {
        if !(t.is_finite() && t >= 0.0) {
            return Err(format!("--tolerance {t}: must be a finite number ≥ 0").into());
        }
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("tbi-out").join(format!("{}-validate", s.name)));
    let limits = Limits::default();
    let mut runs = Vec::new();
    for solver in [SolverKind::Monolithic, SolverKind::Cosim] {
        s.run.solver = solver;
        let dir = out.join(solver.as_str());
        crate::solve::run_scenario(&s, &dir, !args.quiet, &limits)?;
        runs.push(History::read(&dir.join("history.csv"))?);
    }
    let diffs = differences(&runs[0], &runs[1])?;
    let probes: Vec<String> = s.probes.iter().map(|p| p.name.clone()).collect();
    // The largest difference of the columns `keep` selects; the first of equal ones.
    let largest = |keep: &dyn Fn(&ColumnDifference) -> bool| {
        diffs
            .iter()
            .filter(|d| keep(d))
            .fold(None, |best: Option<&ColumnDifference>, d| match best {
                Some(b) if b.relative >= d.relative => Some(b),
                _ => Some(d),
            })
    };
    let groups: Vec<(&str, &ColumnDifference)> = ["deck", "car bodies", "wheelsets"]
        .into_iter()
        .filter_map(|g| largest(&|d| group_of(&d.column, &probes) == g).map(|w| (g, w)))
        .collect();
    let worst = largest(&|_| true).ok_or("the histories have no columns to compare")?;
    crate::say!(
        "{}: co-simulation ({}, {}) against the monolithic solver",
        s.name,
        s.coupling.scheme.as_str(),
        s.coupling.acceleration.as_str()
    );
    crate::say!("| group | worst column | relative difference | at t (s) |\n|---|---|---:|---:|");
    for (g, d) in &groups {
        crate::say!(
            "| {g} | {} | {:.3e} | {:.4} |",
            d.column,
            d.relative,
            d.time_s
        );
    }
    let passed = args.tolerance.is_none_or(|t| worst.relative <= t);
    let json = serde_json::json!({
        "scenario": s.name,
        "scheme": s.coupling.scheme.as_str(),
        "acceleration": s.coupling.acceleration.as_str(),
        "rtol": s.coupling.rtol,
        "groups": groups.iter().map(|(g, d)| serde_json::json!({
            "group": g, "column": d.column, "relative": d.relative, "time_s": d.time_s,
        })).collect::<Vec<_>>(),
        "worst": worst,
        "tolerance": args.tolerance,
        "passed": passed,
    });
    crate::output::outdir::write_atomically(
        &out.join("validation.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    plot_worst(&out.join("validation_worst.svg"), &runs, &worst.column)?;
    eprintln!(
        "tbi: validation.json and validation_worst.svg in {}",
        out.display()
    );
    if !passed {
        return Err(format!(
            "the worst difference, {:.3e} in {} at t = {} s, exceeds --tolerance {}",
            worst.relative,
            worst.column,
            worst.time_s,
            crate::text::num(args.tolerance.expect("checked"))
        )
        .into());
    }
    Ok(())
}

fn plot_worst(path: &Path, runs: &[History], column: &str) -> Result<(), String> {
    let t = runs[0]
        .column("time_s")
        .ok_or("history without time_s")?
        .to_vec();
    let a = runs[0]
        .column(column)
        .ok_or("worst column missing")?
        .to_vec();
    let b = runs[1]
        .column(column)
        .ok_or("worst column missing")?
        .to_vec();
    let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| y - x).collect();
    crate::output::plots::figure(
        path,
        &[
            (
                &format!("{column}: both solvers"),
                "",
                vec![("monolithic".into(), a), ("co-simulation".into(), b)],
            ),
            (
                "co-simulation − monolithic",
                "",
                vec![("difference".into(), d)],
            ),
        ],
        &t,
    )
}

#[cfg(test)]
mod tests {
    use super::group_of;

    #[test]
    fn columns_of_later_trains_fall_in_their_groups() {
        let probes = vec!["mid".to_string(), "train9".to_string()];
        for (column, group) in [
            ("mid.torsion_rad", "deck"),
            ("train9.vertical_displacement_m", "deck"),
            ("veh2.lateral_acceleration_m_s2", "car bodies"),
            ("train2.veh1.lateral_acceleration_m_s2", "car bodies"),
            ("ws4.derail_factor", "wheelsets"),
            ("train2.ws32.vertical_force_n", "wheelsets"),
        ] {
            assert_eq!(group_of(column, &probes), group, "{column}");
        }
    }
}
