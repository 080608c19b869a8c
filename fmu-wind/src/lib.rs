//! The turbulent wind along the deck as an FMI 2.0 Co-Simulation FMU: only the model — the
//! FMI plumbing is `fmi-export`'s, the field is [`tbi_wind::WindField`].
//!
//! Resources: `wind.json` ([`WindResources`]: mean speed, turbulence with its seed, deck
//! points, duration, vehicle count, or a measured record at the deck points). At
//! instantiation it generates the field at the deck points, exactly as the monolithic solver
//! does from the same data. Variables: [`layout`].
//! At every communication point `t` (after `fmi2DoStep(t − h, h)`) its outputs are the
//! turbulence (u, w) at each deck point (through the deck's admittance when the resources
//! give one: the turbulence as the deck's forces see it) and at each car body's centre
//! `veh[i].x` (its input,
//! from the train FMU): linear between the deck points and in time, the end points' values
//! beyond the deck. A user may replace it with their own FMU of the same variables (a
//! measured record, another generator); the bridge and train FMUs apply the forces.

pub use contract::*;
use fmi_export::{FmuModel, Log, ModelError, Phase, StepOutcome};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::Arc;
pub mod contract;
pub mod layout;
pub mod package;

use fmu_contract::BUILD_ID;
use layout::{WindLayout, WindVar, PARKED_X};
use tbi_dynamics::bridge::buffeting::admittance_gain;
use tbi_wind::WindField;

/// GUID of a wind FMU with these resource bytes (`wind.json`).
pub fn guid_for(resource_bytes: &[u8]) -> String {
    fmi_export::guid(WIND_ID, BUILD_ID, resource_bytes)
}

/// The wind FMU's model.
#[derive(Clone)]
pub struct WindFmu {
    layout: Arc<WindLayout>,
    field: Arc<WindField>,
    /// The field the deck's forces see (through the admittance, if any).
    deck_field: Arc<WindField>,
    guid: String,
    /// Current time, s.
    t: f64,
    start_time: f64,
    /// Car-body positions, m.
    x: Vec<f64>,
    outputs: Vec<f64>,
    dirty: bool,
}

#[derive(Serialize, Deserialize)]
struct Saved {
    t: f64,
    start_time: f64,
    x: Vec<f64>,
}

impl WindFmu {
    /// Build from resource data (used by `instantiate` and by tests): checks them and
    /// generates the field.
    pub fn from_parts(res: WindResources, guid: String) -> Result<Self, String> {
        if !(res.mean_speed_m_s.is_finite() && res.mean_speed_m_s > 0.0) {
            return Err(format!(
                "mean_speed_m_s = {}: the mean wind speed must be positive",
                res.mean_speed_m_s
            ));
        }
        let (field, admitted) = match &res.record {
            Some(r) if r.x_m == res.points_m => (r.clone(), None),
            Some(_) => return Err("record: its points are not the deck points".into()),
            None => WindField::generate_pair(
                &res.turbulence,
                res.mean_speed_m_s,
                &res.points_m,
                res.duration_s,
                res.admittance
                    .map(|(c, b)| admittance_gain(c, b, res.mean_speed_m_s)),
            )
            .map_err(|e| format!("turbulence: {e}"))?,
        };
        let layout = WindLayout::of(&res);
        Ok(WindFmu {
            x: vec![PARKED_X; res.n_vehicles],
            outputs: vec![0.0; layout.n_outputs()],
            layout: Arc::new(layout),
            deck_field: Arc::new(admitted.unwrap_or_else(|| field.clone())),
            field: Arc::new(field),
            guid,
            t: 0.0,
            start_time: 0.0,
            dirty: true,
        })
    }

