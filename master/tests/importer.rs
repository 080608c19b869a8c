//! The importer's API on the C test FMU: values of every type, FMU state save/restore and
//! serialization across instances, status queries, resource URI, logging, cleanup.

mod fmu_support;

use fmi_import::{
    CallStatus, FmiError, Fmu, Instance, InstantiateOptions, Status, StatusKind, StepResult,
};
use fmu_support::*;
use std::sync::Arc;

const K: u32 = 0;
const D: u32 = 1;
const X0: u32 = 3;
const F: u32 = 4;
const X: u32 = 5;
const V: u32 = 6;
const A: u32 = 7;

fn fmu(name: &str) -> Arc<Fmu> {
    Fmu::load(build_fmu(&Variant::new(name))).unwrap_or_else(|e| panic!("{e}"))
}

fn initialized(fmu: &Arc<Fmu>, name: &str) -> Instance {
    let mut inst = fmu
        .instantiate(&InstantiateOptions {
            instance_name: Some(name.into()),
            ..InstantiateOptions::default()
        })
        .unwrap();
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst
}

fn get(inst: &mut Instance, vrs: &[u32]) -> Vec<f64> {
    let mut v = vec![0.0; vrs.len()];
    inst.get_real(vrs, &mut v).unwrap();
    v
}

fn run(inst: &mut Instance, from: f64, to: f64, h: f64) {
    let n = ((to - from) / h).round() as usize;
    for i in 0..n {
        let t = from + i as f64 * h;
        assert_eq!(inst.do_step(t, h, true).unwrap(), StepResult::Ok);
    }
}

#[test]
fn load_reports_the_description_library_and_resources() {
    let fmu = fmu("Load");
    assert_eq!(fmu.name(), "Load.fmu");
    assert_eq!(fmu.model_description().model_name, "Oscillator");
    assert_eq!(fmu.version(), "2.0");
    assert_eq!(fmu.types_platform(), "default");
    assert!(fmu
        .library_path()
        .ends_with("binaries/linux64/oscillator.so"));
    let uri = fmu.resource_uri();
    assert!(
        uri.starts_with("file:///") && uri.ends_with("/resources"),
        "{uri}"
    );
    assert_eq!(
        fmi_import::file_uri(&fmu.unpacked_dir().join("resources")).unwrap(),
        uri
    );
    assert!(fmu.unpacked_dir().join("resources/gain.txt").is_file());
    assert!(fmu
        .unpacked_dir()
        .join("documentation/index.html")
        .is_file());
}

#[test]
fn values_of_every_type() {
    let fmu = fmu("Values");
    let mut inst = fmu.instantiate(&InstantiateOptions::default()).unwrap();
    assert_eq!(
        inst.name(),
        "oscillator",
        "default instance name is the modelIdentifier"
    );
    inst.setup_experiment(Some(1e-6), 0.0, Some(10.0)).unwrap();
    inst.set_real(&[K, X0], &[9.0, 2.0]).unwrap();
    inst.set_string(&[0], &["renamed"]).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    assert_eq!(get(&mut inst, &[K, X, V, A]), [9.0, 2.0, 0.0, -18.0]);
    assert_eq!(inst.get_string(&[0]).unwrap(), ["renamed"]);
    let messages = inst.take_messages();
    assert!(
        messages.is_empty(),
        "messages of exit_initialization_mode were taken by the next call"
    );

    inst.set_real(&[F], &[1.0]).unwrap();
    run(&mut inst, 0.0, 0.1, 0.01);
    let mut steps = [0];
    inst.get_integer(&[0], &mut steps).unwrap();
    assert_eq!(steps, [10]);
    let mut moving_right = [true];
    inst.get_boolean(&[0], &mut moving_right).unwrap();
    assert_eq!(
        moving_right,
        [false],
        "released from x0 = 2 the mass moves left"
    );
    assert_eq!(inst.last_successful_time().unwrap(), 9.0 * 0.01 + 0.01);
    assert!(!inst.terminated().unwrap());
    inst.terminate().unwrap();
}

#[test]
fn failures_name_the_call_status_and_log() {
    let fmu = fmu("Failures");
    let mut inst = initialized(&fmu, "inst1");
    let e = inst.set_real(&[K], &[1.0]).unwrap_err();
    match &e {
        FmiError::Call {
            call,
            status,
            messages,
            ..
        } => {
            assert_eq!(call, "fmi2SetReal(k = [1.0])");
            assert_eq!(*status, CallStatus::Status(Status::Error));
            assert_eq!(messages.len(), 1);
            assert_eq!(messages[0].instance, "inst1");
            assert_eq!(messages[0].category, "logStatusError");
            assert_eq!(
                messages[0].message,
                "fmi2SetReal: value reference 0 is fixed after initialization"
            );
        }
        other => panic!("{other}"),
    }
    assert_eq!(
        e.to_string(),
        "Failures.fmu: fmi2SetReal(k = [1.0]) returned fmi2Error (instance \"inst1\"); the FMU logged:\n  [inst1] fmi2Error [logStatusError] fmi2SetReal: value reference 0 is fixed after initialization"
    );
    let e = inst.get_real(&[99], &mut [0.0]).unwrap_err().to_string();
    assert!(
        e.contains("fmi2GetReal(<unknown value reference 99>) returned fmi2Error"),
        "{e}"
    );
    // a Discard from a call other than DoStep is a failure
    let e = inst
        .get_status(StatusKind::DoStepStatus)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("fmi2GetStatus(fmi2DoStepStatus) returned fmi2Discard"),
        "{e}"
    );
    // wrong step: communication point differs from the FMU's time
    let e = inst.do_step(0.5, 0.1, true).unwrap_err().to_string();
    assert!(
        e.contains("communication point 0.5 differs from the FMU time 0"),
        "{e}"
    );
    // mismatched lengths never reach the FMU
    let e = inst.set_real(&[F, D], &[1.0]).unwrap_err().to_string();
    assert_eq!(
        e,
        "Failures.fmu: fmi2SetReal: 2 value references but 1 values (instance \"inst1\")"
    );
    let e = inst
        .set_string(&[0], &["nul\0inside"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("contains a NUL character"), "{e}");
}

