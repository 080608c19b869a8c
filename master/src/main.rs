//! `tbi`: train–bridge interaction command line.
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "tbi", version, about = "Train–bridge dynamic interaction: monolithic solver, FMI 2.0 FMUs and co-simulation master")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scenario (default: the embedded Tsing Ma case) and write summary.json, history.csv and plots.
    Run(tbi::run::RunArgs),
    /// Package a scenario's bridge and train as FMI 2.0 Co-Simulation FMUs plus an SSP system.
    Export(tbi::export::ExportArgs),
    /// Run any FMI 2.0 Co-Simulation FMU alone (same defaults and CSV layout as `fmpy simulate`).
    Simulate(tbi::simulate::SimulateArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate(args) => tbi::simulate::main(args),
        Command::Run(args) => tbi::run::main(args),
        Command::Export(args) => tbi::export::main(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tbi: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
