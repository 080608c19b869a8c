//! Static checks of the exported FMUs driven alone through the FMI 2.0 C ABI (importer
//! `tbi::fmi`), each against a reference computed independently in the test:
//!
//! * the bridge FMU under a constant vertical force at a fixed position settles to the static
//!   deflection of its modal model (vertical bending and torsion from the eccentric track);
//! * the train FMU on a rigid, smooth rail stays in static equilibrium with the Table 1 weight
//!   shares on every wheelset.

mod common;

use common::reference::{analytic_modes, closed_form, truncated_series, truncation_bounds};
use common::scenarios::{self, *};
use fmi_import::{Fmu, Instance, InstantiateOptions};
use fmu_bridge::BridgeResources;
use std::f64::consts::PI;
use std::sync::Arc;
use tbi_dynamics::bridge::Shapes;
use tbi_tests::fmu::{export, vr_of};

fn instantiate(fmu: &Arc<Fmu>, name: &str) -> Instance {
    fmu.instantiate(&InstantiateOptions {
        instance_name: Some(name.into()),
        ..Default::default()
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

fn get(inst: &mut Instance, vr: u32) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[vr], &mut v)
        .unwrap_or_else(|e| panic!("{e}"));
    v[0]
}

fn vr(fmu: &Fmu, name: &str) -> u32 {
    vr_of(fmu.model_description(), name)
}

/// Σₙ φₙ(x) φₙ(a) (generalised force)ₙ / ωₙ² from the modal data inside the exported FMU
/// (`resources/bridge.json`): (deck y, z, θ) at `x`.
fn modal_sum_from_resources(res: &BridgeResources, x: f64, a: f64, f: f64) -> [f64; 3] {
    let m = &res.modal;
    let Shapes::Sine {
        span_m,
        half_waves,
        amplitudes,
    } = &m.shapes
    else {
        panic!("a simply supported span exports sine shapes");
    };
    let mut out = [0.0; 3];
    for n in 0..m.n_modes() {
        let w = 2.0 * PI * m.frequencies_hz[n];
        let k = half_waves[n] as f64;
        let s = |x: f64| (k * PI * (x - m.x_start_m) / span_m).sin();
        let amp = amplitudes[n];
        // rail vertical shape at the load: φ_v + e φ_θ (eq. 13)
        let psi_z = (amp[1] + m.e_m * amp[2]) * s(a);
        let q = psi_z * f / (w * w);
        for c in 0..3 {
            out[c] += amp[c] * s(x) * q;
        }
    }
    out
}

#[test]
fn bridge_fmu_settles_to_the_static_deflection_of_its_modal_model() {
    let e = export("static-bridge", &scenarios::moving_force());
    let fmu = Fmu::load(&e.bridge).unwrap_or_else(|err| panic!("{err}"));
    let res: BridgeResources = serde_json::from_slice(
        &std::fs::read(fmu.unpacked_dir().join("resources/bridge.json")).expect("bridge.json"),
    )
    .expect("bridge.json parses");
    // The exported modal data are the analytic modes of the section (frequencies, labels).
    let analytic = analytic_modes();
    assert_eq!(res.modal.n_modes(), FORCE_MODES);
    for (n, (fam, hw, w)) in analytic.iter().enumerate() {
        let f_hz = w / (2.0 * PI);
        assert!(
            (res.modal.frequencies_hz[n] - f_hz).abs() <= 1e-9 * f_hz,
            "mode {n}: exported {} Hz, analytic {f_hz} Hz ({fam}{hw})",
            res.modal.frequencies_hz[n]
        );
        assert!(
            res.modal.labels[n].starts_with(*fam),
            "{:?}",
            res.modal.labels
        );
    }
    assert_eq!((res.modal.e_m, res.modal.h4_m), (E_TRACK_M, H4_M));

    let (a, f) = (12.0, 2.0e5);
    let mut inst = instantiate(&fmu, "bridge");
    inst.setup_experiment(None, 0.0, None).expect("setup");
    inst.enter_initialization_mode().expect("enter init");
    inst.set_real(
        &[
            vr(&fmu, "ws[1].x"),
            vr(&fmu, "ws[1].vx"),
            vr(&fmu, "ws[1].F_z"),
        ],
        &[a, 0.0, f],
    )
    .expect("set inputs");
    inst.exit_initialization_mode().expect("exit init");
    // Step load with 20 % damping: the slowest mode (about 4 Hz) decays as exp(-ζωt), i.e. by
    // e^-25 over 5 s. Each DoStep is one Newmark step, whose fixed point for a constant load is
    // the exact static solution q = F/ω².
    let h = 0.002;
    let mut t = 0.0;
    for _ in 0..2500 {
        inst.do_step(t, h, true).expect("step");
        t += h;
    }

    let (bound_z, bound_th) = truncation_bounds(f);
    let z_scale = closed_form(a, a, f).0;
    let th_scale = closed_form(a, a, f).1;
    println!("static deflection under F = {f} N at x = {a} m (truncated series | closed form):");
    let mut checks: Vec<(String, f64, f64, f64, f64)> = Vec::new(); // name, fmu, ref, tol, closed
    for (p, &x) in FORCE_PROBES_M.iter().enumerate() {
        let k = p + 1;
        let (zs, ths) = truncated_series(x, a, f);
        let (zc, thc) = closed_form(x, a, f);
        let from_res = modal_sum_from_resources(&res, x, a, f);
        let z = get(&mut inst, vr(&fmu, &format!("probe[{k}].z")));
        let th = get(&mut inst, vr(&fmu, &format!("probe[{k}].theta")));
        let y = get(&mut inst, vr(&fmu, &format!("probe[{k}].y")));
        let zdd = get(&mut inst, vr(&fmu, &format!("probe[{k}].z_dd")));
        // the reference computed from the exported modal data agrees with the analytic one
        assert!(
            (from_res[1] - zs).abs() <= 1e-9 * z_scale,
            "{from_res:?} vs {zs}"
        );
        assert!(
            (from_res[2] - ths).abs() <= 1e-9 * th_scale,
            "{from_res:?} vs {ths}"
        );
        checks.push((format!("probe[{k}].z"), z, zs, 1e-7 * z_scale, zc));
        checks.push((format!("probe[{k}].theta"), th, ths, 1e-7 * th_scale, thc));
        checks.push((format!("probe[{k}].y"), y, 0.0, 1e-12, 0.0));
        assert!(zdd.abs() < 1e-7, "probe[{k}].z_dd = {zdd} after settling");
        // truncated series against the closed form: within the bound of the dropped terms
        assert!(
            (zs - zc).abs() <= bound_z,
            "x = {x}: {zs} vs closed form {zc}"
        );
        assert!(
            (ths - thc).abs() <= bound_th,
            "x = {x}: {ths} vs closed form {thc}"
        );
    }
    // Rail under the loaded wheelset (eq. 13, smooth track): u_z = z + e θ, u_θ = θ,
    // u_y = y + h4 θ.
    let (za, tha) = truncated_series(a, a, f);
    let (zca, thca) = closed_form(a, a, f);
    checks.push((
        "ws[1].z".into(),
        get(&mut inst, vr(&fmu, "ws[1].z")),
        za + E_TRACK_M * tha,
        1e-7 * z_scale,
        zca + E_TRACK_M * thca,
    ));
    checks.push((
        "ws[1].theta".into(),
        get(&mut inst, vr(&fmu, "ws[1].theta")),
        tha,
        1e-7 * th_scale,
        thca,
    ));
    checks.push((
        "ws[1].y".into(),
        get(&mut inst, vr(&fmu, "ws[1].y")),
        H4_M * tha,
        1e-7 * th_scale,
        H4_M * thca,
    ));
    for (name, got, want, tol, closed) in &checks {
        let rel = if *want != 0.0 {
            ((got - want) / want).abs()
        } else {
            0.0
        };
        println!(
            "  {name:12} FMU {got:+.9e}  series {want:+.9e} (rel. err {rel:.1e})  closed form {closed:+.6e}"
        );
        assert!(
            (got - want).abs() <= *tol,
            "{name}: FMU {got} vs reference {want} (tolerance {tol})"
        );
    }
    // the rail velocity and acceleration have settled
    for ch in ["ws[1].z_d", "ws[1].z_dd", "ws[1].theta_dd"] {
        let v = get(&mut inst, vr(&fmu, ch));
        assert!(v.abs() < 1e-7, "{ch} = {v} after settling");
    }
    // The second wheelset is off the deck (start value x = -1e6): its rail does not move.
    assert_eq!(get(&mut inst, vr(&fmu, "ws[2].z")), 0.0);
    // Unloading brings the deck back: linear superposition, zero load → zero deflection.
    inst.set_real(&[vr(&fmu, "ws[1].F_z")], &[0.0])
        .expect("unload");
    for _ in 0..2500 {
        inst.do_step(t, h, true).expect("step");
        t += h;
    }
    let z = get(&mut inst, vr(&fmu, "probe[2].z"));
    assert!(z.abs() < 1e-7 * z_scale, "after unloading probe[2].z = {z}");
}

/// Table 1 of Xia, Xu & Chan (2000), crush load, written down here independently of the
/// `xia2000` preset: car body, bogie and wheelset masses, kg.
const M_CAR: f64 = 50_990.0;
const M_BOGIE: f64 = 4_360.0;
const M_WHEELSET: f64 = 1_770.0;
const G: f64 = 9.81;

#[test]
fn train_fmu_on_a_rigid_smooth_rail_stays_in_static_equilibrium() {
    let e = export("static-train", &scenarios::coach2());
    let fmu = Fmu::load(&e.train).unwrap_or_else(|err| panic!("{err}"));
    let mut inst = instantiate(&fmu, "train");
    inst.setup_experiment(None, 0.0, None).expect("setup");
    inst.enter_initialization_mode().expect("enter init");
    // the FMU carries the Table 1 masses as parameters (readable once initialising)
    for (p, want) in [
        ("coach.car_mass_kg", M_CAR),
        ("coach.bogie_mass_kg", M_BOGIE),
        ("coach.wheelset_mass_kg", M_WHEELSET),
    ] {
        assert_eq!(get(&mut inst, vr(&fmu, p)), want, "{p}");
    }
    inst.exit_initialization_mode().expect("exit init");

    let nw = 8; // two coaches of four wheelsets
    let share = (M_WHEELSET + M_BOGIE / 2.0 + M_CAR / 4.0) * G;
    let names = ["F_y", "M_x", "F_z", "P_left", "P_right"];
    let vrs: Vec<u32> = (1..=nw)
        .flat_map(|w| names.map(|n| vr(&fmu, &format!("ws[{w}].{n}"))))
        .collect();
    let acc_vrs: Vec<u32> = (1..=2)
        .flat_map(|i| ["a_y", "a_z"].map(|n| vr(&fmu, &format!("veh[{i}].{n}"))))
        .collect();
    let rail_inputs: Vec<u32> = fmu
        .model_description()
        .model_variables
        .iter()
        .filter(|v| v.causality == model_description::Causality::Input)
        .map(|v| v.value_reference)
        .collect();
    assert_eq!(rail_inputs.len(), 9 * nw);
    let zeros = vec![0.0; rail_inputs.len()];

    let (mut worst_fz, mut worst_p, mut worst_lat, mut worst_acc) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut values = vec![0.0; vrs.len()];
    let mut acc = vec![0.0; acc_vrs.len()];
    let (h, steps) = (0.002, 2000);
    let mut t = 0.0;
    for step in 0..=steps {
        if step > 0 {
            inst.set_real(&rail_inputs, &zeros).expect("rail inputs");
            inst.do_step(t, h, true).expect("step");
            t += h;
        }
        inst.get_real(&vrs, &mut values).expect("wheel outputs");
        inst.get_real(&acc_vrs, &mut acc)
            .expect("car-body accelerations");
        for w in values.chunks(5) {
            let [fy, mx, fz, pl, pr] = [w[0], w[1], w[2], w[3], w[4]];
            worst_fz = worst_fz.max((fz - share).abs() / share);
            worst_p = worst_p
                .max((pl - fz / 2.0).abs() / share)
                .max((pr - fz / 2.0).abs() / share);
            worst_lat = worst_lat.max(fy.abs()).max(mx.abs());
        }
        worst_acc = acc.iter().fold(worst_acc, |m, a| m.max(a.abs()));
    }
    println!(
        "train at rest over {steps} steps: weight share {share} N; max |F_z - share|/share = \
         {worst_fz:.2e}, max |P - F_z/2|/share = {worst_p:.2e}, max |F_y|,|M_x| = {worst_lat:.2e}, \
         max |a| = {worst_acc:.2e} m/s2"
    );
    assert!(
        worst_fz < 1e-9,
        "wheel load departs from the weight share by {worst_fz:e} (relative)"
    );
    assert!(
        worst_p < 1e-9,
        "P_left/P_right depart from F_z/2 by {worst_p:e} (relative)"
    );
    assert!(
        worst_lat < 1e-6,
        "lateral force or roll moment {worst_lat:e} on a straight rail"
    );
    assert!(
        worst_acc < 1e-9,
        "car-body acceleration {worst_acc:e} m/s2 at rest"
    );
    // the weight of the whole train is carried by the rail
    let total: f64 = values.chunks(5).map(|w| w[2]).sum();
    let weight = 2.0 * (M_CAR + 2.0 * M_BOGIE + 4.0 * M_WHEELSET) * G;
    assert!(
        (total - weight).abs() < 1e-9 * weight,
        "{total} vs {weight}"
    );
}
