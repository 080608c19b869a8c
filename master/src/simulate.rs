//! `tbi simulate`: run one FMI 2.0 Co-Simulation FMU alone.

/// Command-line arguments of `tbi simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// Path of the FMU (.fmu zip).
    pub fmu: std::path::PathBuf,
}

pub fn main(args: SimulateArgs) -> Result<(), Box<dyn std::error::Error>> {
    Err(format!("{}: simulate is not available yet", args.fmu.display()).into())
}
