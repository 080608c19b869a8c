//! The master side: an FMU instance in a worker process ([`RemoteInstance`]), called as an
//! in-process one through [`FmiCalls`].
//!
//! Each call is one frame to the worker; the value setters and the state saves and
//! restores are not answered (a failure comes back with the next answer). After a step the outputs the master reads are those it
//! read after the step before, so `fmi2DoStep` asks for them in the same round trip and the
//! next `fmi2GetReal` of those value references takes them: a coupling sweep's inputs, step
//! and outputs cost one round trip. A reader thread hands the worker's answers over, and the
//! caller waits for them in slices of 100 ms: between slices it ends the worker when the
//! call has taken longer than [`WorkerOptions::timeout`] or when
//! [`WorkerOptions::cancelled`] says the run was interrupted. A worker that dies (a crash,
//! `abort`, `exit`) or is ended gives an error naming the instance, the FMI call and the
//! time, and its unpacked folders are removed.

use super::protocol::{read_frame, write_frame, In, Op, Out};
use crate::participant::FmiCalls;
use std::io::{BufReader, BufWriter, Write};
use std::os::fd::AsRawFd;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

/// How a worker is started and watched.
#[derive(Clone)]
pub struct WorkerOptions {
    /// The program that serves as worker ([`super::serve`]) and its arguments (for `tbi`:
    /// its own executable and `fmu-worker`).
    pub program: PathBuf,
    pub args: Vec<String>,
    /// Longest wall time of one FMI call, or none.
    pub timeout: Option<Duration>,
    /// Asked between waits: `true` ends the worker and fails the call (a signal arrived).
    pub cancelled: fn() -> bool,
    /// Print the FMU's log messages to standard error as they come (messages of a failed
    /// call are part of its error either way).
    pub echo_log: bool,
}

/// How long the master looks for an answer before it sleeps until one comes.
const SPIN: Duration = Duration::from_micros(200);

/// The answers waited for by every worker of this process so far (for `tbi bench`).
static ROUND_TRIPS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// How many answers this process has waited for from its workers so far: its round trips.
pub fn round_trips() -> u64 {
    ROUND_TRIPS.load(std::sync::atomic::Ordering::Relaxed)
}

/// Reals fetched with a step: their value references and values (or the failure of
/// reading them).
type Fetched = (Vec<u32>, Result<Vec<f64>, String>);

/// An FMU instance served by a worker process.
pub struct RemoteInstance {
    name: String,
    /// What messages call it: `component "NAME"` unless [`RemoteInstance::start_labelled`].
    label: String,
    child: Child,
    to: Option<BufWriter<ChildStdin>>,
    from: BufReader<ChildStdout>,
    options: WorkerOptions,
    /// The communication point of the last `fmi2DoStep`, for messages.
    time: f64,
    /// Why the worker is gone, once it is.
    gone: Option<String>,
    /// The value references read first after the last step: fetched with the next step.
    after_step: Option<Vec<u32>>,
    /// What that step fetched (the values or `fmi2GetReal`'s failure), until the next call.
    fetched: Option<Fetched>,
    /// Whether a step was the last call (so the next `fmi2GetReal` is "after the step").
    stepped: bool,
    /// A step sent and not yet answered ([`FmiCalls::start_step`]).
    running: Option<Op>,
    /// Whether steps are sent with `noSetFMUStatePriorToCurrentPoint` ([`FmiCalls::do_step_final`]).
    last_steps: bool,
}

impl RemoteInstance {
    /// Starts a worker, which loads the FMU at `fmu` and instantiates it as `name`.
    pub fn start(fmu: &Path, name: &str, options: &WorkerOptions) -> Result<Self, String> {
        Self::start_labelled(fmu, name, &format!("component \"{name}\""), options)
    }

    /// [`RemoteInstance::start`], messages calling the instance `label`.
    pub fn start_labelled(
        fmu: &Path,
        name: &str,
        label: &str,
        options: &WorkerOptions,
    ) -> Result<Self, String> {
        let mut child = Command::new(&options.program)
            .args(&options.args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| {
                format!(
                    "{label}: cannot start an FMU worker ({}): {e}",
                    options.program.display()
                )
            })?;
        let from = BufReader::new(child.stdout.take().expect("piped"));
        let to = child.stdin.take().map(BufWriter::new);
        let mut remote = RemoteInstance {
            name: name.to_owned(),
            label: label.to_owned(),
            child,
            to,
            from,
            options: options.clone(),
            time: 0.0,
            gone: None,
            after_step: None,
            fetched: None,
            stepped: false,
            running: None,
            last_steps: false,
        };
        let path = fmu.to_string_lossy();
        let echo = u8::from(options.echo_log);
        remote.call(Out::op(Op::Load).str(&path).str(name).u8(echo))?;
        Ok(remote)
    }

    /// The process id of the worker.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Sends `msg`; for an operation with an answer, waits for it and returns its values.
    fn call(&mut self, msg: Out) -> Result<Vec<u8>, String> {
        let op = self.send(msg)?;
        if !op.replies() {
            return Ok(Vec::new());
        }
        self.wait(op)
    }

