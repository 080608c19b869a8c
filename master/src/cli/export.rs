//! `tbi export`: a scenario's FMUs and SSP system into a folder.

use crate::fmus::export::{export_scenario, FmiVersion};
use std::path::PathBuf;

/// Command-line arguments of `tbi export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Output folder for bridge.fmu, train.fmu (wind.fmu) and system.ssp.
    #[arg(long)]
    pub out: PathBuf,
    /// FMI version of the FMUs: 2 (FMI 2.0) or 3 (FMI 3.0 Co-Simulation, the same models
    /// and variables).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub fmi_version: u8,
}

pub fn main(args: ExportArgs) -> Result<(), Box<dyn std::error::Error>> {
    let scenario = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    let version = FmiVersion::from_major(args.fmi_version)?;
    let e = export_scenario(&scenario, &args.out, version)?;
    let mut files = vec![
        e.bridge.display().to_string(),
        e.train.display().to_string(),
    ];
    files.extend(e.more_trains.iter().map(|t| t.path.display().to_string()));
    if let Some((wind, _, _)) = &e.wind {
        files.push(wind.display().to_string());
    }
    files.push(e.ssp.display().to_string());
    crate::say!("{}", files.join("\n"));
    Ok(())
}
