//! From a scenario to the objects the solvers integrate: the modal bridge, the train, the
//! track irregularity, the probes and the time grid.

pub mod modes;
pub mod suspension;
mod trains;

pub(crate) use trains::first_time;

use crate::scenario::{Bridge, ModalOptions, Scenario};
use crate::text::num;
use std::sync::Arc;
use tbi_dynamics::bridge::{ModalBridge, ModeSet};
use tbi_dynamics::train::Train;
use tbi_dynamics::train::TrainDescription;
use tbi_dynamics::InputError;
use tbi_track::Irregularity;

/// Everything a solver needs.
#[derive(Debug, Clone)]
pub struct Model {
    pub name: String,
    pub bridge: ModalBridge,
    /// The trains together as built from `trains` (monolithic solver, recorder).
    pub train: Train,
    /// Each train's description: what its train FMU carries and builds the same train from.
    pub trains: Vec<TrainDescription>,
    pub track: Arc<Irregularity>,
    /// Probe names and positions, m.
    pub probes: Vec<(String, f64)>,
    /// Time step, s.
    pub dt: f64,
    /// Number of steps.
    pub steps: usize,
    /// Write every n-th step.
    pub output_every: usize,
}

impl Model {
    /// Simulated end time, s.
    pub fn t_end(&self) -> f64 {
        self.steps as f64 * self.dt
    }

    /// The bytes of a `history.csv` row: a value that changes from step to step takes
    /// [`VALUE_BYTES`] (`{:e}` of an f64 and its comma); a moving force's wheelset columns
    /// hold the same five numbers at every step (no lateral force, moment and derail or
    /// offload factor, `0e0`, and the axle load).
    pub fn history_row_bytes(&self) -> f64 {
        let varying = 1.0
            + 5.0 * self.probes.len() as f64
            + self
                .train
                .vehicles
                .iter()
                .map(|v| {
                    f64::from(u8::from(v.model.body.lateral.is_some()))
                        + f64::from(u8::from(v.model.body.vertical.is_some()))
                })
                .sum::<f64>();
        let wheelsets: f64 = (self.trains.iter())
            .map(|t| match &t.spec {
                tbi_dynamics::train::TrainSpec::MovingForce(axles) => axles
                    .iter()
                    .map(|a| 16.0 + format!("{:e},", a.load_n).len() as f64)
                    .sum(),
                spec => 5.0 * VALUE_BYTES * spec.n_wheelsets() as f64,
            })
            .sum();
        varying * VALUE_BYTES + wheelsets
    }

    /// What a run of this model will cost, estimated before any step is taken.
    pub fn estimate(&self) -> Estimate {
        let steps = self.steps as f64;
        let nw = self.train.n_wheelsets() as f64;
        let nv = self.train.vehicles.len() as f64;
        let nb = self.bridge.n_modes() as f64;
        let rows = steps / self.output_every as f64 + 1.0;
        Estimate {
            steps,
            history_bytes: rows * self.history_row_bytes(),
            // car-body acceleration histories (Sperling indices) and the per-step
            // mode-shape and interface arrays
            memory_bytes: 16.0 * nv * steps + 8.0 * 24.0 * nw * nb + 4096.0 * (nw + nb),
        }
    }
}

/// The bytes of a value in `history.csv` that changes from step to step (`{:e}` of an f64,
/// e.g. `-7.253234597970186e-3`, and its comma).
pub const VALUE_BYTES: f64 = 22.0;

/// The cost of a run, estimated from the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub steps: f64,
    /// Size of `history.csv`, bytes.
    pub history_bytes: f64,
    /// Memory that grows with the run, bytes.
    pub memory_bytes: f64,
}

/// What a run may cost before it is refused (override: `--allow-large`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Time steps. Default 10 million.
    pub max_steps: f64,
    /// `history.csv` size, bytes. Default 2 GiB.
    pub max_history_bytes: f64,
    /// Memory growing with the run, bytes. Default 4 GiB.
    pub max_memory_bytes: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_steps: 1e7,
            max_history_bytes: 2.0 * (1u64 << 30) as f64,
            max_memory_bytes: 4.0 * (1u64 << 30) as f64,
        }
    }
}

impl Limits {
    /// No limits (`--allow-large`).
    pub fn none() -> Limits {
        Limits {
            max_steps: f64::INFINITY,
            max_history_bytes: f64::INFINITY,
            max_memory_bytes: f64::INFINITY,
        }
    }