#[test]
fn fmu_state_restores_the_trajectory() {
    let fmu = fmu("State");
    let mut inst = initialized(&fmu, "a");
    inst.set_real(&[F], &[0.5]).unwrap();
    run(&mut inst, 0.0, 0.5, 0.05);
    let saved = inst.get_fmu_state(None).unwrap();
    let at_save = get(&mut inst, &[X, V]);
    run(&mut inst, 0.5, 1.0, 0.05);
    let first = get(&mut inst, &[X, V]);
    assert_ne!(first, at_save);

    inst.set_fmu_state(&saved).unwrap();
    assert_eq!(get(&mut inst, &[X, V]), at_save);
    run(&mut inst, 0.5, 1.0, 0.05);
    assert_eq!(
        get(&mut inst, &[X, V]),
        first,
        "a restored run repeats exactly"
    );

    // overwrite the saved state in place, then serialize it
    let saved = inst.get_fmu_state(Some(saved)).unwrap();
    let bytes = inst.serialize_fmu_state(&saved).unwrap();
    assert!(!bytes.is_empty());
    inst.free_fmu_state(saved).unwrap();

    // another instance continues from the serialized state
    let mut other = initialized(&fmu, "b");
    let state = other.deserialize_fmu_state(&bytes).unwrap();
    other.set_fmu_state(&state).unwrap();
    assert_eq!(get(&mut other, &[X, V]), first);
    run(&mut other, 1.0, 1.5, 0.05);
    run(&mut inst, 1.0, 1.5, 0.05);
    assert_eq!(get(&mut other, &[X, V]), get(&mut inst, &[X, V]));

    // a state belongs to the instance that made it
    let e = inst.set_fmu_state(&state).unwrap_err().to_string();
    assert!(
        e.contains("the FMU state belongs to another instance than \"a\""),
        "{e}"
    );
    other.free_fmu_state(state).unwrap();

    let e = other
        .deserialize_fmu_state(&bytes[..bytes.len() - 1])
        .unwrap_err()
        .to_string();
    assert!(e.contains("fmi2DeSerializeFMUstate(size="), "{e}");
    assert!(e.contains("expected"), "{e}");
}

#[test]
fn reset_returns_to_the_instantiated_state() {
    let fmu = fmu("Reset");
    let mut inst = initialized(&fmu, "r");
    run(&mut inst, 0.0, 0.2, 0.1);
    let after_first = get(&mut inst, &[X]);
    inst.reset().unwrap();
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    run(&mut inst, 0.0, 0.2, 0.1);
    assert_eq!(get(&mut inst, &[X]), after_first);
}

#[test]
fn two_loads_are_independent_and_cleaned_up() {
    let path = build_fmu(&Variant::new("Twice"));
    let first = Fmu::load(&path).unwrap();
    let second = Fmu::load(&path).unwrap();
    assert_ne!(first.unpacked_dir(), second.unpacked_dir());
    let mut a = initialized(&first, "a");
    let mut b = initialized(&second, "b");
    a.set_real(&[F], &[10.0]).unwrap();
    run(&mut a, 0.0, 0.1, 0.01);
    run(&mut b, 0.0, 0.1, 0.01);
    assert_ne!(get(&mut a, &[X]), get(&mut b, &[X]));

    let dir = first.unpacked_dir().to_path_buf();
    drop(first);
    assert!(
        dir.exists(),
        "an instance keeps its FMU loaded and unpacked"
    );
    drop(a);
    assert!(!dir.exists(), "the unpacked files go with the last user");
}

#[test]
fn messages_can_be_echoed_and_are_collected_per_call() {
    let fmu = fmu("Messages");
    let mut inst = fmu
        .instantiate(&InstantiateOptions {
            instance_name: Some("m".into()),
            echo_log: true,
            ..InstantiateOptions::default()
        })
        .unwrap();
    inst.set_echo_log(false);
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let messages = inst.take_messages();
    assert_eq!(messages.len(), 1);
    assert_eq!(messages[0].status, Some(Status::Ok));
    assert_eq!(messages[0].message, "initialized: x=1 gain=1 label=osc");
    assert!(inst.take_messages().is_empty());
}

#[test]
fn instance_is_send() {
    fn assert_send<T: Send>() {}
    assert_send::<Instance>();
    let fmu = fmu("Threads");
    let mut inst = initialized(&fmu, "t");
    let handle = std::thread::spawn(move || {
        run(&mut inst, 0.0, 0.1, 0.01);
        get(&mut inst, &[X])[0]
    });
    assert!(handle.join().unwrap().is_finite());
}
