//! The system the project exports, written as SSP 1.0: the components (bridge, train and
//! wind FMUs), their connections from the FMU layouts, the system's recorded outputs and the
//! coupling annotation, into `SystemStructure.ssd` and the `.ssp` archive.

use fmu_bridge::layout::BridgeLayout;
use fmu_contract::{Causality, Var};
use fmu_train::layout::TrainLayout;
use fmu_wind::layout::WindLayout;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;
use tbi_ssp::SSP_FMU_FOLDER;

/// The FMUs of the coupled system, in the order of [`tbi_coupling::System`]'s
/// participants: the bridge, each train (one FMU per train), and the wind last (in a
/// turbulent wind only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Bridge,
    /// Train `k` (0-based).
    Train(usize),
    Wind,
}

impl Side {
    /// The SSP component name: `bridge`, `train` (the first train), `train2`, …, `wind`.
    pub fn name(self) -> String {
        match self {
            Side::Bridge => "bridge".into(),
            Side::Train(0) => "train".into(),
            Side::Train(k) => format!("train{}", k + 1),
            Side::Wind => "wind".into(),
        }
    }

    /// Its participant index in a system of `n_trains` trains.
    pub fn index(self, n_trains: usize) -> usize {
        match self {
            Side::Bridge => 0,
            Side::Train(k) => 1 + k,
            Side::Wind => 1 + n_trains,
        }
    }

    /// The FMU's file in the export folder, `<name>.fmu`.
    pub fn fmu_file(self) -> String {
        format!("{}.fmu", self.name())
    }

    /// The FMU's entry in the system archive, its component's `source`:
    /// [`SSP_FMU_FOLDER`] + [`Side::fmu_file`].
    pub fn ssp_source(self) -> String {
        format!("{SSP_FMU_FOLDER}{}", self.fmu_file())
    }
}

/// One connection: an output of one FMU feeds an input of the other. The variable has the
/// same name on both sides (`name`) except where a train's wheelset meets the bridge slot
/// it fills, which a later train's wheelsets number on from the trains before it
/// (`to_name`, the input's name, then).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Link {
    pub from: Side,
    pub from_vr: u32,
    pub to: Side,
    pub to_vr: u32,
    /// The output's name.
    pub name: String,
    /// The input's name when it differs.
    pub to_name: Option<String>,
}

impl Link {
    /// The input's name.
    pub fn input_name(&self) -> &str {
        self.to_name.as_deref().unwrap_or(&self.name)
    }
}

