//! The bridge FMU's `fmi2GetDirectionalDerivative` equals central finite differences taken
//! through the FMI 2.0 C ABI of the exported FMU, every input against every output:
//!
//! * at a communication point after a step (the rail motion under wheelset i against
//!   `ws[i].x` and `ws[i].vx`; nothing else feeds through), the state restored with
//!   `fmi2SetFMUstate` between probes;
//! * in initialisation mode (the accelerations also follow every load and the turbulence
//!   inputs), a fresh instance per probe.
//!
//! Each entry is held to 1e-6 of the largest finite-difference entry of its output (and
//! exactly zero where the outputs do not move at all); the derivatives of a combined seed
//! equal the sum of the single ones. Two bridges: the 30 m span's sine shapes with
//! irregularity and turbulence inputs, and a two-span continuous beam whose FE modes are
//! interpolated from nodes (Lagrange). The train and wind FMUs declare no directional
//! derivatives and refuse the call.

mod common;

use fmi_import::{Fmu, Instance, InstantiateOptions};
use model_description::{Causality, ModelDescription};
use std::sync::Arc;
use tbi_tests::fmu::export;

struct Case {
    fmu: Arc<Fmu>,
    inputs: Vec<(u32, f64)>,
}

impl Case {
    fn md(&self) -> &ModelDescription {
        self.fmu.model_description()
    }

    fn vrs(&self, causality: Causality) -> Vec<u32> {
        tbi_tests::fmu::vrs_of(self.md(), causality)
    }

    fn name(&self, vr: u32) -> String {
        tbi_tests::fmu::name_of(self.md(), vr).to_owned()
    }

