//! Building the C test FMUs (tests/c-fmu: `<model>.c` with its description `<model>.xml`;
//! the oscillator, the sprung-mass vehicle, the Integer/Boolean counter) in variants and packaging them with
//! `tbi::fmus::package::write_fmu` (needs master's internals, so it stays here). Running `tbi`,
//! scratch folders, FMPy and the CSV comparison are in the shared `tbi_tests` library.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use tbi_tests::{repo_path, scratch};

/// How to build one test FMU.
#[derive(Clone, Debug)]
pub struct Variant {
    /// File stem of the .fmu.
    pub name: String,
    /// The model: `tests/c-fmu/<model>.c` and `.xml`, and the model identifier.
    pub model: &'static str,
    /// `-D` definitions for the C source.
    pub defines: Vec<String>,
    /// Replacements applied to the model's description.
    pub xml_replacements: Vec<(String, String)>,
    /// Content of resources/gain.txt; `None` leaves the file out.
    pub gain: Option<String>,
}

impl Variant {
    /// A variant of the oscillator (which reads resources/gain.txt).
    pub fn new(name: &str) -> Self {
        Self {
            name: name.into(),
            model: "oscillator",
            defines: Vec::new(),
            xml_replacements: Vec::new(),
            gain: Some("1.0\n".into()),
        }
    }
    /// Another model of tests/c-fmu (`sprung_mass`, `counter`), which reads no resources.
    pub fn model(model: &'static str, name: &str) -> Self {
        Self {
            model,
            gain: None,
            ..Self::new(name)
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
    let path = repo_path(&format!("tests/c-fmu/{}.xml", variant.model));
    let mut xml = std::fs::read_to_string(&path).unwrap();
    for (from, to) in &variant.xml_replacements {
        assert!(
            xml.contains(from.as_str()),
            "{} has no {from:?}",
            path.display()
        );
        xml = xml.replace(from.as_str(), to);
    }
    xml
}

/// Compile `<model>.c` with the variant's definitions into `dir`/`<model>.so`.
pub fn compile(variant: &Variant, dir: &Path) -> PathBuf {
    let source = repo_path(&format!("tests/c-fmu/{}.c", variant.model));
    let so = dir.join(format!("{}.so", variant.model));
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
        .arg(repo_path("tests/c-fmu"))
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
    let dir = scratch(&variant.name);
    let so = compile(variant, &dir);
    let fmu = dir.join(format!("{}.fmu", variant.name));
    let resources: Vec<(String, Vec<u8>)> = variant
        .gain
        .iter()
        .map(|g| ("gain.txt".to_owned(), g.clone().into_bytes()))
        .collect();
    tbi::fmus::package::write_fmu(
        &fmu,
        &model_description_xml(variant),
        variant.model,
        &so,
        &resources,
        Some(&format!(
            "<html><body>Test FMU {} (tests/c-fmu)</body></html>",
            variant.model
        )),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    fmu
}
