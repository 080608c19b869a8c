//! Scenario files (TOML): what to simulate. Every key, its unit, default and range:
//! `docs/scenario.md` (the one reference; a test holds it to the keys these structs accept).
//!
//! Unknown keys are refused; every check names the file, the field and the value.
//!
//! # Two layers
//!
//! The file is read into private `File…` structs that mirror the TOML (a `kind` string and
//! the optional keys of every kind), so that serde's errors keep their line. [`Scenario`]
//! is what the rest of the tool sees: every field checked once, here, and the kinds as
//! enums ([`Bridge`], [`TrainSpec`]) that carry exactly the data of their kind. The train
//! speed is checked by [`Speed::from_m_s`] alone, also for `--speed-kmh` and `tbi sweep`:
//! TOML → [`Scenario::from_toml`] → `Check::run` → [`Speed::from_m_s`] →
//! [`crate::model::build`] → [`TrainDescription::build`](tbi_dynamics::train::TrainDescription::build)
//! → [`Train::x_at`](tbi_dynamics::train::Train::x_at).

mod bridge;
mod check;
pub mod examples;
mod file;
pub mod limits;
mod train;

use crate::text::num;
use check::Check;
use file::{with_suggestion, FileScenario};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;
use tbi_dynamics::bridge::SimplySupported;
use tbi_dynamics::train::Speed;
use tbi_dynamics::train::TrainSpec;
use tbi_dynamics::vehicle::simple::{AxleVehicle, MovingForceAxle};
use tbi_dynamics::InputError;
use tbi_track::{HuntingParams, IrregularitySpec};

/// The embedded default scenario: the paper's Tsing Ma case.
pub const DEFAULT_SCENARIO: &str = include_str!("../../scenarios/tsing-ma.toml");

/// The embedded meeting case (`tbi run --meeting`): the default case with a second train on
/// the other track, the two meeting at mid main span.
pub const MEETING_SCENARIO: &str = include_str!("../../scenarios/tsing-ma-meeting.toml");

/// A checked scenario.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Name used in reports and as the default output folder.
    pub name: String,
    pub run: Run,
    pub bridge: Bridge,
    /// The damping rule the bridge's damping ratio came from, if the scenario chose one.
    pub damping_rule: Option<DampingRule>,
    /// `bridge.modes_rule`: which of the `bridge.modes` computed the run keeps.
    pub modes_rule: ModesRule,
    /// The train, or the first of several (`[[train]]`): its speed and start are `run`'s.
    pub train: Train,
    /// The trains after the first, on the deck at the same time.
    pub more_trains: Vec<Train>,
    /// `[[bridge.track]]`: each track's `(eccentricity, height)` on the deck, m (empty: one
    /// track, at the bridge's `track_eccentricity_m` and `track_height_m`).
    pub tracks: Vec<[f64; 2]>,
    /// Track irregularity (paths relative to `base_dir`).
    pub track: IrregularitySpec,
    pub probes: Vec<Probe>,
    pub coupling: CouplingConfig,
    /// `[wind]`: the mean wind on the deck; None (off) by default.
    pub wind: Option<Wind>,
    /// Directory relative paths are resolved against (the scenario file's folder).
    pub base_dir: PathBuf,
    /// Where the scenario came from, for messages.
    pub origin: String,
}

