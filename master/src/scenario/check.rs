//! The checks: every field once, each error naming the file, the field and the value.

use super::file::{FileBridge, FileRun, FileTrain};
use super::{limits, Bridge, DampingRule, DeckAero, ModesRule, Probe, Run, Wind};
use crate::text::num;
use tbi_dynamics::train::Speed;
use tbi_dynamics::InputError;

pub(super) struct Check<'a> {
    pub(super) origin: &'a str,
}

impl Check<'_> {
    pub(super) fn err(
        &self,
        field: &str,
        value: impl std::fmt::Display,
        reason: &str,
    ) -> InputError {
        InputError::field(self.origin, field, value, reason)
    }

    pub(super) fn positive(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(self.err(field, num(v), "must be a positive finite number"));
        }
        Ok(v)
    }

    pub(super) fn non_negative(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(v.is_finite() && v >= 0.0) {
            return Err(self.err(field, num(v), "must be a finite number ≥ 0"));
        }
        Ok(v)
    }

    pub(super) fn finite(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !v.is_finite() {
            return Err(self.err(field, num(v), "must be finite"));
        }
        Ok(v)
    }

    pub(super) fn ratio(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if !(0.0..1.0).contains(&v) {
            return Err(self.err(field, num(v), "must lie in [0, 1)"));
        }
        Ok(v)
    }

    pub(super) fn within(
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

    pub(super) fn at_most(&self, field: &str, n: usize, max: usize) -> Result<usize, InputError> {
        if n > max {
            return Err(self.err(field, n, &format!("must be at most {max}")));
        }
        Ok(n)
    }

    /// The name becomes the default output folder `tbi-out/<name>`: one plain path
    /// component of letters, digits, `-`, `_` and `.`, not starting with a dot.
    pub(super) fn name(&self, name: &str) -> Result<(), InputError> {
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

    /// `[run]`, its speed the first train's own (`first_speed_kmh`) when it gives one.
    pub(super) fn run(&self, r: &FileRun, first_speed_kmh: Option<f64>) -> Result<Run, InputError> {
        // km/h as written for reports, m/s checked for the physics.
        let (field, speed_kmh) = match (first_speed_kmh, r.speed_kmh) {
            (Some(v), _) => ("train.speed_kmh", v),
            (None, Some(v)) => ("run.speed_kmh", v),
            (None, None) => {
                return Err(self.err(
                    "run.speed_kmh",
                    "(missing)",
                    "give the speed in [run] or in every train (train.speed_kmh)",
                ))
            }
        };
        let speed = Speed::from_m_s(speed_kmh / 3.6)
            .map_err(|e| self.err(field, num(speed_kmh), &e.to_string()))?;
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
        if !matches!(r.fmi_version, 2 | 3) {
            return Err(self.err("run.fmi_version", r.fmi_version, "must be 2 or 3"));
        }
        Ok(Run {
            speed_kmh,
            speed,
            dt_s,
            solver: r.solver,
            free_vibration_s,
            start_x_m: r.start_x_m,
            output_every: r.output_every,
            fmi_version: r.fmi_version,
        })
    }

    /// `[[bridge.track]]`: each track's `(eccentricity, height)`, m; refused beside
    /// `track_eccentricity_m` or `track_height_m`.
    pub(super) fn tracks(&self, b: &FileBridge) -> Result<Vec<[f64; 2]>, InputError> {
        let Some(tracks) = &b.track else {
            return Ok(Vec::new());
        };
        if b.track_eccentricity_m.is_some() || b.track_height_m.is_some() {
            return Err(self.err(
                "bridge.track",
                "(set)",
                "give the tracks either as [[bridge.track]] or as track_eccentricity_m and track_height_m, not both",
            ));
        }
        if tracks.is_empty() {
            return Err(self.err("bridge.track", "[]", "give at least one track"));
        }
        (tracks.iter().enumerate())
            .map(|(k, t)| {
                let e = self.within(
                    &format!("bridge.track[{}].eccentricity_m", k + 1),
                    t.eccentricity_m,
                    (-50.0, 50.0),
                    "m",
                )?;
                let h = self.within(
                    &format!("bridge.track[{}].height_m", k + 1),
                    t.height_m,
                    (-50.0, 50.0),
                    "m",
                )?;
                Ok([e, h])
            })
            .collect()
    }

    /// `bridge.modes_rule`, or its default for the train's kind.
    pub(super) fn modes_rule(
        &self,
        b: &FileBridge,
        t: &FileTrain,
    ) -> Result<ModesRule, InputError> {
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
    pub(super) fn damping_rule(&self, b: &FileBridge) -> Result<Option<DampingRule>, InputError> {
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

    /// `[wind]`, with the deck's coefficients defaulted for the suspension preset.
    pub(super) fn wind(&self, mut w: Wind, bridge: &Bridge) -> Result<Wind, InputError> {
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

    pub(super) fn probes(&self, probes: &[Probe]) -> Result<(), InputError> {
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
