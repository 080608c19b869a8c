//! `tbi cosim SYSTEM.ssp`: run any SSP 1.0 system of FMI 2.0 and 3.0 Co-Simulation FMUs with the
//! coupling algorithms of [`tbi_coupling`] (see [`tbi_ssp`] for what is read).
//!
//! Times and step: the command line, else the SSD (`DefaultExperiment`, and `step_size`
//! of the coupling annotation); the step size is required. Coupling options: the
//! command line over the annotation over the defaults of [`CouplingConfig`].
//!
//! Output: a CSV (default `<SYSTEM stem>_out.csv`) with `time`, then the system's own
//! outputs by name (the annotation's `tbi:Output`s: `tbi export` declares each probe's deck
//! response and each car body's accelerations), or with `--record-all` (or a system that
//! declares none) every connected output as `component.variable` (in connection order;
//! Integer and Boolean values as integers, Booleans 0/1), then the `--record` variables. Its
//! size is estimated first and refused past 2 GiB (`--allow-large`); a row
//! after initialisation and one after each communication step (with `--output-interval`,
//! after each step ending at a multiple of the interval, and after the last), every number in full
//! precision (shortest round-trip form, scientific notation as in `history.csv`). Beside it `<CSV>.json`: steps, iterations per step
//! (mean, max), the largest final residual of the interface iteration (explicit schemes:
//! the interface defect, also printed, with a word when it passes
//! [`EXPLICIT_DEFECT_NOTICE`]) in tolerances and relative, with its measure named, the
//! options used (the acceleration `null` for an explicit scheme), and the connections the scheme lagged by one
//! step per pair of components (`lagged_connections`: for Gauss–Seidel the connections
//! that close a cycle in the SSD's component order).

use crate::solve::system::{
    lagged_connections, step_and_record, steps_per_row, Column, Times, RESIDUAL_MEASURE,
};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use tbi_coupling::CouplingStatistics;
use tbi_coupling::{AccelerationKind, CouplingConfig, SchemeKind};

/// Command-line arguments of `tbi cosim`.
#[derive(Debug, Clone, clap::Args)]
pub struct CosimArgs {
    /// The system: a `.ssp` archive or a `SystemStructure.ssd` file.
    pub system: PathBuf,
    /// Start time, s (default: DefaultExperiment startTime, else 0).
    #[arg(long, allow_negative_numbers = true)]
    pub start_time: Option<f64>,
    /// Stop time, s (default: DefaultExperiment stopTime).
    #[arg(long, allow_negative_numbers = true)]
    pub stop_time: Option<f64>,
    /// Communication step, s (default: the annotation's step_size).
    #[arg(long, allow_negative_numbers = true)]
    pub step_size: Option<f64>,
    /// Coupling scheme: `implicit` (the interface iterated in every step until it converges:
    /// the monolithic solution), `gauss-seidel` or `jacobi` (explicit: one pass, inputs
    /// lagged). Default: the annotation's, else `implicit`.
    #[arg(long)]
    pub scheme: Option<String>,
    /// Acceleration of the implicit scheme: `iqn-ils`, `aitken`, `newton` or `constant`.
    /// Default: the annotation's, else `iqn-ils` reusing the last 8 steps' columns. Refused
    /// with an explicit scheme.
    #[arg(long)]
    pub acceleration: Option<String>,
    /// Relative tolerance of the interface: a step converges when the weighted RMS of the
    /// change of the exchanged values, each over rtol·max|value of its group| + atol, is ≤ 1.
    /// Default: the annotation's, else 1e-10.
    #[arg(long, allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance of the interface, in the units of the exchanged values (> 0).
    /// Default: the annotation's, else 1e-12.
    #[arg(long, allow_negative_numbers = true)]
    pub atol: Option<f64>,
    /// Most sweeps of the implicit scheme in one step. Default: the annotation's, else 50.
    #[arg(long)]
    pub max_iterations: Option<usize>,
    /// Set a parameter or input before initialisation: `COMPONENT.VARIABLE=VALUE`.
    #[arg(long = "set", value_name = "COMPONENT.VARIABLE=VALUE")]
    pub set: Vec<String>,
    /// Also record `COMPONENT.VARIABLE` (repeatable).
    #[arg(long = "record", value_name = "COMPONENT.VARIABLE")]
    pub record: Vec<String>,
    /// Record every connected output, not only the system's own outputs (the probes and car
    /// bodies `tbi export` declares). A system that declares none records every connected
    /// output anyway.
    #[arg(long)]
    pub record_all: bool,
    /// Result CSV. Default: `<SYSTEM stem>_out.csv` in the working folder.
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Time between result rows, s: a whole multiple of the step size. Default: the
    /// annotation's `output_interval` (`tbi export` writes the scenario's
    /// `dt_s × output_every`) where it is a whole multiple of the step, else a row after
    /// every step. The last step always has a row.
    #[arg(long, allow_negative_numbers = true)]
    pub output_interval: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Write the CSV even when its estimated size passes 2 GiB (the limit of `tbi run`).
    #[arg(long)]
    pub allow_large: bool,
    /// Load every FMU into this process instead of one worker process per FMU (faster
    /// calls; an FMU that crashes or exits then ends `tbi` with it).
    #[arg(long)]
    pub in_process: bool,
    /// Longest wall time of one FMI call, s: a call that takes longer ends its FMU's worker
    /// and fails the run, naming the component, the call and the time. Default: no limit.
    /// Needs the FMUs in worker processes (not with --in-process).
    #[arg(long, value_name = "SECONDS")]
    pub fmu_timeout: Option<f64>,
}

