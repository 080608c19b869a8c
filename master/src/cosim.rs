//! Co-simulation of the bridge and train FMUs through the FMI 2.0 C ABI.
//!
//! The scenario's FMUs are exported (or reused) in `<out>/fmus`, loaded with the importer,
//! wired along [`crate::export::connections`] and advanced by the configured coupling
//! scheme. The bridge comes first in the sweep, so the iterated interface (the feedback
//! connections) is what the train sends to the bridge: wheelset positions, speeds and
//! forces. Every step's outputs fill the same [`Sample`] as the monolithic solver.

use crate::coupling::{
    advance, build_scheme, CouplingConfig, CouplingError, CouplingStatistics, Participant,
    StepStatus, System,
};
use crate::export::{Exported, Side};
use crate::model::Model;
use crate::summary::CouplingSummary;
use fmi_import::{Fmu, FmuState, Instance, InstantiateOptions, StepResult};
use fmu_bridge::layout::probe_values;
use model_description::VariableKind;
use std::collections::HashMap;
use std::path::Path;
use tbi_dynamics::interface::wheel;
use tbi_dynamics::response::{Recorder, Sample};

/// An FMU instance as a coupling participant, with one rollback slot.
pub struct FmuParticipant {
    pub inst: Instance,
    saved: Option<FmuState>,
    /// Declared unit of each Real variable, by value reference.
    units: HashMap<u32, String>,
}

impl FmuParticipant {
    /// Wrap an instance of `fmu`; the units of its Real variables come from its model
    /// description.
    pub fn new(fmu: &Fmu, inst: Instance) -> Self {
        let units = fmu
            .model_description()
            .model_variables
            .iter()
            .filter_map(|v| match &v.kind {
                VariableKind::Real(r) => r.attributes.unit.clone().map(|u| (v.value_reference, u)),
                _ => None,
            })
            .collect();
        FmuParticipant {
            inst,
            saved: None,
            units,
        }
    }
}

fn cerr(e: impl std::fmt::Display) -> CouplingError {
    CouplingError::new(e.to_string())
}

