//! The cases of a design check as scenario files.
//!
//! Every case of `tbi sweep --trains` is the scenario file with its `[train]` replaced by an
//! HSLM train (keeping `train.vehicle`) and its `run.speed_kmh` set, read back by the same
//! code that reads any scenario ([`Scenario::from_toml`]). A governing case is written as
//! such a file (`governing/<check>.toml`), so `tbi run` of it computes the same model, modes,
//! time step and probes, and reproduces the reported value.
//!
//! Relative paths in the scenario (`bridge.path`, `track.irregularity.file`, `wind.record`)
//! are written absolute, so that a case file runs from any folder.

use crate::scenario::{Scenario, DEFAULT_SCENARIO};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The scenario a check varies, as written.
#[derive(Debug, Clone)]
pub struct Source {
    table: toml::Table,
    base_dir: PathBuf,
    /// The file's path as given, or the embedded scenario's description.
    pub origin: String,
    /// SHA-256 of the file's bytes, hex.
    pub sha256: String,
    /// The scenario's `name`.
    pub name: String,
    /// Overrides: every case runs with this solver; every case keeps all modes.
    pub solver: Option<String>,
    pub all_modes: bool,
}

/// One case: a train at a speed.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub train: String,
    pub speed_kmh: f64,
}

impl Source {
    /// Read the scenario file (or the embedded default), checked as `tbi run` checks it.
    pub fn load(path: Option<&Path>) -> Result<Source, String> {
        let (bytes, origin, base_dir) = match path {
            Some(p) => {
                let text = tbi_modes::input::read_text(p, tbi_modes::input::MAX_SCENARIO_BYTES)
                    .map_err(|e| format!("{}: cannot read scenario: {e}", p.display()))?;
                let base = p.parent().map(Path::to_path_buf).unwrap_or_default();
                let base = std::path::absolute(&base).unwrap_or(base);
                (text, p.display().to_string(), base)
            }
            None => (
                DEFAULT_SCENARIO.to_string(),
                "<embedded default scenario>".to_string(),
                std::path::absolute(".").unwrap_or_default(),
            ),
        };
        // the checks of a scenario file first, with their messages
        let checked = Scenario::from_toml(&bytes, &origin, &base_dir).map_err(|e| e.to_string())?;
        if !checked.more_trains.is_empty() {
            return Err(format!(
                "{origin}: field `train` = {} trains: --trains runs each HSLM train alone in place of the scenario's train (EN 1991-2 §6.4.6.1.2 loads one track); give a scenario with one [train]",
                1 + checked.more_trains.len()
            ));
        }
        let table: toml::Table = bytes.parse().map_err(|e| format!("{origin}: {e}"))?;
        let name = table
            .get("name")
            .and_then(toml::Value::as_str)
            .unwrap_or("scenario")
            .to_string();
        Ok(Source {
            sha256: hex(&Sha256::digest(bytes.as_bytes())),
            table,
            base_dir,
            origin,
            name,
            solver: None,
            all_modes: false,
        })
    }

    /// The case as a scenario file; `name` replaces the scenario's name when given.
    pub fn case_text(&self, case: &Case, name: Option<&str>) -> String {
        let mut t = self.table.clone();
        if let Some(n) = name {
            t.insert("name".into(), n.into());
        }
        let old_train = t.remove("train");
        let mut train = toml::Table::new();
        train.insert("kind".into(), "hslm_a".into());
        train.insert("name".into(), case.train.as_str().into());
        if let Some(v) = old_train.as_ref().and_then(|tr| tr.get("vehicle")).cloned() {
            train.insert("vehicle".into(), v);
        }
        t.insert("train".into(), train.into());
        let run = table_mut(&mut t, "run");
        run.insert("speed_kmh".into(), case.speed_kmh.into());
        if let Some(s) = &self.solver {
            run.insert("solver".into(), s.as_str().into());
        }
        if self.all_modes {
            table_mut(&mut t, "bridge").insert("modes_rule".into(), "all".into());
        }
        self.absolute_paths(&mut t);
        toml::to_string(&t).expect("a TOML table serialises")
    }

    /// The case as the scenario `tbi run` reads from [`Source::case_text`].
    pub fn scenario(&self, case: &Case) -> Result<Scenario, String> {
        let text = self.case_text(case, None);
        Scenario::from_toml(&text, &self.origin, &self.base_dir).map_err(|e| {
            format!(
                "{} at {} km/h: {e}",
                case.train,
                crate::text::num(case.speed_kmh)
            )
        })
    }

    /// Write `path` with the paths of data files made absolute.
    fn absolute_paths(&self, t: &mut toml::Table) {
        let fix = |v: &mut toml::Value| {
            if let Some(s) = v.as_str() {
                let p = Path::new(s);
                if p.is_relative() {
                    *v = self.base_dir.join(p).display().to_string().into();
                }
            }
        };
        if let Some(v) = t
            .get_mut("bridge")
            .and_then(toml::Value::as_table_mut)
            .and_then(|b| b.get_mut("path"))
        {
            fix(v);
        }
        if let Some(v) = t
            .get_mut("track")
            .and_then(toml::Value::as_table_mut)
            .and_then(|b| b.get_mut("irregularity"))
            .and_then(toml::Value::as_table_mut)
            .and_then(|b| b.get_mut("file"))
        {
            fix(v);
        }
        if let Some(v) = t
            .get_mut("wind")
            .and_then(toml::Value::as_table_mut)
            .and_then(|b| b.get_mut("record"))
        {
            fix(v);
        }
    }
}

/// The sub-table `key` of `t`, created when missing.
fn table_mut<'a>(t: &'a mut toml::Table, key: &str) -> &'a mut toml::Table {
    t.entry(key)
        .or_insert_with(|| toml::Value::Table(Default::default()))
        .as_table_mut()
        .expect("a scenario section is a table")
}

/// Bytes as lower-case hexadecimal.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A case file reads back as the case: the train, the speed bit for bit, the modes rule.
    #[test]
    fn a_case_file_reads_back_as_the_case() {
        let dir = std::env::temp_dir().join(format!("tbi-cases-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.toml");
        std::fs::write(
            &path,
            "name = \"s\"\n[run]\nspeed_kmh = 300.0\n[bridge]\nkind = \"simply_supported\"\nspan_m = 20.0\nyoungs_modulus_pa = 3.5e10\ninertia_vertical_m4 = 0.9\nmass_per_length_kg_m = 12000.0\n[train]\nkind = \"moving_force\"\naxles = [{ offset_m = 0.0, load_n = 1e5 }]\n[[probe]]\nname = \"mid\"\nx_m = 10.0\n",
        )
        .unwrap();
        let mut source = Source::load(Some(&path)).unwrap();
        let case = Case {
            train: "A7".into(),
            speed_kmh: 257.538_196_601_125_1,
        };
        let s = source.scenario(&case).unwrap();
        assert_eq!(s.run.speed_kmh.to_bits(), case.speed_kmh.to_bits());
        assert_eq!(s.train.kind(), "moving_force");
        assert_eq!(s.modes_rule, crate::scenario::ModesRule::En1990);
        source.all_modes = true;
        let s = source.scenario(&case).unwrap();
        assert_eq!(s.modes_rule, crate::scenario::ModesRule::All);
        assert_eq!(source.sha256.len(), 64);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
