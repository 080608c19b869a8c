//! Co-simulation of the bridge and train FMUs through the FMI 2.0 C ABI.
//!
//! The scenario's FMUs are exported (or reused) in `<out>/fmus`, loaded with the importer,
//! wired along [`crate::fmus::ssd::connections`] and advanced by the configured coupling
//! scheme. The bridge comes first in the sweep, so the iterated interface (the feedback
//! connections) is what the train sends to the bridge: wheelset positions, speeds and
//! forces. Every step's outputs fill the same [`Sample`] as the monolithic solver.

use crate::model::Model;
use crate::output::summary::CouplingSummary;
use fmu_bridge::layout::probe_values;
use fmu_contract::wheel;
use std::path::Path;
use tbi_coupling::{
    advance_into, build_scheme, CouplingConfig, CouplingError, CouplingStatistics, System,
};
use tbi_dynamics::response::{Recorder, Sample};

/// Run the model by co-simulation of its two FMUs (exported into `fmu_dir` as FMI
/// `version` 2 or 3); returns the `coupling` part of the summary.
pub fn run_cosim<W: std::io::Write>(
    cfg: &CouplingConfig,
    model: &Model,
    (fmu_dir, version): (&Path, u8),
    rec: &mut Recorder<W>,
    show_progress: bool,
) -> Result<CouplingSummary, Box<dyn std::error::Error>> {
    // One co-simulation code path: the FMUs are run as the exported SSP system (its
    // description, with the FMUs written beside the archive), as `tbi cosim system.ssp`
    // runs it.
    let version = crate::fmus::export::FmiVersion::from_major(version)?;
    let exported = crate::fmus::export::export_with(model, cfg, fmu_dir, true, version)?;
    let t_end = model.t_end();
    let open = tbi_ssp::open_exported(&exported.ssd, &exported.ssp)?;
    let mut sys = tbi_ssp::wire(&open, &[], 0.0, t_end)?.system;
    let mut scheme = build_scheme(cfg)?;
    scheme.initialize(&mut sys)?;
    let bl = &exported.bridge_layout;
    let trains: Vec<&fmu_train::layout::TrainLayout> = std::iter::once(&exported.train_layout)
        .chain(exported.more_trains.iter().map(|t| &t.layout))
        .collect();
    let probe_vrs = bl.probe_out.vrs(&[0, 1, 2, 3, 4]);
    // per train: its participant, its wheel forces' and car bodies' value references
    let reads: Vec<(usize, Vec<u32>, Vec<u32>)> = (trains.iter().enumerate())
        .map(|(k, tl)| {
            (
                crate::fmus::ssd::Side::Train(k).index(trains.len()),
                tl.wheel_out.vrs(&[wheel::F_Y, wheel::M_X, wheel::F_Z]),
                tl.vehicle_out.vrs(&[0, 1]),
            )
        })
        .collect();
    let layout = rec.layout.clone();
    // One sample and its read buffers, refilled at every step (no allocation per step).
    let (mut pv, mut fv, mut vv) = (vec![0.0; probe_vrs.len()], Vec::new(), Vec::new());
    let mut sample = Sample::default();
    let mut sample_at =
        |sys: &mut System, t: f64, sample: &mut Sample| -> Result<(), CouplingError> {
            sys.participants[0].get_real(&probe_vrs, &mut pv)?;
            sample.t = t;
            sample.probes.clear();
            sample
                .probes
                .extend(pv.chunks(bl.probe_out.width()).map(probe_values));
            sample.vehicles.clear();
            sample.forces.clear();
            for (p, force_vrs, veh_vrs) in &reads {
                fv.resize(force_vrs.len(), 0.0);
                vv.resize(veh_vrs.len(), 0.0);
                sys.participants[*p].get_real(force_vrs, &mut fv)?;
                sys.participants[*p].get_real(veh_vrs, &mut vv)?;
                let first = sample.vehicles.len();
                sample.vehicles.extend((0..vv.len() / 2).map(|i| {
                    let has = layout.vehicles[first + i];
                    [has[0].then_some(vv[2 * i]), has[1].then_some(vv[2 * i + 1])]
                }));
                sample.forces.extend(
                    fv.chunks(3)
                        .map(|c| nalgebra::Vector3::new(c[0], c[1], c[2])),
                );
            }
            Ok(())
        };
    sample_at(&mut sys, 0.0, &mut sample)?;
    rec.record(&sample, true)?;
    let mut stats = CouplingStatistics::new();
    let mut report = tbi_coupling::AdvanceReport::default();
    let pb = crate::output::progress::bar(model.steps, show_progress);
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
