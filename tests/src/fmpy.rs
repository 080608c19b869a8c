//! FMPy (the reference importer) from the virtual environment of
//! `tests/python/setup-venv.sh`.

use crate::{paths, run, text};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The FMPy venv's folder, or `None` when `TBI_SKIP_PYTHON=1` asks to skip the FMPy side.
///
/// The first call of a process runs `tests/python/setup-venv.sh` (idempotent; creates the
/// venv if needed) and takes the last line of its standard output; later calls reuse the
/// answer. Panics with the script's messages when the venv is missing and cannot be created.
pub fn venv() -> Option<&'static Path> {
    static VENV: OnceLock<Option<PathBuf>> = OnceLock::new();
    let venv = VENV.get_or_init(|| {
        if std::env::var("TBI_SKIP_PYTHON").as_deref() == Ok("1") {
            return None;
        }
        Some(set_up())
    });
    if venv.is_none() {
        eprintln!("TBI_SKIP_PYTHON=1: the FMPy side of this test is skipped");
    }
    venv.as_deref()
}

fn set_up() -> PathBuf {
    let script = paths::repo_path("tests/python/setup-venv.sh");
    let out = run(Command::new("bash").arg(&script));
    let stdout = text(&out.stdout);
    assert!(
        out.status.success(),
        "the FMPy venv is missing and {} could not create it ({}):\n{}\n{}\n\
         (set TBI_SKIP_PYTHON=1 to skip the FMPy comparison explicitly)",
        script.display(),
        out.status,
        stdout,
        text(&out.stderr)
    );
    let venv = PathBuf::from(
        stdout
            .lines()
            .last()
            .unwrap_or_else(|| panic!("{} printed nothing", script.display()))
            .trim(),
    );
    assert!(
        venv.join("bin/python").is_file() && venv.join("bin/fmpy").is_file(),
        "{} reported the venv {} but it has no bin/python or bin/fmpy",
        script.display(),
        venv.display()
    );
    venv
}

/// A command running the venv's `fmpy`.
pub fn fmpy(venv: &Path) -> Command {
    Command::new(venv.join("bin/fmpy"))
}

/// A command running the venv's `python`.
pub fn python(venv: &Path) -> Command {
    Command::new(venv.join("bin/python"))
}
