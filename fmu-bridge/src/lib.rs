//! The bridge with its track as an FMI 2.0 Co-Simulation FMU: only the model — the FMI
//! plumbing is `fmi-export`'s, the equations are `tbi_dynamics::solver::partitioned::BridgeSide`.
//!
//! Resources: `bridge.json` ([`BridgeResources`]: modal bridge, probes, wheelset count) and,
//! when the track is not smooth, `track.csv` (irregularity record). With `[wind]
//! turbulence` the deck takes the turbulence at its points as inputs (from the wind FMU) and
//! applies the buffeting forces itself. Variables: [`layout`]
//! (the one description of them). Each `fmi2DoStep(t, h)` is one Newmark step of size `h`
//! with the wheelset positions, speeds and forces at `t + h`. The C symbols are exported by
//! the `bridge` shared object of `fmu-bridge/so`.

// Index loops mirror the equations (q_n, ω_n, rows k of Ψ) and are kept on purpose.
#![allow(clippy::needless_range_loop)]

pub use contract::*;
use fmi_export::model::{get_each, set_each};
use fmi_export::{FmuModel, Log, ModelError, Phase, StepOutcome};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;
pub mod contract;
pub mod layout;
pub mod package;

use fmu_contract::{rail_values, wheel_channel, wheel_from_values, Block, BUILD_ID};
use layout::{probe_channels, BridgeLayout, BridgeVar, PARKED_X};
use tbi_dynamics::solver::partitioned::{BridgeSide, ModalState, ProbeValues, WheelInput};
use tbi_dynamics::solver::share;
use tbi_dynamics::track::{RailProfile, Smooth};

/// GUID of a bridge FMU with these resource bytes: `bridge.json`, then (with a track
/// record) the record's [`tbi_track::Profile::identity_bytes`], which its reader and its
/// writer compute alike without hashing the text.
pub fn guid_for(resource_bytes: &[u8]) -> String {
    fmi_export::guid(BRIDGE_ID, BUILD_ID, resource_bytes)
}

/// The bridge FMU's model.
pub struct BridgeFmu {
    res: Arc<BridgeResources>,
    layout: Arc<BridgeLayout>,
    /// Constant from instantiation on (shared by the instance's saved states).
    guid: Arc<str>,
    side: BridgeSide,
    inputs: Vec<WheelInput>,
    initialized: bool,
    outputs: Vec<f64>,
    /// The outputs are not those of the current state and inputs.
    dirty: bool,
    /// The probe outputs are current (meaningful once `dirty` is false): they are derived
    /// only when read, as a master iterating a step reads the rail motion every sweep and
    /// the probes once.
    probes_current: bool,
}

impl Clone for BridgeFmu {
    fn clone(&self) -> Self {
        BridgeFmu {
            res: self.res.clone(),
            layout: self.layout.clone(),
            guid: self.guid.clone(),
            side: self.side.clone(),
            inputs: self.inputs.clone(),
            initialized: self.initialized,
            outputs: self.outputs.clone(),
            dirty: self.dirty,
            probes_current: self.probes_current,
        }
    }

    /// Reuses this model's allocations: a rollback copies the modal state and the inputs.
    /// The outputs, derived from those, are not copied but derived again when read (a master
    /// sets new inputs and steps after a rollback before it reads any).
    fn clone_from(&mut self, source: &Self) {
        share(&mut self.res, &source.res);
        share(&mut self.layout, &source.layout);
        share(&mut self.guid, &source.guid);
        self.side.clone_from(&source.side);
        self.inputs.clone_from(&source.inputs);
        self.initialized = source.initialized;
        self.outputs.resize(source.outputs.len(), 0.0);
        self.dirty = true;
        self.probes_current = false;
    }
}

#[derive(Serialize, Deserialize)]
struct Saved {
    state: ModalState,
    inputs: Vec<WheelInput>,
    initialized: bool,
    /// The turbulence inputs at the deck points.
    #[serde(default)]
    deck_wind: Option<Vec<[f64; 2]>>,
}

