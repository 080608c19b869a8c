//! The `dependencies` the three FMUs declare in `<ModelStructure>` equal finite differences
//! taken through the FMI 2.0 C ABI of the exported FMUs, with no missing and no spurious
//! entries:
//!
//! * `<InitialUnknowns>`: in initialisation mode, every input and parameter moved in turn
//!   (a fresh instance per probe);
//! * `<Outputs>`: at a communication point after a step, every input moved in turn (the
//!   state restored with `fmi2SetFMUstate` between probes).
//!
//! The train's `<InitialUnknowns>` are declared as vehicle blocks (the rails under the
//! vehicle's own wheelsets and the parameters), a superset: there the test checks that no
//! dependency is missing, and that a rail of one vehicle moves nothing of another. The
//! bridge's are declared from its equations (every acceleration follows from all the loads):
//! there no dependency may be missing, and the only entries finite differences may not see
//! are those of an acceleration on a load (a wheelset's position or force, the turbulence),
//! whose share can lie below the output's last bit.
//!
//! The operating point here (positions, speeds, forces, rail motion, hunting) differs from
//! the one the exporter probes, so the declared structure is checked to hold beyond it.
//! The case: two 27-DOF coaches with hunting over a 30 m span with irregularity, in a
//! turbulent crosswind (so the bridge and the train have their wind inputs, and the wind
//! FMU its car-body positions).

mod common;

use fmi_import::{Fmu, Instance, InstantiateOptions};
use model_description::{Causality, ModelDescription, Unknown};
use std::collections::{BTreeSet, HashMap};
use std::sync::Arc;
use tbi_tests::fmu::export;

/// How one FMU is put at the test's operating point.
struct Case {
    fmu: Arc<Fmu>,
    /// (input vr, value) at the operating point.
    inputs: Vec<(u32, f64)>,
}

impl Case {
    fn md(&self) -> &ModelDescription {
        self.fmu.model_description()
    }

    fn vrs(&self, causality: Causality) -> Vec<u32> {
        tbi_tests::fmu::vrs_of(self.md(), causality)
    }