/// `[wind]`: a steady mean wind of speed U normal to the bridge, blowing towards +y, on the
/// deck (per unit length at the shear centre, with the deck's steady coefficients at the mean
/// angle of attack): drag `q_y = ½ρU²B C_D` (+y), lift `½ρU²B C_L` upward (so
/// `q_z = −½ρU²B C_L`, z down), moment `m_x = ½ρU²B² C_M` about +x (leeward side down).
/// The bridge starts in its static response to these loads. On the car bodies of coaches
/// the same wind gives steady side force, lift and rolling moment from the yaw angle of the
/// relative wind ([`tbi_dynamics::vehicle::aero`]), with the coefficients of the deck or of
/// the ground by where each body is. `turbulence` buffets the deck and adds its along-wind
/// component at each car body to the mean.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wind {
    /// Mean wind speed U at deck level, m/s (≥ 0, at most 100).
    pub mean_speed_m_s: f64,
    /// Air density ρ, kg/m³. Default 1.225.
    #[serde(default = "default_air_density")]
    pub air_density_kg_m3: f64,
    /// The deck section's steady aerodynamics. Default: the suspension preset's (documented
    /// assumptions in [`DeckAero::tsing_ma`]); required for other bridges.
    pub deck: Option<DeckAero>,
    /// The car bodies' coefficients against the yaw angle of the relative wind (coaches;
    /// moving forces and sprung masses carry no wind load). Default: the assumed ones of
    /// [`tbi_dynamics::vehicle::aero::VehicleAero::default`].
    #[serde(default)]
    pub vehicle: tbi_dynamics::vehicle::aero::VehicleAero,
    /// The car bodies' coefficients while on the deck (its shielding by wind barriers, or its
    /// exposure); `vehicle` applies off the deck. Default: `vehicle` everywhere.
    pub vehicle_on_deck: Option<tbi_dynamics::vehicle::aero::VehicleAero>,
    /// Turbulence buffeting the deck (quasi-steady, [`tbi_dynamics::bridge::buffeting`]);
    /// None (steady wind only) by default. `turbulence = {}` takes the defaults of
    /// [`tbi_wind::Turbulence`].
    pub turbulence: Option<tbi_wind::Turbulence>,
    /// A measured record of the turbulence instead (CSV `time_s,x_m,u_m_s,w_m_s`, u and w
    /// about the mean U; [`tbi_wind::record`]), relative to the scenario's folder; read
    /// linearly between its points at the deck points, its end values beyond its ends.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<PathBuf>,
    /// Deck points the turbulence is generated at, equally spaced (2 … 2000). Default 200.
    #[serde(default = "default_deck_points")]
    pub deck_points: usize,
}

fn default_deck_points() -> usize {
    200
}

fn default_air_density() -> f64 {
    1.225
}

/// Steady aerodynamic coefficients of a deck section, referred to its width.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeckAero {
    /// Deck width B, m (> 0).
    pub width_m: f64,
    /// Drag coefficient C_D on B, along the wind, –.
    pub drag: f64,
    /// Lift coefficient C_L on B, upward, –. Default 0.
    #[serde(default)]
    pub lift: f64,
    /// Moment coefficient C_M on B², leeward side down, –. Default 0.
    #[serde(default)]
    pub moment: f64,
    /// Slope C_D′ of the drag coefficient with the angle of attack, per rad. Default 0.
    #[serde(default)]
    pub drag_slope: f64,
    /// Slope C_L′ of the lift coefficient, per rad. Default 0.
    #[serde(default)]
    pub lift_slope: f64,
    /// Slope C_M′ of the moment coefficient, per rad. Default 0.
    #[serde(default)]
    pub moment_slope: f64,
    /// Davenport's aerodynamic admittance constant c of the buffeting forces,
    /// `|χ|² = (2/λ²)(λ − 1 + e^(−λ))`, `λ = c f B / U` (about 7 for a deck; 0 < c ≤ 50);
    /// default none (the quasi-steady limit, χ = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admittance: Option<f64>,
    /// Flutter derivatives against the reduced velocity U/(fB): the self-excited forces,
    /// mode by mode ([`tbi_dynamics::bridge::aeroelastic`]). Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flutter: Option<tbi_dynamics::bridge::aeroelastic::FlutterDerivatives>,
}

impl DeckAero {
    /// The Tsing Ma deck as assumed here: B = 41 m (the deck's width); C_D = 0.14 on B, i.e.
    /// about 0.8 on the 7.3 m depth of the streamlined box-truss deck; C_L = C_M = 0 at zero
    /// angle of attack. Section-model measurements of this deck are published (L. D. Zhu,
    /// Y. L. Xu, F. Zhang, H. F. Xiang, "Tsing Ma bridge deck under skew winds — Part I:
    /// Aerodynamic coefficients", J. Wind Eng. Ind. Aerodyn. 90(7), 781–805, 2002, and its
    /// Part II on the flutter derivatives), but their values were not available to this
    /// tool: give them in `[wind] deck`.
    pub fn tsing_ma() -> DeckAero {
        DeckAero {
            width_m: 41.0,
            drag: 0.14,
            lift: 0.0,
            moment: 0.0,
            drag_slope: 0.0,
            lift_slope: 0.0,
            moment_slope: 0.0,
            admittance: None,
            flutter: None,
        }
    }
}

