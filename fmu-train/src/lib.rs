//! The train as an FMI 2.0 Co-Simulation FMU: only the model — the FMI plumbing is
//! `fmi-export`'s, the equations are `tbi_dynamics::solver::partitioned::TrainSide`.
//!
//! Resources: `train.json` ([`TrainDescription`]: vehicles, speed, start position, hunting).
//! Parameters (speed, start position, hunting, the coach's Table 1 properties) may be changed
//! before `fmi2ExitInitializationMode`, which builds the vehicles. Variables: [`layout`]
//! (the one description of them). Each `fmi2DoStep(t, h)` is one Newmark step of size `h`
//! with the rail motion at `t + h`. The C symbols are exported by the `train` shared object
//! of `fmu-train/so`.

pub use contract::*;
use fmi_export::model::set_each;
use fmi_export::{FmuModel, Log, ModelError, Phase, StepOutcome};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;
pub mod contract;
pub mod layout;
pub mod package;

use fmu_contract::{rail_channel, rail_from_values, wheel, Block, BUILD_ID};
use layout::{parameters, TrainLayout, TrainVar};
use tbi_dynamics::solver::partitioned::TrainSide;
use tbi_dynamics::solver::{share, VehicleState};
use tbi_dynamics::train::Speed;
use tbi_dynamics::vehicle::WheelLoads;

/// GUID of a train FMU with these resource bytes (`train.json`).
pub fn guid_for(resource_bytes: &[u8]) -> String {
    fmi_export::guid(TRAIN_ID, BUILD_ID, resource_bytes)
}

/// The train FMU's model.
pub struct TrainFmu {
    original: Arc<TrainDescription>,
    /// The resources with the parameters set so far (copied on a parameter's write).
    res: Arc<TrainDescription>,
    /// Constant from instantiation on (shared by the instance's saved states).
    guid: Arc<str>,
    layout: Arc<TrainLayout>,
    start_time: f64,
    /// Rail motion inputs (u, u̇, ü) per wheelset.
    rails: Vec<[Vector3<f64>; 3]>,
    /// Along-wind turbulence inputs per car body (a turbulent wind), m/s.
    wind: Vec<f64>,
    side: Option<TrainSide>,
    /// Built from the current parameters but not yet initialised for stepping.
    initialized: bool,
    outputs: Vec<f64>,
    dirty: bool,
}

impl Clone for TrainFmu {
    fn clone(&self) -> Self {
        TrainFmu {
            original: self.original.clone(),
            res: self.res.clone(),
            guid: self.guid.clone(),
            layout: self.layout.clone(),
            start_time: self.start_time,
            rails: self.rails.clone(),
            wind: self.wind.clone(),
            side: self.side.clone(),
            initialized: self.initialized,
            outputs: self.outputs.clone(),
            dirty: self.dirty,
        }
    }

    /// Reuses this model's allocations: a rollback copies the state, not the train. The
    /// outputs, derived from the state and the inputs, are not copied but derived again when
    /// read (a master sets new inputs and steps after a rollback before it reads any).
    fn clone_from(&mut self, source: &Self) {
        share(&mut self.original, &source.original);
        share(&mut self.res, &source.res);
        share(&mut self.guid, &source.guid);
        share(&mut self.layout, &source.layout);
        self.start_time = source.start_time;
        self.rails.clone_from(&source.rails);
        self.wind.clone_from(&source.wind);
        self.side.clone_from(&source.side);
        self.initialized = source.initialized;
        self.outputs.resize(source.outputs.len(), 0.0);
        self.dirty = true;
    }
}

#[derive(Serialize, Deserialize)]
struct Saved {
    res: TrainDescription,
    start_time: f64,
    rails: Vec<[Vector3<f64>; 3]>,
    initialized: bool,
    t: f64,
    states: Option<Vec<VehicleState>>,
    side_rails: Option<Vec<[Vector3<f64>; 3]>>,
    /// The turbulence inputs per car body.
    #[serde(default)]
    wind: Vec<f64>,
}

