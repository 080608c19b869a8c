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

use crate::model::num;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;
use tbi_dynamics::bridge::SimplySupported;
use tbi_dynamics::train::Speed;
use tbi_dynamics::train::TrainSpec;
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_dynamics::vehicle::simple::{AxleVehicle, MovingForceAxle, SprungMassAxle};
use tbi_dynamics::InputError;
use tbi_track::{HuntingParams, IrregularitySpec};

/// The embedded default scenario: the paper's Tsing Ma case.
pub const DEFAULT_SCENARIO: &str = include_str!("../scenarios/tsing-ma.toml");

/// The scenarios `tbi scenario show NAME` prints: the default and the repository's
/// `examples/`, embedded so that a user starts from them in any folder.
pub mod examples {
    /// (name, what it is, TOML).
    pub const EXAMPLES: [(&str, &str, &str); 2] = [
        (
            "tsing-ma",
            "the paper's Tsing Ma case: 8 coaches at 70 km/h over the suspension bridge (the default)",
            super::DEFAULT_SCENARIO,
        ),
        (
            "psc-25m-hslm",
            "a 25 m prestressed-concrete span on a 300 km/h line for the EN 1991-2 HSLM-A check",
            include_str!("../../examples/psc-25m-hslm.toml"),
        ),
    ];

    /// The TOML of the example `name` (None: the default), or an error naming the
    /// examples.
    pub fn text(name: Option<&str>) -> Result<&'static str, Box<dyn std::error::Error>> {
        let name = name.unwrap_or("tsing-ma");
        EXAMPLES
            .iter()
            .find(|e| e.0 == name)
            .map(|e| e.2)
            .ok_or_else(|| {
                format!(
                    "tbi scenario show {name}: no such example; the examples are {}",
                    EXAMPLES.map(|e| e.0).join(", ")
                )
                .into()
            })
    }
}

/// Limits on scenario values (documented in docs/scenario.md, "Limits"). Values outside them are
/// not physically meaningful for a railway bridge or would exhaust the machine.
pub mod limits {
    /// Time step range, s.
    pub const DT_S: (f64, f64) = (1e-6, 0.1);
    /// Longest free vibration after the train has left, s.
    pub const FREE_VIBRATION_S: f64 = 3600.0;
    /// Most bridge modes.
    pub const MODES: usize = 2000;
    /// Most coaches.
    pub const VEHICLES: usize = 1000;
    /// Most axles of a moving-force or sprung-mass train.
    pub const AXLES: usize = 4000;
    /// Most probes.
    pub const PROBES: usize = 1000;
    /// Longest scenario name, characters.
    pub const NAME_CHARS: usize = 100;
    /// Simply supported section data: (field, lowest, highest), SI units.
    pub const SECTION: [(&str, f64, f64); 8] = [
        ("span_m", 0.5, 1e5),
        ("youngs_modulus_pa", 1e6, 1e13),
        ("inertia_vertical_m4", 1e-8, 1e5),
        ("inertia_lateral_m4", 1e-8, 1e5),
        ("shear_modulus_pa", 1e5, 1e13),
        ("torsion_constant_m4", 1e-10, 1e5),
        ("polar_inertia_kg_m", 1e-3, 1e10),
        ("mass_per_length_kg_m", 1.0, 1e7),
    ];
}

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
    pub train: Train,
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
    let mut s = match path {
        Some(p) => Scenario::from_path(p).map_err(|e| e.to_string())?,
        None => Scenario::default_case(),
    };
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