impl Wind {
    /// Whether the wind is turbulent (generated or recorded turbulence about a mean > 0).
    pub fn is_turbulent(&self) -> bool {
        (self.turbulence.is_some() || self.record.is_some()) && self.mean_speed_m_s > 0.0
    }

    /// The deck coefficients used (the given ones).
    pub fn deck(&self) -> DeckAero {
        self.deck.clone().expect("checked: a deck for a wind")
    }

    /// The steady load per unit length `(q_y, q_z, m_x)` on the deck at the shear centre,
    /// N/m, N/m (+ down), N·m/m.
    pub fn deck_load(&self) -> [f64; 3] {
        let d = self.deck();
        let qb = 0.5 * self.air_density_kg_m3 * self.mean_speed_m_s.powi(2) * d.width_m;
        [qb * d.drag, -qb * d.lift, qb * d.width_m * d.moment]
    }
}

/// `bridge.damping = { rule = "en1991-2", structure = "…", additional = true }`: the damping
/// ratio of EN 1991-2 Table 6.6 for the span (plus eq. 6.13 for spans under 30 m when
/// `additional`, the default), used for every mode ([`tbi_dynamics::en1991`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DampingRule {
    pub rule: String,
    pub structure: String,
    /// Table 6.6 lower limit, percent.
    pub minimum_percent: f64,
    /// Eq. (6.13) additional damping, percent (0 when not added).
    pub additional_percent: f64,
    /// The damping ratio used, –.
    pub ratio: f64,
}

/// `bridge.modes_rule`: which of the `bridge.modes` lowest modes a run keeps.
///
/// `"en1990"` keeps those up to max(30 Hz, 1.5 f₁, f₃), the frequencies EN 1990
/// A2.4.4.2.1 considers for the deck acceleration check (all of them when they are not in
/// ascending order); `"all"` keeps every one. Default: `"en1990"` for the EN 1991-2 trains
/// (`train.kind = "hslm_a"` or `"hslm_b"`), `"all"` for every other kind. `tbi run`,
/// `tbi sweep --trains` and the FMUs apply it alike, and `summary.json` reports it with the
/// modes kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModesRule {
    En1990,
    All,
}

impl ModesRule {
    pub fn as_str(self) -> &'static str {
        match self {
            ModesRule::En1990 => "en1990",
            ModesRule::All => "all",
        }
    }
}

/// Which solver runs the scenario.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    Monolithic,
    #[default]
    Cosim,
}

impl SolverKind {
    pub fn as_str(&self) -> &'static str {
        match self {
            SolverKind::Monolithic => "monolithic",
            SolverKind::Cosim => "cosim",
        }
    }

    /// `"monolithic"` or `"cosim"`.
    pub fn parse(s: &str) -> Option<SolverKind> {
        match s {
            "monolithic" => Some(SolverKind::Monolithic),
            "cosim" => Some(SolverKind::Cosim),
            _ => None,
        }
    }
}

/// `[run]`: speed, step and duration.
#[derive(Debug, Clone)]
pub struct Run {
    /// Train speed as written, km/h.
    pub speed_kmh: f64,
    /// The same speed, checked (m/s).
    pub speed: Speed,
    /// Time step, s (> 0). Default 0.001.
    pub dt_s: f64,
    /// Solver. Default `cosim`.
    pub solver: SolverKind,
    /// Simulated time after the last axle has left the bridge, s (≥ 0). Default 1.0.
    pub free_vibration_s: f64,
    /// Position of the first axle at t = 0, m. Default: the deck start (train on the approach).
    pub start_x_m: Option<f64>,
    /// Write every n-th step to `history.csv` (≥ 1). Default 1.
    pub output_every: usize,
    /// FMI version of the FMUs of `solver = "cosim"`: 2 (FMI 2.0) or 3 (FMI 3.0). Default 2.
    pub fmi_version: u8,
}

