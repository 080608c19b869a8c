//! The options of a run ([`SimulationOptions`]), its entry points ([`simulate`],
//! [`simulate_into`]) and the run itself: times, initialisation and the stepping loop.
//!
//! "The module docs" in the items below are those of [`crate::simulate`], which
//! re-exports them.

use super::csv::write_header;
use super::input::{InputTable, Inputs};
use super::record::Recorder;
use super::start_values::{
    apply_start_values, settable_in_initialization_mode, settable_in_instantiated,
};
use super::{auto_interval, isclose, RunEnd, SimulateError, SimulationResult};
use crate::archive::fmu_display_name;
use crate::remote::{RemoteInstance, WorkerOptions};
use crate::{AnyFmu, FmiCalls, Fmu, InstantiateOptions};
use model_description::ModelDescription;
use std::io::Write;
use std::path::Path;

/// Most communication steps of one run.
pub const MAX_STEPS: f64 = 1e7;

/// Settings of one run; `None` fields take the defaults described in the module docs.
#[derive(Debug, Clone, Default)]
pub struct SimulationOptions {
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    /// The communication step size (FMPy's output interval).
    pub step_size: Option<f64>,
    pub relative_tolerance: Option<f64>,
    /// `(variable name, value as text)`, applied in ModelVariables order.
    pub start_values: Vec<(String, String)>,
    pub input: Option<InputTable>,
    /// Print the FMU's log messages to standard error.
    pub echo_log: bool,
    /// Asked before every step; `true` ends the run (`RunEnd::Stopped`) with the rows so
    /// far (e.g. after SIGINT).
    pub stop_requested: Option<fn() -> bool>,
}

/// Run `fmu` once as described in the module documentation, keeping the rows in memory.
pub fn simulate(
    fmu: &AnyFmu,
    options: &SimulationOptions,
) -> Result<SimulationResult, SimulateError> {
    in_process(fmu, options, None)
}

/// Run `fmu` once, writing the CSV (header, then each row as it is sampled) to `out`, so
/// that an interrupted or failed run keeps what was computed. The result holds no rows.
pub fn simulate_into(
    fmu: &AnyFmu,
    options: &SimulationOptions,
    out: &mut dyn Write,
) -> Result<SimulationResult, SimulateError> {
    in_process(fmu, options, Some(out))
}

/// [`simulate_into`] for the FMU at `path` run in a worker process started with `worker`
/// (its library is never loaded in this process): a crash, an `exit` or a hang past the
/// time limit fails the run after the rows computed before were written to `out`.
pub fn simulate_isolated_into(
    path: &Path,
    worker: &WorkerOptions,
    options: &SimulationOptions,
    out: &mut dyn Write,
) -> Result<SimulationResult, SimulateError> {
    let md = Fmu::describe(path)?;
    let name = fmu_display_name(path);
    let instantiate = || -> Result<Box<dyn FmiCalls>, SimulateError> {
        let identifier = &md
            .co_simulation
            .as_ref()
            .expect("described")
            .model_identifier;
        let worker = WorkerOptions {
            echo_log: options.echo_log,
            ..worker.clone()
        };
        let remote = RemoteInstance::start_labelled(path, identifier, &name, &worker)
            .map_err(SimulateError::Call)?;
        Ok(Box::new(remote))
    };
    run(&md, &name, &instantiate, options, Some(out))
}

fn in_process(
    fmu: &AnyFmu,
    options: &SimulationOptions,
    out: Option<&mut dyn Write>,
) -> Result<SimulationResult, SimulateError> {
    let instantiate = || -> Result<Box<dyn FmiCalls>, SimulateError> {
        Ok(fmu.instantiate_calls(&InstantiateOptions {
            echo_log: options.echo_log,
            ..InstantiateOptions::default()
        })?)
    };
    run(
        fmu.model_description(),
        fmu.name(),
        &instantiate,
        options,
        out,
    )
}

/// Where a run's instance comes from (in this process or in a worker).
type Instantiate<'a> = dyn Fn() -> Result<Box<dyn FmiCalls>, SimulateError> + 'a;