impl BridgeFmu {
    /// The dependencies `<ModelStructure>` declares ([`fmi_export::dependencies`]).
    ///
    /// * `<Outputs>`: probed at a generic operating point (every wheelset on the deck at
    ///   distinct positions, with distinct non-zero speeds and forces): at a communication
    ///   point the rail motion under a wheelset depends on that wheelset's position (and
    ///   speed, through the irregularity), and nothing depends on the forces until the next
    ///   step.
    /// * `<InitialUnknowns>`: by the equations of [`BridgeSide::initialize`]. The deck is at
    ///   rest in its steady response, so a rail displacement depends on its wheelset's
    ///   position (through the shapes under steady loads, through the irregularity) and a
    ///   rail velocity on its position and speed (through the irregularity); the deck's
    ///   acceleration `q̈₀ = Σₖ Ψ(xₖ)ᵀ fₖ + B u` follows from every wheelset's position and
    ///   force and the turbulence inputs, so an acceleration (rail and probe) depends on those
    ///   that act through a mode having its component (and a rail acceleration on its speed,
    ///   through the irregularity).
    ///   Declared from the equations, not probed: a force's share of another wheelset's
    ///   acceleration can lie many orders below that output's other terms (a roll moment
    ///   through the torsional modes to a vertical acceleration), where whether a probe sees
    ///   it depends on the rounding at the operating point. A share that is exactly zero
    ///   there (a wheelset over a support, where every shape vanishes) is declared all the
    ///   same: the dependency is structural.
    pub fn dependencies(
        res: &BridgeResources,
        track: Arc<dyn RailProfile>,
    ) -> Result<fmi_export::dependencies::Declared, String> {
        use fmi_export::dependencies::{probe, Declared};
        let flat = track.is_flat();
        let mut m = BridgeFmu::from_parts(res.clone(), track, String::new());
        let l = m.layout.clone();
        let n = l.n_wheelsets().max(1) as f64;
        let (a, b) = (res.modal.x_start_m, res.modal.x_end_m);
        let mut knowns = l.wheel_in.all_vrs();
        knowns.extend(l.wind_in.all_vrs());
        let mut outputs = l.rail_out.all_vrs();
        outputs.extend(l.probe_out.all_vrs());
        let set = |m: &mut BridgeFmu, phase| -> Result<(), String> {
            for w in 0..l.n_wheelsets() {
                let s = 1.0 + 0.1 * w as f64;
                let x = a + (b - a) * (w as f64 + 0.37) / n;
                for (k, v) in [x, 20.0 * s, 1.1e3 * s, 2.3e2 * s, 8.7e4 * s]
                    .iter()
                    .enumerate()
                {
                    m.set_real(l.wheel_in.vr(w, k), *v, phase)?;
                }
            }
            for j in 0..l.wind_in.count {
                let s = 1.0 + 0.05 * j as f64;
                m.set_real(l.wind_in.vr(j, 0), 1.3 * s, phase)?;
                m.set_real(l.wind_in.vr(j, 1), -0.4 * s, phase)?;
            }
            Ok(())
        };
        // small against the spacing of the wheelsets and the deck's end
        let delta = |_: u32, v: f64| 1e-4 * (1.0 + v.abs());
        let steady = res.modal.steady_modal_force.iter().any(|&f| f != 0.0);
        let initial = Self::initial_dependencies(&l, &res.modal, &outputs, flat, steady);
        set(&mut m, Phase::Initialization)?;
        m.exit_initialization()?;
        m.do_step(0.0, 1e-3)?;
        set(&mut m, Phase::Stepping)?;
        let stepping = probe(&mut m, &knowns, &outputs, Phase::Stepping, delta)?;
        Ok(Declared {
            outputs: outputs.iter().copied().zip(stepping).collect(),
            initial: outputs.iter().copied().zip(initial).collect(),
        })
    }