/// `[bridge]`, by kind.
#[derive(Debug, Clone)]
pub enum Bridge {
    /// `kind = "simply_supported"`: analytic sine modes of a prismatic span.
    SimplySupported(SimplySupported),
    /// `kind = "modal_file"`: modes from a file (`path`, as written and resolved).
    ModalFile {
        path: PathBuf,
        resolved: PathBuf,
        modal: ModalOptions,
    },
    /// `kind = "suspension"`: the built-in finite-element model of a preset.
    Suspension {
        preset: SuspensionPreset,
        modal: ModalOptions,
    },
    /// `kind = "beam"`: a prismatic beam continuous over `spans_m` (vertical bending, pinned
    /// supports), modes by the FE crate ([`tbi_fe::beam::ContinuousBeam`]).
    Beam {
        beam: tbi_fe::beam::ContinuousBeam,
        /// Position of the first support along the track, m. Default 0.
        x_start_m: f64,
        modal: ModalOptions,
    },
}

/// How a set of nodal modes becomes the modal bridge.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalOptions {
    /// Number of modes kept (≥ 1). Default 20.
    pub modes: usize,
    /// Damping ratio of lateral and vertical modes, –, in [0, 1). Default 0.
    pub damping_ratio: f64,
    /// Damping ratio of torsional modes, –, in [0, 1). Default: `damping_ratio`.
    pub damping_ratio_torsional: f64,
    /// Track eccentricity e from the shear centre (+y), m. Default 0 (suspension: 2.05).
    pub track_eccentricity_m: f64,
    /// Height h4 of the wheelset reference above the shear centre, m. Default 0
    /// (suspension: 1.25).
    pub track_height_m: f64,
    /// Lagrange interpolation points between nodes (2–8). Default 4.
    pub interpolation_points: usize,
}

/// Built-in suspension-bridge presets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SuspensionPreset {
    /// `"tsing-ma"`: the Tsing Ma Bridge (Hong Kong), the paper's case.
    TsingMa,
}

impl SuspensionPreset {
    pub const ALL: [SuspensionPreset; 1] = [SuspensionPreset::TsingMa];

    pub fn name(self) -> &'static str {
        match self {
            SuspensionPreset::TsingMa => "tsing-ma",
        }
    }

    pub fn parse(name: &str) -> Option<SuspensionPreset> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }
}

impl Bridge {
    /// The `kind` as written in scenarios.
    pub fn kind(&self) -> &'static str {
        match self {
            Bridge::SimplySupported(_) => "simply_supported",
            Bridge::ModalFile { .. } => "modal_file",
            Bridge::Suspension { .. } => "suspension",
            Bridge::Beam { .. } => "beam",
        }
    }

    /// Number of modes kept.
    pub fn modes(&self) -> usize {
        match self {
            Bridge::SimplySupported(b) => b.modes,
            Bridge::ModalFile { modal, .. }
            | Bridge::Suspension { modal, .. }
            | Bridge::Beam { modal, .. } => modal.modes,
        }
    }

    /// Keep the lowest `n` modes (`tbi sweep --trains` keeps those EN 1990 A2.4.4.2.1 asks for).
    pub fn set_modes(&mut self, n: usize) {
        match self {
            Bridge::SimplySupported(b) => b.modes = n,
            Bridge::ModalFile { modal, .. }
            | Bridge::Suspension { modal, .. }
            | Bridge::Beam { modal, .. } => modal.modes = n,
        }
    }
}

/// `[train]`: the vehicles by kind, and wheel hunting.
#[derive(Debug, Clone)]
pub struct Train {
    pub spec: TrainSpec,
    /// Wheel hunting; off by default.
    pub hunting: HuntingParams,
    /// The vehicle under each axle of an axle-load train (`train.vehicle`), which `spec`
    /// already applies; kept so that `tbi sweep --trains` puts it under other trains too.
    /// Default none (moving forces).
    pub axle_vehicle: Option<AxleVehicle>,
    /// The direction of travel: forward (+x, entering at the deck start, the default) or
    /// backward (−x, entering at the deck end).
    pub direction: tbi_dynamics::train::TravelDirection,
    /// The track it runs on, 0-based (`track = 1`, the first, by default).
    pub track: usize,
    /// Its speed at the start, km/h as written and checked (None: `run.speed_kmh`).
    pub speed: Option<(f64, Speed)>,
    /// Its first axle's position at t = 0, m (the first train: `run.start_x_m` too).
    pub start_x_m: Option<f64>,
    /// The time its first axle enters the deck, s (≥ 0).
    pub enter_time_s: Option<f64>,
    /// Where its front meets the first train's front, m (trains after the first).
    pub meet_at_x_m: Option<f64>,
    /// Braking or accelerating once, from `from_x_m` (None: constant speed).
    pub change: Option<tbi_dynamics::train::SpeedChange>,
    /// Whether a braking train's final speed was given (without it, the braking may not stop
    /// the train before its last axle has left the deck).
    pub to_speed_given: bool,
}

