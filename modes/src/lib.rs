//! Deck mode shapes exchanged with finite-element programs: the `modal_file` format, in a
//! crate of its own so that the FE generator (`tbi-fe`) writes it and the physics core
//! (`tbi-dynamics`) reads it without either depending on the other.
//!
//! A [`ModeSet`] holds, for each mode `n`, its natural frequency and the mass-normalised
//! (φₙᵀ M φₙ = 1, M in kg and kg·m²) deck components at the shear centre, sampled at deck
//! nodes `x_m` along the track axis:
//!
//! * `lateral`  φ_h: displacement along +y (to the right, looking in the direction of travel), kg^-1/2;
//! * `vertical` φ_v: displacement along +z (downward), kg^-1/2;
//! * `torsion`  φ_θ: rotation about +x (right side down), rad·kg^-1/2·m^-1.
//!
//! Between nodes the shapes are interpolated with Lagrange polynomials (see
//! `tbi_dynamics::bridge::ModalBridge`). Two encodings are read and written:
//!
//! **CSV** (long format, one row per mode and node; `#` starts a comment line):
//! ```text
//! mode,label,frequency_hz,damping_ratio,x_m,lateral,vertical,torsion
//! 1,L-S-1,0.0690,,0.0,0.0,0.0,0.0
//! 1,L-S-1,0.0690,,18.0,1.2e-5,0.0,3.1e-8
//! ```
//! `mode` is 1-based and rows of one mode are contiguous with increasing `x_m`; every mode
//! uses the same nodes. `damping_ratio` may be empty (the scenario's default applies).
//!
//! **JSON** (`.json`): `{"format": "tbi-modes-1", "x_m": [...], "modes": [{"label": ...,
//! "frequency_hz": ..., "damping_ratio": null, "lateral": [...], "vertical": [...],
//! "torsion": [...]}]}`.

pub mod error;
pub mod input;

pub use error::InputError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Format tag written into JSON mode files.
pub const FORMAT_TAG: &str = "tbi-modes-1";

/// One deck mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Type label such as `V-S-1`, `L-A-1`, `T-S-1` (vertical/lateral/torsional,
    /// symmetric/antisymmetric, order). Free text; `T-` modes get the torsional damping.
    pub label: String,
    /// Natural frequency, Hz (> 0).
    pub frequency_hz: f64,
    /// Modal damping ratio (–); `None` lets the scenario decide.
    pub damping_ratio: Option<f64>,
    /// Lateral component at each node, kg^-1/2.
    pub lateral: Vec<f64>,
    /// Vertical component at each node (+ downward), kg^-1/2.
    pub vertical: Vec<f64>,
    /// Torsional component at each node, rad·kg^-1/2·m^-1.
    pub torsion: Vec<f64>,
}

/// Mass-normalised deck modes at a common set of nodes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeSet {
    #[serde(default = "format_tag")]
    pub format: String,
    /// Deck node positions along the track, m, strictly increasing.
    pub x_m: Vec<f64>,
    pub modes: Vec<Mode>,
}

fn format_tag() -> String {
    FORMAT_TAG.to_string()
}

