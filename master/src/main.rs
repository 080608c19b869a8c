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
    about = "Train–bridge dynamic interaction: monolithic solver, FMI 2.0/3.0 FMUs and co-simulation master"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scenario (default: the embedded Tsing Ma case) and write summary.json, history.csv and plots.
    Run(tbi::cli::run::RunArgs),
    /// Package a scenario's bridge and train as FMI 2.0 (or 3.0) Co-Simulation FMUs plus an SSP system.
    Export(tbi::cli::export::ExportArgs),
    /// The bridge's modes: table, modes file and plots of the first shapes.
    Modes(tbi::cli::modes::ModesArgs),
    /// Run a scenario at several speeds in parallel and tabulate like the paper's Table 2.
    Sweep(tbi::cli::sweep::SweepArgs),
    /// The embedded default scenario.
    Scenario {
        #[command(subcommand)]
        what: ScenarioCommand,
    },
    /// Speed measurements (monolithic, co-simulation, FE modes, sweep).
    Bench(tbi::cli::bench::BenchArgs),
    /// Run any FMI 2.0 or 3.0 Co-Simulation FMU alone (same defaults and CSV layout as `fmpy simulate`).
    Simulate(tbi::cli::simulate::SimulateArgs),
    /// Run an SSP 1.0 system of FMI 2.0 and 3.0 Co-Simulation FMUs with the coupling algorithms.
    Cosim(tbi::cli::cosim::CosimArgs),
    /// Run a scenario both ways (FMUs and monolithic) and report their differences.
    Validate(tbi::cli::validate::ValidateArgs),
    /// Serve one FMU instance to a master over standard input (started by `tbi cosim`).
    #[command(hide = true)]
    FmuWorker,
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
        Command::FmuWorker => {
            return ExitCode::from(fmi_import::remote::serve().clamp(0, 255) as u8);
        }
        Command::Simulate(args) => tbi::cli::simulate::main(args),
        Command::Cosim(args) => tbi::cli::cosim::main(args),
        Command::Validate(args) => tbi::cli::validate::main(args),
        Command::Run(args) => tbi::cli::run::main(args),
        Command::Export(args) => tbi::cli::export::main(args),
        Command::Modes(args) => tbi::cli::modes::main(args),
        Command::Sweep(args) => tbi::cli::sweep::main(args),
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
        Command::Bench(args) => tbi::cli::bench::main(args),
    };
    match result {
        Ok(()) if tbi::output::console::any_check_failed() => {
            ExitCode::from(tbi::output::console::EXIT_CHECK_FAILED)
        }
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tbi: error: {e:#}");
            if e.downcast_ref::<tbi::output::console::UsageError>()
                .is_some()
            {
                ExitCode::from(2)
            } else if tbi::interrupt::interrupted() {
                ExitCode::from(130)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}
