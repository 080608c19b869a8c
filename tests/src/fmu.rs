//! Exporting scenarios with `tbi export` and unpacking FMUs independently of the importer
//! under test.

use crate::{paths, run_ok, scratch};
use model_description::{Causality, ModelDescription};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The files written by `tbi export`.
#[derive(Debug, Clone)]
pub struct Export {
    /// The scratch folder (holds `scenario.toml` and the `out/` folder).
    pub dir: PathBuf,
    pub scenario: PathBuf,
    pub bridge: PathBuf,
    pub train: PathBuf,
    /// `wind.fmu`, exported in a turbulent wind.
    pub wind: Option<PathBuf>,
    pub ssp: PathBuf,
}

/// Write `toml` to `<scratch folder labelled name>/scenario.toml` and run `tbi export` on it
/// (the release `tbi` next to the FMU libraries).
pub fn export(name: &str, toml: &str) -> Export {
    export_as(name, toml, &[])
}

/// [`export`] with more arguments for `tbi export` (e.g. `--fmi-version 3`).
pub fn export_as(name: &str, toml: &str, args: &[&str]) -> Export {
    let dir = scratch(name);
    let scenario = dir.join("scenario.toml");
    std::fs::write(&scenario, toml).expect("write scenario");
    let out = dir.join("out");
    run_ok(
        Command::new(paths::release_dir().join("tbi"))
            .arg("export")
            .arg(&scenario)
            .arg("--out")
            .arg(&out)
            .args(args),
    );
    let e = Export {
        bridge: out.join("bridge.fmu"),
        train: out.join("train.fmu"),
        wind: Some(out.join("wind.fmu")).filter(|p| p.is_file()),
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

/// Value references of the variables of causality `causality`, in the order declared.
pub fn vrs_of(md: &ModelDescription, causality: Causality) -> Vec<u32> {
    md.model_variables
        .iter()
        .filter(|v| v.causality == causality)
        .map(|v| v.value_reference)
        .collect()
}

/// Name of the variable with value reference `vr` (the first declared).
pub fn name_of(md: &ModelDescription, vr: u32) -> &str {
    &md.model_variables
        .iter()
        .find(|v| v.value_reference == vr)
        .unwrap_or_else(|| panic!("the model description has no variable of vr {vr}"))
        .name
}

/// Inputs of a bridge FMU at an operating point: every wheelset on the deck between `a` and
/// `b` (m) with a position, speed and forces of its own, and every deck wind input
/// (`deck[j].…`) at a value of its own.
pub fn bridge_operating_point(md: &ModelDescription, (a, b): (f64, f64)) -> Vec<(u32, f64)> {
    let n = md
        .model_variables
        .iter()
        .filter(|v| v.name.ends_with("].F_z") && v.causality == Causality::Input)
        .count();
    let mut inputs = Vec::new();
    for w in 1..=n {
        let s = w as f64;
        for (channel, value) in [
            ("x", a + (b - a) * (s - 0.55) / n as f64),
            ("vx", 40.0 + s),
            ("F_y", -2.1e3 * s),
            ("M_x", 5.5e2 - 30.0 * s),
            ("F_z", 7.7e4 + 1.0e3 * s),
        ] {
            inputs.push((vr_of(md, &format!("ws[{w}].{channel}")), value));
        }
    }
    let deck = md
        .model_variables
        .iter()
        .filter(|v| v.name.starts_with("deck[") && v.causality == Causality::Input);
    for (j, v) in deck.enumerate() {
        inputs.push((v.value_reference, 1.5 - 0.2 * j as f64));
    }
    inputs
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

/// A zip (an FMU or an SSP) with every file entry passed through `edit(name, bytes)`;
/// directory entries are kept. For tests that damage or modify an exported archive.
pub fn rewrite_zip(bytes: &[u8], edit: impl Fn(&str, Vec<u8>) -> Vec<u8>) -> Vec<u8> {
    use std::io::{Read, Write};
    let mut zin = zip::ZipArchive::new(std::io::Cursor::new(bytes)).expect("a zip archive");
    let mut zout = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    for i in 0..zin.len() {
        let mut e = zin.by_index(i).expect("entry");
        let name = e.name().expect("entry name").into_owned();
        if e.is_dir() {
            zout.add_directory(name, options).expect("add directory");
            continue;
        }
        let mut b = Vec::new();
        e.read_to_end(&mut b).expect("read entry");
        let b = edit(&name, b);
        zout.start_file(name, options).expect("start entry");
        zout.write_all(&b).expect("write entry");
    }
    zout.finish().expect("finish zip").into_inner()
}

/// [`rewrite_zip`] from the file `from` to the file `to`.
pub fn rewrite_zip_file(from: &Path, to: &Path, edit: impl Fn(&str, Vec<u8>) -> Vec<u8>) {
    let bytes = std::fs::read(from).unwrap_or_else(|e| panic!("{}: {e}", from.display()));
    std::fs::write(to, rewrite_zip(&bytes, edit))
        .unwrap_or_else(|e| panic!("{}: {e}", to.display()));
}
