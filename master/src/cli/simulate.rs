//! `tbi simulate`: run one FMI 2.0 or 3.0 Co-Simulation FMU alone, with the runner of
//! [`fmi_import::simulate`] (its docs list the defaults, which are `fmpy simulate`'s), in a
//! worker process of its own unless `--in-process` is given.

use fmi_import::archive::fmu_display_name;
use fmi_import::remote::WorkerOptions;
use fmi_import::simulate::{
    simulate_into, simulate_isolated_into, InputTable, RunEnd, SimulateError, SimulationOptions,
    SimulationResult,
};
use fmi_import::AnyFmu;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Command-line arguments of `tbi simulate`.
#[derive(Debug, Clone, clap::Args)]
pub struct SimulateArgs {
    /// Path of the FMU (.fmu zip).
    pub fmu: PathBuf,
    /// Start time in s (default: DefaultExperiment startTime, else 0).
    #[arg(long, allow_negative_numbers = true)]
    pub start_time: Option<f64>,
    /// Stop time in s (default: DefaultExperiment stopTime, else start time + 1).
    #[arg(long, allow_negative_numbers = true)]
    pub stop_time: Option<f64>,
    /// Communication step size in s, `fmpy simulate --output-interval` (default:
    /// DefaultExperiment stepSize, doubled to at most 1000 steps, else about
    /// (stop − start)/500 rounded to a "nice" number as FMPy does).
    #[arg(long, allow_negative_numbers = true)]
    pub step_size: Option<f64>,
    /// Relative tolerance passed to fmi2SetupExperiment (default: DefaultExperiment
    /// tolerance, else undefined).
    #[arg(long, allow_negative_numbers = true)]
    pub relative_tolerance: Option<f64>,
    /// CSV file with input signals: first column time, then columns named like variables.
    #[arg(long, value_name = "CSV")]
    pub input: Option<PathBuf>,
    /// Result CSV (default: `<FMU file stem>_out.csv`; `-` for standard output).
    #[arg(long, value_name = "CSV")]
    pub output: Option<PathBuf>,
    /// Set a start value before initialisation (repeatable), e.g. `--set k=2.5`.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Do not print the FMU's log messages (errors still carry them).
    #[arg(long)]
    pub quiet: bool,
    /// Load the FMU into this process instead of a worker process of its own (faster
    /// calls; an FMU that crashes or exits then ends `tbi` with it).
    #[arg(long)]
    pub in_process: bool,
    /// Longest wall time of one FMI call, s: a call that takes longer ends the FMU's worker
    /// and fails the run, naming the call and the time. Default: no limit. Needs the worker
    /// (not with --in-process).
    #[arg(long, value_name = "SECONDS")]
    pub fmu_timeout: Option<f64>,
}

/// The FMU, loaded here (`--in-process`) or to be run by a worker.
enum Runner {
    Here(AnyFmu),
    Worker(WorkerOptions),
}

impl Runner {
    fn simulate_into(
        &self,
        path: &Path,
        options: &SimulationOptions,
        out: &mut dyn Write,
    ) -> Result<SimulationResult, SimulateError> {
        match self {
            Runner::Here(fmu) => simulate_into(fmu, options, out),
            Runner::Worker(worker) => simulate_isolated_into(path, worker, options, out),
        }
    }
}

/// Entry point of `tbi simulate` (the error type is the one all `tbi` subcommands share).
pub fn main(args: SimulateArgs) -> Result<(), Box<dyn std::error::Error>> {
    run(args).map_err(Into::into)
}