    /// The dependencies `<ModelStructure>` declares ([`fmi_export::dependencies`]), probed
    /// with every car body on the deck: the wind at a car body depends on its position (at
    /// a communication point and in initialisation), the wind at the deck points on nothing.
    pub fn dependencies(res: &WindResources) -> Result<fmi_export::dependencies::Declared, String> {
        use fmi_export::dependencies::{probe, Declared};
        let mut m = WindFmu::from_parts(res.clone(), String::new())?;
        let l = m.layout.clone();
        let knowns = l.body_in.all_vrs();
        let mut outputs = l.deck_out.all_vrs();
        outputs.extend(l.body_out.all_vrs());
        let (a, b) = match (res.points_m.first(), res.points_m.last()) {
            (Some(a), Some(b)) => (*a, *b),
            _ => return Err("no deck points".into()),
        };
        let n = res.n_vehicles.max(1) as f64;
        let set = |m: &mut WindFmu, phase| -> Result<(), String> {
            for i in 0..l.body_in.count {
                // between deck points, away from them (the field is linear in between)
                let x = a + (b - a) * (i as f64 + 0.37) / n;
                m.set_real(l.body_in.vr(i, 0), x, phase)?;
            }
            Ok(())
        };
        let spacing = (b - a) / res.points_m.len().max(2) as f64;
        let delta = |_: u32, _: f64| 1e-3 * spacing;
        set(&mut m, Phase::Initialization)?;
        let initial = probe(&mut m, &knowns, &outputs, Phase::Initialization, delta)?;
        m.exit_initialization()?;
        m.do_step(0.0, 0.013)?;
        set(&mut m, Phase::Stepping)?;
        let stepping = probe(&mut m, &knowns, &outputs, Phase::Stepping, delta)?;
        Ok(Declared {
            outputs: outputs.iter().copied().zip(stepping).collect(),
            initial: outputs.iter().copied().zip(initial).collect(),
        })
    }

    fn refresh(&mut self) {
        if !self.dirty {
            return;
        }
        let l = &self.layout;
        let f = &self.field;
        let d = &self.deck_field;
        let when = d.time_index(self.t);
        for j in 0..l.deck_out.count {
            let uw = d.at_point(j, when);
            self.outputs[l.deck_out.slots(j)].copy_from_slice(&uw);
        }
        for (i, &x) in self.x.iter().enumerate() {
            let uw = f.at(x, self.t);
            self.outputs[l.body_out.slots(i)].copy_from_slice(&uw);
        }
        self.dirty = false;
    }
}

impl FmuModel for WindFmu {
    fn instantiate(resources: &Path, _log: &dyn Log) -> Result<Self, ModelError> {
        let path = resources.join(WIND_RESOURCE);
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let res: WindResources = serde_json::from_slice(&bytes)
            .map_err(|e| format!("{}: line {}: {e}", path.display(), e.line()))?;
        let guid = guid_for(&bytes);
        WindFmu::from_parts(res, guid)
            .map_err(|e| ModelError::Resources(format!("{}: {e}", path.display())))
    }

    fn guid(&self) -> String {
        self.guid.clone()
    }

    fn setup_experiment(
        &mut self,
        start_time: f64,
        _stop_time: Option<f64>,
    ) -> Result<(), ModelError> {
        self.start_time = start_time;
        self.t = start_time;
        self.dirty = true;
        Ok(())
    }

    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        self.t = self.start_time;
        self.dirty = true;
        Ok(())
    }

    fn set_real(&mut self, vr: u32, value: f64, _phase: Phase) -> Result<(), ModelError> {
        let Some(WindVar::Body(i)) = self.layout.decode(vr) else {
            return Err(ModelError::Refused(format!(
                "value reference {vr} is not an input of the wind FMU"
            )));
        };
        if !value.is_finite() {
            return Err(ModelError::Refused(format!(
                "input {} = {value} is not finite",
                self.layout.body_in.name(i, 0)
            )));
        }
        self.x[i] = value;
        self.dirty = true;
        Ok(())
    }

    fn get_real(&mut self, vr: u32) -> Result<f64, ModelError> {
        match self.layout.decode(vr) {
            Some(WindVar::Body(i)) => Ok(self.x[i]),
            Some(WindVar::Output(slot)) => {
                self.refresh();
                Ok(self.outputs[slot])
            }
            None => Err(ModelError::UnknownVariable { kind: "Real", vr }),
        }
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        self.t = t + h;
        self.dirty = true;
        Ok(StepOutcome::Ok)
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        self.t = self.start_time;
        self.x.iter_mut().for_each(|x| *x = PARKED_X);
        self.dirty = true;
        Ok(())
    }

    fn serialize_state(&self) -> Vec<u8> {
        serde_json::to_vec(&Saved {
            t: self.t,
            start_time: self.start_time,
            x: self.x.clone(),
        })
        .expect("state serialises")
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        let s: Saved = serde_json::from_slice(bytes).map_err(|e| format!("wind state: {e}"))?;
        if s.x.len() != self.x.len() {
            return Err("wind state does not match this FMU's size".into());
        }
        self.t = s.t;
        self.start_time = s.start_time;
        self.x = s.x;
        self.dirty = true;
        Ok(())
    }
}