/// The size an explicit scheme's interface defect may reach, relative to the values, before
/// `tbi cosim` suggests the implicit scheme: 1e-3 (0.1 %).
pub const EXPLICIT_DEFECT_NOTICE: f64 = 1e-3;

fn split_name(item: &str, option: &str) -> Result<(String, String), String> {
    item.split_once('.')
        .map(|(c, v)| (c.to_owned(), v.to_owned()))
        .ok_or_else(|| format!("{option} {item}: expected COMPONENT.VARIABLE"))
}

pub fn main(args: CosimArgs) -> Result<(), Box<dyn std::error::Error>> {
    let open = tbi_ssp::open(&args.system)?;
    let (cfg, annotated_step) = coupling(&args, &open)?;
    let (start, stop, h, steps, every) = timing(&args, &open, annotated_step)?;
    let isolation = super::workers::options(args.in_process, args.fmu_timeout)?;
    let mut wired = tbi_ssp::wire_with(
        &open,
        &parameter_sets(&args)?,
        start,
        stop,
        isolation.as_ref(),
    )?;
    if cfg.scheme == SchemeKind::Implicit {
        can_iterate(&open, &wired)?;
    }
    let (all, columns) = recorded_columns(&args, &open, &wired)?;
    let output = output_file(&args, columns.len(), steps / every + 2)?;
    let times = (start, stop, h, steps, every);
    let (stats, partial, sidecar, failure) = record(
        &args,
        &open,
        &mut wired.system,
        &columns,
        &cfg,
        times,
        &output,
    )?;
    let lagged = lagged_connections(&wired.system, cfg.scheme, &open.ssd.components);
    let summary = serde_json::json!({
        "system": open.origin,
        "start_time_s": start,
        "stop_time_s": stop,
        "step_size_s": h,
        "scheme": cfg.scheme.as_str(),
        "acceleration": (cfg.scheme == SchemeKind::Implicit).then(|| cfg.acceleration.as_str()),
        "rtol": cfg.rtol,
        "atol": cfg.atol,
        "recorded": if all { "every connected output" } else { "the system's outputs" },
        "steps": stats.steps,
        "iterations_mean": stats.mean_iterations(),
        "iterations_max": stats.max_iterations,
        "steps_by_iterations": stats.steps_by_iterations,
        "jacobian_probes": stats.jacobian_probes,
        "residual_measure": RESIDUAL_MEASURE,
        "max_residual_in_tolerances": stats.max_residual,
        "max_residual_relative": stats.max_residual * cfg.rtol,
        "accepted_unconverged": stats.accepted_unconverged,
        "lagged_connections": lagged,
    });
    // the side-car and the CSV replace an earlier pair together: the side-car written whole
    // under a temporary name, the CSV renamed, then the side-car
    let staged =
        crate::output::outdir::with_suffix(&sidecar, &format!(".tmp-{}", std::process::id()));
    std::fs::write(&staged, serde_json::to_string_pretty(&summary)?)
        .map_err(|e| format!("{}: {e}", staged.display()))?;
    std::fs::rename(&partial, &output).map_err(|e| format!("{}: {e}", output.display()))?;
    std::fs::rename(&staged, &sidecar).map_err(|e| format!("{}: {e}", sidecar.display()))?;
    let _ = std::fs::remove_file(&failure);
    if cfg.scheme != SchemeKind::Implicit {
        let relative = stats.max_residual * cfg.rtol;
        eprintln!(
            "tbi: {} scheme: interface defect up to {relative:.3e} relative ({:.3e} tolerances): how far the inputs each FMU stepped with, lagged by the scheme, were from the outputs they stand for{}",
            cfg.scheme.as_str(),
            stats.max_residual,
            if relative > EXPLICIT_DEFECT_NOTICE {
                "; above 0.1 %: the results differ from the coupled solution by about that much, use --scheme implicit"
            } else {
                ""
            }
        );
    }
    if !args.quiet {
        eprintln!(
            "tbi: {} steps, {:.2} iterations per step; results in {}",
            stats.steps,
            stats.mean_iterations(),
            output.display()
        );
    }
    Ok(())
}

