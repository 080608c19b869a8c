//! `tbi modes`: the bridge's modes as a table, a modes file and plots of the first shapes.

use crate::model::modes::{mode_set, table};
use crate::output::mode_plots::plot_shapes;
use std::path::PathBuf;

/// Command-line arguments of `tbi modes`.
#[derive(Debug, Clone, clap::Args)]
pub struct ModesArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Output folder for modes.csv, modes.md and mode_shapes.svg.
    #[arg(long, default_value = "tbi-out/modes")]
    pub out: PathBuf,
}

pub fn main(args: ModesArgs) -> Result<(), Box<dyn std::error::Error>> {
    let s = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    let set = mode_set(&s)?;
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let csv = args.out.join("modes.csv");
    set.write(&csv)
        .map_err(|e| format!("{}: {e}", csv.display()))?;
    let t = table(
        &set,
        matches!(s.bridge, crate::scenario::Bridge::Suspension { .. }),
    );
    std::fs::write(args.out.join("modes.md"), &t)?;
    plot_shapes(&args.out.join("mode_shapes.svg"), &set, 6)?;
    crate::say!("{t}");
    eprintln!(
        "tbi: modes.csv, modes.md and mode_shapes.svg in {}",
        args.out.display()
    );
    Ok(())
}
