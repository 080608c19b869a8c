//! Co-simulation of the bridge and train FMUs through the FMI 2.0 C ABI.
//!
//! The scenario's FMUs are exported (or reused) in `<out>/fmus`, loaded with the importer,
//! wired along [`crate::export::connections`] and advanced by the configured coupling
//! scheme. The bridge comes first in the sweep, so the iterated interface (the feedback
//! connections) is what the train sends to the bridge: wheelset positions, speeds and
//! forces. Every step's outputs fill the same [`Sample`] as the monolithic solver.

use crate::coupling::{
    advance_into, build_scheme, CouplingConfig, CouplingError, CouplingStatistics, Discrete,
    Participant, StepStatus, System,
};
use crate::model::Model;
use crate::summary::CouplingSummary;
use fmi_import::{Fmu, FmuState, Instance, StepResult};
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
    /// Name of each Real variable, by value reference (for messages).
    names: HashMap<u32, String>,
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
        let names = fmu
            .model_description()
            .model_variables
            .iter()
            .filter(|v| matches!(v.kind, VariableKind::Real(_)))
            .map(|v| (v.value_reference, v.name.clone()))
            .collect();
        FmuParticipant {
            inst,
            saved: None,
            units,
            names,
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
    /// The importer's `get_real` refuses a value that is not finite, naming the variable.
    fn get_real_refuses_non_finite(&self) -> bool {
        true
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
    fn variable_name(&self, vr: u32) -> Option<String> {
        self.names.get(&vr).cloned()
    }
    fn exit_initialization(&mut self) -> Result<(), CouplingError> {
        self.inst
            .exit_initialization_mode()
            .map(drop)
            .map_err(|e| CouplingError::new(e.to_string()))
    }
    fn get_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<(), CouplingError> {
        for (&vr, v) in vrs.iter().zip(values) {
            *v = crate::ssp::get_discrete(&mut self.inst, kind, vr).map_err(CouplingError::new)?;
        }
        Ok(())
    }
    fn set_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<(), CouplingError> {
        for (&vr, &v) in vrs.iter().zip(values) {
            crate::ssp::set_discrete(&mut self.inst, kind, vr, v).map_err(CouplingError::new)?;
        }
        Ok(())
    }
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
    // One co-simulation code path: the FMUs are run as the exported SSP system (its
    // description, with the FMUs written beside the archive), as `tbi cosim system.ssp`
    // runs it.
    let exported = crate::export::export_with(model, cfg, fmu_dir, true)?;
    let t_end = model.t_end();
    let open = crate::ssp::open_exported(&exported.ssd, &exported.ssp)?;
    let mut sys = crate::ssp::wire(&open, &[], 0.0, t_end)?.system;
    let mut scheme = build_scheme(cfg);
    scheme.initialize(&mut sys)?;
    let (bl, tl) = (&exported.bridge_layout, &exported.train_layout);
    let nv = tl.n_vehicles();
    let probe_vrs = bl.probe_out.vrs(&[0, 1, 2, 3, 4]);
    let force_vrs = tl.wheel_out.vrs(&[wheel::F_Y, wheel::M_X, wheel::F_Z]);
    let veh_vrs = tl.vehicle_out.vrs(&[0, 1]);
    let layout = rec.layout.clone();
    // One sample and its read buffers, refilled at every step (no allocation per step).
    let (mut pv, mut fv, mut vv) = (
        vec![0.0; probe_vrs.len()],
        vec![0.0; force_vrs.len()],
        vec![0.0; veh_vrs.len()],
    );
    let mut sample = Sample::default();
    let mut sample_at =
        |sys: &mut System, t: f64, sample: &mut Sample| -> Result<(), CouplingError> {
            use crate::export::Side;
            sys.participants[Side::Bridge as usize].get_real(&probe_vrs, &mut pv)?;
            sys.participants[Side::Train as usize].get_real(&force_vrs, &mut fv)?;
            sys.participants[Side::Train as usize].get_real(&veh_vrs, &mut vv)?;
            sample.t = t;
            sample.probes.clear();
            sample
                .probes
                .extend(pv.chunks(bl.probe_out.width()).map(probe_values));
            sample.vehicles.clear();
            sample.vehicles.extend((0..nv).map(|i| {
                let has = layout.vehicles[i];
                [has[0].then_some(vv[2 * i]), has[1].then_some(vv[2 * i + 1])]
            }));
            sample.forces.clear();
            sample.forces.extend(
                fv.chunks(3)
                    .map(|c| nalgebra::Vector3::new(c[0], c[1], c[2])),
            );
            Ok(())
        };
    sample_at(&mut sys, 0.0, &mut sample)?;
    rec.record(&sample, true)?;
    let mut stats = CouplingStatistics::new();
    let mut report = crate::coupling::AdvanceReport::default();
    let pb = crate::progress::bar(model.steps, show_progress);
    let h = model.dt;
    for k in 1..=model.steps {
        let t = (k - 1) as f64 * h;
        crate::interrupt::check(t)?;
        advance_into(scheme.as_mut(), &mut sys, t, h, cfg.policy(h), &mut report)
            .map_err(|e| format!("co-simulation stopped at t = {t} s: {e}"))?;
        stats.record(&report);
        let t1 = k as f64 * h;
        sample_at(&mut sys, t1, &mut sample)?;
        rec.record(&sample, k % model.output_every == 0 || k == model.steps)?;
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
        steps_by_iterations: stats.steps_by_iterations.clone(),
        steps: stats.steps,
        accepted_unconverged: stats.accepted_unconverged,
        rejected: stats.rejected,
        max_residual: stats.max_residual,
        jacobian_probes: stats.jacobian_probes,
        bridge_fmu: exported.bridge.display().to_string(),
        train_fmu: exported.train.display().to_string(),
    })
}
