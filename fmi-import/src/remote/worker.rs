//! The worker side: one FMU instance in a process of its own, serving the master's calls
//! ([`serve`]). Requests come on standard input; replies go to the file descriptor that was
//! standard output, which is then pointed at standard error, so that whatever the FMU
//! prints cannot mix with the replies. At the end of the input (the master closed it, or
//! died) the instance is freed and its unpacked folder removed.

use super::protocol::{read_frame, write_frame, In, Op, Out};
use crate::participant::FmiCalls;
use crate::{AnyFmu, InstantiateOptions};
use std::io::{self, BufReader, BufWriter, Write};

/// Serves one FMU instance until the input ends; the process's exit code.
pub fn serve() -> i32 {
    // SAFETY: process-wide signal settings of the worker process, made before any thread.
    unsafe {
        // a terminal's Ctrl-C reaches the whole process group: the master decides
        libc::signal(libc::SIGINT, libc::SIG_IGN);
        // a master that is killed takes its workers with it, even one stuck in an FMU call
        #[cfg(target_os = "linux")]
        libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
    }
    let replies = match reply_channel() {
        Ok(f) => f,
        Err(e) => {
            eprintln!("tbi fmu-worker: {e}");
            return 2;
        }
    };
    let mut out = BufWriter::new(replies);
    let mut input = BufReader::new(io::stdin().lock());
    let mut instance: Option<Box<dyn FmiCalls>> = None;
    // a failure of a call without a reply, told with the next reply
    let mut pending: Option<String> = None;
    loop {
        let frame = match read_frame(&mut input) {
            Ok(Some(f)) => f,
            Ok(None) => return 0,
            Err(e) => {
                eprintln!("tbi fmu-worker: reading a request: {e}");
                return 2;
            }
        };
        let mut msg = In(&frame);
        let op = msg.u8().ok().and_then(Op::from_u8);
        let Some(op) = op else {
            eprintln!("tbi fmu-worker: an unknown request");
            return 2;
        };
        let result = handle(op, &mut msg, &mut instance);
        if !op.replies() {
            if let Err(e) = result {
                pending.get_or_insert(e);
            }
            continue;
        }
        let reply = match (pending.take(), result) {
            (Some(e), _) | (None, Err(e)) => Out::default().u8(1).str(&e),
            (None, Ok(values)) => {
                let mut r = Out::default().u8(0);
                r.0.extend_from_slice(&values.0);
                r
            }
        };
        if write_frame(&mut out, &reply.0)
            .and_then(|()| out.flush())
            .is_err()
        {
            return 2;
        }
    }
}

/// The descriptor replies go to: a copy of standard output, which then becomes a copy of
/// standard error.
fn reply_channel() -> io::Result<std::fs::File> {
    use std::os::fd::FromRawFd;
    // SAFETY: dup and dup2 on the process's own standard descriptors; the new descriptor is
    // owned by the File from here on.
    unsafe {
        let fd = libc::dup(1);
        if fd < 0 || libc::dup2(2, 1) < 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(std::fs::File::from_raw_fd(fd))
    }
}

/// One request: the values of its reply, or the message of its failure.
fn handle(op: Op, msg: &mut In, instance: &mut Option<Box<dyn FmiCalls>>) -> Result<Out, String> {
    if op == Op::Load {
        let path = msg.str()?;
        let name = msg.str()?;
        let echo_log = msg.u8()? != 0;
        let fmu = AnyFmu::load(&path).map_err(|e| e.to_string())?;
        let options = InstantiateOptions {
            echo_log,
            ..InstantiateOptions::component(&name)
        };
        *instance = Some(fmu.instantiate_calls(&options).map_err(|e| e.to_string())?);
        return Ok(Out::default());
    }
    let inst = instance
        .as_deref_mut()
        .ok_or("the worker has no instance yet")?;
    let none = Out::default();
    match op {
        Op::Load => unreachable!("handled above"),
        Op::SetupExperiment => {
            let (tol, start, stop) = (msg.opt_f64()?, msg.f64()?, msg.opt_f64()?);
            inst.setup_experiment(tol, start, stop).map(|()| none)
        }
        Op::EnterInitialization => inst.enter_initialization_mode().map(|()| none),
        Op::ExitInitialization => inst.exit_initialization_mode().map(|()| none),
        Op::SetReal => inst.set_real(&msg.u32s()?, &msg.f64s()?).map(|()| none),
        Op::GetReal => {
            let vrs = msg.u32s()?;
            let mut v = vec![0.0; vrs.len()];
            inst.get_real(&vrs, &mut v).map(|()| none.f64s(&v))
        }
        Op::SetInteger => inst.set_integer(&msg.u32s()?, &msg.i32s()?).map(|()| none),
        Op::GetInteger => {
            let vrs = msg.u32s()?;
            let mut v = vec![0; vrs.len()];
            inst.get_integer(&vrs, &mut v).map(|()| none.i32s(&v))
        }
        Op::SetBoolean => {
            let vrs = msg.u32s()?;
            let v: Vec<bool> = msg.i32s()?.iter().map(|&b| b != 0).collect();
            inst.set_boolean(&vrs, &v).map(|()| none)
        }
        Op::GetBoolean => {
            let vrs = msg.u32s()?;
            let mut v = vec![false; vrs.len()];
            let as_i32 = |v: Vec<bool>| v.into_iter().map(i32::from).collect::<Vec<_>>();
            inst.get_boolean(&vrs, &mut v)
                .map(|()| none.i32s(&as_i32(v)))
        }
        Op::SetString => {
            let vrs = msg.u32s()?;
            let n = vrs.len();
            let values = (0..n).map(|_| msg.str()).collect::<Result<Vec<_>, _>>()?;
            let refs: Vec<&str> = values.iter().map(String::as_str).collect();
            inst.set_string(&vrs, &refs).map(|()| none)
        }
        Op::DoStep => {
            let (t, h, last) = (msg.f64()?, msg.f64()?, msg.u8()? != 0);
            step(inst, t, h, last).map(|d| none.u8(u8::from(d)))
        }
        Op::DoStepGet => {
            let (t, h, last) = (msg.f64()?, msg.f64()?, msg.u8()? != 0);
            let vrs = msg.u32s()?;
            let discarded = step(inst, t, h, last)?;
            let mut v = vec![0.0; vrs.len()];
            let reply = none.u8(u8::from(discarded));
            Ok(match inst.get_real(&vrs, &mut v) {
                Ok(()) => reply.u8(0).f64s(&v),
                Err(e) => reply.u8(1).str(&e),
            })
        }
        Op::SaveState => inst.save_state().map(|()| none),
        Op::RestoreState => inst.restore_state().map(|()| none),
        Op::Terminated => inst.terminated().map(|t| none.u8(u8::from(t))),
        Op::LastSuccessfulTime => inst.last_successful_time().map(|t| none.f64(t)),
        Op::Terminate => inst.terminate().map(|()| none),
    }
}

/// `fmi2DoStep`, with `noSetFMUStatePriorToCurrentPoint` set when `last`.
fn step(inst: &mut dyn FmiCalls, t: f64, h: f64, last: bool) -> Result<bool, String> {
    if last {
        inst.do_step_final(t, h)
    } else {
        inst.do_step(t, h)
    }
}