/// The coupling options: the system's annotation, then the command line's.
fn coupling(
    args: &CosimArgs,
    open: &tbi_ssp::OpenSystem,
) -> Result<(CouplingConfig, Option<f64>), Box<dyn std::error::Error>> {
    let (mut cfg, annotated_step): (CouplingConfig, Option<f64>) = open.coupling()?;
    if let Some(s) = &args.scheme {
        cfg.scheme = SchemeKind::from_str(s).map_err(|e| format!("--scheme {s}: {e}"))?;
    }
    if let Some(a) = &args.acceleration {
        cfg.acceleration =
            AccelerationKind::from_str(a).map_err(|e| format!("--acceleration {a}: {e}"))?;
        if cfg.scheme != SchemeKind::Implicit {
            return Err(crate::output::console::UsageError(format!(
                "--acceleration {a} with --scheme {}: an explicit scheme makes one pass per step and accelerates nothing; drop --acceleration or use --scheme implicit",
                cfg.scheme.as_str()
            ))
            .into());
        }
    }
    if let Some(v) = args.rtol {
        cfg.rtol = v;
    }
    if let Some(v) = args.atol {
        cfg.atol = v;
    }
    if let Some(v) = args.max_iterations {
        cfg.max_iterations = v;
    }
    cfg.validate()
        .map_err(|e| format!("coupling options: {e}"))?;
    Ok((cfg, annotated_step))
}

/// `(start, stop, h, steps, every)`: the run's times and communication step (the command
/// line's, else the system's), its number of steps and the steps per result row.
fn timing(
    args: &CosimArgs,
    open: &tbi_ssp::OpenSystem,
    annotated_step: Option<f64>,
) -> Result<Times, Box<dyn std::error::Error>> {
    let start = args.start_time.or(open.ssd.start_time).unwrap_or(0.0);
    let stop = args
        .stop_time
        .or(open.ssd.stop_time)
        .ok_or_else(|| format!("{}: no stop time (give --stop-time)", open.origin))?;
    let h = args
        .step_size
        .or(annotated_step)
        .ok_or_else(|| format!("{}: no communication step (give --step-size)", open.origin))?;
    if !(start.is_finite() && stop.is_finite() && stop > start) {
        return Err(format!(
            "start time {start} s and stop time {stop} s: the stop must come after the start"
        )
        .into());
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(format!("--step-size {h}: must be a positive number").into());
    }
    let steps = ((stop - start) / h - 1e-9).ceil().max(1.0);
    if steps > 1e7 {
        return Err(format!(
            "the run would take {steps:.3e} communication steps, more than the limit of 1e7"
        )
        .into());
    }
    let steps = steps as usize;
    let every = match (args.output_interval, open.output_interval()?) {
        (Some(dt), _) => steps_per_row(dt, h)?,
        // the annotation's, where it is a whole number of this run's steps
        (None, Some(dt)) => steps_per_row(dt, h).unwrap_or(1),
        (None, None) => 1,
    };
    Ok((start, stop, h, steps, every))
}