impl Train {
    /// The train of these axle loads: moving forces, or sprung masses under
    /// [`Train::axle_vehicle`].
    pub fn axle_train(&self, axles: Vec<MovingForceAxle>) -> Result<TrainSpec, String> {
        match &self.axle_vehicle {
            None => Ok(TrainSpec::MovingForce(axles)),
            Some(v) => Ok(TrainSpec::SprungMass(
                axles
                    .iter()
                    .map(|a| v.sprung(a))
                    .collect::<Result<_, _>>()?,
            )),
        }
    }
}

impl Train {
    /// The `kind` as written in scenarios.
    pub fn kind(&self) -> &'static str {
        match self.spec {
            TrainSpec::MovingForce(_) => "moving_force",
            TrainSpec::SprungMass(_) => "sprung_mass",
            TrainSpec::Coaches { .. } => "coach_27dof",
        }
    }
}

/// `[[probe]]`: a deck point whose response is recorded.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// Non-empty, no commas or quotes (it names CSV columns).
    pub name: String,
    /// Position along the track, m (on the deck).
    pub x_m: f64,
}

/// Read the scenario named on the command line (or the embedded one) with the command
/// line's overrides of the solver and the speed.
pub fn load(
    path: Option<&Path>,
    solver: Option<&str>,
    speed_kmh: Option<f64>,
) -> Result<Scenario, String> {
    let s = match path {
        Some(p) => Scenario::from_path(p).map_err(|e| e.to_string())?,
        None => Scenario::default_case(),
    };
    overridden(s, solver, speed_kmh)
}

/// [`load`] of the embedded meeting case ([`Scenario::meeting_case`]).
pub fn load_meeting(solver: Option<&str>, speed_kmh: Option<f64>) -> Result<Scenario, String> {
    overridden(Scenario::meeting_case(), solver, speed_kmh)
}

/// `s` with the command line's solver and speed.
fn overridden(
    mut s: Scenario,
    solver: Option<&str>,
    speed_kmh: Option<f64>,
) -> Result<Scenario, String> {
    if let Some(sv) = solver {
        s.run.solver = SolverKind::parse(sv)
            .ok_or_else(|| format!("--solver {sv}: expected \"monolithic\" or \"cosim\""))?;
    }
    if let Some(v) = speed_kmh {
        s.set_speed_kmh(v)
            .map_err(|e| format!("--speed-kmh: {e}"))?;
    }
    Ok(s)
}

/// `e` of train `k` (1-based) of several: its fields named `train[k].…`.
fn train_numbered(e: InputError, k: usize) -> InputError {
    match e {
        InputError::Field {
            file,
            field,
            value,
            reason,
        } => InputError::Field {
            file,
            field: match field.strip_prefix("train") {
                Some(rest) => format!("train[{k}]{rest}"),
                None => field,
            },
            value,
            reason,
        },
        other => other,
    }
}

impl Scenario {
    /// All trains, the first first.
    pub fn trains(&self) -> Vec<&Train> {
        std::iter::once(&self.train)
            .chain(&self.more_trains)
            .collect()
    }

    /// Read and check a scenario file.
    pub fn from_path(path: &Path) -> Result<Scenario, InputError> {
        let text = tbi_modes::input::read_text(path, tbi_modes::input::MAX_SCENARIO_BYTES)
            .map_err(|e| InputError::file(path, format!("cannot read scenario: {e}")))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_toml(&text, &path.display().to_string(), &base)
    }

    /// The embedded meeting case ([`MEETING_SCENARIO`]).
    pub fn meeting_case() -> Scenario {
        Self::from_toml(
            MEETING_SCENARIO,
            "<embedded meeting scenario>",
            Path::new("."),
        )
        .expect("the embedded meeting scenario is valid")
    }

    /// The embedded default scenario.
    pub fn default_case() -> Scenario {
        Self::from_toml(
            DEFAULT_SCENARIO,
            "<embedded default scenario>",
            Path::new("."),
        )
        .expect("the embedded scenario is valid")
    }

