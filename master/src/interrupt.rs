//! SIGINT, SIGTERM and SIGHUP end a run cleanly: the first signal sets a flag that every
//! stepping loop checks once per step, so the run stops at the next step and fails with a
//! message — `summary.json` then says `"status": "failed"`, the rows computed so far stay in
//! `history.csv`, and the FMUs' temporary folders are removed as the instances drop. A second
//! signal ends the process at once (exit code 130).

use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Install the handler (once per process; later calls do nothing).
pub fn install() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = ctrlc::set_handler(|| {
            if INTERRUPTED.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    });
}

/// Whether a signal asked the process to stop.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

/// `Err` once a signal asked the process to stop, naming the simulated time reached.
pub fn check(t: f64) -> Result<(), String> {
    if interrupted() {
        Err(format!("interrupted by a signal at t = {t} s"))
    } else {
        Ok(())
    }
}
