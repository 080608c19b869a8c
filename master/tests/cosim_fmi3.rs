//! The master with FMI 3.0 FMUs:
//!
//! * implicit co-simulation of the FMI 3.0 bridge and train (`tbi run --solver cosim
//!   --fmi-version 3`) equals the monolithic solver on the coach case to 1e-8 of each
//!   history column's largest value, as the FMI 2.0 FMUs do (`cosim_implicit.rs`);
//! * `tbi cosim` runs an FMI 3.0 system and a mixed one (FMI 3.0 bridge, FMI 2.0 train),
//!   isolated and in process, to the same bytes as the FMI 2.0 system, and its rows equal
//!   the monolithic solution to 1e-8;
//! * `tbi simulate` runs an FMI 3.0 FMU to the bytes of its FMI 2.0 twin.

mod cli_support;

use cli_support::{data, run, Scenario};
use std::path::{Path, PathBuf};
use tbi_tests::fmu::rewrite_zip_file;
use tbi_tests::{assert_same_table, require_fmu_libraries, run_ok, scratch, tbi_command, Table};

/// Bound of max |cosim − monolithic| / max |monolithic| in every column.
const TOL: f64 = 1e-8;

/// The `fmiVersion` of an FMU's description.
fn fmi_version(fmu: &Path) -> String {
    let file = std::fs::File::open(fmu).unwrap();
    let mut zip = zip::ZipArchive::new(file).unwrap();
    let mut md = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("modelDescription.xml").unwrap(), &mut md)
        .unwrap();
    md.split("fmiVersion=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .to_owned()
}

#[test]
fn fmi3_cosimulation_equals_the_monolithic_solution() {
    require_fmu_libraries();
    let dir = scratch("fmi3-coaches");
    let scenario = Scenario::from_data("coaches-60m.toml")
        .coupling(
            "scheme = \"implicit\"\nrtol = 1e-12\natol = 1e-12\non_non_convergence = \"stop\"\n",
        )
        .write(&dir, "coaches.toml");
    let mono = run(&scenario, "monolithic", &dir.join("mono"), &[]);
    mono.expect_ok("monolithic");
    let cosim = run(
        &scenario,
        "cosim",
        &dir.join("cosim3"),
        &["--fmi-version", "3"],
    );
    cosim.expect_ok("cosim, FMI 3.0");
    for fmu in ["bridge", "train"] {
        assert_eq!(
            fmi_version(&dir.join(format!("cosim3/fmus/{fmu}.fmu"))),
            "3.0"
        );
    }
    assert_same_table(
        &mono.history(),
        &cosim.history(),
        TOL,
        "FMI 3.0 co-simulation",
    );
    // the FMI version applies to the co-simulation only
    let refused = run(
        &scenario,
        "monolithic",
        &dir.join("refused"),
        &["--fmi-version", "3"],
    );
    assert!(!refused.ok());
    assert!(
        refused
            .stderr
            .contains("--fmi-version 3 applies to --solver cosim"),
        "{}",
        refused.stderr
    );
}

/// `tbi export` of Yang–Yau into `dir/<label>` as FMI `version`; the SSP.
fn export(dir: &Path, label: &str, version: &str) -> PathBuf {
    run_ok(
        tbi_command()
            .arg("export")
            .arg(data("yang-yau.toml"))
            .args(["--fmi-version", version, "--out"])
            .arg(dir.join(label)),
    );
    dir.join(label).join("system.ssp")
}

/// `tbi cosim SSP` recording the wheel force and the mid-span probe; the CSV bytes.
fn cosim(ssp: &Path, out: &Path, extra: &[&str]) -> Vec<u8> {
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(ssp)
            .args([
                "--quiet",
                "--record",
                "train.ws[1].F_z",
                "--record",
                "bridge.probe[1].z",
                "--output",
            ])
            .arg(out)
            .args(extra),
    );
    std::fs::read(out).unwrap()
}

#[test]
fn fmi3_and_mixed_systems_run_as_the_fmi2_one() {
    require_fmu_libraries();
    let dir = scratch("fmi3-systems");
    let two = export(&dir, "two", "2");
    let three = export(&dir, "three", "3");
    let bridge3 = std::fs::read(dir.join("three/bridge.fmu")).unwrap();
    let mixed = dir.join("mixed.ssp");
    rewrite_zip_file(&two, &mixed, |name, bytes| {
        if name == "resources/bridge.fmu" {
            bridge3.clone()
        } else {
            bytes
        }
    });
    let reference = cosim(&two, &dir.join("two.csv"), &[]);
    for (label, ssp, extra) in [
        ("FMI 3.0", &three, &[][..]),
        ("FMI 3.0 in process", &three, &["--in-process"][..]),
        ("mixed", &mixed, &[][..]),
        ("mixed in process", &mixed, &["--in-process"][..]),
    ] {
        let got = cosim(ssp, &dir.join(format!("{label}.csv")), extra);
        assert!(
            got == reference,
            "{label}: the result differs from the FMI 2.0 system's"
        );
    }
    // and the rows are the monolithic solution's
    let mono = run(&data("yang-yau.toml"), "monolithic", &dir.join("mono"), &[]);
    mono.expect_ok("monolithic");
    let history = mono.history();
    let rows = Table::read(&dir.join("FMI 3.0.csv"));
    for (ours, theirs) in [
        ("train.ws[1].F_z", "ws1.vertical_force_n"),
        ("bridge.probe[1].z", "mid.vertical_displacement_m"),
    ] {
        let (a, b) = (rows.column(ours), history.column(theirs));
        assert_eq!(a.len(), b.len());
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
            / scale;
        assert!(worst <= TOL, "{ours} against {theirs}: {worst:e}");
    }
    // one FMU alone under tbi simulate
    let sim = |fmu: &Path, out: &str| {
        run_ok(
            tbi_command()
                .arg("simulate")
                .arg(fmu)
                .args(["--stop-time", "0.2", "--quiet", "--output"])
                .arg(dir.join(out)),
        );
        std::fs::read(dir.join(out)).unwrap()
    };
    assert!(
        sim(&dir.join("three/train.fmu"), "t3.csv") == sim(&dir.join("two/train.fmu"), "t2.csv")
    );
}
