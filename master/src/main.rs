//! `tbi`: train–bridge interaction command line.
use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "tbi",
    version,
    about = "Train–bridge dynamic interaction: monolithic solver, FMI 2.0 FMUs and co-simulation master"
)]
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
    /// The bridge's modes: table, modes file and plots of the first shapes.
    Modes(tbi::modes::ModesArgs),
    /// Run a scenario at several speeds in parallel and tabulate like the paper's Table 2.
    Sweep(tbi::sweep::SweepArgs),
    /// The embedded default scenario.
    Scenario {
        #[command(subcommand)]
        what: ScenarioCommand,
    },
    /// Speed measurements (monolithic, co-simulation, FE modes, sweep).
    Bench(tbi::bench::BenchArgs),
    /// Run any FMI 2.0 Co-Simulation FMU alone (same defaults and CSV layout as `fmpy simulate`).
    Simulate(tbi::simulate::SimulateArgs),
    /// Run an SSP 1.0 system of FMI 2.0 Co-Simulation FMUs with the coupling algorithms.
    Cosim(tbi::cosim_cmd::CosimArgs),
    /// Run a scenario both ways (FMUs and monolithic) and report their differences.
    Validate(tbi::validate::ValidateArgs),
}

#[derive(Subcommand)]
enum ScenarioCommand {
    /// Print the embedded default scenario (the Tsing Ma case) as TOML.
    Show,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Long runs stop cleanly on a signal (the others keep the default: end at once).
    if matches!(
        cli.command,
        Command::Run(_)
            | Command::Sweep(_)
            | Command::Bench(_)
            | Command::Simulate(_)
            | Command::Cosim(_)
            | Command::Validate(_)
    ) {
        tbi::interrupt::install();
    }
    let result = match cli.command {
        Command::Simulate(args) => tbi::simulate::main(args),
        Command::Cosim(args) => tbi::cosim_cmd::main(args),
        Command::Validate(args) => tbi::validate::main(args),
        Command::Run(args) => tbi::run::main(args),
        Command::Export(args) => tbi::export::main(args),
        Command::Modes(args) => tbi::modes::main(args),
        Command::Sweep(args) => tbi::sweep::main(args),
        Command::Scenario {
            what: ScenarioCommand::Show,
        } => {
            print!("{}", tbi::scenario::DEFAULT_SCENARIO);
            Ok(())
        }
        Command::Bench(args) => tbi::bench::main(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tbi: error: {e:#}");
            if tbi::interrupt::interrupted() {
                ExitCode::from(130)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
