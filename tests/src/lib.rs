//! Shared support of the workspace's integration tests (crate `tbi_tests`), used by the
//! cross-crate tests in `tests/tests/`, by master's tests (`master/tests/`) and by the test
//! model's tests (`fmi-export/testmodel/tests/`) as a dev-dependency:
//!
//! * [`paths`]: the source tree, the built binaries (`tbi`, the FMU shared objects, a
//!   package's cdylib) and Cargo's temporary directory, found at run time from the test
//!   executable's path;
//! * [`scratch`], [`run`], [`run_ok`], [`tbi_command`], [`tbi_in`]: scratch folders and
//!   processes;
//! * [`read_json`], [`read_summary`]: `summary.json` of a run;
//! * [`table`]: CSV files (numeric [`Table`], text [`TextCsv`]) and their comparison;
//! * [`fmpy`]: the FMPy venv of `tests/python/setup-venv.sh`;
//! * [`fmu`]: `tbi export` of a scenario and unpacking an FMU.
//!
//! This library depends on no crate of the workspace but `model-description`, so it can be a
//! dev-dependency of `tbi` (master) without a cycle; the tests of this package itself
//! dev-depend on `tbi`.

pub mod browser;
pub mod fmpy;
pub mod fmu;
pub mod fuzz;
pub mod paths;
pub mod table;

pub use paths::{built, cdylib, release_dir, repo_path, repo_root, require_fmu_libraries, tbi};
pub use table::{
    assert_same_table, assert_text_csv_match, compare, worst, ColumnDiff, Table, TextCsv,
};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh, empty folder `<target>/tmp/<test executable>/<label>-<n>` (`n` counts the calls
/// of this process, so equal labels do not collide). A later run of the same test
/// executable empties it instead of piling up new ones.
pub fn scratch(label: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = paths::target_tmp_dir()
        .join(paths::test_binary_stem())
        .join(format!("{label}-{n}"));
    if dir.exists() {
        std::fs::remove_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot clear {}: {e}", dir.display()));
    }
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Bytes of a process's output as text (invalid UTF-8 replaced).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Run a command (any exit status); panics only when it cannot be started.
pub fn run(cmd: &mut Command) -> Output {
    cmd.output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"))
}

/// Run a command and return its output; panics with the command, status, stdout and
/// stderr when it fails to start or exits non-zero.
pub fn run_ok(cmd: &mut Command) -> Output {
    let out = run(cmd);
    assert!(
        out.status.success(),
        "{cmd:?} failed ({})\n--- stdout\n{}\n--- stderr\n{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    out
}

/// Run `cmd` and require it to finish its work: exit code 0 (every check passes) or 3 (a
/// design or limit check FAILs, `tbi`'s documented code for it); the output and the code.
pub fn run_checked(cmd: &mut Command) -> Output {
    let out = run(cmd);
    assert!(
        matches!(out.status.code(), Some(0 | 3)),
        "{cmd:?} failed ({})\n--- stdout\n{}\n--- stderr\n{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    out
}

/// A command running the `tbi` executable.
pub fn tbi_command() -> Command {
    Command::new(tbi())
}

/// `tbi ARGS...` run in the folder `cwd` (any exit status).
pub fn tbi_in(cwd: &Path, args: &[&str]) -> Output {
    run(tbi_command().args(args).current_dir(cwd))
}

/// A JSON file.
pub fn read_json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The steps counted by their sweeps (`steps_by_iterations`: entry k the steps that took
/// k + 1), with the steps and the sweeps they add up to.
pub fn steps_by_sweeps(counts: &serde_json::Value) -> (Vec<u64>, u64, u64) {
    let by: Vec<u64> = counts
        .as_array()
        .unwrap_or_else(|| panic!("steps by sweeps: not an array: {counts}"))
        .iter()
        .map(|n| n.as_u64().unwrap_or_else(|| panic!("not a count: {n}")))
        .collect();
    let steps = by.iter().sum();
    let sweeps = by.iter().zip(1..).map(|(n, k)| n * k).sum();
    (by, steps, sweeps)
}

/// `summary.json` in the output folder `out` of `tbi run`.
pub fn read_summary(out: &Path) -> serde_json::Value {
    read_json(&out.join("summary.json"))
}
