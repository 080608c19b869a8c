//! `tbi export`: a scenario's FMUs and SSP system into a folder.

use crate::fmus::export::export_scenario;
use std::path::PathBuf;

/// Command-line arguments of `tbi export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Output folder for bridge.fmu, train.fmu (wind.fmu) and system.ssp.
    #[arg(long)]
    pub out: PathBuf,
}

pub fn main(args: ExportArgs) -> Result<(), Box<dyn std::error::Error>> {
    let scenario = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    let e = export_scenario(&scenario, &args.out)?;
    crate::say!(
        "{}\n{}\n{}",
        e.bridge.display(),
        e.train.display(),
        e.ssp.display()
    );
    Ok(())
}