    /// Sends `msg` (flushed when it is answered); its operation.
    fn send(&mut self, msg: Out) -> Result<Op, String> {
        let op = Op::from_u8(msg.0[0]).expect("a known operation");
        if let Some(running) = self.running {
            return Err(format!(
                "{}: {} while {} runs",
                self.label,
                op.call(),
                running.call()
            ));
        }
        // anything sent after a step may change what it fetched
        self.fetched = None;
        self.stepped = false;
        if let Some(why) = &self.gone {
            return Err(why.clone());
        }
        let sent = self.to.as_mut().map(|to| {
            write_frame(to, &msg.0).and_then(|()| if op.replies() { to.flush() } else { Ok(()) })
        });
        if !matches!(sent, Some(Ok(()))) {
            return Err(self.ended(op, None));
        }
        Ok(op)
    }

    /// Waits for the answer to `op`: its values, or the failure.
    fn wait(&mut self, op: Op) -> Result<Vec<u8>, String> {
        ROUND_TRIPS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let started = Instant::now();
        loop {
            match self.readable(Duration::from_millis(100)) {
                Ok(true) => {
                    return match read_frame(&mut self.from) {
                        Ok(Some(frame)) => self.answer(op, &frame),
                        Ok(None) | Err(_) => Err(self.ended(op, None)),
                    }
                }
                Ok(false) => {}
                Err(_) => return Err(self.ended(op, None)),
            }
            if (self.options.cancelled)() {
                let why = "the run was interrupted by a signal; the FMU's worker was ended";
                return Err(self.ended(op, Some(why.into())));
            }
            if let Some(limit) = self.options.timeout {
                if started.elapsed() > limit {
                    let why = format!(
                        "the call did not return within {} s (--fmu-timeout); the FMU's worker was ended",
                        limit.as_secs_f64()
                    );
                    return Err(self.ended(op, Some(why)));
                }
            }
        }
    }

    /// Whether the worker's answer can be read (or its end seen) within `wait`.
    fn readable(&mut self, wait: Duration) -> std::io::Result<bool> {
        if !self.from.buffer().is_empty() {
            return Ok(true);
        }
        let mut fd = libc::pollfd {
            fd: self.from.get_ref().as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        // most answers come within microseconds: look for a while before sleeping, as a
        // sleeping process takes far longer to wake than the answer takes to come
        let spin = Instant::now();
        while spin.elapsed() < SPIN {
            // SAFETY: one valid pollfd for the duration of the call.
            if unsafe { libc::poll(&mut fd, 1, 0) } != 0 {
                break;
            }
            std::hint::spin_loop();
        }
        // SAFETY: as above.
        let n = unsafe { libc::poll(&mut fd, 1, wait.as_millis() as libc::c_int) };
        match n {
            n if n > 0 => Ok(true),
            0 => Ok(false),
            _ => {
                let e = std::io::Error::last_os_error();
                if e.kind() == std::io::ErrorKind::Interrupted {
                    Ok(false)
                } else {
                    Err(e)
                }
            }
        }
    }

    /// The values of an answer, or the worker's message.
    fn answer(&self, op: Op, frame: &[u8]) -> Result<Vec<u8>, String> {
        let mut msg = In(frame);
        match msg.u8()? {
            0 => Ok(msg.0.to_vec()),
            _ => Err(msg.str().unwrap_or_else(|e| format!("{}: {e}", op.call()))),
        }
    }

    /// Ends the worker (if it still runs) and says what happened, once, for this and every
    /// later call: its exit, or `why` it was ended.
    fn ended(&mut self, op: Op, why: Option<String>) -> String {
        let how = match why {
            Some(why) => {
                let _ = self.child.kill();
                let _ = self.child.wait();
                why
            }
            None => match wait_briefly(&mut self.child) {
                Some(status) => format!("the FMU's worker process {}", describe_exit(status)),
                None => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    "the FMU's worker process stopped answering and was ended".into()
                }
            },
        };
        crate::archive::UnpackedDir::remove_of_process("tbi-fmu", self.child.id());
        self.to = None;
        let message = format!(
            "{}: {how}, during {} at t = {} s",
            self.label,
            op.call(),
            self.time
        );
        self.gone = Some(message.clone());
        message
    }
}