impl Participant for FmuParticipant {
    fn name(&self) -> &str {
        self.inst.name()
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
        self.inst.set_real(vrs, values).map(|_| ()).map_err(cerr)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
        self.inst.get_real(vrs, values).map(|_| ()).map_err(cerr)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError> {
        match self.inst.do_step(t, h, false).map_err(cerr)? {
            StepResult::Discard => Ok(StepStatus::Discard),
            _ => Ok(StepStatus::Ok),
        }
    }
    fn save_state(&mut self) -> Result<(), CouplingError> {
        let s = self.inst.get_fmu_state(self.saved.take()).map_err(cerr)?;
        self.saved = Some(s);
        Ok(())
    }
    fn restore_state(&mut self) -> Result<(), CouplingError> {
        let s = self
            .saved
            .as_ref()
            .ok_or_else(|| CouplingError::new(format!("{}: no saved state", self.inst.name())))?;
        self.inst.set_fmu_state(s).map(|_| ()).map_err(cerr)
    }
    fn unit(&self, vr: u32) -> Option<&str> {
        self.units.get(&vr).map(String::as_str)
    }
}

/// Value reference of a variable by name.
fn vr_map(fmu: &Fmu) -> HashMap<String, u32> {
    fmu.model_description()
        .model_variables
        .iter()
        .map(|v| (v.name.clone(), v.value_reference))
        .collect()
}

/// Load, instantiate and initialise both FMUs of an export, wired along
/// [`crate::export::connections`]; returns the system (bridge 0, train 1) ready for
/// stepping at t = 0.
pub fn build_system(exported: &Exported, stop: f64) -> Result<System, Box<dyn std::error::Error>> {
    let bfmu = Fmu::load(&exported.bridge)?;
    let tfmu = Fmu::load(&exported.train)?;
    let opts = |name: &str| InstantiateOptions {
        instance_name: Some(name.to_string()),
        visible: false,
        logging_on: false,
        echo_log: true,
    };
    let mut b = bfmu.instantiate(&opts("bridge"))?;
    let mut t = tfmu.instantiate(&opts("train"))?;
    let (bm, tm) = (vr_map(&bfmu), vr_map(&tfmu));
    let links = crate::export::connections(&exported.bridge_layout, &exported.train_layout)?;
    let mut connections = Vec::with_capacity(links.len());
    for link in links {
        // The packaged descriptions must say what the layouts say.
        for (side, vr) in [(link.from, link.from_vr), (link.to, link.to_vr)] {
            let map = if side == Side::Bridge { &bm } else { &tm };
            match map.get(&link.name) {
                Some(&declared) if declared == vr => {}
                declared => {
                    return Err(format!(
                        "{}.fmu: {} has value reference {declared:?}, its layout says {vr}",
                        side.name(),
                        link.name
                    )
                    .into())
                }
            }
        }
        connections.push(crate::coupling::Connection {
            from: link.from as usize,
            from_vr: link.from_vr,
            to: link.to as usize,
            to_vr: link.to_vr,
        });
    }
    for inst in [&mut b, &mut t] {
        inst.setup_experiment(None, 0.0, Some(stop * (1.0 + 1e-12) + 1e-9))?;
        inst.enter_initialization_mode()?;
    }
    // Initial exchange in initialisation mode (outputs depend on inputs there): repeat until
    // the values settle (one pass when the train starts off the deck).
    let mut last: Vec<f64> = Vec::new();
    for _ in 0..50 {
        let mut values = Vec::with_capacity(connections.len());
        for c in &connections {
            let mut v = [0.0];
            let src = if c.from == 0 { &mut b } else { &mut t };
            src.get_real(&[c.from_vr], &mut v)?;
            let dst = if c.to == 0 { &mut b } else { &mut t };
            dst.set_real(&[c.to_vr], &v)?;
            values.push(v[0]);
        }
        if values == last {
            break;
        }
        last = values;
    }
    b.exit_initialization_mode()?;
    t.exit_initialization_mode()?;
    Ok(System {
        participants: vec![
            Box::new(FmuParticipant::new(&bfmu, b)),
            Box::new(FmuParticipant::new(&tfmu, t)),
        ],
        connections,
    })
}

/// Run the model by co-simulation of its two FMUs (exported into `fmu_dir`); returns the
/// `coupling` part of the summary.
pub fn run_cosim<W: std::io::Write>(
    cfg: &CouplingConfig,
    model: &Model,
    fmu_dir: &Path,
    rec: &mut Recorder<W>,
    show_progress: bool,
) -> Result<CouplingSummary, Box<dyn std::error::Error>> {
    let exported = crate::export::export_with(model, fmu_dir, false)?;
    let t_end = model.t_end();
    let mut sys = build_system(&exported, t_end)?;
    let mut scheme = build_scheme(cfg);
    scheme.initialize(&mut sys)?;
    let (bl, tl) = (&exported.bridge_layout, &exported.train_layout);
    let nv = tl.n_vehicles();
    let probe_vrs = bl.probe_out.vrs(&[0, 1, 2, 3, 4]);
    let force_vrs = tl.wheel_out.vrs(&[wheel::F_Y, wheel::M_X, wheel::F_Z]);
    let veh_vrs = tl.vehicle_out.vrs(&[0, 1]);
    let layout = rec.layout.clone();
    let sample_at = |sys: &mut System, t: f64| -> Result<Sample, CouplingError> {
        let mut pv = vec![0.0; probe_vrs.len()];
        let mut fv = vec![0.0; force_vrs.len()];
        let mut vv = vec![0.0; veh_vrs.len()];
        sys.participants[0].get_real(&probe_vrs, &mut pv)?;
        sys.participants[1].get_real(&force_vrs, &mut fv)?;
        sys.participants[1].get_real(&veh_vrs, &mut vv)?;
        Ok(Sample {
            t,
            probes: pv.chunks(bl.probe_out.width()).map(probe_values).collect(),
            vehicles: (0..nv)
                .map(|i| {
                    let has = layout.vehicles[i];
                    [has[0].then_some(vv[2 * i]), has[1].then_some(vv[2 * i + 1])]
                })
                .collect(),
            forces: fv
                .chunks(3)
                .map(|c| nalgebra::Vector3::new(c[0], c[1], c[2]))
                .collect(),
        })
    };
    rec.record(&sample_at(&mut sys, 0.0)?, true)?;
    let mut stats = CouplingStatistics::new();
    let pb = crate::progress::bar(model.steps, show_progress);
    let h = model.dt;
    for k in 1..=model.steps {
        let t = (k - 1) as f64 * h;
        crate::interrupt::check(t)?;
        let report = advance(scheme.as_mut(), &mut sys, t, h, cfg.policy(h))
            .map_err(|e| format!("co-simulation stopped at t = {t} s: {e}"))?;
        stats.record(&report);
        let t1 = k as f64 * h;
        rec.record(
            &sample_at(&mut sys, t1)?,
            k % model.output_every == 0 || k == model.steps,
        )?;
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(CouplingSummary {
        scheme: cfg.scheme.as_str().into(),
        acceleration: cfg.acceleration.as_str().into(),
        iterations_mean: stats.mean_iterations(),
        iterations_max: stats.max_iterations,
        steps: stats.steps,
        accepted_unconverged: stats.accepted_unconverged,
        rejected: stats.rejected,
        max_residual: stats.max_residual,
        bridge_fmu: exported.bridge.display().to_string(),
        train_fmu: exported.train.display().to_string(),
    })
}