impl Scenario {
    /// Read and check a scenario file.
    pub fn from_path(path: &Path) -> Result<Scenario, InputError> {
        let text = tbi_modes::input::read_text(path, tbi_modes::input::MAX_SCENARIO_BYTES)
            .map_err(|e| InputError::file(path, format!("cannot read scenario: {e}")))?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_toml(&text, &path.display().to_string(), &base)
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
        let run = c.run(&file.run)?;
        let damping_rule = c.damping_rule(&file.bridge)?;
        let modes_rule = c.modes_rule(&file.bridge, &file.train)?;
        let bridge = c.bridge(&file.bridge, damping_rule.as_ref(), base_dir)?;
        let train = c.train(&file.train, base_dir)?;
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

// ---- the file as written -------------------------------------------------------------

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileScenario {
    #[serde(default = "default_name")]
    name: String,
    run: FileRun,
    bridge: FileBridge,
    train: FileTrain,
    #[serde(default)]
    track: FileTrack,
    #[serde(default, rename = "probe")]
    probes: Vec<Probe>,
    #[serde(default)]
    coupling: CouplingConfig,
    wind: Option<Wind>,
}

fn default_name() -> String {
    "scenario".into()
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRun {
    speed_kmh: f64,
    #[serde(default = "default_dt")]
    dt_s: f64,
    #[serde(default)]
    solver: SolverKind,
    #[serde(default = "default_free")]
    free_vibration_s: f64,
    #[serde(default)]
    start_x_m: Option<f64>,
    #[serde(default = "default_every")]
    output_every: usize,
}

fn default_dt() -> f64 {
    0.001
}
fn default_free() -> f64 {
    1.0
}
fn default_every() -> usize {
    1
}

/// `[bridge]`: one table for all kinds; keys that do not belong to the kind are refused.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileBridge {
    kind: String,
    #[serde(default = "default_modes")]
    modes: usize,
    #[serde(default)]
    damping_ratio: f64,
    damping_ratio_torsional: Option<f64>,
    damping: Option<FileDamping>,
    /// `"en1990"` or `"all"` ([`ModesRule`]); default by the train's kind.
    modes_rule: Option<String>,
    track_eccentricity_m: Option<f64>,
    track_height_m: Option<f64>,
    // simply supported
    span_m: Option<f64>,
    // beam
    spans_m: Option<Vec<f64>>,
    /// `kind = "beam"`: one section per span, each key defaulting to the bridge's.
    sections: Option<Vec<FileSection>>,
    /// `kind = "beam"`: `"continuous"` (default) or `"simply_supported"` (a chain of spans).
    supports: Option<String>,
    youngs_modulus_pa: Option<f64>,
    inertia_vertical_m4: Option<f64>,
    inertia_lateral_m4: Option<f64>,
    shear_modulus_pa: Option<f64>,
    torsion_constant_m4: Option<f64>,
    polar_inertia_kg_m: Option<f64>,
    mass_per_length_kg_m: Option<f64>,
    x_start_m: Option<f64>,
    // modal file
    path: Option<PathBuf>,
    interpolation_points: Option<usize>,
    // suspension
    preset: Option<String>,
}

fn default_modes() -> usize {
    20
}

/// `bridge.sections[i]` of `kind = "beam"`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSection {
    youngs_modulus_pa: Option<f64>,
    inertia_vertical_m4: Option<f64>,
    mass_per_length_kg_m: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDamping {
    rule: String,
    structure: String,
    additional: Option<bool>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTrain {
    kind: String,
    /// `kind = "hslm_a"`: the train's name, `A1` … `A10`.
    name: Option<String>,
    /// `kind = "hslm_b"`: the number N of point forces of 170 kN.
    forces: Option<usize>,
    /// `kind = "hslm_b"`: their uniform spacing d, m.
    spacing_m: Option<f64>,
    /// `kind = "moving_force"`: a CSV of axles instead of `axles`.
    file: Option<PathBuf>,
    #[serde(default)]
    axles: Vec<toml::Table>,
    preset: Option<String>,
    vehicles: Option<usize>,
    coach: Option<toml::Table>,
    hunting: Option<HuntingParams>,
    /// `kind = "moving_force"` or `"hslm_a"`: a sprung mass under every axle.
    vehicle: Option<toml::Table>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct FileTrack {
    #[serde(default)]
    irregularity: IrregularitySpec,
}

/// serde's "unknown field `x`, expected one of `a`, `b`" (or "unknown variant") with the
/// closest expected name: "…; did you mean `a`?" ([`crate::suggest::closest`]).
pub fn with_suggestion(message: &str) -> String {
    let unknown = ["unknown field `", "unknown variant `"]
        .iter()
        .find_map(|p| message.strip_prefix(p))
        .and_then(|rest| rest.split('`').next());
    let Some(unknown) = unknown else {
        return message.to_string();
    };
    let expected = message
        .split_once("expected")
        .map(|(_, list)| list.split('`').skip(1).step_by(2));
    match expected.and_then(|names| crate::suggest::closest(unknown, names)) {
        Some(name) => format!("{message}; did you mean `{name}`?"),
        None => message.to_string(),
    }
}

/// A table on one line, `{ key = value, ... }`, for messages.
fn inline_table(t: &toml::Table) -> String {
    let items: Vec<String> = t.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    format!("{{ {} }}", items.join(", "))
}

// ---- the checks: every field once ----------------------------------------------------

struct Check<'a> {
    origin: &'a str,
}

impl Check<'_> {
    fn err(&self, field: &str, value: impl std::fmt::Display, reason: &str) -> InputError {
        InputError::field(self.origin, field, value, reason)
    }

    fn positive(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(self.err(field, num(v), "must be a positive finite number"));
        }
        Ok(v)
    }

    fn non_negative(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(v.is_finite() && v >= 0.0) {
            return Err(self.err(field, num(v), "must be a finite number ≥ 0"));
        }
        Ok(v)
    }

    fn finite(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !v.is_finite() {
            return Err(self.err(field, num(v), "must be finite"));
        }
        Ok(v)
    }

    fn ratio(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(0.0..1.0).contains(&v) {
            return Err(self.err(field, num(v), "must lie in [0, 1)"));
        }
        Ok(v)
    }

    fn within(
        &self,
        field: &str,
        v: f64,
        (lo, hi): (f64, f64),
        unit: &str,
    ) -> Result<f64, InputError> {
        if !(lo..=hi).contains(&v) {
            return Err(self.err(
                field,
                num(v),
                &format!("must lie in [{}, {}] {unit}", num(lo), num(hi)),
            ));
        }
        Ok(v)
    }

    fn at_most(&self, field: &str, n: usize, max: usize) -> Result<usize, InputError> {
        if n > max {
            return Err(self.err(field, n, &format!("must be at most {max}")));
        }
        Ok(n)
    }

    /// The name becomes the default output folder `tbi-out/<name>`: one plain path
    /// component of letters, digits, `-`, `_` and `.`, not starting with a dot.
    fn name(&self, name: &str) -> Result<(), InputError> {
        let plain = !name.is_empty()
            && !name.starts_with('.')
            && name.chars().count() <= limits::NAME_CHARS
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
        if !plain {
            return Err(self.err(
                "name",
                format!("{name:?}"),
                &format!(
                    "must be 1 to {} letters, digits, '-', '_' or '.', not starting with '.' (it names the output folder; choose another folder with --out)",
                    limits::NAME_CHARS
                ),
            ));
        }
        Ok(())
    }

    fn run(&self, r: &FileRun) -> Result<Run, InputError> {
        // km/h as written for reports, m/s checked for the physics.
        let speed = Speed::from_m_s(r.speed_kmh / 3.6)
            .map_err(|e| self.err("run.speed_kmh", num(r.speed_kmh), &e.to_string()))?;
        let dt_s = self.within("run.dt_s", r.dt_s, limits::DT_S, "s")?;
        let free_vibration_s = self.within(
            "run.free_vibration_s",
            r.free_vibration_s,
            (0.0, limits::FREE_VIBRATION_S),
            "s",
        )?;
        if let Some(x) = r.start_x_m {
            self.finite("run.start_x_m", x)?;
        }
        if r.output_every == 0 {
            return Err(self.err("run.output_every", 0, "must be at least 1"));
        }
        Ok(Run {
            speed_kmh: r.speed_kmh,
            speed,
            dt_s,
            solver: r.solver,
            free_vibration_s,
            start_x_m: r.start_x_m,
            output_every: r.output_every,
        })
    }

    /// `bridge.modes_rule`, or its default for the train's kind.
    fn modes_rule(&self, b: &FileBridge, t: &FileTrain) -> Result<ModesRule, InputError> {
        match b.modes_rule.as_deref() {
            None if matches!(t.kind.as_str(), "hslm_a" | "hslm_b") => Ok(ModesRule::En1990),
            None => Ok(ModesRule::All),
            Some("en1990") => Ok(ModesRule::En1990),
            Some("all") => Ok(ModesRule::All),
            Some(other) => Err(self.err(
                "bridge.modes_rule",
                format!("\"{other}\""),
                "expected \"en1990\" (the modes up to max(30 Hz, 1.5 f₁, f₃), EN 1990 A2.4.4.2.1) or \"all\"",
            )),
        }
    }

    /// `bridge.damping`, checked and evaluated for the span.
    fn damping_rule(&self, b: &FileBridge) -> Result<Option<DampingRule>, InputError> {
        let Some(d) = &b.damping else {
            return Ok(None);
        };
        if d.rule != "en1991-2" {
            return Err(self.err(
                "bridge.damping.rule",
                format!("\"{}\"", d.rule),
                "unknown rule; available: \"en1991-2\"",
            ));
        }
        let structure: tbi_dynamics::en1991::Structure =
            d.structure.parse().map_err(|e: String| {
                self.err(
                    "bridge.damping.structure",
                    format!("\"{}\"", d.structure),
                    &e,
                )
            })?;
        if b.damping_ratio != 0.0 || b.damping_ratio_torsional.is_some() {
            return Err(self.err(
                "bridge.damping_ratio",
                "(set)",
                "give either damping_ratio or damping = { rule = … }, not both",
            ));
        }
        let span = match (b.kind.as_str(), b.span_m) {
            ("simply_supported", Some(l)) if l > 0.0 && l.is_finite() => l,
            _ => {
                return Err(self.err(
                    "bridge.damping",
                    "(set)",
                    "the EN 1991-2 rule needs the span: it applies to kind \"simply_supported\" with span_m",
                ))
            }
        };
        let minimum_percent = structure.minimum_damping_percent(span);
        let additional_percent = if d.additional.unwrap_or(true) {
            tbi_dynamics::en1991::additional_damping_percent(span)
        } else {
            0.0
        };
        Ok(Some(DampingRule {
            rule: d.rule.clone(),
            structure: d.structure.clone(),
            minimum_percent,
            additional_percent,
            ratio: (minimum_percent + additional_percent) / 100.0,
        }))
    }

    fn bridge(
        &self,
        b: &FileBridge,
        rule: Option<&DampingRule>,
        base_dir: &Path,
    ) -> Result<Bridge, InputError> {
        if b.modes == 0 {
            return Err(self.err("bridge.modes", 0, "must be at least 1"));
        }
        self.at_most("bridge.modes", b.modes, limits::MODES)?;
        let (damping_ratio, damping_ratio_torsional) = match rule {
            Some(r) => (r.ratio, r.ratio),
            None => {
                let z = self.ratio("bridge.damping_ratio", b.damping_ratio)?;
                let zt = match b.damping_ratio_torsional {
                    Some(z) => self.ratio("bridge.damping_ratio_torsional", z)?,
                    None => z,
                };
                (z, zt)
            }
        };
        for (name, v) in [
            ("bridge.track_eccentricity_m", b.track_eccentricity_m),
            ("bridge.track_height_m", b.track_height_m),
        ] {
            if let Some(v) = v {
                self.finite(name, v)?;
            }
        }
        let section: [(&str, Option<f64>); 9] = [
            ("span_m", b.span_m),
            ("youngs_modulus_pa", b.youngs_modulus_pa),
            ("inertia_vertical_m4", b.inertia_vertical_m4),
            ("inertia_lateral_m4", b.inertia_lateral_m4),
            ("shear_modulus_pa", b.shear_modulus_pa),
            ("torsion_constant_m4", b.torsion_constant_m4),
            ("polar_inertia_kg_m", b.polar_inertia_kg_m),
            ("mass_per_length_kg_m", b.mass_per_length_kg_m),
            ("x_start_m", b.x_start_m),
        ];
        let refuse = |keys: &[(&str, bool)]| -> Result<(), InputError> {
            match keys.iter().find(|(_, set)| *set) {
                Some((name, _)) => Err(self.err(
                    &format!("bridge.{name}"),
                    "(set)",
                    &format!("does not apply to kind \"{}\"", b.kind),
                )),
                None => Ok(()),
            }
        };
        // The kinds that interpolate nodal shapes: the interpolation order, no section data.
        let modal = |e_default: f64, h4_default: f64| -> Result<ModalOptions, InputError> {
            let interpolation_points = b.interpolation_points.unwrap_or(4);
            if !(2..=8).contains(&interpolation_points) {
                return Err(self.err(
                    "bridge.interpolation_points",
                    interpolation_points,
                    "must lie in 2..=8",
                ));
            }
            let set: Vec<(&str, bool)> = section.iter().map(|(n, v)| (*n, v.is_some())).collect();
            refuse(&set)?;
            Ok(ModalOptions {
                modes: b.modes,
                damping_ratio,
                damping_ratio_torsional,
                track_eccentricity_m: b.track_eccentricity_m.unwrap_or(e_default),
                track_height_m: b.track_height_m.unwrap_or(h4_default),
                interpolation_points,
            })
        };
        if b.kind != "beam" {
            refuse(&[
                ("spans_m", b.spans_m.is_some()),
                ("sections", b.sections.is_some()),
                ("supports", b.supports.is_some()),
            ])?;
        }
        match b.kind.as_str() {
            "simply_supported" => {
                let required = |name: &str, v: Option<f64>| match v {
                    None => Err(self.err(
                        &format!("bridge.{name}"),
                        "(missing)",
                        "is required for kind \"simply_supported\"",
                    )),
                    Some(v) => self.positive(&format!("bridge.{name}"), v),
                };
                let span_m = required("span_m", b.span_m)?;
                let youngs_modulus_pa = required("youngs_modulus_pa", b.youngs_modulus_pa)?;
                let inertia_vertical_m4 = required("inertia_vertical_m4", b.inertia_vertical_m4)?;
                let mass_per_length_kg_m =
                    required("mass_per_length_kg_m", b.mass_per_length_kg_m)?;
                for (name, lo, hi) in limits::SECTION {
                    if let Some((_, Some(v))) = section.iter().find(|f| f.0 == name) {
                        self.within(&format!("bridge.{name}"), *v, (lo, hi), "(SI units)")?;
                    }
                }
                let tors = [
                    b.shear_modulus_pa,
                    b.torsion_constant_m4,
                    b.polar_inertia_kg_m,
                ];
                let n = tors.iter().filter(|t| t.is_some()).count();
                if n != 0 && n != 3 {
                    return Err(self.err("bridge.shear_modulus_pa", format!("{:?}", b.shear_modulus_pa), "torsion needs shear_modulus_pa, torsion_constant_m4 and polar_inertia_kg_m together"));
                }
                if let Some(x) = b.x_start_m {
                    self.finite("bridge.x_start_m", x)?;
                }
                refuse(&[
                    ("path", b.path.is_some()),
                    ("preset", b.preset.is_some()),
                    ("interpolation_points", b.interpolation_points.is_some()),
                ])?;
                Ok(Bridge::SimplySupported(SimplySupported {
                    span_m,
                    youngs_modulus_pa,
                    inertia_vertical_m4,
                    inertia_lateral_m4: b.inertia_lateral_m4,
                    shear_modulus_pa: b.shear_modulus_pa,
                    torsion_constant_m4: b.torsion_constant_m4,
                    polar_inertia_kg_m: b.polar_inertia_kg_m,
                    mass_per_length_kg_m,
                    modes: b.modes,
                    damping_ratio,
                    damping_ratio_torsional,
                    e_m: b.track_eccentricity_m.unwrap_or(0.0),
                    h4_m: b.track_height_m.unwrap_or(0.0),
                    x_start_m: b.x_start_m.unwrap_or(0.0),
                }))
            }
            "beam" => {
                let spans = b.spans_m.clone().unwrap_or_default();
                if spans.is_empty() {
                    return Err(self.err(
                        "bridge.spans_m",
                        "(missing)",
                        "kind \"beam\" needs spans_m = [ … ] (m)",
                    ));
                }
                for (i, &l) in spans.iter().enumerate() {
                    self.positive(&format!("bridge.spans_m[{i}]"), l)?;
                    self.within(&format!("bridge.spans_m[{i}]"), l, (0.1, 1e4), "(m)")?;
                }
                self.at_most("bridge.spans_m (count)", spans.len(), 100)?;
                for (name, lo, hi) in limits::SECTION {
                    if let Some((_, Some(v))) = section.iter().find(|f| f.0 == name) {
                        self.positive(&format!("bridge.{name}"), *v)?;
                        self.within(&format!("bridge.{name}"), *v, (lo, hi), "(SI units)")?;
                    }
                }
                let given = b.sections.clone().unwrap_or_default();
                if b.sections.is_some() && given.len() != spans.len() {
                    return Err(self.err(
                        "bridge.sections",
                        format!("({} sections)", given.len()),
                        &format!("give one section per span ({} spans)", spans.len()),
                    ));
                }
                let sections = (0..spans.len())
                    .map(|i| {
                        let own = given.get(i);
                        let pick = |name: &str, mine: Option<f64>, bridge: Option<f64>| {
                            match (mine, bridge) {
                                (Some(v), _) => {
                                    let field = format!("bridge.sections[{i}].{name}");
                                    self.positive(&field, v)?;
                                    if let Some((_, lo, hi)) =
                                        limits::SECTION.iter().find(|f| f.0 == name)
                                    {
                                        self.within(&field, v, (*lo, *hi), "(SI units)")?;
                                    }
                                    Ok(v)
                                }
                                (None, Some(v)) => Ok(v),
                                (None, None) => Err(self.err(
                                    &format!("bridge.{name}"),
                                    "(missing)",
                                    &format!(
                                        "is required for kind \"beam\" (or in every bridge.sections[…]; span {i} has none)"
                                    ),
                                )),
                            }
                        };
                        Ok(tbi_fe::beam::SpanSection {
                            youngs_modulus_pa: pick(
                                "youngs_modulus_pa",
                                own.and_then(|s| s.youngs_modulus_pa),
                                b.youngs_modulus_pa,
                            )?,
                            inertia_m4: pick(
                                "inertia_vertical_m4",
                                own.and_then(|s| s.inertia_vertical_m4),
                                b.inertia_vertical_m4,
                            )?,
                            mass_per_length_kg_m: pick(
                                "mass_per_length_kg_m",
                                own.and_then(|s| s.mass_per_length_kg_m),
                                b.mass_per_length_kg_m,
                            )?,
                        })
                    })
                    .collect::<Result<Vec<_>, InputError>>()?;
                refuse(&[
                    ("span_m", b.span_m.is_some()),
                    ("inertia_lateral_m4", b.inertia_lateral_m4.is_some()),
                    ("shear_modulus_pa", b.shear_modulus_pa.is_some()),
                    ("torsion_constant_m4", b.torsion_constant_m4.is_some()),
                    ("polar_inertia_kg_m", b.polar_inertia_kg_m.is_some()),
                    ("path", b.path.is_some()),
                    ("preset", b.preset.is_some()),
                ])?;
                let x_start_m = b.x_start_m.unwrap_or(0.0);
                self.finite("bridge.x_start_m", x_start_m)?;
                let continuous = match b.supports.as_deref().unwrap_or("continuous") {
                    "continuous" => true,
                    "simply_supported" => false,
                    other => {
                        return Err(self.err(
                            "bridge.supports",
                            format!("\"{other}\""),
                            "expected \"continuous\" or \"simply_supported\" (a chain of spans)",
                        ))
                    }
                };
                Ok(Bridge::Beam {
                    beam: tbi_fe::beam::ContinuousBeam {
                        spans_m: spans,
                        sections,
                        elements_per_span: 40,
                        continuous,
                    },
                    x_start_m,
                    modal: ModalOptions {
                        modes: b.modes,
                        damping_ratio,
                        damping_ratio_torsional,
                        track_eccentricity_m: b.track_eccentricity_m.unwrap_or(0.0),
                        track_height_m: b.track_height_m.unwrap_or(0.0),
                        // linear between the nodes of a chain: no smoothing over its hinges
                        interpolation_points: b
                            .interpolation_points
                            .unwrap_or(if continuous { 4 } else { 2 }),
                    },
                })
            }
            "modal_file" => {
                let Some(path) = b.path.clone() else {
                    return Err(self.err(
                        "bridge.path",
                        "(missing)",
                        "is required for kind \"modal_file\"",
                    ));
                };
                let modal = modal(0.0, 0.0)?;
                refuse(&[("preset", b.preset.is_some())])?;
                Ok(Bridge::ModalFile {
                    resolved: base_dir.join(&path),
                    path,
                    modal,
                })
            }
            "suspension" => {
                let available = SuspensionPreset::ALL.map(|p| format!("\"{}\"", p.name()));
                let preset = match b.preset.as_deref() {
                    Some(p) => SuspensionPreset::parse(p).ok_or_else(|| {
                        self.err(
                            "bridge.preset",
                            format!("\"{p}\""),
                            &format!("unknown preset; available: {}", available.join(", ")),
                        )
                    })?,
                    None => {
                        return Err(self.err(
                            "bridge.preset",
                            "(missing)",
                            &format!(
                                "is required for kind \"suspension\" (available: {})",
                                available.join(", ")
                            ),
                        ))
                    }
                };
                let modal = modal(2.05, 1.25)?;
                refuse(&[("path", b.path.is_some())])?;
                Ok(Bridge::Suspension { preset, modal })
            }
            other => Err(self.err(
                "bridge.kind",
                format!("\"{other}\""),
                "unknown kind; expected \"simply_supported\", \"beam\", \"modal_file\" or \"suspension\"",
            )),
        }
    }

    fn train(&self, t: &FileTrain, base_dir: &Path) -> Result<Train, InputError> {
        let spec = match (&t.file, t.kind.as_str()) {
            (Some(file), "moving_force") => {
                if !t.axles.is_empty() {
                    return Err(self.err(
                        "train.axles",
                        "(set)",
                        "give either axles or file, not both",
                    ));
                }
                TrainSpec::MovingForce(self.axles_file(&base_dir.join(file))?)
            }
            (Some(_), kind) => {
                return Err(self.err(
                    "train.file",
                    "(set)",
                    &format!("does not apply to kind \"{kind}\" (only \"moving_force\")"),
                ))
            }
            (None, _) => self.train_spec(t)?,
        };
        let hunting = t.hunting.clone().unwrap_or_default();
        hunting
            .validate()
            .map_err(|e| self.err("train.hunting", format!("{hunting:?}"), &e.to_string()))?;
        let axle_vehicle = t
            .vehicle
            .as_ref()
            .map(|table| self.axle_vehicle(t, table))
            .transpose()?;
        let mut train = Train {
            spec,
            hunting,
            axle_vehicle,
        };
        if train.axle_vehicle.is_some() {
            let TrainSpec::MovingForce(axles) = &train.spec else {
                unreachable!("axle_vehicle refuses other kinds")
            };
            train.spec = train.axle_train(axles.clone()).map_err(|e| {
                self.err(
                    "train.vehicle.wheel_mass_kg",
                    inline_table(t.vehicle.as_ref().expect("set")),
                    &e,
                )
            })?;
        }
        Ok(train)
    }

    /// `train.vehicle`: the sprung mass under every axle of a `moving_force` or `hslm_a` train.
    fn axle_vehicle(&self, t: &FileTrain, table: &toml::Table) -> Result<AxleVehicle, InputError> {
        if !matches!(t.kind.as_str(), "moving_force" | "hslm_a" | "hslm_b") {
            return Err(self.err(
                "train.vehicle",
                inline_table(table),
                &format!(
                    "does not apply to kind \"{}\" (only \"moving_force\", \"hslm_a\" and \"hslm_b\")",
                    t.kind
                ),
            ));
        }
        let v: AxleVehicle = table.clone().try_into().map_err(|e: toml::de::Error| {
            self.err("train.vehicle", inline_table(table), e.message())
        })?;
        if v.model != "sprung_mass" {
            return Err(self.err(
                "train.vehicle.model",
                format!("\"{}\"", v.model),
                "unknown model; expected \"sprung_mass\"",
            ));
        }
        self.positive("train.vehicle.frequency_hz", v.frequency_hz)?;
        self.non_negative("train.vehicle.damping_ratio", v.damping_ratio)?;
        self.non_negative("train.vehicle.wheel_mass_kg", v.wheel_mass_kg)?;
        Ok(v)
    }

    /// `train.file`: a CSV of axles, header `offset_m,load_n` (distance behind the first
    /// axle, m; vertical load, N), one axle per line.
    fn axles_file(&self, path: &Path) -> Result<Vec<MovingForceAxle>, InputError> {
        let text = tbi_modes::input::read_text(path, tbi_modes::input::MAX_DATA_FILE_BYTES)
            .map_err(|e| InputError::file(path, format!("train.file: {e}")))?;
        let at = |line: usize, why: String| InputError::line(path, line, why);
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        match lines.next() {
            Some((_, h)) if h.trim().replace(' ', "") == "offset_m,load_n" => {}
            Some((i, h)) => {
                return Err(at(
                    i + 1,
                    format!("the header is `{}`, expected `offset_m,load_n`", h.trim()),
                ))
            }
            None => {
                return Err(at(
                    1,
                    "the file is empty; expected the header offset_m,load_n and one axle per line"
                        .into(),
                ))
            }
        }
        let mut axles = Vec::new();
        for (i, line) in lines {
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let [o, p] = fields.as_slice() else {
                return Err(at(
                    i + 1,
                    format!(
                        "`{}` has {} fields, expected offset_m,load_n",
                        line.trim(),
                        fields.len()
                    ),
                ));
            };
            let num = |v: &str, what: &str| -> Result<f64, InputError> {
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| at(i + 1, format!("{what} `{v}` is not a number")))
            };
            let (offset_m, load_n) = (num(o, "offset_m")?, num(p, "load_n")?);
            if offset_m < 0.0 {
                return Err(at(i + 1, format!("offset_m = {offset_m} is negative")));
            }
            axles.push(MovingForceAxle { offset_m, load_n });
            if axles.len() > limits::AXLES {
                return Err(at(i + 1, format!("more than {} axles", limits::AXLES)));
            }
        }
        if axles.is_empty() {
            return Err(at(1, "no axles after the header".into()));
        }
        Ok(axles)
    }

