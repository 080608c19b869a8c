//! Shared helpers of the FMU integration tests: locating the release binaries, exporting
//! scenarios with `tbi export`, unpacking FMUs, and finding the FMPy venv.
//!
//! The tests build nothing themselves. They use the `tbi` executable and the FMU shared
//! objects `libbridge.so` / `libtrain.so` that `cargo build --release --workspace` puts next
//! to the test executable's `deps/` folder (`./tests/run.sh` does that build first).

#![allow(dead_code)] // each test binary uses a different subset

pub mod elf;
pub mod reference;
pub mod scenarios;

use model_description::ModelDescription;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root (parent of the `tests` crate).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// The cargo profile directory holding `tbi`, `libbridge.so` and `libtrain.so`
/// (`target/release` when the test runs from `target/release/deps/<test>`).
pub fn release_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("path of the test executable");
    let deps = exe.parent().expect("test executable has a folder");
    let dir = if deps.file_name().is_some_and(|n| n == "deps") {
        deps.parent().expect("deps/ has a parent").to_path_buf()
    } else {
        deps.to_path_buf()
    };
    let missing: Vec<&str> = ["tbi", "libbridge.so", "libtrain.so"]
        .into_iter()
        .filter(|f| !dir.join(f).is_file())
        .collect();
    assert!(
        missing.is_empty(),
        "{} not found in {}: these tests use the release binaries of the workspace; build them \
         first with `cargo build --release --workspace` (./tests/run.sh does) and run the tests \
         with `cargo test --release`",
        missing.join(", "),
        dir.display()
    );
    dir
}

/// The `tbi` executable.
pub fn tbi() -> PathBuf {
    release_dir().join("tbi")
}