    fn initializing(&self, inputs: &[(u32, f64)]) -> Instance {
        let mut i = self
            .fmu
            .instantiate(&InstantiateOptions {
                instance_name: Some("dd".into()),
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{e}"));
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        for &(vr, v) in inputs {
            i.set_real(&[vr], &[v]).unwrap();
        }
        i
    }

    fn outputs(i: &mut Instance, vrs: &[u32]) -> Vec<f64> {
        let mut y = vec![0.0; vrs.len()];
        i.get_real(vrs, &mut y).unwrap();
        y
    }

    /// The input values with input `k` moved by `d`.
    fn moved(&self, k: usize, d: f64) -> Vec<(u32, f64)> {
        let mut u = self.inputs.clone();
        u[k].1 += d;
        u
    }

    /// Step of the central difference of input `k`: small against the wheelset spacing and
    /// the irregularity's node spacing, large against round-off.
    fn delta(&self, k: usize) -> f64 {
        1e-6 * (1.0 + self.inputs[k].1.abs())
    }

    /// (directional derivatives, central differences), one column per input.
    fn jacobians(&self, stepping: bool) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let outputs = self.vrs(Causality::Output);
        let knowns: Vec<u32> = self.inputs.iter().map(|p| p.0).collect();
        let mut dd = Vec::new();
        let mut fd = Vec::new();
        let mut i = self.initializing(&self.inputs);
        let state = if stepping {
            i.exit_initialization_mode().unwrap();
            i.do_step(0.0, 1e-3, false).unwrap();
            for &(vr, v) in &self.inputs {
                i.set_real(&[vr], &[v]).unwrap();
            }
            Some(i.get_fmu_state(None).unwrap())
        } else {
            None
        };
        for k in 0..knowns.len() {
            let mut seed = vec![0.0; knowns.len()];
            seed[k] = 1.0;
            let mut col = vec![0.0; outputs.len()];
            i.get_directional_derivative(&outputs, &knowns, &seed, &mut col)
                .unwrap();
            dd.push(col);
            let h = self.delta(k);
            let mut at = |d: f64| match &state {
                Some(s) => {
                    i.set_fmu_state(s).unwrap();
                    let (vr, v) = self.inputs[k];
                    i.set_real(&[vr], &[v + d]).unwrap();
                    Self::outputs(&mut i, &outputs)
                }
                None => Self::outputs(&mut self.initializing(&self.moved(k, d)), &outputs),
            };
            let (plus, minus) = (at(h), at(-h));
            fd.push(
                plus.iter()
                    .zip(&minus)
                    .map(|(a, b)| (a - b) / (2.0 * h))
                    .collect(),
            );
            if let Some(s) = &state {
                i.set_fmu_state(s).unwrap();
            }
        }
        (dd, fd)
    }

    /// Every entry within 1e-6 of its output's largest finite difference; zero rows zero.
    fn check(&self, what: &str) {
        let outputs = self.vrs(Causality::Output);
        for stepping in [true, false] {
            let (dd, fd) = self.jacobians(stepping);
            let mut worst = (0.0_f64, String::new());
            let mut entries = 0;
            for (o, &ovr) in outputs.iter().enumerate() {
                let scale = fd.iter().map(|c| c[o].abs()).fold(0.0, f64::max);
                for (k, (d, f)) in dd.iter().zip(&fd).enumerate() {
                    let (d, f) = (d[o], f[o]);
                    let ok = if scale == 0.0 {
                        d == 0.0
                    } else {
                        (d - f).abs() <= 1e-6 * scale
                    };
                    assert!(
                        ok,
                        "{what} ({}): ∂{}/∂{} = {d:e} by fmi2GetDirectionalDerivative, {f:e} \
                         by central differences (largest of the output {scale:e})",
                        if stepping {
                            "stepping"
                        } else {
                            "initialisation"
                        },
                        self.name(ovr),
                        self.name(self.inputs[k].0)
                    );
                    if scale > 0.0 {
                        if f != 0.0 {
                            entries += 1;
                        }
                        let e = (d - f).abs() / scale;
                        if e > worst.0 {
                            worst = (
                                e,
                                format!("{}/{}", self.name(ovr), self.name(self.inputs[k].0)),
                            );
                        }
                    }
                }
            }
            println!(
                "{what} ({}): {entries} non-zero entries, worst relative difference {:.2e} ({})",
                if stepping {
                    "stepping"
                } else {
                    "initialisation"
                },
                worst.0,
                worst.1
            );
            assert!(
                entries > 0,
                "{what}: the rail motion moves with the positions"
            );
            // linearity in the seed: a combined seed is the sum of the single ones
            let knowns: Vec<u32> = self.inputs.iter().map(|p| p.0).collect();
            let seed: Vec<f64> = (0..knowns.len())
                .map(|k| ((k as f64) * 0.37 + 0.1).sin())
                .collect();
            let mut i = self.initializing(&self.inputs);
            if stepping {
                i.exit_initialization_mode().unwrap();
                i.do_step(0.0, 1e-3, false).unwrap();
                for &(vr, v) in &self.inputs {
                    i.set_real(&[vr], &[v]).unwrap();
                }
            }
            let mut combined = vec![0.0; outputs.len()];
            i.get_directional_derivative(&outputs, &knowns, &seed, &mut combined)
                .unwrap();
            for (o, c) in combined.iter().enumerate() {
                let sum: f64 = dd.iter().zip(&seed).map(|(col, s)| col[o] * s).sum();
                let scale = dd.iter().map(|col| col[o].abs()).fold(0.0, f64::max);
                assert!(
                    (c - sum).abs() <= 1e-12 * scale.max(1e-300),
                    "{what}: combined seed {c:e} vs sum {sum:e} for {}",
                    self.name(outputs[o])
                );
            }
        }
    }
}

/// The bridge FMU's inputs at an operating point: every wheelset on the deck `[a, b]`.
fn bridge_case(fmu: Arc<Fmu>, deck: (f64, f64)) -> Case {
    let inputs = tbi_tests::fmu::bridge_operating_point(fmu.model_description(), deck);
    Case { fmu, inputs }
}

#[test]
fn bridge_directional_derivatives_equal_central_differences() {
    let e = export("dd-sine", &common::scenarios::coach2_windy());
    let bridge = Fmu::load(&e.bridge).unwrap();
    let cs = bridge.model_description().co_simulation.as_ref().unwrap();
    assert!(cs.provides_directional_derivative, "declared by the bridge");
    let case = bridge_case(bridge, (0.0, common::scenarios::SPAN_M));
    assert!(
        case.inputs.len() > 40,
        "wheelset and turbulence inputs: {}",
        case.inputs.len()
    );
    case.check("30 m span, sine shapes, irregularity, turbulence");

    // the train and wind FMUs provide none and say so
    for path in [&e.train, e.wind.as_ref().unwrap()] {
        let fmu = Fmu::load(path).unwrap();
        let md = fmu.model_description();
        assert!(
            !md.co_simulation
                .as_ref()
                .unwrap()
                .provides_directional_derivative
        );
        let (o, i) = (
            md.model_variables
                .iter()
                .find(|v| v.causality == Causality::Output)
                .unwrap()
                .value_reference,
            md.model_variables
                .iter()
                .find(|v| v.causality == Causality::Input)
                .unwrap()
                .value_reference,
        );
        let mut inst = fmu.instantiate(&InstantiateOptions::default()).unwrap();
        inst.setup_experiment(None, 0.0, None).unwrap();
        inst.enter_initialization_mode().unwrap();
        let mut out = [0.0];
        assert!(
            inst.get_directional_derivative(&[o], &[i], &[1.0], &mut out)
                .is_err(),
            "{} refuses",
            path.display()
        );
    }
}

#[test]
fn nodal_shapes_directional_derivatives_equal_central_differences() {
    // the [bridge] table of the 30 m span replaced by a beam over two spans
    let coach2 = common::scenarios::coach2();
    let (start, end) = (
        coach2.find("[bridge]").unwrap(),
        coach2.find("[train]").unwrap(),
    );
    let toml = format!(
        "{}[bridge]\nkind = \"beam\"\nspans_m = [14.0, 16.0]\nyoungs_modulus_pa = 3.45e10\n\
         inertia_vertical_m4 = 3.0\nmass_per_length_kg_m = 2.0e4\nmodes = 6\n\
         damping_ratio = 0.02\n{}",
        &coach2[..start],
        &coach2[end..]
    );
    let e = export("dd-nodal", &toml);
    let bridge = Fmu::load(&e.bridge).unwrap();
    bridge_case(bridge, (0.0, 30.0)).check("two-span beam, nodal shapes");
}

/// Refusals name what is wrong: a known that is not an input, an unknown that is not an
/// output.
#[test]
fn bridge_refuses_knowns_and_unknowns_of_the_wrong_kind() {
    let e = export("dd-refuse", &common::scenarios::coach2());
    let bridge = Fmu::load(&e.bridge).unwrap();
    let md = bridge.model_description();
    let x = tbi_tests::fmu::vr_of(md, "ws[1].x");
    let z = tbi_tests::fmu::vr_of(md, "ws[1].z");
    let mut i = bridge.instantiate(&InstantiateOptions::default()).unwrap();
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    let mut out = [0.0];
    let e1 = i
        .get_directional_derivative(&[z], &[z], &[1.0], &mut out)
        .unwrap_err()
        .to_string();
    assert!(e1.contains("is not an input"), "{e1}");
    let mut i = bridge.instantiate(&InstantiateOptions::default()).unwrap();
    i.setup_experiment(None, 0.0, None).unwrap();
    i.enter_initialization_mode().unwrap();
    let e2 = i
        .get_directional_derivative(&[x], &[x], &[1.0], &mut out)
        .unwrap_err()
        .to_string();
    assert!(e2.contains("is not an output"), "{e2}");
}