fn run(
    md: &ModelDescription,
    name: &str,
    instantiate: &Instantiate,
    options: &SimulationOptions,
    out: Option<&mut dyn Write>,
) -> Result<SimulationResult, SimulateError> {
    let cs = md
        .co_simulation
        .as_ref()
        .expect("Fmu::load and Fmu::describe accept only Co-Simulation FMUs");
    let experiment = md.default_experiment.clone().unwrap_or_default();
    let invalid = |m: String| SimulateError::Invalid(format!("{name}: {m}"));

    let start_time = options.start_time.or(experiment.start_time).unwrap_or(0.0);
    let stop_time = options
        .stop_time
        .or(experiment.stop_time)
        .unwrap_or(start_time + 1.0);
    if !start_time.is_finite() || !stop_time.is_finite() {
        return Err(invalid(format!(
            "start time {start_time} and stop time {stop_time} must be finite"
        )));
    }
    if stop_time <= start_time {
        return Err(invalid(format!(
            "the stop time {stop_time} is not after the start time {start_time}"
        )));
    }
    let tolerance = options.relative_tolerance.or(experiment.tolerance);
    let step = match (options.step_size, experiment.step_size) {
        (Some(h), _) => h,
        (None, Some(h)) => {
            let mut h = h;
            while h > 0.0 && (stop_time - start_time) / h > 1000.0 {
                h *= 2.0;
            }
            h
        }
        (None, None) => auto_interval(stop_time - start_time),
    };
    if !(step.is_finite() && step > 0.0) {
        return Err(invalid(format!(
            "the step size {step} must be a positive number"
        )));
    }
    let steps = (stop_time - start_time) / step;
    if steps > MAX_STEPS {
        return Err(invalid(format!(
            "the step size {step:e} s would take {steps:.3e} steps from {start_time} to {stop_time} s, more than the limit of {MAX_STEPS:e}"
        )));
    }
    let can_vary = cs.can_handle_variable_communication_step_size;

    let mut pending = options.start_values.clone();
    for (name, _) in &pending {
        if md.variable(name).is_none() {
            return Err(invalid(format!(
                "--set {name}: the FMU has no variable \"{name}\""
            )));
        }
    }
    let inputs = Inputs::new(md, options.input.as_ref())?;

    let mut boxed = instantiate()?;
    let instance = boxed.as_mut();
    let call = SimulateError::Call;

    let mut time = start_time;
    (instance.setup_experiment(tolerance, time, Some(stop_time))).map_err(call)?;
    apply_start_values(instance, md, &mut pending, settable_in_instantiated)?;
    instance.enter_initialization_mode().map_err(call)?;
    apply_start_values(instance, md, &mut pending, settable_in_initialization_mode)?;
    if let Some((name, _)) = pending.first() {
        let v = md.variable(name).expect("checked above");
        return Err(invalid(format!(
            "--set {name}: the variable cannot be set before or during initialisation (causality=\"{}\", variability=\"{}\")",
            v.causality, v.variability
        )));
    }
    inputs.apply(instance, time, false)?;
    instance.exit_initialization_mode().map_err(call)?;

    let mut recorder = Recorder::new(md, out);
    if let Some(sink) = recorder.sink.as_mut() {
        write_header(sink, &recorder.columns).map_err(|error| SimulateError::Io {
            path: "the result".into(),
            error,
        })?;
    }
    recorder.sample(instance, time)?;

    let mut end = RunEnd::Completed;
    let mut n_steps: u64 = 0;
    loop {
        if time > stop_time || isclose(time, stop_time) {
            break;
        }
        if options.stop_requested.is_some_and(|stop| stop()) {
            end = RunEnd::Stopped { time };
            break;
        }
        let next_regular = start_time + (n_steps + 1) as f64 * step;
        let mut next = next_regular;
        let next_input_event = inputs.next_event(time);
        if can_vary && next > next_input_event && !isclose(next, next_input_event) {
            next = next_input_event;
        }
        if next > stop_time && !isclose(next, stop_time) {
            if can_vary {
                next = stop_time;
            } else {
                break;
            }
        }
        inputs.apply(instance, time, true)?;
        match instance.do_step_final(time, next - time).map_err(call)? {
            false => time = next,
            true => {
                if instance.terminated().map_err(call)? {
                    time = instance.last_successful_time().map_err(call)?;
                    recorder.sample(instance, time)?;
                    end = RunEnd::Terminated { time };
                } else {
                    end = RunEnd::Discarded { time };
                }
                break;
            }
        }
        recorder.sample(instance, time)?;
        if isclose(time, next_regular) {
            n_steps += 1;
        }
    }
    instance.terminate().map_err(call)?;
    Ok(SimulationResult {
        columns: recorder.columns,
        rows: recorder.rows,
        end,
    })
}
