//! A damped oscillator as an FMI 2.0 Co-Simulation FMU: the fixture that exercises
//! `fmi-export` end to end (the FMU crates of the project follow the same pattern).
//!
//! The model is `m x'' + c x' + k x = F` with the force `F` an input held constant over
//! each communication step (its value set before `fmi2DoStep`, i.e. the value at
//! `t + h`). Each step is integrated with classical RK4 on `ceil(h / max_substep)` equal
//! substeps.
//!
//! | vr | name | causality | variability | unit |
//! |---|---|---|---|---|
//! | 0 | `F` | input (start 0) | continuous | N |
//! | 1 | `x` | output | continuous | m |
//! | 2 | `v` | output | continuous | m/s |
//! | 3 | `energy` = ½ m v² + ½ k x² | output | continuous | J |
//! | 10 | `mass` | parameter | fixed | kg |
//! | 11 | `stiffness` | parameter | fixed | N/m |
//! | 12 | `damping` | parameter | fixed | N·s/m |
//! | 13 | `x0` | parameter | fixed | m |
//! | 14 | `v0` | parameter | fixed | m/s |
//! | 15 | `x_max` | parameter | fixed | m |
//!
//! Parameter defaults and `max_substep` come from `resources/config.txt`
//! (`key = value` lines, `#` comments); the GUID is [`guid_for`]`(<bytes of config.txt>)`
//! = `fmi_export::guid("testmodel", <crate version>, <bytes of config.txt>)`. A step that would take `|x|` beyond `x_max` is discarded
//! (`fmi2Discard`) and leaves the state unchanged.

use std::path::Path;
use std::sync::Arc;

use fmi_export::{FmuModel, Log, ModelError, Phase, StepOutcome};

/// `modelIdentifier` (the library name).
pub const MODEL_IDENTIFIER: &str = "testmodel";
/// The resource file the model reads.
pub const CONFIG_FILE: &str = "config.txt";

/// Value references.
pub mod vr {
    pub const FORCE: u32 = 0;
    pub const X: u32 = 1;
    pub const V: u32 = 2;
    pub const ENERGY: u32 = 3;
    pub const MASS: u32 = 10;
    pub const STIFFNESS: u32 = 11;
    pub const DAMPING: u32 = 12;
    pub const X0: u32 = 13;
    pub const V0: u32 = 14;
    pub const X_MAX: u32 = 15;
}

/// The GUID for a given content of `config.txt`.
pub fn guid_for(config_bytes: &[u8]) -> String {
    fmi_export::guid(MODEL_IDENTIFIER, env!("CARGO_PKG_VERSION"), config_bytes)
}

/// The parameters (all in SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parameters {
    pub mass: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub x0: f64,
    pub v0: f64,
    pub x_max: f64,
}

impl Parameters {
    fn validate(&self) -> Result<(), String> {
        let checks = [
            ("mass", self.mass, self.mass > 0.0),
            ("stiffness", self.stiffness, self.stiffness > 0.0),
            ("damping", self.damping, self.damping >= 0.0),
            ("x_max", self.x_max, self.x_max > 0.0),
        ];
        for (name, value, ok) in checks {
            if !(ok && value.is_finite()) {
                return Err(format!("parameter {name} = {value} is out of range"));
            }
        }
        if !(self.x0.is_finite() && self.v0.is_finite()) {
            return Err("initial state must be finite".to_owned());
        }
        if self.x0.abs() > self.x_max {
            return Err(format!(
                "|x0| = {} exceeds x_max = {}",
                self.x0.abs(),
                self.x_max
            ));
        }
        Ok(())
    }
}

/// What `config.txt` defines.
#[derive(Debug, Clone, PartialEq)]
struct Config {
    parameters: Parameters,
    max_substep: f64,
    guid: String,
}

impl Config {
    fn parse(text: &str, guid: String) -> Result<Config, String> {
        let mut values = std::collections::BTreeMap::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let (key, value) = line
                .split_once('=')
                .ok_or_else(|| format!("line {}: expected 'key = value'", i + 1))?;
            let key = key.trim();
            let value: f64 = value
                .trim()
                .parse()
                .map_err(|e| format!("line {}: {key}: {e}", i + 1))?;
            if values.insert(key.to_owned(), value).is_some() {
                return Err(format!("line {}: {key} given twice", i + 1));
            }
        }
        let mut take = |key: &str| {
            values
                .remove(key)
                .ok_or_else(|| format!("missing key '{key}'"))
        };
        let parameters = Parameters {
            mass: take("mass")?,
            stiffness: take("stiffness")?,
            damping: take("damping")?,
            x0: take("x0")?,
            v0: take("v0")?,
            x_max: take("x_max")?,
        };
        let max_substep = take("max_substep")?;
        if let Some(key) = values.keys().next() {
            return Err(format!("unknown key '{key}'"));
        }
        parameters.validate()?;
        if !(max_substep.is_finite() && max_substep > 0.0) {
            return Err(format!("max_substep = {max_substep} must be positive"));
        }
        Ok(Config {
            parameters,
            max_substep,
            guid,
        })
    }
}

