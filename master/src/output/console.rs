//! Standard output for people and scripts, and the exit status of checks.
//!
//! * [`say!`](crate::say) prints a line like `println!`, but a closed standard output
//!   (`tbi run | head -1`) is not an error: the first failed write stops further printing
//!   and the command goes on to finish its files, ending with its normal exit code.
//! * [`check_failed`] records that a design or limit check FAILed; `tbi` then exits with
//!   [`EXIT_CHECK_FAILED`] (3) instead of 0. The exit codes: 0 every check passes, 1 an
//!   error, 2 a command line clap refused, 3 a check FAILs, 130 interrupted by a signal.

use std::io::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};

/// Exit code of a run whose checks did not all pass.
pub const EXIT_CHECK_FAILED: u8 = 3;

static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);
static CHECK_FAILED: AtomicBool = AtomicBool::new(false);

/// Write `args` and a newline to standard output; after a failed write (a closed pipe)
/// nothing more is printed.
pub fn say_fmt(args: std::fmt::Arguments<'_>) {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if out
        .write_fmt(args)
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush())
        .is_err()
    {
        STDOUT_CLOSED.store(true, Ordering::Relaxed);
    }
}

/// Print a line on standard output, quietly stopping at a closed pipe ([`say_fmt`]).
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::output::console::say_fmt(format_args!($($arg)*))
    };
}

/// Record that a check FAILed (the process exits with [`EXIT_CHECK_FAILED`]).
pub fn check_failed() {
    CHECK_FAILED.store(true, Ordering::Relaxed);
}

/// Whether a check FAILed in this process.
pub fn any_check_failed() -> bool {
    CHECK_FAILED.load(Ordering::Relaxed)
}

/// Forget the checks that FAILed so far (a command that runs checks as measurements).
pub fn clear_check_failed() {
    CHECK_FAILED.store(false, Ordering::Relaxed);
}

/// A command line whose options contradict each other (exit code 2, as for a command line
/// clap refuses).
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}