/// The `--set COMPONENT.VARIABLE=VALUE` options as `(component, variable, value)`.
fn parameter_sets(args: &CosimArgs) -> Result<Vec<(String, String, String)>, String> {
    let mut sets = Vec::new();
    for item in &args.set {
        let (name, value) = item
            .split_once('=')
            .ok_or_else(|| format!("--set {item}: expected COMPONENT.VARIABLE=VALUE"))?;
        let (c, v) = split_name(name.trim(), "--set")?;
        // typed by the variable when it is set (a number, an integer, true/false)
        sets.push((c, v, value.trim().to_owned()));
    }
    Ok(sets)
}

/// Refuses, for the implicit scheme, a component that cannot roll back and a discrete
/// connection: the interface iteration repeats each step after rolling the FMUs back, on
/// Real values.
fn can_iterate(
    open: &tbi_ssp::OpenSystem,
    wired: &tbi_ssp::Wired,
) -> Result<(), Box<dyn std::error::Error>> {
    for (c, fmu) in open.ssd.components.iter().zip(&wired.fmus) {
        let can = fmu
            .co_simulation
            .as_ref()
            .is_some_and(|cs| cs.can_get_and_set_fmu_state);
        if !can {
            return Err(format!(
                "{}: component \"{}\" ({}) cannot roll back (canGetAndSetFMUstate is not true), which the implicit scheme needs; use --scheme gauss-seidel or jacobi",
                open.origin, c.name, c.source
            )
            .into());
        }
    }
    if let Some(c) = wired.system.discrete.first() {
        return Err(format!(
            "{}: the connection {} is {}; the implicit scheme iterates Real connections only, use --scheme gauss-seidel or jacobi",
            open.origin, c.name, c.kind
        )
        .into());
    }
    Ok(())
}

/// The recorded columns, and whether they are every connected output.
fn recorded_columns(
    args: &CosimArgs,
    open: &tbi_ssp::OpenSystem,
    wired: &tbi_ssp::Wired,
) -> Result<(bool, Vec<Column>), Box<dyn std::error::Error>> {
    // the system's own outputs by default; every connected output with --record-all or
    // when the system declares none
    let all = args.record_all || wired.recorded.is_empty();
    let mut columns: Vec<Column> = if all { &wired.outputs } else { &wired.recorded }
        .iter()
        .map(|o| (o.name.clone(), o.participant, o.vr, o.kind))
        .collect();
    for r in &args.record {
        let (c, v) = split_name(r, "--record")?;
        let i = open
            .ssd
            .components
            .iter()
            .position(|x| x.name == c)
            .ok_or_else(|| {
                format!(
                    "--record {r}: the system has no component \"{c}\"{}",
                    crate::text::did_you_mean(
                        &c,
                        open.ssd.components.iter().map(|x| x.name.as_str())
                    )
                )
            })?;
        let md = &wired.fmus[i];
        let var = md.variable(&v).ok_or_else(|| {
            format!(
                "--record {r}: component \"{c}\" has no variable \"{v}\"{}",
                crate::text::did_you_mean(&v, md.model_variables.iter().map(|x| x.name.as_str()))
            )
        })?;
        let kind = tbi_ssp::exchanged_kind(&var.kind)
            .ok_or_else(|| format!("--record {r}: a String variable cannot be recorded"))?;
        columns.push((r.clone(), i, var.value_reference, kind));
    }
    Ok((all, columns))
}