    /// The `<InitialUnknowns>` dependencies of `outputs` ([`Self::dependencies`]), value
    /// references ascending, on a track that is `flat` (no irregularity: the rail motion is
    /// the deck's alone) or not, with `steady` deck loads (a deck displaced at rest) or
    /// without. A wheelset's force component acts on an acceleration component through the
    /// modes that have both (`modal.nonzero_components`): a vertical-only beam couples no
    /// lateral force to anything.
    fn initial_dependencies(
        l: &BridgeLayout,
        modal: &tbi_dynamics::bridge::ModalBridge,
        outputs: &[u32],
        flat: bool,
        steady: bool,
    ) -> Vec<Vec<u32>> {
        use fmu_contract::wheel::{F_Y, VX, X};
        let (deck, rail) = modal.nonzero_components();
        // the loads acting on an acceleration whose shapes are `has`: the forces (F_y, M_x,
        // F_z on the rail's y, θ, z) of every wheelset through a mode with both, with those
        // wheelsets' positions; the turbulence on every mode
        let loads = |has: &dyn Fn(usize) -> bool| -> Vec<u32> {
            let acting: Vec<usize> = (0..3)
                .filter(|&c| (0..rail.len()).any(|n| has(n) && rail[n][c]))
                .collect();
            let mut d = Vec::new();
            if !acting.is_empty() {
                for k in 0..l.n_wheelsets() {
                    d.push(l.wheel_in.vr(k, X));
                    d.extend(acting.iter().map(|&c| l.wheel_in.vr(k, F_Y + c)));
                }
            }
            if (0..rail.len()).any(has) {
                d.extend(l.wind_in.all_vrs());
            }
            d
        };
        outputs
            .iter()
            .map(|&vr| {
                let mut deps = if let Some((w, c)) = l.rail_out.decode(vr) {
                    // y, θ, z (Ψ(x) q₀ + r(x)); their rates (ẋ r′(x), the deck at rest);
                    // their accelerations (Ψ(x) q̈₀ + ẋ² r″(x))
                    let (x, vx) = (l.wheel_in.vr(w, X), l.wheel_in.vr(w, VX));
                    let k = c % 3;
                    let shaped = (0..rail.len()).any(|n| rail[n][k]);
                    match c / 3 {
                        0 if !flat || steady && shaped => vec![x],
                        1 if !flat => vec![x, vx],
                        0 | 1 => Vec::new(),
                        _ => {
                            let mut d = loads(&|n| rail[n][k]);
                            d.extend((shaped || !flat).then_some(x));
                            d.extend((!flat).then_some(vx));
                            d
                        }
                    }
                } else {
                    let (_, c) = l.probe_out.decode(vr).expect("a rail or probe output");
                    // y, z, θ at rest; y_dd, z_dd (deck components h, v)
                    match c {
                        3 => loads(&|n| deck[n][0]),
                        4 => loads(&|n| deck[n][1]),
                        _ => Vec::new(),
                    }
                };
                deps.sort_unstable();
                deps.dedup();
                deps
            })
            .collect()
    }

    /// Build from resource data (used by `instantiate` and by tests).
    pub fn from_parts(res: BridgeResources, track: Arc<dyn RailProfile>, guid: String) -> Self {
        let layout = BridgeLayout::of(&res);
        let mut side = BridgeSide::new(Arc::new(res.modal.clone()), track);
        side.tracks = Arc::new(res.wheelset_tracks.clone());
        // the turbulence comes from the wind FMU
        side.take_wind_from_inputs();
        BridgeFmu {
            inputs: (0..layout.n_wheelsets())
                .map(|_| WheelInput {
                    x: PARKED_X,
                    ..Default::default()
                })
                .collect(),
            outputs: vec![0.0; layout.n_outputs()],
            layout: Arc::new(layout),
            res: Arc::new(res),
            guid: guid.into(),
            side,
            initialized: false,
            dirty: true,
            probes_current: false,
        }
    }

    /// Sets the damping ratio of mode `n` (before initialisation ends): the modal model is
    /// made again with it, as a scenario with that damping makes it.
    fn set_damping(&mut self, n: usize, value: f64) -> Result<(), String> {
        let name = BridgeLayout::damping_name(n);
        if self.initialized {
            return Err(format!("parameter {name} is fixed after initialisation"));
        }
        if !(0.0..1.0).contains(&value) {
            return Err(format!("parameter {name} = {value} must lie in [0, 1)"));
        }
        Arc::make_mut(&mut self.res).modal.damping[n] = value;
        let track = self.side.track.clone();
        let wind = self.side.deck_wind.clone();
        self.side = BridgeSide::new(Arc::new(self.res.modal.clone()), track);
        self.side.tracks = Arc::new(self.res.wheelset_tracks.clone());
        self.side.take_wind_from_inputs();
        if let (Some(new), Some(old)) = (self.side.deck_wind.as_mut(), wind) {
            *new = old;
        }
        self.dirty = true;
        Ok(())
    }

