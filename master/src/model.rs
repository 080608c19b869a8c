//! From a scenario to the objects the solvers integrate: the modal bridge, the train, the
//! track irregularity, the probes and the time grid.

use crate::scenario::Scenario;
use std::sync::Arc;
use tbi_dynamics::bridge::{ModalBridge, ModeSet, SimplySupported};
use tbi_dynamics::interface::TrainSpec;
use tbi_dynamics::train::Train;
use tbi_dynamics::InputError;
use tbi_track::{HuntingParams, Irregularity};

/// Everything a solver needs.
#[derive(Debug, Clone)]
pub struct Model {
    pub name: String,
    pub bridge: ModalBridge,
    pub train: Train,
    pub track: Arc<Irregularity>,
    /// Probe names and positions, m.
    pub probes: Vec<(String, f64)>,
    /// Time step, s.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Write every n-th step.
    pub output_every: usize,
    /// Hunting parameters (kept for the FMU export).
    pub hunting: HuntingParams,
    /// The train description (kept for the FMU export).
    pub axles: TrainSpec,
}

impl Model {
    /// Simulated end time, s.
    pub fn t_end(&self) -> f64 {
        self.steps as f64 * self.dt
    }
}

/// Build the bridge of a scenario.
pub fn build_bridge(s: &Scenario) -> Result<ModalBridge, InputError> {
    let b = &s.bridge;
    let tors = b.damping_ratio_torsional.unwrap_or(b.damping_ratio);
    match b.kind.as_str() {
        "simply_supported" => Ok(SimplySupported {
            span_m: b.span_m.unwrap_or_default(),
            youngs_modulus_pa: b.youngs_modulus_pa.unwrap_or_default(),
            inertia_vertical_m4: b.inertia_vertical_m4.unwrap_or_default(),
            inertia_lateral_m4: b.inertia_lateral_m4,
            shear_modulus_pa: b.shear_modulus_pa,
            torsion_constant_m4: b.torsion_constant_m4,
            polar_inertia_kg_m: b.polar_inertia_kg_m,
            mass_per_length_kg_m: b.mass_per_length_kg_m.unwrap_or_default(),
            modes: b.modes,
            damping_ratio: b.damping_ratio,
            damping_ratio_torsional: tors,
            e_m: b.track_eccentricity_m.unwrap_or(0.0),
            h4_m: b.track_height_m.unwrap_or(0.0),
            x_start_m: b.x_start_m.unwrap_or(0.0),
        }
        .modal()),
        "modal_file" => {
            let rel = b.path.as_ref().expect("validated: path is set");
            let path = s.base_dir.join(rel);
            let set = ModeSet::read(&path).map_err(|e| {
                InputError::field(
                    &s.origin,
                    "bridge.path",
                    format!("\"{}\"", rel.display()),
                    e.to_string(),
                )
            })?;
            modal_from_set(s, &set, &path.display().to_string(), 0.0, 0.0)
        }
        "suspension" => {
            let set =
                crate::suspension::preset_modes(b.preset.as_deref().unwrap_or("tsing-ma"), b.modes)
                    .map_err(|e| {
                        InputError::field(
                            &s.origin,
                            "bridge.preset",
                            b.preset.clone().unwrap_or_default(),
                            e,
                        )
                    })?;
            modal_from_set(s, &set, "built-in suspension model", 2.05, 1.25)
        }
        other => Err(InputError::field(
            &s.origin,
            "bridge.kind",
            other,
            "unknown kind",
        )),
    }
}

fn modal_from_set(
    s: &Scenario,
    set: &ModeSet,
    source: &str,
    e_default: f64,
    h4_default: f64,
) -> Result<ModalBridge, InputError> {
    let b = &s.bridge;
    if b.modes > set.modes.len() {
        return Err(InputError::field(
            &s.origin,
            "bridge.modes",
            b.modes,
            format!("{source} has only {} modes", set.modes.len()),
        ));
    }
    Ok(set.to_modal(
        b.modes,
        b.damping_ratio,
        b.damping_ratio_torsional.unwrap_or(b.damping_ratio),
        b.track_eccentricity_m.unwrap_or(e_default),
        b.track_height_m.unwrap_or(h4_default),
        b.interpolation_points.unwrap_or(4),
    ))
}

/// Build everything.
pub fn build(s: &Scenario) -> Result<Model, InputError> {
    let bridge = build_bridge(s)?;
    for (i, p) in s.probes.iter().enumerate() {
        if !bridge.on_deck(p.x_m) {
            return Err(InputError::field(
                &s.origin,
                format!("probe[{i}].x_m"),
                p.x_m,
                format!(
                    "probe \"{}\" is off the bridge (the deck spans {} to {} m)",
                    p.name, bridge.x_start_m, bridge.x_end_m
                ),
            ));
        }
    }
    let axles = s.train_axles()?;
    let hunting_params = s.train.hunting.clone().unwrap_or_default();
    let speed = s.speed_m_s();
    let x0 = s.run.start_x_m.unwrap_or(bridge.x_start_m);
    let train = axles
        .build(speed, x0, &hunting_params)
        .map_err(|e| InputError::field(&s.origin, "train", &s.train.kind, &e))?;
    let length = train.length_m();
    let t_end = (bridge.x_end_m - x0 + length).max(0.0) / speed + s.run.free_vibration_s;
    let steps = (t_end / s.run.dt_s - 1e-9).ceil().max(1.0) as usize;
    let x_lo = x0 - length - 1.0;
    let x_hi = x0 + speed * steps as f64 * s.run.dt_s + 1.0;
    let track = s
        .track
        .irregularity
        .build(x_lo, x_hi, &s.base_dir)
        .map_err(|e| {
            InputError::field(
                &s.origin,
                "track.irregularity",
                track_spec_text(&s.track.irregularity),
                e.to_string(),
            )
        })?;
    Ok(Model {
        name: s.name.clone(),
        bridge,
        train,
        track: Arc::new(track),
        probes: s.probes.iter().map(|p| (p.name.clone(), p.x_m)).collect(),
        dt: s.run.dt_s,
        steps,
        output_every: s.run.output_every,
        hunting: hunting_params,
        axles,
    })
}

/// The irregularity spec as a user wrote it (for messages).
fn track_spec_text(spec: &tbi_track::IrregularitySpec) -> String {
    match spec {
        tbi_track::IrregularitySpec::None => "\"none\"".into(),
        tbi_track::IrregularitySpec::Record(r) => format!("{{ file = \"{}\" }}", r.file.display()),
        tbi_track::IrregularitySpec::Generated(g) => format!(
            "{{ spectrum = \"{}\", seed = {}, lambda_min_m = {}, lambda_max_m = {} }}",
            g.spectrum, g.seed, g.lambda_min_m, g.lambda_max_m
        ),
    }
}
