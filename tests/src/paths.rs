//! Where things are: the source tree, the Cargo profile directory holding the built binaries
//! and shared objects, and Cargo's temporary directory.
//!
//! Everything is found at run time from the path of the running test executable
//! (`target/<profile>/deps/<test>-<hash>`): `CARGO_BIN_EXE_*` and `CARGO_TARGET_TMPDIR` are
//! only set when an integration test itself is compiled, not this library. Cargo puts
//! `CARGO_BIN_EXE_tbi` and `CARGO_TARGET_TMPDIR` at the same places as found here.

use std::path::{Path, PathBuf};

/// The workspace root (the parent of this `tests` package).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// `rel` below the workspace root, e.g. `repo_path("tests/c-fmu")`.
pub fn repo_path(rel: &str) -> PathBuf {
    repo_root().join(rel)
}

/// The running test executable.
fn current_exe() -> PathBuf {
    std::env::current_exe().expect("path of the test executable")
}

/// The Cargo profile directory (`target/release` when the test runs from
/// `target/release/deps/<test>`), where `cargo build` puts binaries and shared objects.
pub fn profile_dir() -> PathBuf {
    let exe = current_exe();
    let dir = exe.parent().expect("the test executable has a folder");
    if dir.file_name().is_some_and(|n| n == "deps") {
        dir.parent().expect("deps/ has a parent").to_path_buf()
    } else {
        dir.to_path_buf()
    }
}

/// The file stem of the running test executable (`cli_errors-0123abcd…`).
pub fn test_binary_stem() -> String {
    current_exe()
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Cargo's target directory: the nearest ancestor of the profile directory holding Cargo's
/// `CACHEDIR.TAG` (`target/`, also with `--target <triple>`), else the profile's parent.
pub fn target_dir() -> PathBuf {
    let profile = profile_dir();
    profile
        .ancestors()
        .skip(1)
        .find(|d| d.join("CACHEDIR.TAG").is_file())
        .or_else(|| profile.parent())
        .expect("the profile directory has a parent")
        .to_path_buf()
}

/// Cargo's temporary directory for tests, `<target>/tmp` (= `CARGO_TARGET_TMPDIR`).
pub fn target_tmp_dir() -> PathBuf {
    target_dir().join("tmp")
}

fn missing_message(missing: &[String], dir: &Path) -> String {
    format!(
        "{} not found in {}: these tests use the binaries of the workspace; build them first \
         with `cargo build --release --workspace` (./tests/run.sh does; same target dir and \
         profile) and run the tests with `cargo test --release`",
        missing.join(", "),
        dir.display()
    )
}

/// Panics with the build command to run unless every one of `names` is a file in the
/// profile directory; returns that directory.
fn require_built(names: &[&str]) -> PathBuf {
    let dir = profile_dir();
    let missing: Vec<String> = names
        .iter()
        .filter(|n| !dir.join(n).is_file())
        .map(|n| n.to_string())
        .collect();
    assert!(missing.is_empty(), "{}", missing_message(&missing, &dir));
    dir
}

/// `name` in the profile directory; panics with the build command when it is not there.
pub fn built(name: &str) -> PathBuf {
    require_built(&[name]).join(name)
}

/// The `tbi` executable (`CARGO_BIN_EXE_tbi` in master's own tests).
pub fn tbi() -> PathBuf {
    built("tbi")
}

/// The FMU shared objects `libbridge.so`, `libtrain.so`, `libwind.so`, which `tbi` exports from next to
/// itself; `cargo test -p tbi` alone does not build them. Panics when one is missing.
pub fn require_fmu_libraries() {
    require_built(&["libbridge.so", "libtrain.so", "libwind.so"]);
}

/// The profile directory after checking that it holds `tbi` and the FMU libraries (the
/// release binaries the cross-crate tests drive).
pub fn release_dir() -> PathBuf {
    require_built(&["tbi", "libbridge.so", "libtrain.so", "libwind.so"])
}

/// The shared library `<DLL_PREFIX><stem><DLL_SUFFIX>` (`libtestmodel.so`) of a cdylib that
/// Cargo built for this test run: in `deps/` (next to the test executable) or in the profile
/// directory above it.
pub fn cdylib(stem: &str) -> PathBuf {
    let name = format!(
        "{}{stem}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    );
    let exe = current_exe();
    let candidates: Vec<PathBuf> = exe
        .ancestors()
        .skip(1)
        .take(2)
        .map(|d| d.join(&name))
        .collect();
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .unwrap_or_else(|| panic!("{name} not found; looked at {candidates:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_profile_and_tmp_dirs_come_from_the_test_executable() {
        let profile = profile_dir();
        assert!(current_exe().starts_with(&profile));
        assert_ne!(profile.file_name().unwrap(), "deps");
        let tmp = target_tmp_dir();
        assert!(profile.starts_with(tmp.parent().unwrap()));
        assert!(repo_path("tests/python/setup-venv.sh").is_file());
    }
}