    /// Makes the rail-motion outputs current.
    fn refresh(&mut self) {
        if !self.dirty {
            return;
        }
        if !self.initialized {
            self.side.initialize(&self.inputs);
        }
        let l = &self.layout;
        let outputs = &mut self.outputs;
        self.side.rails(&self.inputs, |w, r| {
            outputs[l.rail_out.slots(w)].copy_from_slice(&rail_values(r))
        });
        self.dirty = false;
        self.probes_current = false;
    }

    /// Makes every output current, the probes' included.
    fn refresh_probes(&mut self) {
        self.refresh();
        if self.probes_current {
            return;
        }
        let l = &self.layout;
        for (p, probe) in self.res.probes.iter().enumerate() {
            let v = self.side.probe(probe.x_m);
            self.outputs[l.probe_out.slots(p)].copy_from_slice(&probe_channels(&v));
        }
        self.probes_current = true;
    }

    /// Makes the outputs in `slots` current.
    fn refresh_slots(&mut self, slots: std::ops::Range<usize>) {
        let probes = &self.layout.probe_out;
        let overlap = |first: usize| slots.start < first + probes.len() && first < slots.end;
        if probes.count > 0 && overlap(probes.slot(0, 0)) {
            self.refresh_probes();
        } else {
            self.refresh();
        }
    }
}

impl FmuModel for BridgeFmu {
    fn instantiate(resources: &Path, _log: &dyn Log) -> Result<Self, ModelError> {
        let path = resources.join(BRIDGE_RESOURCE);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let res: BridgeResources = serde_json::from_slice(&bytes)
            .map_err(|e| format!("{}: line {}: {e}", path.display(), e.line()))?;
        res.check_tracks()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let mut all = bytes;
        let track: Arc<dyn RailProfile> = if res.has_track_record {
            let tp = resources.join(TRACK_RESOURCE);
            let record = tbi_track::Record::read(&tp).map_err(|e| e.to_string())?;
            all.extend_from_slice(&record.profile().identity_bytes());
            Arc::new(tbi_track::Irregularity::Record(record))
        } else {
            Arc::new(Smooth)
        };
        let guid = guid_for(&all);
        Ok(BridgeFmu::from_parts(res, track, guid))
    }