/// The exit status of a worker whose pipe closed, once it has one (up to 2 s).
fn wait_briefly(child: &mut Child) -> Option<std::process::ExitStatus> {
    let until = Instant::now() + Duration::from_secs(2);
    loop {
        if let Ok(Some(s)) = child.try_wait() {
            return Some(s);
        }
        if Instant::now() > until {
            return None;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// "exited with status 0", "was killed by signal 11 (SIGSEGV)".
fn describe_exit(status: std::process::ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("exited with status {code}"),
        (None, Some(sig)) => {
            let name = match sig {
                6 => " (SIGABRT)",
                9 => " (SIGKILL)",
                11 => " (SIGSEGV)",
                15 => " (SIGTERM)",
                _ => "",
            };
            format!("was killed by signal {sig}{name}")
        }
        _ => format!("ended ({status})"),
    }
}

impl Drop for RemoteInstance {
    /// Closes the worker's input, so that it frees its instance and exits; ends it if it
    /// has not within 2 s.
    fn drop(&mut self) {
        self.to = None;
        if self.gone.is_none() && wait_briefly(&mut self.child).is_some() {
            return;
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        crate::archive::UnpackedDir::remove_of_process("tbi-fmu", self.child.id());
    }
}

/// Copies an answer's values into `values`, which must be as many.
fn fill<T: Copy>(values: &mut [T], got: Vec<T>) -> Result<(), String> {
    if got.len() != values.len() {
        return Err(format!(
            "the worker answered {} values for {}",
            got.len(),
            values.len()
        ));
    }
    values.copy_from_slice(&got);
    Ok(())
}

fn bools(v: &[bool]) -> Vec<i32> {
    v.iter().map(|&b| i32::from(b)).collect()
}

impl FmiCalls for RemoteInstance {
    fn name(&self) -> &str {
        &self.name
    }
    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), String> {
        self.time = start;
        let m = Out::op(Op::SetupExperiment)
            .opt_f64(tolerance)
            .f64(start)
            .opt_f64(stop);
        self.call(m).map(drop)
    }
    fn enter_initialization_mode(&mut self) -> Result<(), String> {
        self.call(Out::op(Op::EnterInitialization)).map(drop)
    }
    fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.call(Out::op(Op::ExitInitialization)).map(drop)
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        self.call(Out::op(Op::SetReal).u32s(vrs).f64s(values))
            .map(drop)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), String> {
        if let Some((fetched_vrs, got)) = self.fetched.take() {
            if fetched_vrs == vrs {
                self.stepped = false;
                return fill(values, got?);
            }
        }
        if self.stepped {
            self.after_step = Some(vrs.to_vec());
        }
        let bytes = self.call(Out::op(Op::GetReal).u32s(vrs))?;
        fill(values, In(&bytes).f64s()?)
    }
    fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), String> {
        self.call(Out::op(Op::SetInteger).u32s(vrs).i32s(values))
            .map(drop)
    }
    fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<(), String> {
        let bytes = self.call(Out::op(Op::GetInteger).u32s(vrs))?;
        fill(values, In(&bytes).i32s()?)
    }
    fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), String> {
        self.call(Out::op(Op::SetBoolean).u32s(vrs).i32s(&bools(values)))
            .map(drop)
    }
    fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<(), String> {
        let bytes = self.call(Out::op(Op::GetBoolean).u32s(vrs))?;
        let got: Vec<bool> = In(&bytes).i32s()?.into_iter().map(|b| b != 0).collect();
        fill(values, got)
    }
    fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), String> {
        let m = values
            .iter()
            .fold(Out::op(Op::SetString).u32s(vrs), |m, s| m.str(s));
        self.call(m).map(drop)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<bool, String> {
        match self.start_step(t, h)? {
            Some(discarded) => Ok(discarded),
            None => self.finish_step(),
        }
    }
    /// Sends the step (asking for the outputs read after the step before) and returns at
    /// once: the worker steps while the master goes on.
    fn start_step(&mut self, t: f64, h: f64) -> Result<Option<bool>, String> {
        self.time = t;
        let last = u8::from(self.last_steps);
        let msg = match &self.after_step {
            Some(vrs) => Out::op(Op::DoStepGet).f64(t).f64(h).u8(last).u32s(vrs),
            None => Out::op(Op::DoStep).f64(t).f64(h).u8(last),
        };
        let op = self.send(msg)?;
        self.running = Some(op);
        Ok(None)
    }
    fn finish_step(&mut self) -> Result<bool, String> {
        let op = self
            .running
            .take()
            .ok_or_else(|| format!("{}: no step is running", self.label))?;
        let bytes = self.wait(op)?;
        let mut answer = In(&bytes);
        let discarded = answer.u8()? != 0;
        if op == Op::DoStepGet {
            let got = match answer.u8()? {
                0 => Ok(answer.f64s()?),
                _ => Err(answer.str()?),
            };
            let vrs = self.after_step.clone().expect("asked for these");
            self.fetched = Some((vrs, got));
        }
        self.stepped = true;
        Ok(discarded)
    }
    fn save_state(&mut self) -> Result<(), String> {
        self.call(Out::op(Op::SaveState)).map(drop)
    }
    fn restore_state(&mut self) -> Result<(), String> {
        self.call(Out::op(Op::RestoreState)).map(drop)
    }
    fn do_step_final(&mut self, t: f64, h: f64) -> Result<bool, String> {
        self.last_steps = true;
        let discarded = self.do_step(t, h);
        self.last_steps = false;
        discarded
    }
    fn terminated(&mut self) -> Result<bool, String> {
        let bytes = self.call(Out::op(Op::Terminated))?;
        Ok(In(&bytes).u8()? != 0)
    }
    fn last_successful_time(&mut self) -> Result<f64, String> {
        let bytes = self.call(Out::op(Op::LastSuccessfulTime))?;
        In(&bytes).f64()
    }
    fn terminate(&mut self) -> Result<(), String> {
        self.call(Out::op(Op::Terminate)).map(drop)
    }
}
