//! Shared helpers of the FMU tests: build the C test FMU (tests/c-fmu) in variants,
//! package it with `tbi::package::write_fmu`, run `tbi`, and run FMPy from the venv of
//! tests/python/setup-venv.sh.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("master/ has a parent")
        .to_path_buf()
}

/// A fresh empty directory under Cargo's per-target test temp dir.
pub fn scratch_dir(label: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    // per test binary and label; reused (emptied) by the next run instead of piling up
    let binary = std::env::current_exe()
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_default();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("fmu-tests")
        .join(format!("{binary}-{label}-{n}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// How to build one test FMU.
#[derive(Clone, Debug)]
pub struct Variant {
    /// File stem of the .fmu.
    pub name: String,
    /// `-D` definitions for oscillator.c.
    pub defines: Vec<String>,
    /// Replacements applied to tests/c-fmu/modelDescription.xml.
    pub xml_replacements: Vec<(String, String)>,
    /// Content of resources/gain.txt; `None` leaves the file out.
    pub gain: Option<String>,
}

impl Variant {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.into(),
            defines: Vec::new(),
            xml_replacements: Vec::new(),
            gain: Some("1.0\n".into()),
        }
    }
    pub fn define(mut self, d: &str) -> Self {
        self.defines.push(d.into());
        self
    }
    pub fn replace(mut self, from: &str, to: &str) -> Self {
        self.xml_replacements.push((from.into(), to.into()));
        self
    }
    pub fn gain(mut self, gain: Option<&str>) -> Self {
        self.gain = gain.map(str::to_owned);
        self
    }
}

pub fn model_description_xml(variant: &Variant) -> String {
    let mut xml =
        std::fs::read_to_string(repo_root().join("tests/c-fmu/modelDescription.xml")).unwrap();
    for (from, to) in &variant.xml_replacements {
        assert!(
            xml.contains(from.as_str()),
            "modelDescription.xml has no {from:?}"
        );
        xml = xml.replace(from.as_str(), to);
    }
    xml
}

/// Compile oscillator.c with the variant's definitions into `dir`/oscillator.so.
pub fn compile(variant: &Variant, dir: &Path) -> PathBuf {
    let source = repo_root().join("tests/c-fmu/oscillator.c");
    let so = dir.join("oscillator.so");
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let output = Command::new(&compiler)
        .args([
            "-shared",
            "-fPIC",
            "-O2",
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-fvisibility=hidden",
        ])
        .args(&variant.defines)
        .arg("-I")
        .arg(repo_root().join("tests/c-fmu"))
        .arg(&source)
        .arg("-o")
        .arg(&so)
        .arg("-lm")
        .output()
        .unwrap_or_else(|e| panic!("cannot run the C compiler {compiler}: {e}"));
    assert!(
        output.status.success(),
        "compiling {} failed:\n{}",
        source.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    so
}

/// Build the variant's .fmu in a fresh scratch directory and return its path.
pub fn build_fmu(variant: &Variant) -> PathBuf {
    let dir = scratch_dir(&variant.name);
    let so = compile(variant, &dir);
    let fmu = dir.join(format!("{}.fmu", variant.name));
    let resources: Vec<(String, Vec<u8>)> = variant
        .gain
        .iter()
        .map(|g| ("gain.txt".to_owned(), g.clone().into_bytes()))
        .collect();
    tbi::package::write_fmu(
        &fmu,
        &model_description_xml(variant),
        "oscillator",
        &so,
        &resources,
        Some("<html><body>Damped oscillator test FMU</body></html>"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    fmu
}

/// Run the `tbi` binary.
pub fn tbi(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tbi"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("cannot run tbi")
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The directory of the FMPy virtual environment, or `None` when TBI_SKIP_PYTHON=1.
/// Panics with the script's output when the venv cannot be created.
pub fn fmpy_venv() -> Option<PathBuf> {
    static VENV: OnceLock<Option<PathBuf>> = OnceLock::new();
    VENV.get_or_init(|| {
        if std::env::var("TBI_SKIP_PYTHON").as_deref() == Ok("1") {
            eprintln!("TBI_SKIP_PYTHON=1: skipping the comparison with FMPy");
            return None;
        }
        let script = repo_root().join("tests/python/setup-venv.sh");
        let output = Command::new("bash")
            .arg(&script)
            .output()
            .unwrap_or_else(|e| panic!("cannot run {}: {e}", script.display()));
        assert!(
            output.status.success(),
            "{} failed (set TBI_SKIP_PYTHON=1 to skip the FMPy comparison explicitly):\n{}{}",
            script.display(),
            text(&output.stdout),
            text(&output.stderr)
        );
        let venv = text(&output.stdout)
            .lines()
            .last()
            .map(|l| PathBuf::from(l.trim()))
            .expect("setup-venv.sh prints the venv directory");
        assert!(
            venv.join("bin/fmpy").is_file(),
            "{} has no bin/fmpy",
            venv.display()
        );
        Some(venv)
    })
    .clone()
}

/// Run `fmpy simulate` with the given arguments.
pub fn fmpy(venv: &Path, args: &[&str], cwd: &Path) -> Output {
    Command::new(venv.join("bin/fmpy"))
        .arg("simulate")
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("cannot run fmpy")
}

/// A CSV as written by `tbi simulate` / `fmpy simulate`: header and text fields.
#[derive(Debug)]
pub struct Csv {
    pub header: String,
    pub rows: Vec<Vec<String>>,
}

pub fn read_csv(path: &Path) -> Csv {
    let content =
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = content.lines();
    let header = lines
        .next()
        .unwrap_or_else(|| panic!("{} is empty", path.display()))
        .to_owned();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    Csv { header, rows }
}

/// Assert equal headers and row counts, identical non-numeric fields, and numbers equal
/// to 1e-9 (relative to max(1, |value|)).
pub fn assert_csv_match(tbi_csv: &Csv, fmpy_csv: &Csv) {
    assert_eq!(tbi_csv.header, fmpy_csv.header, "headers differ");
    assert_eq!(
        tbi_csv.rows.len(),
        fmpy_csv.rows.len(),
        "row counts differ: tbi {} vs fmpy {}",
        tbi_csv.rows.len(),
        fmpy_csv.rows.len()
    );
    for (i, (a, b)) in tbi_csv.rows.iter().zip(&fmpy_csv.rows).enumerate() {
        assert_eq!(a.len(), b.len(), "row {i}: field counts differ");
        for (j, (x, y)) in a.iter().zip(b).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => assert!(
                    (x - y).abs() <= 1e-9 * y.abs().max(1.0),
                    "row {i}, column {j} ({}): tbi {x} vs fmpy {y}",
                    tbi_csv.header
                ),
                _ => assert_eq!(x, y, "row {i}, column {j}"),
            }
        }
    }
}