/// `tbi simulate` with its own error type.
pub fn run(args: SimulateArgs) -> Result<(), SimulateError> {
    let runner = match super::workers::options(args.in_process, args.fmu_timeout)
        .map_err(SimulateError::Invalid)?
    {
        None => Runner::Here(AnyFmu::load(&args.fmu)?),
        Some(worker) => Runner::Worker(worker),
    };
    let fmu_name = fmu_display_name(&args.fmu);
    let input = args
        .input
        .as_deref()
        .map(InputTable::from_path)
        .transpose()?;
    let mut start_values = Vec::new();
    for item in &args.set {
        let (name, value) = item
            .split_once('=')
            .ok_or_else(|| SimulateError::Invalid(format!("--set {item}: expected NAME=VALUE")))?;
        start_values.push((name.trim().to_owned(), value.trim().to_owned()));
    }
    let options = SimulationOptions {
        start_time: args.start_time,
        stop_time: args.stop_time,
        step_size: args.step_size,
        relative_tolerance: args.relative_tolerance,
        start_values,
        input,
        echo_log: !args.quiet,
        stop_requested: Some(crate::interrupt::interrupted),
    };
    // Rows are written as they are computed: to standard output, or to `<output>.partial`,
    // renamed to `<output>` when the run ends at the stop time or where the FMU ended it
    // (termination, discard); an error or a signal keeps what was computed under the
    // .partial name, so a result file is never half of a run without saying so.
    let result;
    let output_name;
    if args.output.as_deref() == Some(Path::new("-")) {
        output_name = "standard output".to_owned();
        let stdout = io::stdout();
        let mut lock = stdout.lock();
        result = runner.simulate_into(&args.fmu, &options, &mut lock)?;
    } else {
        let path = args.output.clone().unwrap_or_else(|| {
            let stem = args
                .fmu
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "result".into());
            PathBuf::from(format!("{stem}_out.csv"))
        });
        let partial = crate::output::outdir::with_suffix(&path, ".partial");
        let mut inputs = vec![(args.fmu.clone(), "the FMU".to_string())];
        if let Some(i) = &args.input {
            inputs.push((i.clone(), "the --input file".to_string()));
        }
        crate::output::outdir::refuse_inputs(&[path.clone(), partial.clone()], &inputs)
            .map_err(SimulateError::Invalid)?;
        let mut sink = LazyFile::new(&partial);
        let run = runner.simulate_into(&args.fmu, &options, &mut sink);
        let io_error = |error| SimulateError::Io {
            path: partial.display().to_string(),
            error,
        };
        sink.flush().map_err(io_error)?;
        let complete = matches!(
            run,
            Ok(SimulationResult {
                end: RunEnd::Completed | RunEnd::Terminated { .. } | RunEnd::Discarded { .. },
                ..
            })
        );
        if complete {
            std::fs::rename(&partial, &path).map_err(|error| SimulateError::Io {
                path: path.display().to_string(),
                error,
            })?;
            output_name = path.display().to_string();
        } else {
            output_name = partial.display().to_string();
        }
        result = match run {
            Ok(r) => r,
            Err(e) if sink.opened() => {
                return Err(SimulateError::Invalid(format!(
                    "{e} (the rows computed before are in {output_name})"
                )))
            }
            Err(e) => return Err(e),
        };
    }
    match result.end {
        RunEnd::Completed => Ok(()),
        RunEnd::Terminated { time } => {
            if !args.quiet {
                eprintln!(
                    "tbi: {}: the FMU requested termination at t={time}; the simulation ended there",
                    fmu_name
                );
            }
            Ok(())
        }
        RunEnd::Discarded { time } => Err(SimulateError::Discarded {
            fmu: fmu_name.to_owned(),
            time,
            output: output_name,
        }),
        RunEnd::Stopped { time } => Err(SimulateError::Invalid(format!(
            "{}: interrupted by a signal at t={time}; the rows up to there are in {output_name}",
            fmu_name
        ))),
    }
}

/// A file created at the first write (so a run refused before its first row leaves none).
struct LazyFile<'a> {
    path: &'a Path,
    file: Option<io::BufWriter<std::fs::File>>,
}

impl<'a> LazyFile<'a> {
    fn new(path: &'a Path) -> Self {
        LazyFile { path, file: None }
    }

    fn opened(&self) -> bool {
        self.file.is_some()
    }
}

impl Write for LazyFile<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.file.is_none() {
            let f = std::fs::File::create(self.path)
                .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", self.path.display())))?;
            self.file = Some(io::BufWriter::new(f));
        }
        let f = self.file.as_mut().expect("opened above");
        let n = f.write(buf)?;
        // each row reaches the file as it ends: an FMU that ends the process (with
        // --in-process) leaves every row computed before in the .partial file
        if buf[..n].ends_with(b"\n") {
            f.flush()?;
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        match self.file.as_mut() {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}