    /// Refuse the `[train]` keys that kind `t.kind` does not take (all but `allowed`), naming
    /// the first one set; `hint` says what the kind does take.
    fn only(&self, t: &FileTrain, allowed: &[&str], hint: &str) -> Result<(), InputError> {
        let keys = [
            ("axles", !t.axles.is_empty()),
            ("preset", t.preset.is_some()),
            ("vehicles", t.vehicles.is_some()),
            ("coach", t.coach.is_some()),
            ("name", t.name.is_some()),
            ("forces", t.forces.is_some()),
            ("spacing_m", t.spacing_m.is_some()),
        ];
        match keys.iter().find(|(k, set)| *set && !allowed.contains(k)) {
            Some((k, _)) => Err(self.err(
                &format!("train.{k}"),
                "(set)",
                &format!("does not apply to kind \"{}\"{hint}", t.kind),
            )),
            None => Ok(()),
        }
    }

    /// The axles of `moving_force` / `sprung_mass` trains, each table converted and checked.
    fn axles<A: serde::de::DeserializeOwned>(
        &self,
        t: &FileTrain,
        check: impl Fn(usize, &A) -> Result<(), InputError>,
    ) -> Result<Vec<A>, InputError> {
        self.only(t, &["axles"], "")?;
        if t.axles.is_empty() {
            return Err(self.err(
                "train.axles",
                "[]",
                &format!("kind \"{}\" needs at least one axle", t.kind),
            ));
        }
        self.at_most("train.axles (count)", t.axles.len(), limits::AXLES)?;
        t.axles
            .iter()
            .enumerate()
            .map(|(i, table)| {
                let axle: A = table.clone().try_into().map_err(|e: toml::de::Error| {
                    self.err(
                        &format!("train.axles[{i}]"),
                        inline_table(table),
                        e.message(),
                    )
                })?;
                check(i, &axle)?;
                Ok(axle)
            })
            .collect()
    }

