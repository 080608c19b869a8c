//! Scenario files (TOML): what to simulate.
//!
//! ```toml
//! name = "yang-yau"
//! [run]
//! speed_kmh = 100.0            # train speed, km/h (> 0)
//! dt_s = 0.0005                # time step, s (> 0); default 0.001
//! solver = "monolithic"        # or "cosim" (default)
//! free_vibration_s = 1.0       # simulated time after the last axle leaves the bridge, s
//! start_x_m = 0.0              # first axle position at t = 0, m (default: deck start)
//! output_every = 1             # write every n-th step to history.csv (default 1)
//! [bridge]
//! kind = "simply_supported"    # or "modal_file" (path = "modes.csv"), "suspension" (preset = "tsing-ma")
//! span_m = 25.0
//! youngs_modulus_pa = 2.87e9
//! inertia_vertical_m4 = 2.9    # inertia_lateral_m4, shear_modulus_pa, torsion_constant_m4, polar_inertia_kg_m optional
//! mass_per_length_kg_m = 2303.0
//! modes = 20
//! damping_ratio = 0.0          # bending modes; damping_ratio_torsional defaults to it
//! track_eccentricity_m = 0.0   # e, track offset from the shear centre (+y), m
//! track_height_m = 0.0         # h4, wheelset reference above the shear centre, m
//! [train]
//! kind = "sprung_mass"         # or "moving_force", "coach_27dof"
//! axles = [{ offset_m = 0.0, sprung_mass_kg = 5750.0, stiffness_n_m = 1.595e6, damping_ns_m = 0.0 }]
//! # coach_27dof: preset = "xia2000", vehicles = 8, coach = { k1v_n_m = ... } overrides
//! # hunting = { amplitude_m = 0.003, wavelength_m = 15.0, seed = 1 }
//! [track]
//! irregularity = "none"        # or { spectrum = "german-low", seed = 1, lambda_min_m = 1.0, lambda_max_m = 80.0 } or { file = "track.csv" }
//! [[probe]]
//! name = "mid"
//! x_m = 12.5
//! [coupling]                   # co-simulation only
//! scheme = "implicit"
//! ```
//!
//! Unknown keys are refused; every check names the file, the field and the value.

use crate::coupling::CouplingConfig;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use tbi_dynamics::interface::TrainSpec;
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_dynamics::vehicle::simple::{MovingForceAxle, SprungMassAxle};
use tbi_dynamics::InputError;
use tbi_track::{HuntingParams, IrregularitySpec};

/// The embedded default scenario: the paper's Tsing Ma case.
pub const DEFAULT_SCENARIO: &str = include_str!("../scenarios/tsing-ma.toml");

/// A complete scenario.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name used in reports.
    #[serde(default = "default_name")]
    pub name: String,
    pub run: RunConfig,
    pub bridge: BridgeConfig,
    pub train: TrainConfig,
    #[serde(default)]
    pub track: TrackConfig,
    #[serde(default, rename = "probe")]
    pub probes: Vec<Probe>,
    #[serde(default)]
    pub coupling: CouplingConfig,
    /// Directory relative paths are resolved against (the scenario file's folder).
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// Where the scenario came from, for messages.
    #[serde(skip)]
    pub origin: String,
    /// Where co-simulation keeps the exported FMUs (set by `tbi run`: `<out>/fmus`).
    #[serde(skip)]
    pub fmu_dir: Option<PathBuf>,
}

fn default_name() -> String {
    "scenario".into()
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
}

/// `[run]`: speed, step and duration.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunConfig {
    /// Train speed, km/h (> 0).
    pub speed_kmh: f64,
    /// Time step, s (> 0). Default 0.001.
    #[serde(default = "default_dt")]
    pub dt_s: f64,
    /// Solver. Default `cosim`.
    #[serde(default)]
    pub solver: SolverKind,
    /// Simulated time after the last axle has left the bridge, s (≥ 0). Default 1.0.
    #[serde(default = "default_free")]
    pub free_vibration_s: f64,
    /// Position of the first axle at t = 0, m. Default: the deck start (train on the approach).
    #[serde(default)]
    pub start_x_m: Option<f64>,
    /// Write every n-th step to `history.csv` (≥ 1). Default 1.
    #[serde(default = "default_every")]
    pub output_every: usize,
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

