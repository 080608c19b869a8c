//! The FMU worker processes of `tbi cosim` and `tbi simulate`: one per FMU running this
//! executable's hidden `fmu-worker` command, unless `--in-process` is given.

use fmi_import::remote::WorkerOptions;
use std::time::Duration;

/// The worker options of `--in-process` and `--fmu-timeout SECONDS`: `None` for in process.
pub fn options(
    in_process: bool,
    fmu_timeout: Option<f64>,
) -> Result<Option<WorkerOptions>, String> {
    let timeout = match fmu_timeout {
        None => None,
        Some(s) if s.is_finite() && s > 0.0 && s <= 1e9 => Some(Duration::from_secs_f64(s)),
        Some(s) => {
            return Err(format!(
                "--fmu-timeout {s}: expected a positive number of seconds"
            ))
        }
    };
    if in_process {
        if timeout.is_some() {
            return Err(
                "--fmu-timeout needs the FMUs in worker processes; drop --in-process".into(),
            );
        }
        return Ok(None);
    }
    let program = std::env::current_exe()
        .map_err(|e| format!("cannot find the tbi executable for the FMU workers: {e}"))?;
    Ok(Some(WorkerOptions {
        program,
        args: vec!["fmu-worker".into()],
        timeout,
        cancelled: crate::interrupt::interrupted,
        echo_log: true,
    }))
}
