//! An SSP system opened from a `.ssp` archive (unpacked) or an `.ssd` in a folder, its
//! `.ssv` files read, and its annotation's coupling options and outputs.

use super::read::{parse_ssd, parse_ssv, Ssd};
use fmi_import::archive::UnpackedDir;
use fmi_import::UnpackLimits;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;

/// An SSP system on disk: its description and where its files are.
pub struct OpenSystem {
    pub ssd: Ssd,
    /// Where `source` paths are resolved.
    pub base: PathBuf,
    /// The unpacked archive (removed on drop), if it was one.
    pub(super) _unpacked: Option<UnpackedDir>,
    /// The file named on the command line, for messages.
    pub origin: String,
}

/// Open a `.ssp` archive, or a `SystemStructure.ssd` file.
pub fn open(path: &Path) -> Result<OpenSystem, String> {
    let origin = path.display().to_string();
    let (base, unpacked, ssd_path) = if path.extension().is_some_and(|e| e == "ssd") {
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        (base, None, path.to_path_buf())
    } else {
        let dir = fmi_import::archive::unpack(path, &UnpackLimits::default())
            .map_err(|e| e.to_string())?;
        let ssd = dir.path().join("SystemStructure.ssd");
        if !ssd.is_file() {
            return Err(format!(
                "{origin}: the archive has no SystemStructure.ssd at its root"
            ));
        }
        (dir.path().to_path_buf(), Some(dir), ssd)
    };
    let text = tbi_modes::input::read_text(&ssd_path, tbi_modes::input::MAX_SCENARIO_BYTES)
        .map_err(|e| format!("{origin}: SystemStructure.ssd: {e}"))?;
    let mut ssd = parse_ssd(&text, &format!("{origin}: SystemStructure.ssd"))?;
    if unpacked.is_some() {
        for c in &ssd.components {
            for source in std::iter::once(&c.source).chain(&c.parameter_files) {
                if !inside_archive(source) {
                    return Err(format!(
                        "{origin}: SystemStructure.ssd: component \"{}\": source \"{source}\" lies outside the archive; an .ssp refers to its own files by relative paths",
                        c.name
                    ));
                }
            }
        }
    }
    for c in &mut ssd.components {
        for f in c.parameter_files.clone() {
            let p = base.join(&f);
            let text = tbi_modes::input::read_text(&p, tbi_modes::input::MAX_SCENARIO_BYTES)
                .map_err(|e| format!("{origin}: {f}: {e}"))?;
            c.parameters
                .extend(parse_ssv(&text, &format!("{origin}: {f}"))?);
        }
    }
    Ok(OpenSystem {
        ssd,
        base,
        _unpacked: unpacked,
        origin,
    })
}

/// Whether `source` names a file inside the archive: a relative path that never climbs out
/// (no root, no `..`, no drive prefix).
fn inside_archive(source: &str) -> bool {
    use std::path::Component;
    !source.is_empty()
        && Path::new(source)
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir))
}

/// The system just exported to `ssp` with description `ssd` (the text the archive holds),
/// its components' FMUs read where the exporter wrote them beside the archive (a component
/// whose `source` is [`crate::SSP_FMU_FOLDER`]`x.fmu` is read from `x.fmu` in the archive's
/// folder), so that the archive is not unpacked only to copy them out again. Everything
/// after the opening is the path `open` leads to.
pub fn open_exported(ssd: &str, ssp: &Path) -> Result<OpenSystem, String> {
    let origin = ssp.display().to_string();
    let mut ssd = parse_ssd(ssd, &format!("{origin}: SystemStructure.ssd"))?;
    for c in &mut ssd.components {
        let Some(file) = c.source.strip_prefix(crate::SSP_FMU_FOLDER) else {
            return Err(format!(
                "{origin}: component \"{}\": source {} is not an exported FMU",
                c.name, c.source
            ));
        };
        c.source = file.to_owned();
    }
    Ok(OpenSystem {
        ssd,
        base: ssp.parent().map(Path::to_path_buf).unwrap_or_default(),
        _unpacked: None,
        origin,
    })
}

impl OpenSystem {
    /// The coupling options of the annotation.
    /// The annotation's `output_interval` (s): the time between the rows `tbi cosim` writes
    /// by default (`tbi export` writes the scenario's `dt_s × output_every`).
    pub fn output_interval(&self) -> Result<Option<f64>, String> {
        self.ssd
            .coupling
            .iter()
            .find(|(k, _)| k == "output_interval")
            .map(|(_, v)| {
                v.parse::<f64>().map_err(|_| {
                    format!(
                        "{}: coupling annotation: output_interval=\"{v}\" is not a number",
                        self.origin
                    )
                })
            })
            .transpose()
    }

    pub fn coupling(&self) -> Result<(CouplingConfig, Option<f64>), String> {
        let mut step = None;
        let mut toml = String::new();
        for (k, v) in &self.ssd.coupling {
            if k == "output_interval" {
                continue;
            }
            if k == "step_size" {
                step = Some(v.parse::<f64>().map_err(|_| {
                    format!(
                        "{}: coupling annotation: step_size=\"{v}\" is not a number",
                        self.origin
                    )
                })?);
                continue;
            }
            let value = if v.parse::<f64>().is_ok() {
                v.clone()
            } else {
                format!("{v:?}")
            };
            toml.push_str(&format!("{k} = {value}\n"));
        }
        let cfg: CouplingConfig = toml::from_str(&toml)
            .map_err(|e| format!("{}: coupling annotation: {}", self.origin, e.message()))?;
        cfg.validate()
            .map_err(|e| format!("{}: coupling annotation: {e}", self.origin))?;
        Ok((cfg, step))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn archive_sources_stay_inside_it() {
        for ok in ["resources/a.fmu", "a.fmu", "./x/b.ssv"] {
            assert!(super::inside_archive(ok), "{ok}");
        }
        for out in ["/etc/a.fmu", "../a.fmu", "x/../../a.fmu", ""] {
            assert!(!super::inside_archive(out), "{out}");
        }
    }
}