/// The CSV file (`--output`, or `<system>_out.csv`), refused when `rows_total` rows of
/// `n_columns` would pass the history limit without `--allow-large`.
fn output_file(
    args: &CosimArgs,
    n_columns: usize,
    rows_total: usize,
) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = args
            .system
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "system".into());
        PathBuf::from(format!("{stem}_out.csv"))
    });
    let rows_total = rows_total as f64;
    let estimate = rows_total * (1 + n_columns) as f64 * crate::model::VALUE_BYTES;
    let limit = crate::model::Limits::default().max_history_bytes;
    if estimate > limit && !args.allow_large {
        return Err(format!(
            "{}: the CSV would grow to about {:.0} MiB ({} columns × {rows_total:.0} rows), more than the limit of {:.0} MiB; record fewer signals (without --record-all), raise --output-interval, or give --allow-large",
            output.display(),
            estimate / (1u64 << 20) as f64,
            n_columns + 1,
            limit / (1u64 << 20) as f64
        )
        .into());
    }
    Ok(output)
}

/// Steps the system, streaming the rows into `<output>.partial`; on failure the rows so far
/// stay there and the error goes beside them into `<output>.partial.json`. Returns the
/// statistics and the paths of the partial file, the side-car and the failure report.
#[allow(clippy::type_complexity)]
fn record(
    args: &CosimArgs,
    open: &tbi_ssp::OpenSystem,
    system: &mut tbi_coupling::System,
    columns: &[Column],
    cfg: &CouplingConfig,
    times: Times,
    output: &Path,
) -> Result<(CouplingStatistics, PathBuf, PathBuf, PathBuf), Box<dyn std::error::Error>> {
    let partial = crate::output::outdir::with_suffix(output, ".partial");
    let sidecar = crate::output::outdir::with_suffix(output, ".json");
    let failure = crate::output::outdir::with_suffix(&partial, ".json");
    crate::output::outdir::refuse_inputs(
        &[
            output.to_path_buf(),
            sidecar.clone(),
            partial.clone(),
            failure.clone(),
        ],
        &system_inputs(args, open),
    )?;
    // rows stream into <output>.partial, renamed at success: a failed run leaves an earlier
    // result and its side-car as they were, and says what it computed beside its .partial
    let mut csv = crate::output::outdir::NamedFile::create(&partial)?;
    let stepped =
        step_and_record(system, columns, cfg, times, &mut csv, args.quiet).and_then(|stats| {
            csv.flush()?;
            Ok(stats)
        });
    let stats = match stepped {
        Ok(stats) => stats,
        Err(e) => {
            let _ = csv.flush();
            let said = serde_json::json!({
                "system": open.origin,
                "status": "failed",
                "error": e.to_string(),
                "rows": partial.display().to_string(),
            });
            let _ = crate::output::outdir::write_atomically(
                &failure,
                serde_json::to_string_pretty(&said)?.as_bytes(),
            );
            return Err(format!(
                "{e} (the rows computed so far are in {}; {} is left as it was)",
                partial.display(),
                output.display()
            )
            .into());
        }
    };
    Ok((stats, partial, sidecar, failure))
}

/// The files a run reads, which no output may replace: the system file, and for an `.ssd`
/// given directly the components' FMUs and `.ssv` files beside it (an `.ssp`'s are inside
/// it).
fn system_inputs(args: &CosimArgs, open: &tbi_ssp::OpenSystem) -> Vec<(PathBuf, String)> {
    let mut inputs = vec![(args.system.clone(), "the system".to_string())];
    let archive = args
        .system
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ssp"));
    if !archive {
        for c in &open.ssd.components {
            inputs.push((
                open.base.join(&c.source),
                format!("the FMU of component \"{}\"", c.name),
            ));
            for f in &c.parameter_files {
                inputs.push((
                    open.base.join(f),
                    format!("a parameter file of component \"{}\"", c.name),
                ));
            }
        }
    }
    inputs
}
