//! The checks of `[train]`: the kinds, their axles and vehicles.

use super::check::Check;
use super::file::{inline_table, FileTrain};
use super::{limits, Train};
use crate::text::num;
use std::path::Path;
use tbi_dynamics::train::{Speed, SpeedChange, TrainSpec};
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_dynamics::vehicle::simple::{AxleVehicle, MovingForceAxle, SprungMassAxle};
use tbi_dynamics::InputError;

impl Check<'_> {
    pub(super) fn train(&self, t: &FileTrain, base_dir: &Path) -> Result<Train, InputError> {
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
        use tbi_dynamics::train::TravelDirection;
        let direction = match t.direction.as_deref() {
            None | Some("forward") => TravelDirection::Forward,
            Some("backward") => TravelDirection::Backward,
            Some(other) => {
                return Err(self.err(
                    "train.direction",
                    format!("{other:?}"),
                    "must be \"forward\" or \"backward\"",
                ))
            }
        };
        let (change, to_speed_given) = self.speed_change(t)?;
        let speed = (t.speed_kmh)
            .map(|v| {
                Speed::from_m_s(v / 3.6)
                    .map(|s| (v, s))
                    .map_err(|e| self.err("train.speed_kmh", num(v), &e.to_string()))
            })
            .transpose()?;
        if let Some(x) = t.start_x_m {
            self.finite("train.start_x_m", x)?;
        }
        if let Some(x) = t.meet_at_x_m {
            self.finite("train.meet_at_x_m", x)?;
        }
        if let Some(te) = t.enter_time_s {
            self.within("train.enter_time_s", te, (0.0, 1e6), "s")?;
        }
        let placed = [
            ("start_x_m", t.start_x_m.is_some()),
            ("enter_time_s", t.enter_time_s.is_some()),
            ("meet_at_x_m", t.meet_at_x_m.is_some()),
        ];
        if let [(a, _), (b, _), ..] = placed.iter().filter(|p| p.1).collect::<Vec<_>>()[..] {
            return Err(self.err(
                &format!("train.{b}"),
                "(set)",
                &format!("give one of start_x_m, enter_time_s and meet_at_x_m, not {a} and {b}"),
            ));
        }
        if t.track == Some(0) {
            return Err(self.err("train.track", 0, "tracks are numbered from 1"));
        }
        let mut train = Train {
            spec,
            hunting,
            axle_vehicle,
            direction,
            track: t.track.unwrap_or(1) - 1,
            speed,
            start_x_m: t.start_x_m,
            enter_time_s: t.enter_time_s,
            meet_at_x_m: t.meet_at_x_m,
            change,
            to_speed_given,
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

    /// `train.braking` or `train.accelerating` as a speed change, and whether its final speed
    /// was given (braking may leave it out: to a stop). Whether the final speed lies beyond
    /// the starting speed is checked with the trains, where that is known.
    fn speed_change(&self, t: &FileTrain) -> Result<(Option<SpeedChange>, bool), InputError> {
        let (key, from_x_m, (rate_key, rate), sign, to_kmh) = match (&t.braking, &t.accelerating) {
            (Some(_), Some(_)) => {
                return Err(self.err(
                    "train.accelerating",
                    "(set)",
                    "give braking or accelerating, not both",
                ))
            }
            (Some(b), None) => (
                "braking",
                b.from_x_m,
                ("deceleration_m_s2", b.deceleration_m_s2),
                -1.0,
                b.to_speed_kmh,
            ),
            (None, Some(c)) => (
                "accelerating",
                c.from_x_m,
                ("acceleration_m_s2", c.acceleration_m_s2),
                1.0,
                Some(c.to_speed_kmh),
            ),
            (None, None) => return Ok((None, true)),
        };
        self.finite(&format!("train.{key}.from_x_m"), from_x_m)?;
        let field = format!("train.{key}.{rate_key}");
        let a = self.within(&field, rate, (1e-3, 10.0), "m/s²")?;
        let field = format!("train.{key}.to_speed_kmh");
        let to_kmh = (to_kmh)
            .map(|v| self.within(&field, v, (0.0, Speed::MAX_M_S * 3.6), "km/h"))
            .transpose()?;
        let change = SpeedChange {
            from_x_m,
            rate_m_s2: sign * a,
            to_speed_m_s: to_kmh.unwrap_or(0.0) / 3.6,
        };
        Ok((Some(change), to_kmh.is_some()))
    }

    /// `train.vehicle`: the sprung mass under every axle of a `moving_force` or `hslm_a` train.
    pub(super) fn axle_vehicle(
        &self,
        t: &FileTrain,
        table: &toml::Table,
    ) -> Result<AxleVehicle, InputError> {
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
    pub(super) fn axles_file(&self, path: &Path) -> Result<Vec<MovingForceAxle>, InputError> {
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
            if load_n < 0.0 {
                return Err(at(
                    i + 1,
                    format!("load_n = {load_n} is negative: an axle load is downward, N ≥ 0"),
                ));
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
    pub(super) fn only(
        &self,
        t: &FileTrain,
        allowed: &[&str],
        hint: &str,
    ) -> Result<(), InputError> {
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
    pub(super) fn axles<A: serde::de::DeserializeOwned>(
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

    pub(super) fn train_spec(&self, t: &FileTrain) -> Result<TrainSpec, InputError> {
        let field = |i: usize, name: &str| format!("train.axles[{i}].{name}");
        match t.kind.as_str() {
            "moving_force" => Ok(TrainSpec::MovingForce(self.axles(
                t,
                |i, a: &MovingForceAxle| {
                    self.non_negative(&field(i, "offset_m"), a.offset_m)?;
                    self.non_negative(&field(i, "load_n"), a.load_n)?;
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
}