    fn train_spec(&self, t: &FileTrain) -> Result<TrainSpec, InputError> {
        let field = |i: usize, name: &str| format!("train.axles[{i}].{name}");
        match t.kind.as_str() {
            "moving_force" => Ok(TrainSpec::MovingForce(self.axles(
                t,
                |i, a: &MovingForceAxle| {
                    self.non_negative(&field(i, "offset_m"), a.offset_m)?;
                    self.finite(&field(i, "load_n"), a.load_n)?;
                    Ok(())
                },
            )?)),
            "sprung_mass" => Ok(TrainSpec::SprungMass(self.axles(
                t,
                |i, a: &SprungMassAxle| {
                    self.non_negative(&field(i, "offset_m"), a.offset_m)?;
                    self.positive(&field(i, "sprung_mass_kg"), a.sprung_mass_kg)?;
                    self.positive(&field(i, "stiffness_n_m"), a.stiffness_n_m)?;
                    self.non_negative(&field(i, "damping_ns_m"), a.damping_ns_m)?;
                    self.non_negative(&field(i, "wheel_mass_kg"), a.wheel_mass_kg)?;
                    Ok(())
                },
            )?)),
            "coach_27dof" => {
                self.only(
                    t,
                    &["preset", "vehicles", "coach"],
                    " (use preset, vehicles, coach)",
                )?;
                let mut params = match t.preset.as_deref().unwrap_or("xia2000") {
                    "xia2000" => CoachParams::xia2000(),
                    p => {
                        return Err(self.err(
                            "train.preset",
                            format!("\"{p}\""),
                            "unknown preset; available: \"xia2000\"",
                        ))
                    }
                };
                for (k, v) in t.coach.iter().flatten() {
                    let val = v
                        .as_float()
                        .or_else(|| v.as_integer().map(|i| i as f64))
                        .ok_or_else(|| {
                            self.err(&format!("train.coach.{k}"), v, "must be a number")
                        })?;
                    *params.field_mut(k).ok_or_else(|| {
                        self.err(&format!("train.coach.{k}"), val, "unknown coach parameter")
                    })? = val;
                }
                params
                    .check()
                    .map_err(|(f, v, why)| self.err(&format!("train.coach.{f}"), v, &why))?;
                let count = t.vehicles.unwrap_or(1);
                if count == 0 {
                    return Err(self.err("train.vehicles", 0, "must be at least 1"));
                }
                self.at_most("train.vehicles", count, limits::VEHICLES)?;
                Ok(TrainSpec::Coaches { params, count })
            }
            "hslm_a" => {
                self.only(t, &["name"], " (give name = \"A1\" … \"A10\")")?;
                let name = t.name.as_deref().ok_or_else(|| {
                    self.err("train.name", "(missing)", "kind \"hslm_a\" needs name = \"A1\" … \"A10\"")
                })?;
                Ok(TrainSpec::MovingForce(
                    tbi_dynamics::hslm::hslm_a(name)
                        .map_err(|e| self.err("train.name", format!("\"{name}\""), &e))?,
                ))
            }
            "hslm_b" => {
                self.only(t, &["forces", "spacing_m"], " (give forces = N, spacing_m = d)")?;
                let forces = t.forces.ok_or_else(|| {
                    self.err("train.forces", "(missing)", "kind \"hslm_b\" needs forces = N (EN 1991-2 §6.4.6.1.1, read for the span)")
                })?;
                let spacing = t.spacing_m.ok_or_else(|| {
                    self.err("train.spacing_m", "(missing)", "kind \"hslm_b\" needs spacing_m = d (EN 1991-2 §6.4.6.1.1, read for the span)")
                })?;
                if forces == 0 {
                    return Err(self.err("train.forces", 0, "must be at least 1"));
                }
                self.at_most("train.forces", forces, limits::AXLES)?;
                self.positive("train.spacing_m", spacing)?;
                Ok(TrainSpec::MovingForce(
                    tbi_dynamics::hslm::hslm_b(forces, spacing)
                        .map_err(|e| self.err("train.forces", forces, &e))?,
                ))
            }
            other => Err(self.err(
                "train.kind",
                format!("\"{other}\""),
                "unknown kind; expected \"moving_force\", \"sprung_mass\", \"coach_27dof\", \"hslm_a\" or \"hslm_b\"",
            )),
        }
    }