    /// Refuse a run whose estimate passes a limit, naming the scenario fields behind it.
    pub fn check(&self, s: &Scenario, e: &Estimate) -> Result<(), InputError> {
        let mib = |b: f64| format!("{:.0} MiB", b / (1u64 << 20) as f64);
        let refuse = |what: String| {
            InputError::field(
                &s.origin,
                "run",
                format!(
                    "speed_kmh = {}, dt_s = {}, output_every = {}",
                    num(s.run.speed_kmh),
                    num(s.run.dt_s),
                    s.run.output_every
                ),
                format!("{what}; give --allow-large to run it anyway"),
            )
        };
        if e.steps > self.max_steps {
            return Err(refuse(format!(
                "the run would take {:.3e} time steps, more than the limit of {:.0e}",
                e.steps, self.max_steps
            )));
        }
        if e.history_bytes > self.max_history_bytes {
            return Err(refuse(format!(
                "history.csv would grow to about {}, more than the limit of {} (raise run.output_every)",
                mib(e.history_bytes),
                mib(self.max_history_bytes)
            )));
        }
        if e.memory_bytes > self.max_memory_bytes {
            return Err(refuse(format!(
                "the run would need about {} of memory, more than the limit of {}",
                mib(e.memory_bytes),
                mib(self.max_memory_bytes)
            )));
        }
        Ok(())
    }
}

/// The nodal modes of a bridge given by nodal modes (`None` for analytic kinds).
pub fn nodal_modes(s: &Scenario) -> Result<Option<(ModeSet, &ModalOptions, String)>, InputError> {
    match &s.bridge {
        Bridge::SimplySupported(_) => Ok(None),
        Bridge::ModalFile {
            path,
            resolved,
            modal,
        } => {
            let set = ModeSet::read(resolved).map_err(|e| {
                InputError::field(
                    &s.origin,
                    "bridge.path",
                    format!("\"{}\"", path.display()),
                    e.to_string(),
                )
            })?;
            Ok(Some((set, modal, resolved.display().to_string())))
        }
        Bridge::Beam {
            beam,
            x_start_m,
            modal,
        } => {
            let mut set = beam.modes(modal.modes).map_err(|e| {
                InputError::field(
                    &s.origin,
                    "bridge.spans_m",
                    format!("{:?}", beam.spans_m),
                    e.to_string(),
                )
            })?;
            set.x_m.iter_mut().for_each(|x| *x += x_start_m);
            Ok(Some((set, modal, "continuous beam".into())))
        }
        Bridge::Suspension { preset, modal } => {
            let set = crate::model::suspension::preset_modes(*preset, modal.modes)
                .map_err(|e| InputError::field(&s.origin, "bridge.preset", preset.name(), e))?;
            Ok(Some((set, modal, "built-in suspension model".into())))
        }
    }
}

/// The bridge's modes as the scenario keeps them: the `bridge.modes` lowest, then those
/// [`crate::scenario::ModesRule`] keeps. The modes are computed once (an FE or file
/// source's mode set is truncated, not solved again).
pub fn build_bridge(s: &Scenario) -> Result<ModalBridge, InputError> {
    let Some((set, o, source)) = nodal_modes(s)? else {
        let Bridge::SimplySupported(b) = &s.bridge else {
            unreachable!("nodal_modes covers the other kinds")
        };
        let all = b.modal();
        let kept = modes_kept(s, &all.frequencies_hz);
        if kept == all.n_modes() {
            return Ok(all);
        }
        let mut fewer = b.clone();
        fewer.modes = kept;
        return Ok(fewer.modal());
    };
    if o.modes > set.modes.len() {
        return Err(InputError::field(
            &s.origin,
            "bridge.modes",
            o.modes,
            format!("{source} has only {} modes", set.modes.len()),
        ));
    }
    let f: Vec<f64> = set.modes[..o.modes]
        .iter()
        .map(|m| m.frequency_hz)
        .collect();
    Ok(ModalBridge::from_mode_set(
        &set,
        modes_kept(s, &f),
        o.damping_ratio,
        o.damping_ratio_torsional,
        o.track_eccentricity_m,
        o.track_height_m,
        o.interpolation_points,
    ))
}

/// How many of the modes of frequencies `f` the scenario's modes rule keeps: all, or those
/// up to max(30 Hz, 1.5 f₁, f₃) when they are in ascending order.
fn modes_kept(s: &Scenario, f: &[f64]) -> usize {
    let ascending = f.windows(2).all(|w| w[0] <= w[1]);
    if s.modes_rule == crate::scenario::ModesRule::All || !ascending {
        return f.len();
    }
    tbi_dynamics::en1991::modes_considered(f).0.min(f.len())
}

