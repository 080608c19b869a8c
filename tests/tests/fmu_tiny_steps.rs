//! Communication steps far below the nominal one (some masters end a run with a step of
//! about 1e-13 s) give accurate outputs: over a step of h the accelerations of a smooth
//! linear system change by about h·ω·|a|, so after a step of 1e-9 s or 1e-12 s from a
//! vibrating state they must equal the values before the step to far better than 1e-4
//! (relative to the response's size). Solving Newmark for the new displacement and
//! differencing it would give values off by round-off / h² (10⁷ m/s² and more).

mod common;

use common::scenarios;
use fmi_import::{Fmu, Instance, InstantiateOptions};
use std::sync::Arc;
use tbi_tests::fmu::{export, vr_of};

fn instantiate(fmu: &Arc<Fmu>) -> Instance {
    fmu.instantiate(&InstantiateOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

fn get(inst: &mut Instance, vrs: &[u32]) -> Vec<f64> {
    let mut v = vec![0.0; vrs.len()];
    inst.get_real(vrs, &mut v).unwrap_or_else(|e| panic!("{e}"));
    v
}

/// Step `inst` with 2 ms steps to `steps × 2 ms`, then with each tiny step, comparing the
/// outputs `vrs` after each tiny step with their values before it.
fn check_tiny_steps(inst: &mut Instance, vrs: &[u32], names: &[String], steps: usize) {
    let h = 0.002;
    let mut t = 0.0;
    for _ in 0..steps {
        inst.do_step(t, h, true).unwrap_or_else(|e| panic!("{e}"));
        t += h;
    }
    let scale = get(inst, vrs).iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(scale > 1e-3, "the system must be moving ({scale})");
    for tiny in [1e-9, 1e-12, 1.4e-13] {
        let before = get(inst, vrs);
        inst.do_step(t, tiny, true)
            .unwrap_or_else(|e| panic!("{e}"));
        t += tiny;
        let after = get(inst, vrs);
        for ((a, b), name) in after.iter().zip(&before).zip(names) {
            assert!(
                (a - b).abs() <= 1e-4 * scale,
                "{name}: {b} before a step of {tiny} s, {a} after (scale {scale})"
            );
        }
    }
}

#[test]
fn bridge_outputs_stay_accurate_for_tiny_steps() {
    let e = export("tiny-bridge", &scenarios::moving_force());
    let fmu = Fmu::load(&e.bridge).unwrap_or_else(|err| panic!("{err}"));
    let md = fmu.model_description();
    let mut inst = instantiate(&fmu);
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    // a step load at 12 m sets the deck vibrating
    let inputs = ["ws[1].x", "ws[1].vx", "ws[1].F_z"].map(|n| vr_of(md, n));
    inst.set_real(&inputs, &[12.0, 0.0, 2.0e5]).unwrap();
    let names: Vec<String> = [
        "probe[1].z_dd",
        "probe[2].z_dd",
        "probe[3].z_dd",
        "ws[1].z_dd",
    ]
    .map(String::from)
    .to_vec();
    let vrs: Vec<u32> = names.iter().map(|n| vr_of(md, n)).collect();
    check_tiny_steps(&mut inst, &vrs, &names, 10);
}

#[test]
fn train_outputs_stay_accurate_for_tiny_steps() {
    let e = export("tiny-train", &scenarios::coach2());
    let fmu = Fmu::load(&e.train).unwrap_or_else(|err| panic!("{err}"));
    let md = fmu.model_description();
    let mut inst = instantiate(&fmu);
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    // the rail under the first wheelset drops by 5 mm: the coach starts to pitch and bounce
    inst.set_real(&[vr_of(md, "ws[1].z")], &[5e-3]).unwrap();
    let names: Vec<String> = ["veh[1].a_z", "veh[1].a_y", "ws[1].F_z", "ws[2].F_z"]
        .map(String::from)
        .to_vec();
    let vrs: Vec<u32> = names.iter().map(|n| vr_of(md, n)).collect();
    // forces are in N and accelerations in m/s²: compare each group on its own scale
    check_tiny_steps(&mut inst, &vrs[..2], &names[..2], 10);
    let mut inst = instantiate(&fmu);
    inst.setup_experiment(None, 0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst.set_real(&[vr_of(md, "ws[1].z")], &[5e-3]).unwrap();
    check_tiny_steps(&mut inst, &vrs[2..], &names[2..], 10);
}