/// `[bridge]`: one table for all kinds; fields that do not belong to the kind are refused.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeConfig {
    /// `simply_supported`, `modal_file` or `suspension`.
    pub kind: String,
    /// Number of modes kept (≥ 1). Default 20.
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Damping ratio of lateral and vertical modes, –. Default 0.
    #[serde(default)]
    pub damping_ratio: f64,
    /// Damping ratio of torsional modes, –. Default: `damping_ratio`.
    #[serde(default)]
    pub damping_ratio_torsional: Option<f64>,
    /// Track eccentricity e from the shear centre (+y), m. Default 0 (suspension preset: 2.05).
    #[serde(default)]
    pub track_eccentricity_m: Option<f64>,
    /// Height h4 of the wheelset reference above the shear centre, m. Default 0 (preset: 1.25).
    #[serde(default)]
    pub track_height_m: Option<f64>,
    // simply supported
    pub span_m: Option<f64>,
    pub youngs_modulus_pa: Option<f64>,
    pub inertia_vertical_m4: Option<f64>,
    pub inertia_lateral_m4: Option<f64>,
    pub shear_modulus_pa: Option<f64>,
    pub torsion_constant_m4: Option<f64>,
    pub polar_inertia_kg_m: Option<f64>,
    pub mass_per_length_kg_m: Option<f64>,
    /// Deck start along the track, m (simply supported). Default 0.
    pub x_start_m: Option<f64>,
    // modal file
    /// Modes file (`.csv` or `.json`), relative to the scenario file.
    pub path: Option<PathBuf>,
    /// Lagrange interpolation points between nodes (2–8). Default 4.
    pub interpolation_points: Option<usize>,
    // suspension
    /// Built-in suspension bridge preset (`tsing-ma`).
    pub preset: Option<String>,
}

fn default_modes() -> usize {
    20
}

/// A table on one line, `{ key = value, ... }`, for messages.
fn inline_table(t: &toml::Table) -> String {
    let items: Vec<String> = t.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    format!("{{ {} }}", items.join(", "))
}

/// `[train]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainConfig {
    /// `moving_force`, `sprung_mass` or `coach_27dof`.
    pub kind: String,
    /// Axles of `moving_force` / `sprung_mass` trains (tables, see the module docs).
    #[serde(default)]
    pub axles: Vec<toml::Table>,
    /// Coach preset (`xia2000`).
    pub preset: Option<String>,
    /// Number of coaches (≥ 1). Default 1.
    pub vehicles: Option<usize>,
    /// Overrides of the coach preset's fields (see `CoachParams`).
    pub coach: Option<toml::Table>,
    /// Wheel hunting; off by default.
    pub hunting: Option<HuntingParams>,
}

/// `[track]`.
#[derive(Debug, Clone, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct TrackConfig {
    #[serde(default)]
    pub irregularity: IrregularitySpec,
}

/// `[[probe]]`: a deck point whose response is recorded.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    pub name: String,
    /// Position along the track, m (on the deck).
    pub x_m: f64,
}