/// Build everything.
pub fn build(s: &Scenario) -> Result<Model, InputError> {
    let mut bridge = build_bridge(s)?;
    if let Some(w) = &s.wind {
        bridge.steady_modal_force = bridge.uniform_load(w.deck_load());
        let d = w.deck();
        if let (Some(table), true) = (&d.flutter, w.mean_speed_m_s > 0.0) {
            tbi_dynamics::bridge::aeroelastic::apply(
                &mut bridge,
                table,
                w.air_density_kg_m3,
                w.mean_speed_m_s,
                d.width_m,
            )
            .map_err(|e| InputError::field(&s.origin, "wind.deck.flutter", "", e))?;
        }
    }
    if let Some((n, f)) = bridge
        .frequencies_hz
        .iter()
        .enumerate()
        .find(|(_, f)| !(f.is_finite() && **f > 0.0))
    {
        return Err(InputError::field(
            &s.origin,
            "bridge",
            s.bridge.kind(),
            format!(
                "mode {} ({}) has the frequency {} Hz; the section data or modes file are not physical",
                n + 1,
                bridge.labels[n],
                num(*f)
            ),
        ));
    }
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
    if !s.tracks.is_empty() {
        [bridge.e_m, bridge.h4_m] = s.tracks[0];
        bridge.other_tracks = s.tracks[1..].to_vec();
    }
    let trains::Trains {
        descriptions: trains,
        train,
        last_leaves_s,
    } = trains::trains(s, &bridge)?;
    let t_end = last_leaves_s + s.run.free_vibration_s;
    // (saturates at usize::MAX for absurd inputs; Limits::check refuses those)
    let steps = (t_end / s.run.dt_s - 1e-9).ceil().max(1.0) as usize;
    // the stretch of track every axle runs over
    let t_last = steps as f64 * s.run.dt_s;
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (k, run) in train.runs.iter().enumerate() {
        for x in [0.0, train.length_m(k)] {
            for t in [0.0, t_last] {
                let at = run.x_at(x, t);
                (x_lo, x_hi) = (x_lo.min(at - 1.0), x_hi.max(at + 1.0));
            }
        }
    }
    let track = s.track.build(x_lo, x_hi, &s.base_dir).map_err(|e| {
        InputError::field(
            &s.origin,
            "track.irregularity",
            track_spec_text(&s.track),
            e.to_string(),
        )
    })?;
    if let Some(w) = s.wind.as_ref().filter(|w| w.is_turbulent()) {
        {
            let record = match &w.record {
                Some(path) => {
                    let file = s.base_dir.join(path);
                    let text = std::fs::read_to_string(&file).map_err(|e| {
                        InputError::field(&s.origin, "wind.record", path.display(), e.to_string())
                    })?;
                    let field = tbi_wind::record::parse(
                        &text,
                        &file.display().to_string(),
                        w.mean_speed_m_s,
                    )
                    .map_err(|e| {
                        InputError::field(&s.origin, "wind.record", path.display(), e.to_string())
                    })?;
                    Some(Arc::new(field))
                }
                None => None,
            };
            let d = w.deck();
            let spec = tbi_dynamics::bridge::buffeting::BuffetingSpec {
                mean_speed_m_s: w.mean_speed_m_s,
                air_density_kg_m3: w.air_density_kg_m3,
                width_m: d.width_m,
                coefficients: [d.drag, d.lift, d.moment],
                slopes: [d.drag_slope, d.lift_slope, d.moment_slope],
                turbulence: w.turbulence.clone().unwrap_or_default(),
                record,
                admittance: d.admittance,
                points: w.deck_points,
                duration_s: steps as f64 * s.run.dt_s,
            };
            // refused before any step (each solver generates the field when it starts)
            tbi_dynamics::bridge::buffeting::DeckBuffeting::check(&bridge, &spec)
                .map_err(|e| InputError::field(&s.origin, "wind.turbulence", "", e))?;
            bridge.buffeting = Some(spec);
        }
    }
    Ok(Model {
        name: s.name.clone(),
        bridge,
        train,
        trains,
        track: Arc::new(track),
        probes: s.probes.iter().map(|p| (p.name.clone(), p.x_m)).collect(),
        dt: s.run.dt_s,
        steps,
        output_every: s.run.output_every,
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