/// The connections of the coupled system, from the layouts: per wheelset, its
/// [`WHEEL_CHANNELS`](fmu_contract::WHEEL_CHANNELS) train → bridge, then its
/// [`RAIL_CHANNELS`](fmu_contract::RAIL_CHANNELS) bridge → train, the wheelsets of the first
/// train in the bridge's first slots, the next train's after them, and so on; with a wind
/// FMU (one train), per car body its position train → wind and its along-wind turbulence
/// wind → train, then per deck point its turbulence wind → bridge.
pub fn connections(
    b: &BridgeLayout,
    trains: &[&TrainLayout],
    wind: Option<&WindLayout>,
) -> Result<Vec<Link>, String> {
    let total: usize = trains.iter().map(|t| t.n_wheelsets()).sum();
    if b.n_wheelsets() != total {
        return Err(format!(
            "the bridge FMU has {} wheelsets, the train FMUs {total}",
            b.n_wheelsets(),
        ));
    }
    if wind.is_some() && trains.len() != 1 {
        return Err(format!(
            "a wind FMU couples to one train FMU, not {}",
            trains.len()
        ));
    }
    let mut c = Vec::new();
    let mut slot = 0;
    for (i, t) in trains.iter().enumerate() {
        for w in 0..t.n_wheelsets() {
            let s = slot + w;
            for k in 0..b.wheel_in.width() {
                c.push(Link {
                    from: Side::Train(i),
                    from_vr: t.wheel_out.vr(w, k),
                    to: Side::Bridge,
                    to_vr: b.wheel_in.vr(s, k),
                    name: t.wheel_out.name(w, k),
                    to_name: (s != w).then(|| b.wheel_in.name(s, k)),
                });
            }
            for k in 0..b.rail_out.width() {
                c.push(Link {
                    from: Side::Bridge,
                    from_vr: b.rail_out.vr(s, k),
                    to: Side::Train(i),
                    to_vr: t.rail_in.vr(w, k),
                    name: b.rail_out.name(s, k),
                    to_name: (s != w).then(|| t.rail_in.name(w, k)),
                });
            }
        }
        slot += t.n_wheelsets();
    }
    if let (Some(wl), [t]) = (wind, trains) {
        if wl.body_in.count != t.body_x_out.count || wl.deck_out.count != b.wind_in.count {
            return Err(format!(
                "the wind FMU has {} car bodies and {} deck points, the train FMU {} car bodies, the bridge FMU {} deck points",
                wl.body_in.count,
                wl.deck_out.count,
                t.body_x_out.count,
                b.wind_in.count
            ));
        }
        for i in 0..wl.body_in.count {
            c.push(Link {
                from: Side::Train(0),
                from_vr: t.body_x_out.vr(i, 0),
                to: Side::Wind,
                to_vr: wl.body_in.vr(i, 0),
                name: wl.body_in.name(i, 0),
                to_name: None,
            });
            c.push(Link {
                from: Side::Wind,
                from_vr: wl.body_out.vr(i, 0),
                to: Side::Train(0),
                to_vr: t.wind_in.vr(i, 0),
                name: t.wind_in.name(i, 0),
                to_name: None,
            });
        }
        for j in 0..wl.deck_out.count {
            for k in 0..wl.deck_out.width() {
                c.push(Link {
                    from: Side::Wind,
                    from_vr: wl.deck_out.vr(j, k),
                    to: Side::Bridge,
                    to_vr: b.wind_in.vr(j, k),
                    name: b.wind_in.name(j, k),
                    to_name: None,
                });
            }
        }
    }
    Ok(c)
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The system's own outputs, `(name, component, variable)`: each probe's deck response by
/// the probe's name (`mid.z` for the bridge's `probe[1].z`), each car body's accelerations
/// (`veh1.a_z` for the train's `veh[1].a_z`).
pub(crate) fn system_outputs(
    parts: &[(Side, PathBuf, Vec<Var>)],
    probe_names: &[String],
) -> Vec<(String, Side, String)> {
    let mut out = Vec::new();
    for (side, _, vars) in parts {
        for v in vars.iter().filter(|v| v.causality == Causality::Output) {
            let Some((block, channel)) = v.name.split_once("].") else {
                continue;
            };
            let Some((prefix, k)) = block.split_once('[') else {
                continue;
            };
            let Ok(k) = k.parse::<usize>() else { continue };
            let name = match (side, prefix) {
                (Side::Bridge, "probe") => match probe_names.get(k - 1) {
                    Some(p) => format!("{p}.{channel}"),
                    None => continue,
                },
                (Side::Train(0), "veh") => format!("veh{k}.{channel}"),
                (Side::Train(i), "veh") => format!("train{}.veh{k}.{channel}", i + 1),
                _ => continue,
            };
            out.push((name, *side, v.name.clone()));
        }
    }
    out
}

/// Writes the system archive (unless the one at `path` is current) and returns its
/// description.
pub(crate) fn write_ssp(
    path: &Path,
    parts: &[(Side, PathBuf, Vec<Var>)],
    links: &[Link],
    outputs: &[(String, Side, String)],
    stop: f64,
    (coupling, step, output_every): (&CouplingConfig, f64, usize),
) -> Result<String, String> {
    let annotation: String = coupling
        .attributes()
        .iter()
        .map(|(k, v)| format!(" {k}=\"{}\"", xml_escape(v)))
        .collect();
    let connectors = |vars: &[Var]| -> String {
        vars.iter()
            .filter(|v| v.causality != Causality::Parameter)
            .map(|v| {
                let kind = if v.causality == Causality::Input { "input" } else { "output" };
                format!("          <ssd:Connector name=\"{}\" kind=\"{kind}\"><ssc:Real/></ssd:Connector>\n", xml_escape(&v.name))
            })
            .collect()
    };
    let components: String = parts
        .iter()
        .map(|(side, _, vars)| {
            let (n, source) = (side.name(), side.ssp_source());
            format!(
                "      <ssd:Component name=\"{n}\" type=\"application/x-fmu-sharedlibrary\" source=\"{source}\">\n        <ssd:Connectors>\n{}        </ssd:Connectors>\n      </ssd:Component>\n",
                connectors(vars)
            )
        })
        .collect();
    let mut conns = String::new();
    for link in links {
        let (from, to) = (xml_escape(&link.name), xml_escape(link.input_name()));
        conns.push_str(&format!(
            "      <ssd:Connection startElement=\"{}\" startConnector=\"{from}\" endElement=\"{}\" endConnector=\"{to}\"/>\n",
            link.from.name(),
            link.to.name(),
        ));
    }
    let ssd = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:tbi="urn:tbi:coupling" version="1.0" name="train-bridge">
  <ssd:System name="train-bridge">
    <ssd:Elements>
{}    </ssd:Elements>
    <ssd:Connections>
{}    </ssd:Connections>
    <ssd:Annotations>
      <ssc:Annotation type="{}">
        <tbi:Coupling step_size="{step}" output_interval="{}"{annotation}>
{}        </tbi:Coupling>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="{stop}"/>
</ssd:SystemStructureDescription>
"#,
        components,
        conns,
        tbi_ssp::COUPLING_ANNOTATION,
        step * output_every as f64,
        outputs
            .iter()
            .map(|(name, side, var)| format!(
                "          <tbi:Output name=\"{}\" element=\"{}\" connector=\"{}\"/>\n",
                xml_escape(name),
                side.name(),
                xml_escape(var)
            ))
            .collect::<String>(),
    );
    let identities: Vec<(String, u64, u32)> = parts
        .iter()
        .map(|(side, fmu, _)| {
            length_and_crc(fmu)
                .map(|(len, crc)| (side.ssp_source(), len, crc))
                .map_err(|e| format!("{}: {e}", fmu.display()))
        })
        .collect::<Result<_, _>>()?;
    if !ssp_is_current(path, &ssd, &identities) {
        let fmus: Vec<(String, Vec<u8>)> = parts
            .iter()
            .map(|(side, fmu, _)| {
                std::fs::read(fmu)
                    .map(|bytes| (side.ssp_source(), bytes))
                    .map_err(|e| format!("{}: {e}", fmu.display()))
            })
            .collect::<Result<_, _>>()?;
        // the system is complete or untouched
        crate::output::outdir::replace_atomically(path, |tmp| write_ssp_zip(tmp, &ssd, &fmus))?;
    }
    Ok(ssd)
}