    /// Parse and check TOML text; `origin` names it in messages.
    pub fn from_toml(text: &str, origin: &str, base_dir: &Path) -> Result<Scenario, InputError> {
        let file: FileScenario = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|sp| text[..sp.start.min(text.len())].matches('\n').count() + 1)
                .unwrap_or(0);
            InputError::line(origin, line, with_suggestion(e.message()))
        })?;
        let c = Check { origin };
        c.name(&file.name)?;
        let (file_trains, many) = file.train.items();
        let first = file_trains.first().ok_or_else(|| {
            c.err(
                "train",
                "[]",
                "give at least one train ([train] or [[train]])",
            )
        })?;
        let mut run = c.run(&file.run, first.speed_kmh)?;
        let damping_rule = c.damping_rule(&file.bridge)?;
        let modes_rule = c.modes_rule(&file.bridge, first)?;
        let bridge = c.bridge(&file.bridge, damping_rule.as_ref(), base_dir)?;
        let tracks = c.tracks(&file.bridge)?;
        let mut trains = Vec::new();
        for (k, t) in file_trains.iter().enumerate() {
            let named = |e| if many { train_numbered(e, k + 1) } else { e };
            let mut train = c.train(t, base_dir).map_err(named)?;
            let n_tracks = tracks.len().max(1);
            if train.track >= n_tracks {
                return Err(named(c.err(
                    "train.track",
                    train.track + 1,
                    &format!(
                        "there {} ([[bridge.track]])",
                        match n_tracks {
                            1 => "is 1 track".to_string(),
                            n => format!("are {n} tracks"),
                        }
                    ),
                )));
            }
            if k == 0 {
                if train.meet_at_x_m.is_some() {
                    return Err(named(c.err(
                        "train.meet_at_x_m",
                        num(train.meet_at_x_m.unwrap_or_default()),
                        "the first train is the one the others meet; give it to a later train",
                    )));
                }
                // the first train's speed and start are the run's
                train.speed = None;
                match (train.start_x_m.take(), run.start_x_m) {
                    (Some(_), Some(_)) => {
                        return Err(named(c.err(
                            "train.start_x_m",
                            "(set)",
                            "give the first train's start in run.start_x_m or in train.start_x_m, not both",
                        )))
                    }
                    (Some(x), None) => run.start_x_m = Some(x),
                    _ => {}
                }
                if run.start_x_m.is_some() && train.enter_time_s.is_some() {
                    return Err(named(c.err(
                        "train.enter_time_s",
                        "(set)",
                        "give one of run.start_x_m and train.enter_time_s, not both",
                    )));
                }
            }
            trains.push(train);
        }
        let train = trains.remove(0);
        c.probes(&file.probes)?;
        file.coupling
            .validate()
            .map_err(|e| c.err("coupling", "", &e.to_string()))?;
        let wind = match file.wind {
            Some(w) => Some(c.wind(w, &bridge)?),
            None => None,
        };
        Ok(Scenario {
            name: file.name,
            run,
            bridge,
            damping_rule,
            modes_rule,
            train,
            more_trains: trains,
            tracks,
            track: file.track.irregularity,
            probes: file.probes,
            coupling: file.coupling,
            wind,
            base_dir: base_dir.to_path_buf(),
            origin: origin.to_string(),
        })
    }

    /// Set the mean wind speed (m/s; `tbi run --wind-speed`), checked as in the file; without
    /// a `[wind]` table the deck takes the suspension preset's coefficients.
    pub fn set_wind_speed(&mut self, u: f64) -> Result<(), InputError> {
        let c = Check {
            origin: &self.origin,
        };
        let mut w = self.wind.clone().unwrap_or(Wind {
            mean_speed_m_s: u,
            air_density_kg_m3: default_air_density(),
            deck: None,
            vehicle: Default::default(),
            vehicle_on_deck: None,
            turbulence: None,
            record: None,
            deck_points: default_deck_points(),
        });
        w.mean_speed_m_s = u;
        self.wind = Some(c.wind(w, &self.bridge)?);
        Ok(())
    }

    /// Change the speed (km/h), checked as in the file.
    pub fn set_speed_kmh(&mut self, v: f64) -> Result<(), InputError> {
        self.run.speed = Speed::from_m_s(v / 3.6)
            .map_err(|e| InputError::field(&self.origin, "run.speed_kmh", num(v), e.to_string()))?;
        self.run.speed_kmh = v;
        Ok(())
    }
}