impl TrainFmu {
    /// The dependencies `<ModelStructure>` declares ([`fmi_export::dependencies`]).
    ///
    /// * `<Outputs>`: probed at a generic operating point (distinct non-zero rail motion
    ///   under every wheelset): at a communication point the outputs are those of the state
    ///   reached by the last step and depend on no input.
    /// * `<InitialUnknowns>`: each vehicle starts in equilibrium on the rails under its own
    ///   wheelsets, so the outputs of its wheelsets and body depend on those rails and on
    ///   the parameters, declared as that block (a superset: some of its entries are exact
    ///   zeros, such as the body acceleration in equilibrium, which a probe can only see as
    ///   rounding); a wheelset's position and speed depend on the parameters only (probed).
    pub fn dependencies(
        res: &TrainDescription,
    ) -> Result<fmi_export::dependencies::Declared, String> {
        use fmi_export::dependencies::{probe, Declared};
        let mut m = TrainFmu::from_parts(res.clone(), String::new());
        let l = m.layout.clone();
        let rails = l.rail_in.all_vrs();
        let params: Vec<u32> = (0..parameters(res).len() as u32)
            .map(|j| layout::PARAM_BASE + j)
            .collect();
        let mut outputs = l.wheel_out.all_vrs();
        outputs.extend(l.vehicle_out.all_vrs());
        outputs.extend(l.body_x_out.all_vrs());
        let mut knowns = rails.clone();
        knowns.extend(l.wind_in.all_vrs());
        let set = |m: &mut TrainFmu, phase| -> Result<(), String> {
            for (i, &vr) in rails.iter().enumerate() {
                let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
                m.set_real(vr, sign * 1e-3 * (1.0 + 0.013 * i as f64), phase)?;
            }
            for i in 0..l.wind_in.count {
                m.set_real(l.wind_in.vr(i, 0), 2.0 + 0.1 * i as f64, phase)?;
            }
            Ok(())
        };
        let seed = layout::PARAM_BASE + 4;
        let delta = |vr: u32, v: f64| {
            if vr == seed {
                1.0
            } else {
                1e-4 * (1.0 + v.abs())
            }
        };
        // initialisation: positions and speeds probed (hunting on, so that all its
        // parameters show), everything else the vehicle block
        set(&mut m, Phase::Initialization)?;
        let amplitude = layout::PARAM_BASE + 2;
        if m.get_real(amplitude)? == 0.0 {
            m.set_real(amplitude, 1e-3, Phase::Initialization)?;
        }
        let mut kinematic = l.wheel_out.vrs(&[wheel::X, wheel::VX]);
        kinematic.extend(l.body_x_out.all_vrs());
        let probed = probe(&mut m, &params, &kinematic, Phase::Initialization, delta)?;
        let vehicle_of: Vec<usize> = res
            .build(0.0)?
            .wheelsets()
            .iter()
            .map(|w| w.vehicle)
            .collect();
        let block = |vehicle: usize| -> Vec<u32> {
            let mut d: Vec<u32> = (0..l.n_wheelsets())
                .filter(|&w| vehicle_of[w] == vehicle)
                .flat_map(|w| (0..l.rail_in.width()).map(move |k| (w, k)))
                .map(|(w, k)| l.rail_in.vr(w, k))
                .collect();
            if vehicle < l.wind_in.count {
                d.push(l.wind_in.vr(vehicle, 0));
            }
            d.extend(&params);
            d
        };
        let initial = outputs
            .iter()
            .map(|&vr| {
                if let Some(p) = kinematic.iter().position(|&k| k == vr) {
                    return (vr, probed[p].clone());
                }
                let vehicle = l
                    .wheel_out
                    .decode(vr)
                    .map(|(w, _)| vehicle_of[w])
                    .or_else(|| l.vehicle_out.decode(vr).map(|(i, _)| i))
                    .expect("an output of the wheelset or vehicle block");
                (vr, block(vehicle))
            })
            .collect();
        m.exit_initialization()?;
        m.do_step(0.0, 1e-3)?;
        set(&mut m, Phase::Stepping)?;
        let stepping = probe(&mut m, &knowns, &outputs, Phase::Stepping, delta)?;
        Ok(Declared {
            outputs: outputs.iter().copied().zip(stepping).collect(),
            initial,
        })
    }

    /// Build from resource data (used by `instantiate` and by tests).
    pub fn from_parts(res: TrainDescription, guid: String) -> Self {
        let layout = TrainLayout::of(&res);
        TrainFmu {
            original: Arc::new(res.clone()),
            res: Arc::new(res),
            guid: guid.into(),
            start_time: 0.0,
            rails: vec![[Vector3::zeros(); 3]; layout.n_wheelsets()],
            wind: vec![0.0; layout.wind_in.count],
            side: None,
            initialized: false,
            outputs: vec![0.0; layout.n_outputs()],
            layout: Arc::new(layout),
            dirty: true,
        }
    }

    fn build_side(&self) -> Result<TrainSide, String> {
        // the train's first axle is at x0 at the start time
        Ok(TrainSide::new(Arc::new(self.res.build(self.start_time)?)))
    }