    /// A fresh instance in initialisation mode at the operating point.
    fn initializing(&self) -> Instance {
        let mut i = self
            .fmu
            .instantiate(&InstantiateOptions {
                instance_name: Some("deps".into()),
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{e}"));
        i.setup_experiment(None, 0.0, None).unwrap();
        i.enter_initialization_mode().unwrap();
        self.set_inputs(&mut i);
        i
    }

    fn set_inputs(&self, i: &mut Instance) {
        for &(vr, v) in &self.inputs {
            i.set_real(&[vr], &[v]).unwrap();
        }
    }

    fn outputs(&self, i: &mut Instance) -> Vec<u64> {
        let vrs = self.vrs(Causality::Output);
        let mut y = vec![0.0; vrs.len()];
        i.get_real(&vrs, &mut y).unwrap();
        y.iter().map(|v| v.to_bits()).collect()
    }

    /// Moved known: 1e-4 of its magnitude (at least 1e-4), the hunting seed by one, a
    /// wheelset's force on the bridge by 1e3 times its magnitude (at least 1e3; the bridge's
    /// outputs are linear in the forces, and a contribution many orders below an output's
    /// other terms must still move its last bits).
    fn moved(&self, vr: u32, v: f64) -> f64 {
        let name = &self
            .md()
            .model_variables
            .iter()
            .find(|x| x.value_reference == vr)
            .unwrap()
            .name;
        let force =
            name.starts_with("ws[") && [".F_y", ".M_x", ".F_z"].iter().any(|c| name.ends_with(c));
        if name == "hunting.seed" {
            v + 1.0
        } else if force {
            v + 1e3 * (1.0 + v.abs())
        } else {
            v + 1e-4 * (1.0 + v.abs())
        }
    }

    fn get(&self, i: &mut Instance, vr: u32) -> f64 {
        let mut v = [0.0];
        i.get_real(&[vr], &mut v).unwrap();
        v[0]
    }

    /// Per output vr, the knowns it depends on, by finite differences.
    fn differences(&self, stepping: bool) -> HashMap<u32, BTreeSet<u32>> {
        let outputs = self.vrs(Causality::Output);
        let mut knowns = self.vrs(Causality::Input);
        if !stepping {
            knowns.extend(self.vrs(Causality::Parameter));
        }
        let mut deps: HashMap<u32, BTreeSet<u32>> =
            outputs.iter().map(|&o| (o, BTreeSet::new())).collect();
        let mut record = |inst: &mut Instance, k: u32, base: &[u64]| {
            let v = self.get(inst, k);
            inst.set_real(&[k], &[self.moved(k, v)]).unwrap();
            for ((o, a), b) in outputs.iter().zip(&self.outputs(inst)).zip(base) {
                if a != b {
                    deps.get_mut(o).unwrap().insert(k);
                }
            }
        };
        if stepping {
            let mut i = self.initializing();
            i.exit_initialization_mode().unwrap();
            i.do_step(0.0, 1e-3, false).unwrap();
            self.set_inputs(&mut i);
            let state = i.get_fmu_state(None).unwrap();
            let base = self.outputs(&mut i);
            for &k in &knowns {
                i.set_fmu_state(&state).unwrap();
                record(&mut i, k, &base);
            }
        } else {
            let base = self.outputs(&mut self.initializing());
            for &k in &knowns {
                record(&mut self.initializing(), k, &base);
            }
        }
        deps
    }

    /// Per output vr, the knowns the description declares for `unknowns`.
    fn declared(&self, unknowns: &[Unknown]) -> HashMap<u32, BTreeSet<u32>> {
        let vars = &self.md().model_variables;
        unknowns
            .iter()
            .map(|u| {
                let deps = u.dependencies.as_ref().unwrap_or_else(|| {
                    panic!(
                        "{}: no dependencies declared",
                        vars[u.index as usize - 1].name
                    )
                });
                (
                    vars[u.index as usize - 1].value_reference,
                    deps.iter()
                        .map(|&d| vars[d as usize - 1].value_reference)
                        .collect(),
                )
            })
            .collect()
    }

    fn check(&self, what: &str) {
        let md = self.md();
        for (list, unknowns, stepping) in [
            ("Outputs", &md.model_structure.outputs, true),
            (
                "InitialUnknowns",
                &md.model_structure.initial_unknowns,
                false,
            ),
        ] {
            let declared = self.declared(unknowns);
            let found = self.differences(stepping);
            let name = |vr: &u32| {
                md.model_variables
                    .iter()
                    .find(|v| v.value_reference == *vr)
                    .unwrap()
                    .name
                    .clone()
            };
            // the train's initial unknowns are declared as vehicle blocks, a superset; the
            // bridge's accelerations depend on all the loads, some below their last bit
            let superset = what == "train" && !stepping;
            let below_last_bit = |o: &u32, k: &u32| {
                let (out, known) = (name(o), name(k));
                what == "bridge"
                    && !stepping
                    && out.ends_with("_dd")
                    && (known.starts_with("deck[")
                        || [".x", ".F_y", ".M_x", ".F_z"]
                            .iter()
                            .any(|c| known.ends_with(c)))
            };
            let mut problems = Vec::new();
            let mut entries = 0;
            for (o, d) in &declared {
                let f = &found[o];
                entries += f.len();
                let missing: Vec<String> = f.difference(d).map(name).collect();
                let spurious: Vec<String> = if superset {
                    Vec::new()
                } else {
                    d.difference(f)
                        .filter(|k| !below_last_bit(o, k))
                        .map(name)
                        .collect()
                };
                if !missing.is_empty() || !spurious.is_empty() {
                    problems.push(format!(
                        "{}: missing {missing:?}, spurious {spurious:?}",
                        name(o)
                    ));
                }
            }
            println!(
                "{what} {list}: {} unknowns, {entries} dependencies",
                declared.len()
            );
            assert_eq!(
                declared.len(),
                found.len(),
                "{what} {list}: every output listed"
            );
            assert!(
                problems.is_empty(),
                "{what} {list}:\n{}",
                problems.join("\n")
            );
            if stepping && what == "bridge" {
                assert!(
                    entries > 0,
                    "the bridge's rail motion depends on the positions"
                );
            }
        }
    }
}

fn scenario() -> String {
    common::scenarios::coach2_windy().replace(
        "vehicles = 2\n",
        "vehicles = 2\nhunting = { amplitude_m = 0.003, wavelength_m = 15.77, seed = 1 }\n",
    )
}

#[test]
fn declared_dependencies_equal_finite_differences() {
    let e = export("dependencies", &scenario());
    let bridge = Fmu::load(&e.bridge).unwrap();
    let train = Fmu::load(&e.train).unwrap();
    let wind = Fmu::load(e.wind.as_ref().expect("a turbulent wind exports wind.fmu")).unwrap();

    // bridge: every wheelset on the 30 m span, at positions, speeds and forces of its own
    let md = bridge.model_description();
    let inputs = tbi_tests::fmu::bridge_operating_point(md, (1.3, 28.3));
    let deck_points = (md.model_variables.iter())
        .filter(|v| v.name.starts_with("deck[") && v.causality == Causality::Input)
        .count();
    assert_eq!(deck_points, 2 * 12, "deck[j].u and .w inputs");
    Case {
        fmu: bridge,
        inputs,
    }
    .check("bridge");

    // train: rail motion of its own under every wheelset
    let rails: Vec<(u32, f64)> = train
        .model_description()
        .model_variables
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .enumerate()
        .map(|(i, v)| (v.value_reference, 2e-3 * ((i as f64) * 0.7 + 0.3).sin()))
        .collect();
    let case = Case {
        fmu: train,
        inputs: rails,
    };
    case.check("train");
    // wind: every car body on the span
    let bodies: Vec<(u32, f64)> = wind
        .model_description()
        .model_variables
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .enumerate()
        .map(|(i, v)| (v.value_reference, 4.1 + 11.3 * i as f64))
        .collect();
    assert_eq!(bodies.len(), 2, "veh[i].x inputs");
    Case {
        fmu: wind,
        inputs: bodies,
    }
    .check("wind");
    // the blocks: nothing of vehicle 1 moves with the rails under vehicle 2
    let found = case.differences(false);
    let md = case.md();
    let name = |vr: u32| {
        md.model_variables
            .iter()
            .find(|v| v.value_reference == vr)
            .unwrap()
            .name
            .clone()
    };
    for (o, deps) in &found {
        let out = name(*o);
        let first = out.starts_with("veh[1]")
            || ["ws[1]", "ws[2]", "ws[3]", "ws[4]"]
                .iter()
                .any(|p| out.starts_with(p));
        for d in deps {
            let input = name(*d);
            let other = ["ws[5]", "ws[6]", "ws[7]", "ws[8]"]
                .iter()
                .any(|p| input.starts_with(p));
            assert!(!(first && other), "{out} moves with {input}");
        }
    }
}

/// The Tsing Ma bridge FMU of the default scenario (20 FE modes with nodal shapes, 32
/// wheelsets): in initialisation mode every rail acceleration follows from all the loads,
/// and the contribution of one wheelset's force to another's acceleration can be many
/// orders below that output's other terms (a roll moment through the torsional modes to a
/// vertical acceleration), so that whether it moves the output's last bits depends on the
/// operating point. Finite differences here, at an operating point of their own, find no
/// dependency the description does not declare.
#[test]
fn the_tsing_ma_bridge_declares_the_dependencies_finite_differences_find() {
    let toml = std::fs::read_to_string(tbi_tests::repo_path("master/scenarios/tsing-ma.toml"))
        .expect("the default scenario");
    let e = export("dependencies-tsing-ma", &toml);
    let bridge = Fmu::load(&e.bridge).unwrap();
    let inputs = tbi_tests::fmu::bridge_operating_point(bridge.model_description(), (5.0, 2150.0));
    Case {
        fmu: bridge,
        inputs,
    }
    .check("bridge");
}

/// A train at the highest speed accepted (720 km/h = 200 m/s): the exporter's probe of the
/// train's `speed` parameter moves it down, as moving it up would leave the range, and the
/// wheelsets' initial speeds are declared to depend on it (their initial positions do not).
#[test]
fn a_train_at_the_highest_speed_exports_with_its_speed_dependencies() {
    let toml = common::scenarios::coach2().replace("speed_kmh = 200.0", "speed_kmh = 720.0");
    assert!(toml.contains("speed_kmh = 720.0"), "the case's speed line");
    let e = export("dependencies-top-speed", &toml);
    let train = Fmu::load(&e.train).unwrap();
    let md = train.model_description();
    let index_of = |name: &str| {
        1 + md
            .model_variables
            .iter()
            .position(|v| v.name == name)
            .unwrap_or_else(|| panic!("no variable {name}")) as u32
    };
    let speed = index_of("speed");
    let v = md
        .model_variables
        .iter()
        .find(|v| v.name == "speed")
        .and_then(|v| match &v.kind {
            model_description::VariableKind::Real(r) => r.start,
            _ => None,
        })
        .expect("speed has a start value");
    assert_eq!(v, 200.0, "speed start value, m/s");
    for (name, depends) in [("ws[1].vx", true), ("ws[8].vx", true), ("ws[1].x", false)] {
        let i = index_of(name);
        let unknown = (md.model_structure.initial_unknowns.iter())
            .find(|u| u.index == i)
            .unwrap_or_else(|| panic!("{name} is no initial unknown"));
        let deps = unknown
            .dependencies
            .as_ref()
            .expect("declared dependencies");
        assert_eq!(deps.contains(&speed), depends, "{name} on speed: {deps:?}");
    }
}