impl Scenario {
    /// Read and validate a scenario file.
    pub fn from_path(path: &Path) -> Result<Scenario, InputError> {
        let text = std::fs::read_to_string(path)
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

    /// Parse and validate TOML text; `origin` names it in messages.
    pub fn from_toml(text: &str, origin: &str, base_dir: &Path) -> Result<Scenario, InputError> {
        let mut s: Scenario = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|sp| text[..sp.start.min(text.len())].matches('\n').count() + 1)
                .unwrap_or(0);
            InputError::line(origin, line, e.message().to_string())
        })?;
        s.base_dir = base_dir.to_path_buf();
        s.origin = origin.to_string();
        s.validate()?;
        Ok(s)
    }

    fn err(&self, field: &str, value: impl std::fmt::Display, reason: &str) -> InputError {
        InputError::field(&self.origin, field, value, reason)
    }

    fn positive(&self, field: &str, v: f64) -> Result<(), InputError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(self.err(field, v, "must be a positive finite number"));
        }
        Ok(())
    }

    fn non_negative(&self, field: &str, v: f64) -> Result<(), InputError> {
        if !(v.is_finite() && v >= 0.0) {
            return Err(self.err(field, v, "must be a finite number ≥ 0"));
        }
        Ok(())
    }

    /// Check every field (ranges, kinds, fields that do not apply to the kind).
    pub fn validate(&self) -> Result<(), InputError> {
        let r = &self.run;
        self.positive("run.speed_kmh", r.speed_kmh)?;
        self.positive("run.dt_s", r.dt_s)?;
        self.non_negative("run.free_vibration_s", r.free_vibration_s)?;
        if let Some(x) = r.start_x_m {
            if !x.is_finite() {
                return Err(self.err("run.start_x_m", x, "must be finite"));
            }
        }
        if r.output_every == 0 {
            return Err(self.err("run.output_every", 0, "must be at least 1"));
        }
        self.validate_bridge()?;
        self.train_axles()?;
        if let Some(h) = &self.train.hunting {
            h.validate()
                .map_err(|e| self.err("train.hunting", format!("{h:?}"), &e.to_string()))?;
        }
        let mut names = std::collections::HashSet::new();
        for (i, p) in self.probes.iter().enumerate() {
            if p.name.is_empty() || p.name.contains(',') || p.name.contains('"') {
                return Err(self.err(
                    &format!("probe[{i}].name"),
                    format!("{:?}", p.name),
                    "must be non-empty without commas or quotes",
                ));
            }
            if !names.insert(p.name.clone()) {
                return Err(self.err(&format!("probe[{i}].name"), &p.name, "is used twice"));
            }
            if !p.x_m.is_finite() {
                return Err(self.err(&format!("probe[{i}].x_m"), p.x_m, "must be finite"));
            }
        }
        self.coupling
            .validate()
            .map_err(|e| self.err("coupling", "", &e.to_string()))?;
        Ok(())
    }

    fn validate_bridge(&self) -> Result<(), InputError> {
        let b = &self.bridge;
        if b.modes == 0 {
            return Err(self.err("bridge.modes", 0, "must be at least 1"));
        }
        if !(0.0..1.0).contains(&b.damping_ratio) {
            return Err(self.err(
                "bridge.damping_ratio",
                b.damping_ratio,
                "must lie in [0, 1)",
            ));
        }
        if let Some(z) = b.damping_ratio_torsional {
            if !(0.0..1.0).contains(&z) {
                return Err(self.err("bridge.damping_ratio_torsional", z, "must lie in [0, 1)"));
            }
        }
        for (name, v) in [
            ("bridge.track_eccentricity_m", b.track_eccentricity_m),
            ("bridge.track_height_m", b.track_height_m),
        ] {
            if let Some(v) = v {
                if !v.is_finite() {
                    return Err(self.err(name, v, "must be finite"));
                }
            }
        }
        let ss_fields: [(&str, Option<f64>); 9] = [
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
        let refuse = |fields: &[(&str, bool)]| -> Result<(), InputError> {
            for (name, set) in fields {
                if *set {
                    return Err(self.err(
                        &format!("bridge.{name}"),
                        "(set)",
                        &format!("does not apply to kind \"{}\"", b.kind),
                    ));
                }
            }
            Ok(())
        };
        // Shared by the kinds that interpolate nodal shapes: the interpolation order, and no
        // simply supported section data.
        let modal_kinds = || -> Result<(), InputError> {
            if let Some(p) = b.interpolation_points {
                if !(2..=8).contains(&p) {
                    return Err(self.err("bridge.interpolation_points", p, "must lie in 2..=8"));
                }
            }
            let set: Vec<(&str, bool)> = ss_fields.iter().map(|(n, v)| (*n, v.is_some())).collect();
            refuse(&set)
        };
        match b.kind.as_str() {
            "simply_supported" => {
                for name in [
                    "span_m",
                    "youngs_modulus_pa",
                    "inertia_vertical_m4",
                    "mass_per_length_kg_m",
                ] {
                    let v = ss_fields.iter().find(|f| f.0 == name).and_then(|f| f.1);
                    match v {
                        None => {
                            return Err(self.err(
                                &format!("bridge.{name}"),
                                "(missing)",
                                "is required for kind \"simply_supported\"",
                            ))
                        }
                        Some(v) => self.positive(&format!("bridge.{name}"), v)?,
                    }
                }
                for (name, v) in &ss_fields[3..7] {
                    if let Some(v) = v {
                        self.positive(&format!("bridge.{name}"), *v)?;
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
                    if !x.is_finite() {
                        return Err(self.err("bridge.x_start_m", x, "must be finite"));
                    }
                }
                refuse(&[
                    ("path", b.path.is_some()),
                    ("preset", b.preset.is_some()),
                    ("interpolation_points", b.interpolation_points.is_some()),
                ])?;
            }
            "modal_file" => {
                if b.path.is_none() {
                    return Err(self.err(
                        "bridge.path",
                        "(missing)",
                        "is required for kind \"modal_file\"",
                    ));
                }
                modal_kinds()?;
                refuse(&[("preset", b.preset.is_some())])?;
            }
            "suspension" => {
                match b.preset.as_deref() {
                    Some("tsing-ma") => {}
                    Some(p) => {
                        return Err(self.err(
                            "bridge.preset",
                            format!("\"{p}\""),
                            "unknown preset; available: \"tsing-ma\"",
                        ))
                    }
                    None => {
                        return Err(self.err(
                            "bridge.preset",
                            "(missing)",
                            "is required for kind \"suspension\" (available: \"tsing-ma\")",
                        ))
                    }
                }
                modal_kinds()?;
                refuse(&[("path", b.path.is_some())])?;
            }
            other => {
                return Err(self.err(
                    "bridge.kind",
                    format!("\"{other}\""),
                    "unknown kind; expected \"simply_supported\", \"modal_file\" or \"suspension\"",
                ))
            }
        }
        Ok(())
    }

    /// The validated train description.
    pub fn train_axles(&self) -> Result<TrainSpec, InputError> {
        let t = &self.train;
        let only_axles = |kind: &str| -> Result<(), InputError> {
            for (name, set) in [
                ("preset", t.preset.is_some()),
                ("vehicles", t.vehicles.is_some()),
                ("coach", t.coach.is_some()),
            ] {
                if set {
                    return Err(self.err(
                        &format!("train.{name}"),
                        "(set)",
                        &format!("does not apply to kind \"{kind}\""),
                    ));
                }
            }
            if t.axles.is_empty() {
                return Err(self.err(
                    "train.axles",
                    "[]",
                    &format!("kind \"{kind}\" needs at least one axle"),
                ));
            }
            Ok(())
        };
        match t.kind.as_str() {
            "moving_force" => {
                only_axles("moving_force")?;
                let mut out = Vec::new();
                for (i, a) in t.axles.iter().enumerate() {
                    let ax: MovingForceAxle =
                        a.clone().try_into().map_err(|e: toml::de::Error| {
                            self.err(&format!("train.axles[{i}]"), inline_table(a), e.message())
                        })?;
                    self.non_negative(&format!("train.axles[{i}].offset_m"), ax.offset_m)?;
                    if !ax.load_n.is_finite() {
                        return Err(self.err(
                            &format!("train.axles[{i}].load_n"),
                            ax.load_n,
                            "must be finite",
                        ));
                    }
                    out.push(ax);
                }
                Ok(TrainSpec::MovingForce(out))
            }
            "sprung_mass" => {
                only_axles("sprung_mass")?;
                let mut out = Vec::new();
                for (i, a) in t.axles.iter().enumerate() {
                    let ax: SprungMassAxle =
                        a.clone().try_into().map_err(|e: toml::de::Error| {
                            self.err(&format!("train.axles[{i}]"), inline_table(a), e.message())
                        })?;
                    self.non_negative(&format!("train.axles[{i}].offset_m"), ax.offset_m)?;
                    self.positive(
                        &format!("train.axles[{i}].sprung_mass_kg"),
                        ax.sprung_mass_kg,
                    )?;
                    self.positive(&format!("train.axles[{i}].stiffness_n_m"), ax.stiffness_n_m)?;
                    self.non_negative(&format!("train.axles[{i}].damping_ns_m"), ax.damping_ns_m)?;
                    self.non_negative(
                        &format!("train.axles[{i}].wheel_mass_kg"),
                        ax.wheel_mass_kg,
                    )?;
                    out.push(ax);
                }
                Ok(TrainSpec::SprungMass(out))
            }
            "coach_27dof" => {
                if !t.axles.is_empty() {
                    return Err(self.err(
                        "train.axles",
                        "(set)",
                        "does not apply to kind \"coach_27dof\" (use preset, vehicles, coach)",
                    ));
                }
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
                if let Some(over) = &t.coach {
                    for (k, v) in over {
                        let val = v
                            .as_float()
                            .or_else(|| v.as_integer().map(|i| i as f64))
                            .ok_or_else(|| {
                                self.err(&format!("train.coach.{k}"), v, "must be a number")
                            })?;
                        match params.field_mut(k) {
                            Some(f) => *f = val,
                            None => {
                                return Err(self.err(
                                    &format!("train.coach.{k}"),
                                    val,
                                    "unknown coach parameter",
                                ))
                            }
                        }
                    }
                }
                params
                    .check()
                    .map_err(|(f, v, why)| self.err(&format!("train.coach.{f}"), v, &why))?;
                let count = t.vehicles.unwrap_or(1);
                if count == 0 {
                    return Err(self.err("train.vehicles", 0, "must be at least 1"));
                }
                Ok(TrainSpec::Coaches { params, count })
            }
            other => Err(self.err(
                "train.kind",
                format!("\"{other}\""),
                "unknown kind; expected \"moving_force\", \"sprung_mass\" or \"coach_27dof\"",
            )),
        }
    }

    /// Speed in m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.run.speed_kmh / 3.6
    }
}
