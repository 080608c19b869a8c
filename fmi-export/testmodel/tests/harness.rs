//! The fmi-export C-ABI harness against the test model's shared object.

mod common;

use fmi_import::harness::{run, HarnessConfig};
use testmodel::vr;

fn config() -> HarnessConfig {
    HarnessConfig::new(
        common::library(),
        testmodel::MODEL_IDENTIFIER,
        common::guid(),
        common::resources(),
        vr::FORCE,
        vr::X,
    )
}

#[test]
fn testmodel_passes_every_harness_check() {
    let report = run(&config());
    println!("{report}");
    assert!(report.all_passed(), "{report}");
    // The report covers the groups the harness promises (guards against checks silently
    // disappearing).
    assert!(
        report.checks.len() >= 60,
        "only {} checks",
        report.checks.len()
    );
    for name in [
        "exports all 34 fmi2 functions",
        "fmi2Instantiate refuses a wrong GUID with a logged reason",
        "NULL component: every function returns fmi2Error",
        "illegal call: fmi2DoStep in Instantiated → fmi2Error with a logged message",
        "GetFMUstate → DoStep → SetFMUstate → DoStep is bit-identical",
        "serialize → deserialize into a fresh instance continues bit-identically",
    ] {
        assert!(report.get(name).is_some_and(|c| c.passed), "{name}");
    }
}

#[test]
fn harness_with_a_larger_step_and_logging_on_also_passes() {
    let mut cfg = config();
    cfg.step_size = 0.05;
    cfg.input_value = 20.0;
    cfg.start_time = 1.5;
    cfg.logging_on = true;
    let report = run(&cfg);
    assert!(report.all_passed(), "{report}");
}

#[test]
fn harness_detects_a_wrong_guid_or_identifier() {
    // The harness must be able to fail: with a GUID the FMU does not accept, every check
    // that needs an instance fails.
    let mut cfg = config();
    cfg.guid = "not-the-guid".into();
    let report = run(&cfg);
    assert!(!report.all_passed());
    let failed = report
        .get("valid instantiation reaches step mode and steps")
        .expect("check present");
    assert!(!failed.passed);
    assert!(
        failed.message.contains("GUID mismatch"),
        "{}",
        failed.message
    );

    let mut cfg = config();
    cfg.model_identifier = "bridge".into();
    let report = run(&cfg);
    let stem = report
        .get("library file stem is the model identifier")
        .expect("check present");
    assert!(!stem.passed);
}

#[test]
fn harness_reports_an_unloadable_library() {
    let mut cfg = config();
    cfg.library = common::resources().join("config.txt");
    let report = run(&cfg);
    assert_eq!(report.checks.len(), 1);
    assert!(!report.all_passed());
    assert!(report.checks[0].message.contains("cannot load"));
}