/// A fresh, empty scratch folder `<target>/tmp/tbi-tests/<name>` (removed first if present).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("tbi-tests")
        .join(name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir)
            .unwrap_or_else(|e| panic!("cannot clear {}: {e}", dir.display()));
    }
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Run a command and return its output; panics with the command, status, stdout and
/// stderr when it fails to start or exits non-zero.
pub fn run_ok(cmd: &mut Command) -> Output {
    let out = run(cmd);
    assert!(
        out.status.success(),
        "{cmd:?} failed ({})\n--- stdout\n{}\n--- stderr\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Run a command (any exit status); panics only when it cannot be started.
pub fn run(cmd: &mut Command) -> Output {
    cmd.output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"))
}

/// The files written by `tbi export`.
#[derive(Debug, Clone)]
pub struct Export {
    /// The scratch folder (holds `scenario.toml` and the `out/` folder).
    pub dir: PathBuf,
    pub scenario: PathBuf,
    pub bridge: PathBuf,
    pub train: PathBuf,
    pub ssp: PathBuf,
}

/// Write `toml` to `<scratch name>/scenario.toml` and run `tbi export` on it.
pub fn export(name: &str, toml: &str) -> Export {
    let dir = scratch(name);
    let scenario = dir.join("scenario.toml");
    std::fs::write(&scenario, toml).expect("write scenario");
    let out = dir.join("out");
    run_ok(
        Command::new(tbi())
            .arg("export")
            .arg(&scenario)
            .arg("--out")
            .arg(&out),
    );
    let e = Export {
        bridge: out.join("bridge.fmu"),
        train: out.join("train.fmu"),
        ssp: out.join("system.ssp"),
        dir,
        scenario,
    };
    for f in [&e.bridge, &e.train, &e.ssp] {
        assert!(f.is_file(), "tbi export did not write {}", f.display());
    }
    e
}

/// An FMU unpacked by the test (independently of the importer under test).
#[derive(Debug)]
pub struct Unpacked {
    pub dir: PathBuf,
    pub md: ModelDescription,
    /// `binaries/linux64/<modelIdentifier>.so`.
    pub library: PathBuf,
    pub resources: PathBuf,
    pub model_identifier: String,
}

impl Unpacked {
    /// Value reference of the variable called `name`.
    pub fn vr(&self, name: &str) -> u32 {
        vr_of(&self.md, name)
    }
}

/// Value reference of the variable `name` of a model description.
pub fn vr_of(md: &ModelDescription, name: &str) -> u32 {
    md.model_variables
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("the model description has no variable {name}"))
        .value_reference
}

/// Extract `fmu` into `into` with the `zip` crate and read its model description.
pub fn unpack(fmu: &Path, into: &Path) -> Unpacked {
    if into.exists() {
        std::fs::remove_dir_all(into).expect("clear unpack folder");
    }
    let file = std::fs::File::open(fmu).unwrap_or_else(|e| panic!("{}: {e}", fmu.display()));
    let mut zip = zip::ZipArchive::new(file).unwrap_or_else(|e| panic!("{}: {e}", fmu.display()));
    zip.extract(into)
        .unwrap_or_else(|e| panic!("unpacking {}: {e}", fmu.display()));
    let xml = std::fs::read_to_string(into.join("modelDescription.xml"))
        .unwrap_or_else(|e| panic!("{}: modelDescription.xml: {e}", fmu.display()));
    let md =
        ModelDescription::parse(&xml, &fmu.display().to_string()).unwrap_or_else(|e| panic!("{e}"));
    let model_identifier = md
        .co_simulation
        .as_ref()
        .expect("a Co-Simulation FMU")
        .model_identifier
        .clone();
    let library = into
        .join("binaries")
        .join("linux64")
        .join(format!("{model_identifier}.so"));
    assert!(
        library.is_file(),
        "{} has no {}",
        fmu.display(),
        library.display()
    );
    Unpacked {
        dir: into.to_path_buf(),
        library,
        resources: into.join("resources"),
        model_identifier,
        md,
    }
}

/// The FMPy venv's folder, or `None` when `TBI_SKIP_PYTHON=1` asks to skip the FMPy tests.
///
/// Runs `tests/python/setup-venv.sh` (idempotent; creates the venv if needed) and takes the
/// last line of its standard output. Panics with the script's messages when the venv is
/// missing and cannot be created.
pub fn fmpy_venv() -> Option<PathBuf> {
    if std::env::var("TBI_SKIP_PYTHON").as_deref() == Ok("1") {
        eprintln!("TBI_SKIP_PYTHON=1: FMPy test skipped");
        return None;
    }
    let script = repo_root().join("tests/python/setup-venv.sh");
    let out = run(Command::new("bash").arg(&script));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "the FMPy venv is missing and {} could not create it ({}):\n{}\n{}\n\
         (set TBI_SKIP_PYTHON=1 to skip the FMPy tests explicitly)",
        script.display(),
        out.status,
        stdout,
        String::from_utf8_lossy(&out.stderr)
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
    Some(venv)
}

/// A CSV table (header and numeric rows); names are unquoted.
#[derive(Debug, Clone)]
pub struct Table {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    pub fn read(path: &Path) -> Table {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text.lines();
        let names: Vec<String> = lines
            .next()
            .unwrap_or_else(|| panic!("{} is empty", path.display()))
            .split(',')
            .map(|n| n.trim().trim_matches('"').to_string())
            .collect();
        let rows: Vec<Vec<f64>> = lines
            .filter(|l| !l.trim().is_empty())
            .enumerate()
            .map(|(i, l)| {
                l.split(',')
                    .map(|v| {
                        v.trim().parse::<f64>().unwrap_or_else(|e| {
                            panic!("{} row {}: {v:?}: {e}", path.display(), i + 1)
                        })
                    })
                    .collect()
            })
            .collect();
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(
                r.len(),
                names.len(),
                "{} row {} has {} values for {} columns",
                path.display(),
                i + 1,
                r.len(),
                names.len()
            );
        }
        Table { names, rows }
    }

    /// Index of column `name`.
    pub fn col(&self, name: &str) -> usize {
        self.names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("no column {name:?} in {:?}", self.names))
    }

    /// The values of column `name`.
    pub fn column(&self, name: &str) -> Vec<f64> {
        let c = self.col(name);
        self.rows.iter().map(|r| r[c]).collect()
    }
}