/// The SSP archive: the description, deflated, and the FMUs (zip archives already) stored.
fn write_ssp_zip(path: &Path, ssd: &str, fmus: &[(String, Vec<u8>)]) -> std::io::Result<()> {
    use std::io::Write;
    let mut z = zip::ZipWriter::new(std::io::BufWriter::new(std::fs::File::create(path)?));
    let deflated = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    z.start_file("SystemStructure.ssd", deflated)?;
    z.write_all(ssd.as_bytes())?;
    for (name, bytes) in fmus {
        z.start_file(
            name,
            deflated.compression_method(zip::CompressionMethod::Stored),
        )?;
        z.write_all(bytes)?;
    }
    z.finish()?.flush()
}

/// The length of the file at `path` and its CRC-32, read through a small buffer (a file of
/// megabytes is not held in memory for it).
pub(crate) fn length_and_crc(path: &Path) -> std::io::Result<(u64, u32)> {
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let mut hasher = crc32fast::Hasher::new();
    let mut buffer = vec![0; 1 << 16];
    let mut len = 0u64;
    loop {
        match file.read(&mut buffer) {
            Ok(0) => return Ok((len, hasher.finalize())),
            Ok(n) => {
                hasher.update(&buffer[..n]);
                len += n as u64;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

/// Whether the SSP at `path` has this description and these FMUs (entry name, length and
/// CRC-32 of each, compared with those the archive's directory records), so that it need
/// not be written.
fn ssp_is_current(path: &Path, ssd: &str, fmus: &[(String, u64, u32)]) -> bool {
    use std::io::Read;
    let archive = std::fs::File::open(path).map(zip::ZipArchive::new);
    let Ok(Ok(mut z)) = archive else {
        return false;
    };
    if z.len() != fmus.len() + 1 {
        return false;
    }
    let mut text = String::new();
    let same_ssd = z
        .by_name("SystemStructure.ssd")
        .is_ok_and(|mut e| e.read_to_string(&mut text).is_ok() && text == ssd);
    same_ssd
        && fmus.iter().all(|(name, len, crc)| {
            z.by_name(name)
                .is_ok_and(|e| e.size() == *len && e.crc32() == *crc)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmi_import::archive::UnpackedDir;

    #[test]
    fn a_system_archive_is_current_only_with_the_same_description_and_fmus() {
        let dir = UnpackedDir::create("tbi-export-test").unwrap();
        let path = dir.path().join("system.ssp");
        let fmus = vec![
            ("resources/a.fmu".to_owned(), b"first archive".to_vec()),
            ("resources/b.fmu".to_owned(), b"second".to_vec()),
        ];
        // each FMU's identity as the export takes it, from its file
        let ids = |fmus: &[(String, Vec<u8>)]| -> Vec<(String, u64, u32)> {
            fmus.iter()
                .map(|(name, bytes)| {
                    let file = dir.path().join("fmu");
                    std::fs::write(&file, bytes).unwrap();
                    let (len, crc) = length_and_crc(&file).unwrap();
                    (name.clone(), len, crc)
                })
                .collect()
        };
        assert!(!ssp_is_current(&path, "<ssd/>", &ids(&fmus)), "no file yet");
        write_ssp_zip(&path, "<ssd/>", &fmus).unwrap();
        assert!(ssp_is_current(&path, "<ssd/>", &ids(&fmus)));
        assert!(
            !ssp_is_current(&path, "<ssd />", &ids(&fmus)),
            "another description"
        );
        let mut changed = fmus.clone();
        changed[1].1 = b"secone".to_vec(); // same length, other bytes
        assert!(!ssp_is_current(&path, "<ssd/>", &ids(&changed)));
        assert!(
            !ssp_is_current(&path, "<ssd/>", &ids(&fmus[..1])),
            "one FMU fewer"
        );
        let mut more = fmus.clone();
        more.push(("resources/c.fmu".to_owned(), Vec::new()));
        assert!(
            !ssp_is_current(&path, "<ssd/>", &ids(&more)),
            "one FMU more"
        );
        std::fs::write(&path, b"not a zip").unwrap();
        assert!(!ssp_is_current(&path, "<ssd/>", &ids(&fmus)));
    }

    /// A file's length and CRC-32 through the buffer equal those of its bytes at once, also
    /// for a file several buffers long and for an empty one.
    #[test]
    fn a_files_length_and_crc_equal_its_bytes() {
        let dir = UnpackedDir::create("tbi-export-crc").unwrap();
        for n in [0usize, 1, 65_535, 65_536, 200_003] {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 7 + i / 251) as u8).collect();
            let file = dir.path().join(format!("f{n}"));
            std::fs::write(&file, &bytes).unwrap();
            assert_eq!(
                length_and_crc(&file).unwrap(),
                (n as u64, crc32fast::hash(&bytes)),
                "{n} bytes"
            );
        }
    }
}