/// The oscillator's complete dynamic state plus a shared handle to its configuration.
#[derive(Debug, Clone)]
pub struct Oscillator {
    config: Arc<Config>,
    p: Parameters,
    force: f64,
    x: f64,
    v: f64,
}

impl Oscillator {
    fn from_config(config: Arc<Config>) -> Oscillator {
        let p = config.parameters;
        Oscillator {
            config,
            p,
            force: 0.0,
            x: p.x0,
            v: p.v0,
        }
    }

    /// (x', v') for the state (x, v).
    fn rhs(&self, x: f64, v: f64) -> (f64, f64) {
        let a = (self.force - self.p.damping * v - self.p.stiffness * x) / self.p.mass;
        (v, a)
    }

    fn rk4(&self, x: f64, v: f64, dt: f64) -> (f64, f64) {
        let (k1x, k1v) = self.rhs(x, v);
        let (k2x, k2v) = self.rhs(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
        let (k3x, k3v) = self.rhs(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
        let (k4x, k4v) = self.rhs(x + dt * k3x, v + dt * k3v);
        (
            x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        )
    }

    fn energy(&self) -> f64 {
        0.5 * self.p.mass * self.v * self.v + 0.5 * self.p.stiffness * self.x * self.x
    }

    fn parameter_mut(&mut self, vr: u32) -> Option<(&'static str, &mut f64)> {
        Some(match vr {
            vr::MASS => ("mass", &mut self.p.mass),
            vr::STIFFNESS => ("stiffness", &mut self.p.stiffness),
            vr::DAMPING => ("damping", &mut self.p.damping),
            vr::X0 => ("x0", &mut self.p.x0),
            vr::V0 => ("v0", &mut self.p.v0),
            vr::X_MAX => ("x_max", &mut self.p.x_max),
            _ => return None,
        })
    }
}

const STATE_LEN: usize = 9 * 8;

impl FmuModel for Oscillator {
    const LOG_CATEGORIES: &'static [(&'static str, &'static str)] =
        &[("logModel", "Configuration read at instantiation")];

    fn instantiate(resources: &Path, log: &dyn Log) -> Result<Self, ModelError> {
        let path = resources.join(CONFIG_FILE);
        let bytes =
            std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let text =
            std::str::from_utf8(&bytes).map_err(|_| format!("{} is not UTF-8", path.display()))?;
        let config = Config::parse(text, guid_for(&bytes))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        log.log(
            "logModel",
            &format!("read {}: {:?}", path.display(), config.parameters),
        );
        Ok(Oscillator::from_config(Arc::new(config)))
    }

    fn guid(&self) -> String {
        self.config.guid.clone()
    }

    fn exit_initialization(&mut self) -> Result<(), ModelError> {
        self.p.validate()?;
        self.x = self.p.x0;
        self.v = self.p.v0;
        Ok(())
    }

    fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), ModelError> {
        match vr {
            vr::FORCE => {
                self.force = value;
                Ok(())
            }
            vr::X | vr::V | vr::ENERGY => Err(ModelError::Refused(format!(
                "value reference {vr} is an output and cannot be set"
            ))),
            _ => {
                let (name, slot) = self
                    .parameter_mut(vr)
                    .ok_or_else(|| format!("unknown Real value reference {vr}"))?;
                if phase == Phase::Stepping {
                    return Err(ModelError::Refused(format!(
                        "{name} (value reference {vr}) is a fixed parameter and cannot be set in step mode"
                    )));
                }
                *slot = value;
                // Outputs reflect the initial state until initialization ends.
                self.x = self.p.x0;
                self.v = self.p.v0;
                Ok(())
            }
        }
    }

    fn get_real(&mut self, vr: u32) -> Result<f64, ModelError> {
        Ok(match vr {
            vr::FORCE => self.force,
            vr::X => self.x,
            vr::V => self.v,
            vr::ENERGY => self.energy(),
            _ => {
                let (_, slot) = self
                    .parameter_mut(vr)
                    .ok_or_else(|| format!("unknown Real value reference {vr}"))?;
                *slot
            }
        })
    }

    fn do_step(&mut self, _t: f64, h: f64) -> Result<StepOutcome, ModelError> {
        let n = (h / self.config.max_substep).ceil().max(1.0);
        if n > 1e7 {
            return Err(ModelError::Refused(format!(
                "step size {h} needs {n} substeps; use smaller steps"
            )));
        }
        let dt = h / n;
        let (mut x, mut v) = (self.x, self.v);
        for _ in 0..n as u64 {
            (x, v) = self.rk4(x, v, dt);
        }
        if !(x.is_finite() && v.is_finite()) {
            return Err(ModelError::Failed(format!(
                "the state became non-finite (x = {x}, v = {v})"
            )));
        }
        if x.abs() > self.p.x_max {
            return Ok(StepOutcome::Discard(format!(
                "|x| = {} would exceed x_max = {}",
                x.abs(),
                self.p.x_max
            )));
        }
        (self.x, self.v) = (x, v);
        Ok(StepOutcome::Ok)
    }

    fn reset(&mut self) -> Result<(), ModelError> {
        *self = Oscillator::from_config(Arc::clone(&self.config));
        Ok(())
    }

    fn serialize_state(&self) -> Vec<u8> {
        let p = &self.p;
        [
            p.mass,
            p.stiffness,
            p.damping,
            p.x0,
            p.v0,
            p.x_max,
            self.force,
            self.x,
            self.v,
        ]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
    }

    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), ModelError> {
        if bytes.len() != STATE_LEN {
            return Err(ModelError::Failed(format!(
                "oscillator state has {} bytes, expected {STATE_LEN}",
                bytes.len()
            )));
        }
        let v: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        if v.iter().any(|x| !x.is_finite()) {
            return Err("oscillator state contains non-finite values".into());
        }
        let p = Parameters {
            mass: v[0],
            stiffness: v[1],
            damping: v[2],
            x0: v[3],
            v0: v[4],
            x_max: v[5],
        };
        p.validate()?;
        self.p = p;
        (self.force, self.x, self.v) = (v[6], v[7], v[8]);
        Ok(())
    }
}

