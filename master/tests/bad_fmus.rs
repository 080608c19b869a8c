//! Broken and misbehaving FMUs: `tbi simulate` refuses them with a message naming the
//! FMU and the problem, exits with status 1 (never a crash or a panic), and leaves no
//! files outside its temporary directory.

mod fmu_support;

use fmu_support::*;
use std::io::Write;
use std::path::{Path, PathBuf};
use tbi_tests::{scratch, tbi_in, text, TextCsv};
use zip::write::SimpleFileOptions;

/// Run `tbi simulate FMU --output out.csv` in the FMU's directory; expect failure.
fn refused(fmu: &Path) -> String {
    let dir = fmu.parent().unwrap();
    let run = tbi_in(
        dir,
        &[
            "simulate",
            fmu.file_name().unwrap().to_str().unwrap(),
            "--output",
            "out.csv",
            "--quiet",
        ],
    );
    let stderr = text(&run.stderr);
    assert_eq!(
        run.status.code(),
        Some(1),
        "expected a clean failure, got {:?}:\n{stderr}",
        run.status
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// A zip with the given entries (name, bytes) at `dir/name`.
fn zip_with(dir: &Path, name: &str, entries: &[(&str, &[u8])]) -> PathBuf {
    let path = dir.join(name);
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    for (entry, bytes) in entries {
        zip.start_file(*entry, SimpleFileOptions::default())
            .unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap();
    path
}

#[test]
fn corrupt_zip() {
    let dir = scratch("corrupt");
    let fmu = dir.join("Corrupt.fmu");
    let good = build_fmu(&Variant::new("ToCorrupt"));
    let mut bytes = std::fs::read(good).unwrap();
    bytes.truncate(bytes.len() / 2);
    std::fs::write(&fmu, bytes).unwrap();
    let e = refused(&fmu);
    assert!(
        e.contains("tbi: error: Corrupt.fmu: not a valid zip archive"),
        "{e}"
    );
}

#[test]
fn not_a_zip_at_all() {
    let dir = scratch("text");
    let fmu = dir.join("Text.fmu");
    std::fs::write(&fmu, "this is a text file").unwrap();
    assert!(refused(&fmu).contains("Text.fmu: not a valid zip archive"));
}

#[test]
fn path_traversal_entry() {
    let dir = scratch("traversal");
    let nested = dir.join("a/b");
    std::fs::create_dir_all(&nested).unwrap();
    let xml = model_description_xml(&Variant::new("x"));
    let fmu = zip_with(
        &nested,
        "Traversal.fmu",
        &[
            ("modelDescription.xml", xml.as_bytes()),
            ("resources/../../../escaped.txt", b"gotcha"),
        ],
    );
    let e = refused(&fmu);
    assert!(
        e.contains("Traversal.fmu: entry \"resources/../../../escaped.txt\": the path contains a '..' component"),
        "{e}"
    );
    assert!(!dir.join("escaped.txt").exists() && !nested.join("escaped.txt").exists());
}

#[test]
fn absolute_entry() {
    let dir = scratch("absolute");
    let fmu = zip_with(
        &dir,
        "Absolute.fmu",
        &[("/tmp/tbi-absolute-entry.txt", b"x")],
    );
    let e = refused(&fmu);
    assert!(
        e.contains("Absolute.fmu: entry \"/tmp/tbi-absolute-entry.txt\": absolute path"),
        "{e}"
    );
}

#[test]
fn no_linux64_binary() {
    let dir = scratch("nolinux");
    let xml = model_description_xml(&Variant::new("x"));
    let fmu = zip_with(
        &dir,
        "WindowsOnly.fmu",
        &[
            ("modelDescription.xml", xml.as_bytes()),
            ("binaries/win64/oscillator.dll", b"MZ"),
        ],
    );
    let e = refused(&fmu);
    assert!(
        e.contains("WindowsOnly.fmu: no binaries/linux64/oscillator.so in the archive (binaries for: win64)"),
        "{e}"
    );
}

#[test]
fn binary_that_is_not_a_library() {
    let dir = scratch("notelf");
    let xml = model_description_xml(&Variant::new("x"));
    let fmu = zip_with(
        &dir,
        "NotElf.fmu",
        &[
            ("modelDescription.xml", xml.as_bytes()),
            ("binaries/linux64/oscillator.so", b"not an ELF file"),
        ],
    );
    let e = refused(&fmu);
    assert!(
        e.contains("NotElf.fmu: cannot load binaries/linux64/oscillator.so: "),
        "{e}"
    );
}

#[test]
fn missing_symbol() {
    let fmu = build_fmu(&Variant::new("MissingSymbol").define("-DOMIT_GET_REAL_STATUS"));
    let e = refused(&fmu);
    assert!(
        e.contains("MissingSymbol.fmu: binaries/linux64/oscillator.so does not export the required FMI 2.0 function fmi2GetRealStatus"),
        "{e}"
    );
}

#[test]
fn invalid_xml() {
    let dir = scratch("badxml");
    let xml = model_description_xml(&Variant::new("x"));
    let broken = xml.replace("</ModelVariables>", "</ModelVariable>");
    let fmu = zip_with(
        &dir,
        "BadXml.fmu",
        &[("modelDescription.xml", broken.as_bytes())],
    );
    let e = refused(&fmu);
    assert!(
        e.contains("BadXml.fmu: modelDescription.xml: malformed XML at line 70, column 3"),
        "{e}"
    );
}

#[test]
fn invalid_attribute_value() {
    let variant =
        Variant::new("BadCausality").replace("causality=\"input\"", "causality=\"inptu\"");
    let e = refused(&build_fmu_unchecked(&variant));
    assert!(
        e.contains("BadCausality.fmu: modelDescription.xml: line 43: <ScalarVariable> 5 \"F\": causality \"inptu\" is not one of"),
        "{e}"
    );
}

/// Package a variant whose description the packager would refuse, by writing the zip
/// directly.
fn build_fmu_unchecked(variant: &Variant) -> PathBuf {
    let dir = scratch(&variant.name);
    let so = compile(variant, &dir);
    let xml = model_description_xml(variant);
    let library = std::fs::read(so).unwrap();
    zip_with(
        &dir,
        &format!("{}.fmu", variant.name),
        &[
            ("modelDescription.xml", xml.as_bytes()),
            ("binaries/linux64/oscillator.so", &library),
            ("resources/gain.txt", b"1"),
        ],
    )
}

#[test]
fn no_model_description() {
    let dir = scratch("nomd");
    let fmu = zip_with(&dir, "Empty.fmu", &[("resources/gain.txt", b"1")]);
    let e = refused(&fmu);
    assert!(
        e.contains("Empty.fmu: the archive has no modelDescription.xml at its root"),
        "{e}"
    );
}

#[test]
fn a_description_breaking_fmi_rules_is_refused_before_the_fmu_runs() {
    // two variables named "x" (what `fmpy validate` reports), as FMPy's simulate refuses it
    let variant = Variant::new("TwoX").replace("name=\"x0\"", "name=\"x\"");
    let fmu = build_fmu_unchecked(&variant);
    let e = refused(&fmu);
    assert!(
        e.contains("TwoX.fmu: modelDescription.xml breaks") && e.contains("\"x\""),
        "{e}"
    );
    assert!(!fmu.parent().unwrap().join("out.csv").exists());
    assert!(!fmu.parent().unwrap().join("out.csv.partial").exists());
}

#[test]
fn a_description_that_is_not_utf8_is_refused_with_the_byte_offset() {
    let dir = scratch("notutf8");
    let xml: &[u8] = b"<?xml version=\"1.0\"?>\n<fmiModelDescription description=\"\xff\"/>\n";
    let at = xml.iter().position(|&b| b == 0xff).unwrap();
    let fmu = zip_with(&dir, "Latin1.fmu", &[("modelDescription.xml", xml)]);
    let e = refused(&fmu);
    assert!(
        e.contains("Latin1.fmu") && e.contains(&format!("not valid UTF-8 at byte {at}")),
        "{e}"
    );
}

#[test]
fn model_exchange_only() {
    let variant = Variant::new("MeOnly").replace("<CoSimulation", "<ModelExchange");
    let e = refused(&build_fmu_unchecked(&variant));
    assert!(
        e.contains("MeOnly.fmu: the FMU has no <CoSimulation> interface"),
        "{e}"
    );
}

#[test]
fn instantiate_failure_carries_the_fmu_log() {
    let fmu = build_fmu(&Variant::new("NoResource").gain(None));
    let e = refused(&fmu);
    assert!(
        e.contains("NoResource.fmu: fmi2Instantiate(instanceName=\"oscillator\") failed (returned NULL); the FMU logged:"),
        "{e}"
    );
    assert!(
        e.contains("fmi2Error [logStatusError] cannot read /"),
        "{e}"
    );
    assert!(e.contains("/resources/gain.txt"), "{e}");
}

#[test]
fn do_step_error() {
    let fmu = build_fmu(&Variant::new("Fails").define("-DFAIL_AT=1.0"));
    let e = refused(&fmu);
    assert!(
        e.contains("Fails.fmu: fmi2DoStep(currentCommunicationPoint=1, communicationStepSize=0.010000000000000009, noSetFMUStatePriorToCurrentPoint=true) returned fmi2Error (instance \"oscillator\"); the FMU logged:\n  [oscillator] fmi2Error [logStatusError] DoStep failed at t=1 (the solver diverged, h=0.01)"),
        "{e}"
    );
    assert!(
        !fmu.parent().unwrap().join("out.csv").exists(),
        "no result file after an error"
    );
    assert!(
        e.contains("(the rows computed before are in out.csv.partial)"),
        "{e}"
    );
    // the rows up to the step that failed (from t = 1) were streamed and kept
    let partial = TextCsv::read(&fmu.parent().unwrap().join("out.csv.partial"));
    assert_eq!(partial.rows.last().unwrap()[0], "1.0");
}

#[test]
fn discard_without_termination_stops_cleanly() {
    let fmu = build_fmu(&Variant::new("Discards").define("-DDISCARD_AT=0.5"));
    let e = refused(&fmu);
    assert!(
        e.contains("Discards.fmu: fmi2DoStep returned fmi2Discard at t=0.5 without requesting termination; the simulation stopped there (results up to t=0.5 were written to out.csv)"),
        "{e}"
    );
    let csv = TextCsv::read(&fmu.parent().unwrap().join("out.csv"));
    assert_eq!(csv.rows.len(), 51);
    assert_eq!(csv.rows.last().unwrap()[0], "0.5");
}

#[test]
fn discard_with_termination_ends_normally() {
    let fmu = build_fmu(
        &Variant::new("Terminates")
            .define("-DDISCARD_AT=0.505")
            .define("-DDISCARD_TERMINATE=1"),
    );
    let dir = fmu.parent().unwrap();
    let run = tbi_in(dir, &["simulate", "Terminates.fmu", "--output", "out.csv"]);
    let stderr = text(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(stderr.contains("[oscillator] fmi2Discard [logStatusDiscard] end of the model's data reached at t=0.505"), "{stderr}");
    assert!(stderr.contains("tbi: Terminates.fmu: the FMU requested termination at t=0.505; the simulation ended there"), "{stderr}");
    let csv = TextCsv::read(&dir.join("out.csv"));
    assert_eq!(csv.rows.last().unwrap()[0], "0.505");
}

#[test]
fn nan_output() {
    let fmu = build_fmu(&Variant::new("NotANumber").define("-DNAN_AT=0.5"));
    let e = refused(&fmu);
    assert!(
        e.contains("NotANumber.fmu: fmi2GetReal (instance \"oscillator\") returned the non-finite value NaN for variable \"x\" (value reference 5)"),
        "{e}"
    );
}

#[test]
fn unpacked_files_are_removed() {
    // every refusal above happens after unpacking; the temp dir must not outlive the run
    // (a private TMPDIR, so that the other tests' runs in parallel are not counted)
    let fmu = build_fmu(&Variant::new("Cleanup").define("-DFAIL_AT=0.1"));
    let dir = fmu.parent().unwrap();
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let run = tbi_tests::run(
        tbi_tests::tbi_command()
            .args(["simulate", "Cleanup.fmu", "--output", "out.csv", "--quiet"])
            .current_dir(dir)
            .env("TMPDIR", &tmp),
    );
    assert_eq!(run.status.code(), Some(1), "{}", text(&run.stderr));
    let left: Vec<_> = std::fs::read_dir(&tmp)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
