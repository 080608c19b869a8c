//! `tbi`: train–bridge interaction command line.
//!
//! Exit codes: 0 every check passes, 1 an error, 2 a command line refused, 3 a check FAILs
//! (`tbi run`'s limits, `tbi sweep --trains`' design checks),
//! 130 interrupted by a signal. A closed standard output ends the printing quietly.
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
    /// Print an embedded scenario as TOML: the default (the Tsing Ma case), or an example
    /// by name (`tbi scenario list`).
    Show {
        /// The example's name (default: the Tsing Ma case).
        name: Option<String>,
    },
    /// The embedded scenarios' names, one per line, with what each is.
    List,
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
            what: ScenarioCommand::Show { name },
        } => tbi::scenario::examples::text(name.as_deref()).map(|t| {
            tbi::say!("{}", t.trim_end());
        }),
        Command::Scenario {
            what: ScenarioCommand::List,
        } => {
            for (name, what, _) in tbi::scenario::examples::EXAMPLES {
                tbi::say!("{name}\t{what}");
            }
            Ok(())
        }
        Command::Bench(args) => tbi::bench::main(args),
    };
    match result {
        Ok(()) if tbi::console::any_check_failed() => {
            ExitCode::from(tbi::console::EXIT_CHECK_FAILED)
        }
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tbi: error: {e:#}");
            if e.downcast_ref::<tbi::console::UsageError>().is_some() {
                ExitCode::from(2)
            } else if tbi::interrupt::interrupted() {
                ExitCode::from(130)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