    fn guid(&self) -> String {
        self.guid.to_string()
    }

    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        self.side.initialize(&self.inputs);
        self.initialized = true;
        self.dirty = true;
        Ok(())
    }

    fn set_real(&mut self, vr: u32, value: f64, _phase: Phase) -> Result<(), ModelError> {
        let l = &self.layout;
        let var = l.decode(vr);
        if !value.is_finite() {
            // named only here: set_real is on the co-simulation's hot path
            let name = match var {
                Some(BridgeVar::Wheel { w, k }) => l.wheel_in.name(w, k),
                Some(BridgeVar::Wind { j, k }) => l.wind_in.name(j, k),
                _ => format!("value reference {vr}"),
            };
            return Err(ModelError::Refused(format!(
                "input {name} = {value} is not finite"
            )));
        }
        match var {
            Some(BridgeVar::Damping(n)) => {
                return self.set_damping(n, value).map_err(ModelError::Refused)
            }
            Some(BridgeVar::Wheel { w, k }) => *wheel_channel(&mut self.inputs[w], k) = value,
            Some(BridgeVar::Wind { j, k }) => {
                self.side
                    .deck_wind
                    .as_mut()
                    .expect("a wind input has its deck point")[j][k] = value
            }
            _ => {
                return Err(ModelError::Refused(format!(
                    "value reference {vr} is not an input of the bridge FMU"
                )))
            }
        }
        self.dirty = true;
        Ok(())
    }

    /// The wheelset inputs as one run of consecutive value references (what the master
    /// sends) go straight into place.
    fn set_reals(&mut self, vr: &[u32], values: &[f64], phase: Phase) -> Result<(), ModelError> {
        let Some(first) = self.layout.wheel_in.run(vr) else {
            return set_each(self, vr, values, phase);
        };
        (self.layout.wheel_in).set_run(
            first,
            values,
            &mut self.inputs,
            wheel_from_values,
            wheel_channel,
        );
        self.dirty = true;
        Ok(())
    }

    /// A run of consecutive value references inside one output block (the rail motion, as
    /// the master asks for it) is one copy from the output buffer.
    fn get_reals(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ModelError> {
        let l = &self.layout;
        let Some(first) = Block::output_run(&[l.rail_out, l.probe_out], vr) else {
            return get_each(self, vr, values);
        };
        self.refresh_slots(first..first + vr.len());
        values.copy_from_slice(&self.outputs[first..first + vr.len()]);
        Ok(())
    }

    fn get_real(&mut self, vr: u32) -> Result<f64, ModelError> {
        match self.layout.decode(vr) {
            Some(BridgeVar::Wheel { w, k }) => Ok(*wheel_channel(&mut self.inputs[w], k)),
            Some(BridgeVar::Wind { j, k }) => Ok(self
                .side
                .deck_wind
                .as_ref()
                .expect("a wind input has its deck point")[j][k]),
            Some(BridgeVar::Output(slot)) => {
                self.refresh_slots(slot..slot + 1);
                Ok(self.outputs[slot])
            }
            Some(BridgeVar::Damping(n)) => Ok(self.res.modal.damping[n]),
            None => Err(ModelError::UnknownVariable { kind: "Real", vr }),
        }
    }

    /// The rail motion under wheelset i has direct feedthrough from `ws[i].x` and `ws[i].vx`
    /// at a communication point; in initialisation mode the accelerations (rail motion and
    /// probes) also follow every load and the turbulence inputs
    /// ([`BridgeSide::linearised_rails`]). Every other partial derivative is zero.
    const PROVIDES_DIRECTIONAL_DERIVATIVE: bool = true;

    fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        let l = self.layout.clone();
        let mut seeds = vec![WheelInput::default(); l.n_wheelsets()];
        let mut wind_seed = self
            .side
            .deck_wind
            .as_ref()
            .map(|d| vec![[0.0; 2]; d.len()]);
        for (&vr, &s) in knowns.iter().zip(seed) {
            match l.decode(vr) {
                Some(BridgeVar::Wheel { w, k }) => *wheel_channel(&mut seeds[w], k) += s,
                Some(BridgeVar::Wind { j, k }) => {
                    wind_seed.as_mut().expect("a wind input has its deck point")[j][k] += s
                }
                _ => {
                    return Err(ModelError::Refused(format!(
                        "vKnown_ref: value reference {vr} is not an input of the bridge FMU"
                    )))
                }
            }
        }
        self.refresh();
        let initializing = !self.initialized;
        let mut d = vec![0.0; l.n_outputs()];
        let dqdd = self.side.linearised_rails(
            &self.inputs,
            &seeds,
            wind_seed.as_deref(),
            initializing,
            |w, r| d[l.rail_out.slots(w)].copy_from_slice(&rail_values(r)),
        );
        if initializing {
            let nb = dqdd.len();
            let (zero, mut shapes) = (vec![0.0; nb], vec![[0.0; 3]; nb]);
            for (p, probe) in self.res.probes.iter().enumerate() {
                self.side.bridge.deck_shapes(probe.x_m, &mut shapes);
                let v = ProbeValues::from_shapes(&shapes, &zero, &dqdd);
                d[l.probe_out.slots(p)].copy_from_slice(&probe_channels(&v));
            }
        }
        for (o, &vr) in out.iter_mut().zip(unknowns) {
            match l.decode(vr) {
                Some(BridgeVar::Output(slot)) => *o = d[slot],
                _ => {
                    return Err(ModelError::Refused(format!(
                        "vUnknown_ref: value reference {vr} is not an output of the bridge FMU"
                    )))
                }
            }
        }
        Ok(())
    }

    fn do_step(&mut self, _t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        self.side.step(h, &self.inputs);
        self.dirty = true;
        if !self.side.state.q.iter().all(|q| q.is_finite()) {
            return Err("bridge response became non-finite".into());
        }
        Ok(StepOutcome::Ok)
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        let fresh = BridgeFmu::from_parts(
            (*self.res).clone(),
            self.side.track.clone(),
            self.guid.to_string(),
        );
        *self = fresh;
        Ok(())
    }

    fn serialize_state(&self) -> Vec<u8> {
        serde_json::to_vec(&Saved {
            state: self.side.state.clone(),
            inputs: self.inputs.clone(),
            initialized: self.initialized,
            deck_wind: self.side.deck_wind.clone(),
        })
        .expect("state serialises")
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let s: Saved = serde_json::from_slice(bytes).map_err(|e| format!("bridge state: {e}"))?;
        if s.inputs.len() != self.res.n_wheelsets
            || s.state.q.len() != self.res.modal.n_modes()
            || s.deck_wind.as_ref().map(Vec::len) != self.side.deck_wind.as_ref().map(Vec::len)
        {
            return Err("bridge state does not match this FMU's size".into());
        }
        self.side.state = s.state;
        self.inputs = s.inputs;
        self.side.deck_wind = s.deck_wind;
        self.initialized = s.initialized;
        self.dirty = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ProbeSpec;
    use tbi_dynamics::bridge::SimplySupported;

    /// A 60 m girder with two wheelsets crossing it and two probes.
    fn bridge_fmu() -> BridgeFmu {
        let modal = SimplySupported::example().modal();
        let probe = |name: &str, x_m| ProbeSpec {
            name: name.into(),
            x_m,
        };
        let res = BridgeResources {
            modal,
            probes: vec![probe("quarter", 15.0), probe("mid", 30.0)],
            n_wheelsets: 2,
            wheelset_tracks: Vec::new(),
            has_track_record: false,
        };
        BridgeFmu::from_parts(res, Arc::new(Smooth), "guid".into())
    }

    /// Wheelset inputs `(x, vx, F_y, M_x, F_z)` at step `k`.
    fn inputs(k: usize) -> Vec<f64> {
        let x = 5.0 + 0.5 * k as f64;
        vec![
            x,
            50.0,
            2.0e3,
            1.0e3,
            1.6e5,
            x - 2.5,
            50.0,
            -1.0e3,
            5.0e2,
            1.5e5,
        ]
    }

    /// The probe outputs, read after the rail motion alone (which leaves them to be derived
    /// on their own read), are the deck motion at the probes of the state after each step,
    /// also when the inputs change after the rail motion was read.
    #[test]
    fn probe_outputs_read_after_the_rail_motion_are_those_of_the_current_state() {
        let mut fmu = bridge_fmu();
        let l = fmu.layout.clone();
        let (wheel_in, rail_out, probe_out) = (
            l.wheel_in.vrs(&[0, 1, 2, 3, 4]),
            l.rail_out.vrs(&(0..l.rail_out.width()).collect::<Vec<_>>()),
            l.probe_out
                .vrs(&(0..l.probe_out.width()).collect::<Vec<_>>()),
        );
        fmu.enter_initialization().unwrap();
        fmu.set_reals(&wheel_in, &inputs(0), Phase::Initialization)
            .unwrap();
        fmu.exit_initialization().unwrap();
        let (mut rails, mut probes) = (vec![0.0; rail_out.len()], vec![0.0; probe_out.len()]);
        let mut seen = Vec::new();
        for k in 1..=20 {
            fmu.set_reals(&wheel_in, &inputs(k), Phase::Stepping)
                .unwrap();
            fmu.do_step(0.01 * (k - 1) as f64, 0.01).unwrap();
            fmu.get_reals(&rail_out, &mut rails).unwrap();
            if k % 2 == 0 {
                // an input change after the read makes every output stale again
                fmu.set_reals(&wheel_in, &inputs(k + 1), Phase::Stepping)
                    .unwrap();
            }
            fmu.get_reals(&probe_out, &mut probes).unwrap();
            let expected: Vec<f64> = fmu
                .res
                .probes
                .clone()
                .iter()
                .flat_map(|p| probe_channels(&fmu.side.probe(p.x_m)))
                .collect();
            assert_eq!(probes, expected, "step {k}");
            seen.push(probes[0]);
        }
        assert!(
            seen.windows(2).all(|w| w[0] != w[1]),
            "the probes move from step to step: {seen:?}"
        );
    }
}