    /// Computes the outputs from the state and inputs unless they are current.
    #[inline]
    fn refresh(&mut self) -> Result<(), String> {
        if self.dirty {
            self.compute_outputs()?;
        }
        Ok(())
    }

    fn compute_outputs(&mut self) -> Result<(), String> {
        if !self.initialized {
            let mut side = self.build_side()?;
            pass_wind(&self.wind, &mut side);
            side.initialize(self.start_time, &self.rails);
            self.side = Some(side);
        }
        let side = self
            .side
            .as_ref()
            .expect("built above or at initialisation");
        let t = side.t;
        let l = &self.layout;
        for w in 0..l.n_wheelsets() {
            let f = side.force(w);
            let ws = side.wheelsets[w];
            let model = &side.train.vehicles[ws.vehicle].model;
            let loads = WheelLoads::from_force(
                &f,
                model.wheelsets[ws.local].reference_load_n(),
                model.contact_distance_m,
            );
            // In the order of layout::WHEEL_OUT.
            self.outputs[l.wheel_out.slots(w)].copy_from_slice(&[
                side.x(w, t),
                side.train.runs[ws.run].vx(t),
                f.x,
                f.y,
                f.z,
                loads.p_left,
                loads.p_right,
                loads.derail,
                loads.offload,
            ]);
        }
        for (i, (tv, s)) in side.train.vehicles.iter().zip(&side.states).enumerate() {
            let acceleration = |dof: Option<usize>| dof.map(|d| s.vdd[d]).unwrap_or(0.0);
            self.outputs[l.vehicle_out.slots(i)].copy_from_slice(&[
                acceleration(tv.model.body.lateral),
                acceleration(tv.model.body.vertical),
            ]);
        }
        for i in 0..l.body_x_out.count {
            self.outputs[l.body_x_out.slot(i, 0)] =
                side.train.runs[0].x_at(side.train.centre_offset_m(i), t);
        }
        self.dirty = false;
        Ok(())
    }

    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), String> {
        let list = parameters(&self.res);
        let name = &list
            .get(index)
            .ok_or_else(|| format!("unknown parameter index {index}"))?
            .name;
        let res = Arc::make_mut(&mut self.res);
        match index {
            0 => {
                res.speed_m_s =
                    Speed::from_m_s(value).map_err(|e| format!("parameter speed = {value}: {e}"))?
            }
            1 => res.x0_m = value,
            2 => res.hunting.amplitude_m = value,
            3 => res.hunting.wavelength_m = value,
            4 => {
                if value < 0.0 || value.fract() != 0.0 || value > 9.0e15 {
                    return Err(format!(
                        "parameter hunting.seed = {value} must be a non-negative integer"
                    ));
                }
                res.hunting.seed = value as u64
            }
            _ => {
                let field = name.trim_start_matches("coach.").to_string();
                match &mut res.spec {
                    TrainSpec::Coaches { params, .. } => {
                        *params
                            .field_mut(&field)
                            .ok_or_else(|| format!("unknown parameter {name}"))? = value
                    }
                    _ => return Err(format!("unknown parameter {name}")),
                }
            }
        }
        // validate now so that the error names the parameter
        if let Err(e) = self.build_side() {
            return Err(format!("parameter {name} = {value}: {e}"));
        }
        Ok(())
    }
}

/// The turbulence inputs of the car bodies into the side (the wind at the end of the coming
/// step); nothing in a steady wind.
fn pass_wind(wind: &[f64], side: &mut TrainSide) {
    if !wind.is_empty() {
        side.body_wind.copy_from_slice(wind);
    }
}

impl FmuModel for TrainFmu {
    fn instantiate(resources: &Path, _log: &dyn Log) -> Result<Self, ModelError> {
        let path = resources.join(TRAIN_RESOURCE);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let res: TrainDescription = serde_json::from_slice(&bytes)
            .map_err(|e| format!("{}: line {}: {e}", path.display(), e.line()))?;
        let guid = guid_for(&bytes);
        let fmu = TrainFmu::from_parts(res, guid);
        fmu.build_side()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(fmu)
    }

    fn guid(&self) -> String {
        self.guid.to_string()
    }