impl ModeSet {
    /// Check internal consistency; `origin` names the source in messages.
    pub fn validate(&self, origin: &Path) -> Result<(), InputError> {
        let n = self.x_m.len();
        if n < 2 {
            return Err(InputError::file(
                origin,
                format!("needs at least 2 nodes, found {n}"),
            ));
        }
        for (i, w) in self.x_m.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater)
                || !w[0].is_finite()
                || !w[1].is_finite()
            {
                return Err(InputError::file(
                    origin,
                    format!(
                        "node positions must be finite and strictly increasing: x_m[{i}] = {}, x_m[{}] = {}",
                        w[0],
                        i + 1,
                        w[1]
                    ),
                ));
            }
        }
        if self.modes.is_empty() {
            return Err(InputError::file(origin, "no modes"));
        }
        for (k, m) in self.modes.iter().enumerate() {
            let id = k + 1;
            if !(m.frequency_hz > 0.0 && m.frequency_hz.is_finite()) {
                return Err(InputError::file(
                    origin,
                    format!(
                        "mode {id}: frequency_hz = {} must be positive and finite",
                        m.frequency_hz
                    ),
                ));
            }
            if let Some(z) = m.damping_ratio {
                if !(0.0..1.0).contains(&z) {
                    return Err(InputError::file(
                        origin,
                        format!("mode {id}: damping_ratio = {z} must lie in [0, 1)"),
                    ));
                }
            }
            for (name, v) in [
                ("lateral", &m.lateral),
                ("vertical", &m.vertical),
                ("torsion", &m.torsion),
            ] {
                if v.len() != n {
                    return Err(InputError::file(
                        origin,
                        format!("mode {id}: {name} has {} values for {n} nodes", v.len()),
                    ));
                }
                if let Some(j) = v.iter().position(|x| !x.is_finite()) {
                    return Err(InputError::file(
                        origin,
                        format!("mode {id}: {name}[{j}] = {} is not finite", v[j]),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Read a `.csv` or `.json` mode file (by extension).
    pub fn read(path: &Path) -> Result<Self, InputError> {
        let text = input::read_text(path, input::MAX_DATA_FILE_BYTES)
            .map_err(|e| InputError::file(path, format!("cannot read modes file: {e}")))?;
        let set = match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => serde_json::from_str::<ModeSet>(&text)
                .map_err(|e| {
                    InputError::line(path, e.line(), format!("malformed JSON modes file: {e}"))
                })?,
            _ => Self::parse_csv(&text, path)?,
        };
        set.validate(path)?;
        Ok(set)
    }

    /// Write as `.csv` or `.json` (by extension).
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("json") => {
                serde_json::to_string_pretty(self).map_err(std::io::Error::other)?
            }
            _ => self.to_csv(),
        };
        std::fs::write(path, text)
    }

    /// The CSV encoding (full round-trip precision).
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "# tbi modes file: mass-normalised deck modes at the shear centre (y right, z down, theta about x)\n\
             mode,label,frequency_hz,damping_ratio,x_m,lateral,vertical,torsion\n",
        );
        for (k, m) in self.modes.iter().enumerate() {
            let z = m.damping_ratio.map(|z| z.to_string()).unwrap_or_default();
            for (j, x) in self.x_m.iter().enumerate() {
                s.push_str(&format!(
                    "{},{},{},{},{},{},{},{}\n",
                    k + 1,
                    m.label,
                    m.frequency_hz,
                    z,
                    x,
                    m.lateral[j],
                    m.vertical[j],
                    m.torsion[j]
                ));
            }
        }
        s
    }

    /// Parse the CSV encoding; errors carry the 1-based line number.
    pub fn parse_csv(text: &str, path: &Path) -> Result<Self, InputError> {
        const HEADER: [&str; 8] = [
            "mode",
            "label",
            "frequency_hz",
            "damping_ratio",
            "x_m",
            "lateral",
            "vertical",
            "torsion",
        ];
        let mut header_seen = false;
        let mut x_m: Vec<f64> = Vec::new();
        let mut modes: Vec<Mode> = Vec::new();
        let mut node = 0usize;
        for (i, raw) in text.lines().enumerate() {
            let line_no = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if !header_seen {
                if cells != HEADER {
                    return Err(InputError::line(
                        path,
                        line_no,
                        format!("expected header `{}`, found `{line}`", HEADER.join(",")),
                    ));
                }
                header_seen = true;
                continue;
            }
            if cells.len() != HEADER.len() {
                return Err(InputError::line(
                    path,
                    line_no,
                    format!("expected {} columns, found {}", HEADER.len(), cells.len()),
                ));
            }
            let num = |col: usize| -> Result<f64, InputError> {
                cells[col].parse::<f64>().map_err(|_| {
                    InputError::line(
                        path,
                        line_no,
                        format!("column `{}`: `{}` is not a number", HEADER[col], cells[col]),
                    )
                })
            };
            let mode_id: usize = cells[0].parse().map_err(|_| {
                InputError::line(
                    path,
                    line_no,
                    format!("column `mode`: `{}` is not a positive integer", cells[0]),
                )
            })?;
            let freq = num(2)?;
            let damping = if cells[3].is_empty() {
                None
            } else {
                Some(num(3)?)
            };
            let x = num(4)?;
            let (lat, ver, tor) = (num(5)?, num(6)?, num(7)?);
            if mode_id == modes.len() + 1 {
                if modes.len() > 1 && node != x_m.len() {
                    return Err(InputError::line(
                        path,
                        line_no,
                        format!(
                            "mode {} has {node} nodes, mode 1 has {}",
                            modes.len(),
                            x_m.len()
                        ),
                    ));
                }
                modes.push(Mode {
                    label: cells[1].to_string(),
                    frequency_hz: freq,
                    damping_ratio: damping,
                    lateral: Vec::new(),
                    vertical: Vec::new(),
                    torsion: Vec::new(),
                });
                node = 0;
            } else if mode_id != modes.len() || modes.is_empty() {
                return Err(InputError::line(
                    path,
                    line_no,
                    format!("mode {mode_id} out of order: modes must be numbered 1, 2, 3... with contiguous rows"),
                ));
            }
            let m = modes.last_mut().expect("a mode was pushed");
            if m.frequency_hz != freq {
                return Err(InputError::line(
                    path,
                    line_no,
                    format!("mode {mode_id}: frequency_hz {freq} differs from the mode's first row ({})", m.frequency_hz),
                ));
            }
            if modes.len() == 1 {
                if let Some(&last) = x_m.last() {
                    if x.partial_cmp(&last) != Some(std::cmp::Ordering::Greater) {
                        return Err(InputError::line(
                            path,
                            line_no,
                            format!("x_m = {x} must be greater than the previous node ({last})"),
                        ));
                    }
                }
                x_m.push(x);
            } else if node >= x_m.len() || x_m[node] != x {
                return Err(InputError::line(
                    path,
                    line_no,
                    format!(
                        "mode {mode_id}: node {} at x_m = {x} does not match mode 1's nodes",
                        node + 1
                    ),
                ));
            }
            let m = modes.last_mut().expect("a mode was pushed");
            m.lateral.push(lat);
            m.vertical.push(ver);
            m.torsion.push(tor);
            node += 1;
        }
        if !header_seen {
            return Err(InputError::line(path, 1, "empty modes file: no header"));
        }
        if modes.len() > 1 && node != x_m.len() {
            return Err(InputError::file(
                path,
                format!(
                    "mode {} has {node} nodes, mode 1 has {}",
                    modes.len(),
                    x_m.len()
                ),
            ));
        }
        Ok(ModeSet {
            format: FORMAT_TAG.to_string(),
            x_m,
            modes,
        })
    }
}