    /// `[wind]`, with the deck's coefficients defaulted for the suspension preset.
    fn wind(&self, mut w: Wind, bridge: &Bridge) -> Result<Wind, InputError> {
        self.non_negative("wind.mean_speed_m_s", w.mean_speed_m_s)?;
        self.within(
            "wind.mean_speed_m_s",
            w.mean_speed_m_s,
            (0.0, 100.0),
            "(m/s)",
        )?;
        self.positive("wind.air_density_kg_m3", w.air_density_kg_m3)?;
        self.within(
            "wind.air_density_kg_m3",
            w.air_density_kg_m3,
            (0.1, 10.0),
            "(kg/m³)",
        )?;
        let deck = match (w.deck.clone(), bridge) {
            (Some(d), _) => d,
            (None, Bridge::Suspension { .. }) => DeckAero::tsing_ma(),
            (None, other) => {
                return Err(self.err(
                    "wind.deck",
                    "(missing)",
                    &format!(
                        "a bridge of kind \"{}\" needs deck = {{ width_m = …, drag = …, lift = …, moment = … }}",
                        other.kind()
                    ),
                ))
            }
        };
        self.positive("wind.deck.width_m", deck.width_m)?;
        self.within("wind.deck.width_m", deck.width_m, (0.1, 1000.0), "(m)")?;
        for (name, v) in [
            ("wind.deck.drag", deck.drag),
            ("wind.deck.lift", deck.lift),
            ("wind.deck.moment", deck.moment),
            ("wind.deck.drag_slope", deck.drag_slope),
            ("wind.deck.lift_slope", deck.lift_slope),
            ("wind.deck.moment_slope", deck.moment_slope),
        ] {
            self.finite(name, v)?;
            self.within(name, v, (-20.0, 20.0), "(–)")?;
        }
        if let Some(c) = deck.admittance {
            self.finite("wind.deck.admittance", c)?;
            self.within("wind.deck.admittance", c, (1e-3, 50.0), "(–)")?;
            if let Some(record) = &w.record {
                return Err(self.err(
                    "wind.deck.admittance",
                    c,
                    &format!(
                        "an admittance applies to the generated turbulence, not to the record {}",
                        record.display()
                    ),
                ));
            }
        }
        if let Some(t) = &deck.flutter {
            t.validate()
                .map_err(|(f, why)| self.err(&format!("wind.deck.flutter.{f}"), "", &why))?;
        }
        if !(2..=2000).contains(&w.deck_points) {
            return Err(self.err("wind.deck_points", w.deck_points, "must lie in 2..=2000"));
        }
        if let Some(record) = &w.record {
            if w.turbulence.is_some() {
                return Err(self.err(
                    "wind.record",
                    record.display(),
                    "give either turbulence (generated) or record (measured), not both",
                ));
            }
            if w.mean_speed_m_s <= 0.0 {
                return Err(self.err(
                    "wind.record",
                    record.display(),
                    "a record of the turbulence needs a mean wind: mean_speed_m_s > 0",
                ));
            }
        }
        if let Some(t) = &w.turbulence {
            t.validate().map_err(|e| match e {
                tbi_wind::WindError::Invalid {
                    field,
                    value,
                    reason,
                } => self.err(&format!("wind.turbulence.{field}"), value, &reason),
                other => self.err("wind.turbulence", "", &other.to_string()),
            })?;
        }
        w.deck = Some(deck);
        w.vehicle
            .validate()
            .map_err(|(f, why)| self.err(&format!("wind.vehicle.{f}"), "", &why))?;
        if let Some(d) = &w.vehicle_on_deck {
            d.validate()
                .map_err(|(f, why)| self.err(&format!("wind.vehicle_on_deck.{f}"), "", &why))?;
        }
        Ok(w)
    }

    fn probes(&self, probes: &[Probe]) -> Result<(), InputError> {
        self.at_most("probe (count)", probes.len(), limits::PROBES)?;
        let mut names = std::collections::HashSet::new();
        for (i, p) in probes.iter().enumerate() {
            // Probe names become CSV column names and plot titles.
            let plain = !p.name.is_empty()
                && p.name.chars().count() <= limits::NAME_CHARS
                && p.name
                    .chars()
                    .all(|c| !c.is_control() && c != ',' && c != '"');
            if !plain {
                return Err(self.err(
                    &format!("probe[{i}].name"),
                    format!("{:?}", p.name),
                    &format!(
                        "must be 1 to {} characters without commas, quotes or control characters",
                        limits::NAME_CHARS
                    ),
                ));
            }
            if !names.insert(p.name.clone()) {
                return Err(self.err(&format!("probe[{i}].name"), &p.name, "is used twice"));
            }
            self.finite(&format!("probe[{i}].x_m"), p.x_m)?;
        }
        Ok(())
    }
}