    fn setup_experiment(
        &mut self,
        start_time: f64,
        _stop_time: Option<f64>,
    ) -> Result<(), ModelError> {
        self.start_time = start_time;
        self.dirty = true;
        Ok(())
    }

    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        let mut side = self.build_side()?;
        pass_wind(&self.wind, &mut side);
        side.initialize(self.start_time, &self.rails);
        self.side = Some(side);
        self.initialized = true;
        self.dirty = true;
        Ok(())
    }

    fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), ModelError> {
        if !value.is_finite() {
            return Err(ModelError::Refused(format!(
                "value reference {vr}: {value} is not finite"
            )));
        }
        match self.layout.decode(vr) {
            Some(TrainVar::Rail { w, k }) => *rail_channel(&mut self.rails[w], k) = value,
            Some(TrainVar::Wind(i)) => self.wind[i] = value,
            Some(TrainVar::Parameter(j)) => {
                if phase == Phase::Stepping {
                    return Err(ModelError::Refused(format!(
                        "parameter (value reference {vr}) is fixed after initialisation"
                    )));
                }
                self.set_parameter(j, value)?;
            }
            _ => {
                return Err(ModelError::Refused(format!(
                    "value reference {vr} is not an input or parameter of the train FMU"
                )))
            }
        }
        self.dirty = true;
        Ok(())
    }

    /// The rail motion as one run of consecutive value references (what the master sends)
    /// goes straight into place.
    fn set_reals(&mut self, vr: &[u32], values: &[f64], phase: Phase) -> Result<(), ModelError> {
        let Some(first) = self.layout.rail_in.run(vr) else {
            return set_each(self, vr, values, phase);
        };
        (self.layout.rail_in).set_run(
            first,
            values,
            &mut self.rails,
            rail_from_values,
            rail_channel,
        );
        self.dirty = true;
        Ok(())
    }

    /// A run of consecutive value references inside one output block is one copy from the
    /// output buffer; other outputs (the master's positions, speeds and forces of every
    /// wheelset) are gathered from it through the decode table.
    fn get_reals(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ModelError> {
        let l = &self.layout;
        if let Some(first) = Block::output_run(&[l.wheel_out, l.vehicle_out, l.body_x_out], vr) {
            self.refresh()?;
            values.copy_from_slice(&self.outputs[first..first + vr.len()]);
            return Ok(());
        }
        for (&r, out) in vr.iter().zip(values.iter_mut()) {
            *out = match self.layout.decode(r) {
                Some(TrainVar::Output(slot)) => {
                    self.refresh()?;
                    self.outputs[slot]
                }
                _ => self.get_real(r)?,
            };
        }
        Ok(())
    }

    fn get_real(&mut self, vr: u32) -> Result<f64, ModelError> {
        let unknown = || ModelError::UnknownVariable { kind: "Real", vr };
        match self.layout.decode(vr).ok_or_else(unknown)? {
            TrainVar::Rail { w, k } => Ok(*rail_channel(&mut self.rails[w], k)),
            TrainVar::Wind(i) => Ok(self.wind[i]),
            TrainVar::Parameter(j) => parameters(&self.res)
                .get(j)
                .map(|p| p.value)
                .ok_or_else(unknown),
            TrainVar::Output(slot) => {
                self.refresh()?;
                Ok(self.outputs[slot])
            }
        }
    }

    fn do_step(&mut self, _t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        let side = self.side.as_mut().ok_or("not initialised")?;
        pass_wind(&self.wind, side);
        side.step(h, &self.rails);
        if !side
            .states
            .iter()
            .all(|s| s.v.iter().all(|x| x.is_finite()))
        {
            return Err("vehicle response became non-finite".into());
        }
        self.dirty = true;
        Ok(StepOutcome::Ok)
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        *self = TrainFmu::from_parts((*self.original).clone(), self.guid.to_string());
        Ok(())
    }

    fn serialize_state(&self) -> Vec<u8> {
        serde_json::to_vec(&Saved {
            res: (*self.res).clone(),
            start_time: self.start_time,
            rails: self.rails.clone(),
            initialized: self.initialized,
            t: self.side.as_ref().map(|s| s.t).unwrap_or(self.start_time),
            states: self.side.as_ref().map(|s| s.states.clone()),
            side_rails: self.side.as_ref().map(|s| s.rails.clone()),
            wind: self.wind.clone(),
        })
        .expect("state serialises")
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let s: Saved = serde_json::from_slice(bytes).map_err(|e| format!("train state: {e}"))?;
        if s.rails.len() != self.layout.n_wheelsets() || s.wind.len() != self.wind.len() {
            return Err("train state does not match this FMU's size".into());
        }
        self.res = Arc::new(s.res);
        self.start_time = s.start_time;
        self.rails = s.rails;
        self.wind = s.wind;
        self.initialized = s.initialized;
        self.side = match (s.states, s.side_rails) {
            (Some(states), Some(rails)) => {
                let mut side = self.build_side()?;
                side.states = states;
                side.rails = rails;
                side.t = s.t;
                Some(side)
            }
            _ => None,
        };
        self.dirty = true;
        Ok(())
    }
}