fmi_export::export_fmi2!(Oscillator);

#[cfg(test)]
mod tests {
    use super::*;

    const CONFIG: &str = include_str!("../resources/config.txt");

    #[test]
    fn shipped_config_parses() {
        let c = Config::parse(CONFIG, "g".into()).unwrap();
        assert_eq!(c.parameters.mass, 2.0);
        assert_eq!(c.parameters.stiffness, 50.0);
        assert_eq!(c.max_substep, 1e-3);
    }

    #[test]
    fn config_errors_name_the_problem() {
        let err = |t: &str| Config::parse(t, String::new()).unwrap_err();
        let full = "mass=1\nstiffness=1\ndamping=0\nx0=0\nv0=0\nx_max=1\nmax_substep=0.1\n";
        assert!(Config::parse(full, String::new()).is_ok());
        assert!(err("mass = 1\n").contains("missing key 'stiffness'"));
        assert!(err(&format!("{full}extra = 2\n")).contains("unknown key 'extra'"));
        assert!(err(&format!("{full}mass = 2\n")).contains("given twice"));
        assert!(err("mass 1\n").contains("line 1"));
        assert!(err(&full.replace("mass=1", "mass=-1")).contains("mass"));
        assert!(err(&full.replace("x0=0", "x0=2")).contains("x_max"));
    }

    #[test]
    fn serialized_state_round_trips_and_rejects_bad_bytes() {
        let config = Arc::new(Config::parse(CONFIG, "g".into()).unwrap());
        let mut a = Oscillator::from_config(Arc::clone(&config));
        a.force = 3.0;
        a.do_step(0.0, 0.01).unwrap();
        let bytes = a.serialize_state();
        let mut b = Oscillator::from_config(config);
        b.deserialize_state(&bytes).unwrap();
        assert_eq!(b.serialize_state(), bytes);
        assert!(b.deserialize_state(&bytes[1..]).is_err());
        let mut nan = bytes.clone();
        nan[56..64].copy_from_slice(&f64::NAN.to_le_bytes());
        assert!(b.deserialize_state(&nan).is_err());
    }
}
fmi_export::export_fmi3!(Oscillator);
