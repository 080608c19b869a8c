//! `tbi export`: package a scenario's bridge and train (and, in a turbulent wind, the wind)
//! as FMI 2.0 Co-Simulation FMUs and an SSP 1.0 system (`system.ssp`) that wires them.
//!
//! The FMUs' binaries are the `cdylib`s `libbridge.so`, `libtrain.so` and `libwind.so` built with the
//! workspace (`cargo build --release`); they are looked up next to the `tbi` executable (or
//! in `$TBI_FMU_LIB_DIR`). The scenario's data travel in `resources/`: the modal bridge,
//! probes and wheelset count (`bridge.json`), the irregularity record (`track.csv`) and the
//! train (`train.json`), the turbulence (`wind.json`). GUIDs are derived from the build
//! identifier and those bytes (for the track record, from the bits its text is written from:
//! [`tbi_track::Irregularity::record_identity`]), so a description always matches its
//! resources. An FMU already in the folder is reused when its GUID matches and its packed
//! shared object has the length and CRC-32 of the current library.

use crate::model::Model;
use crate::package::write_fmu;
use fmi_export::dependencies::Declared;
use fmu_bridge::layout::BridgeLayout;
use fmu_bridge::{BridgeResources, ProbeSpec, BRIDGE_ID, BRIDGE_RESOURCE, TRACK_RESOURCE};
use fmu_contract::{Causality, Var, BUILD_ID};
use fmu_train::layout::TrainLayout;
use fmu_train::{TRAIN_ID, TRAIN_RESOURCE};
use fmu_wind::layout::WindLayout;
use fmu_wind::{WindResources, WIND_ID, WIND_RESOURCE};
use model_description::builder::{ModelDescriptionBuilder, RealBuilder};
use model_description::{
    DefaultExperiment, DependencyKind, Initial, ModelDescription, Unknown, Variability,
    VariableNamingConvention,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;
use tbi_dynamics::train::TrainDescription;

/// Command-line arguments of `tbi export`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// Scenario file (TOML). Default: the embedded Tsing Ma case.
    pub scenario: Option<PathBuf>,
    /// Output folder for bridge.fmu, train.fmu (wind.fmu) and system.ssp.
    #[arg(long)]
    pub out: PathBuf,
}

/// Paths and GUIDs of an export.
#[derive(Debug, Clone)]
pub struct Exported {
    pub bridge: PathBuf,
    pub train: PathBuf,
    pub ssp: PathBuf,
    /// The system description `ssp` holds (`SystemStructure.ssd`; empty when no SSP was
    /// written).
    pub ssd: String,
    pub bridge_guid: String,
    pub train_guid: String,
    pub bridge_resources: BridgeResources,
    pub train_resources: TrainDescription,
    pub bridge_layout: BridgeLayout,
    pub train_layout: TrainLayout,
    /// The wind FMU, its resources and layout, in a turbulent wind.
    pub wind: Option<(PathBuf, WindResources, WindLayout)>,
}

pub fn main(args: ExportArgs) -> Result<(), Box<dyn std::error::Error>> {
    let scenario = crate::scenario::load(args.scenario.as_deref(), None, None)?;
    let e = export_scenario(&scenario, &args.out)?;
    crate::say!(
        "{}\n{}\n{}",
        e.bridge.display(),
        e.train.display(),
        e.ssp.display()
    );
    Ok(())
}

/// `tbi export`: the scenario's FMUs and SSP into `out`, each FMU instantiated once as an
/// importer would; when one does not instantiate nothing is left exported.
pub fn export_scenario(
    scenario: &crate::scenario::Scenario,
    out: &Path,
) -> Result<Exported, Box<dyn std::error::Error>> {
    let model = crate::model::build(scenario)?;
    let e = export(&model, &scenario.coupling, out)?;
    for fmu in [&e.bridge, &e.train] {
        if let Err(why) = check_instantiates(fmu) {
            for f in [&e.bridge, &e.train, &e.ssp] {
                let _ = std::fs::remove_file(f);
            }
            return Err(format!(
                "{}: the exported FMU does not instantiate, so nothing was exported: {why}",
                fmu.display()
            )
            .into());
        }
    }
    Ok(e)
}

/// Load an exported FMU and instantiate it once, as an importer would.
pub fn check_instantiates(fmu: &Path) -> Result<(), String> {
    let loaded = fmi_import::Fmu::load(fmu).map_err(|e| e.to_string())?;
    loaded
        .instantiate(&fmi_import::InstantiateOptions {
            instance_name: Some("check".into()),
            visible: false,
            logging_on: false,
            echo_log: false,
        })
        .map(drop)
        .map_err(|e| e.to_string())
}

/// The FMUs' shared objects.
pub const LIBRARIES: [&str; 3] = ["libbridge.so", "libtrain.so", "libwind.so"];

/// The folders holding the FMU libraries in a program that embeds the tool (the Python
/// package's own copy).
static LIBRARY_DIRS: std::sync::OnceLock<Vec<PathBuf>> = std::sync::OnceLock::new();

/// Search these folders for the FMU libraries instead of the executable's (set once, by an
/// embedding program: the executable is then not the tool's).
pub fn set_library_dirs(dirs: Vec<PathBuf>) {
    let _ = LIBRARY_DIRS.set(dirs);
}

/// Directory holding `libbridge.so`, `libtrain.so` and `libwind.so`: `TBI_FMU_LIB_DIR`, then
/// the folders of [`set_library_dirs`] when an embedding program set them, else the
/// executable's folder and its parent.
pub fn library_dir() -> Result<PathBuf, String> {
    let mut candidates = Vec::new();
    if let Ok(d) = std::env::var("TBI_FMU_LIB_DIR") {
        candidates.push(PathBuf::from(d));
    }
    if let Some(dirs) = LIBRARY_DIRS.get() {
        candidates.extend(dirs.iter().cloned());
    } else if let Ok(exe) = std::env::current_exe() {
        if let Some(dir) = exe.parent() {
            candidates.push(dir.to_path_buf());
            if let Some(up) = dir.parent() {
                candidates.push(up.to_path_buf());
            }
        }
    }
    for c in &candidates {
        if LIBRARIES.iter().all(|l| c.join(l).is_file()) {
            return Ok(c.clone());
        }
    }
    Err(format!(
        "the FMU libraries libbridge.so, libtrain.so and libwind.so were not found in {:?}; build them with `cargo build --release` (workspace root) or set TBI_FMU_LIB_DIR",
        candidates
    ))
}

fn real_var(v: &Var) -> RealBuilder {
    let b = match v.causality {
        Causality::Parameter => RealBuilder::parameter(&v.name, v.vr, v.start.unwrap_or(0.0))
            .variability(Variability::Fixed)
            .initial(Initial::Exact),
        Causality::Input => RealBuilder::input(&v.name, v.vr, v.start.unwrap_or(0.0)),
        // outputs (the layouts declare no other causality)
        other => RealBuilder::output(&v.name, v.vr).causality(other),
    };
    let b = b.description(&v.description);
    if v.unit == "1" {
        b
    } else {
        b.unit(&v.unit)
    }
}

fn description_xml(
    id: &str,
    guid: &str,
    what: &str,
    vars: &[Var],
    declared: &Declared,
    (stop, step): (f64, f64),
    caps: fmi_export::CoSimulationCapabilities,
) -> Result<String, String> {
    let mut b = ModelDescriptionBuilder::new(id, guid, id)
        .description(what)
        .generation_tool(format!("tbi {}", env!("CARGO_PKG_VERSION")))
        .variable_naming_convention(VariableNamingConvention::Structured)
        .default_experiment(DefaultExperiment {
            start_time: Some(0.0),
            stop_time: Some(stop),
            tolerance: None,
            step_size: Some(step),
        })
        .capabilities(|cs| {
            cs.needs_execution_tool = caps.needs_execution_tool;
            cs.can_handle_variable_communication_step_size =
                caps.can_handle_variable_communication_step_size;
            cs.can_interpolate_inputs = caps.can_interpolate_inputs;
            cs.max_output_derivative_order = caps.max_output_derivative_order;
            cs.can_run_asynchronuously = caps.can_run_asynchronuously;
            cs.can_be_instantiated_only_once_per_process =
                caps.can_be_instantiated_only_once_per_process;
            cs.can_not_use_memory_management_functions =
                caps.can_not_use_memory_management_functions;
            cs.can_get_and_set_fmu_state = caps.can_get_and_set_fmu_state;
            cs.can_serialize_fmu_state = caps.can_serialize_fmu_state;
            cs.provides_directional_derivative = caps.provides_directional_derivative;
        });
    for (name, desc) in fmi_export::logging::LOG_CATEGORIES {
        b = b.log_category(*name, *desc);
    }
    for v in vars {
        b = b.real(real_var(v));
    }
    let mut md = b
        .build()
        .map_err(|e| format!("{id} model description: {e}"))?;
    declare_dependencies(&mut md, declared);
    let problems = md.validate();
    if !problems.is_empty() {
        return Err(format!(
            "{id} model description with dependencies: {}",
            problems.join("; ")
        ));
    }
    Ok(md.to_xml_string())
}

/// Write the probed dependencies into `<Outputs>` and `<InitialUnknowns>` (every kind
/// `dependent`: the FMUs are not linear in all their knowns, e.g. the wheelset positions).
fn declare_dependencies(md: &mut ModelDescription, declared: &Declared) {
    let index: HashMap<u32, u32> = md
        .model_variables
        .iter()
        .enumerate()
        .map(|(i, v)| (v.value_reference, i as u32 + 1))
        .collect();
    let apply = |unknowns: &mut Vec<Unknown>, list: &[(u32, Vec<u32>)]| {
        let by_index: HashMap<u32, &Vec<u32>> =
            list.iter().map(|(vr, deps)| (index[vr], deps)).collect();
        for u in unknowns.iter_mut() {
            if let Some(deps) = by_index.get(&u.index) {
                let mut d: Vec<u32> = deps.iter().map(|vr| index[vr]).collect();
                d.sort_unstable();
                u.dependencies_kind = Some(vec![DependencyKind::Dependent; d.len()]);
                u.dependencies = Some(d);
            }
        }
    };
    apply(&mut md.model_structure.outputs, &declared.outputs);
    apply(&mut md.model_structure.initial_unknowns, &declared.initial);
}

const DOC: &str = "<html><body><h1>{TITLE}</h1><p>{WHAT}</p><p>Variables follow the pattern <code>ws[i].name</code> (wheelset i, 1-based; <code>veh[i]</code> vehicle i, <code>deck[j]</code> deck point j), SI units; y right, z down, roll about x right side down. Inputs set before fmi2DoStep(t, h) are the values at t + h: an implicit (iterating) master reproduces the monolithic solution, a plain fixed-step master sees a one-step lag. Each fmi2DoStep is one Newmark (average acceleration) step of size h.</p></body></html>";

/// Package the model's FMUs and SSP into `out`. Existing files with the same GUIDs are reused.
pub fn export(model: &Model, coupling: &CouplingConfig, out: &Path) -> Result<Exported, String> {
    export_with(model, coupling, out, true)
}

/// As [`export`]; `with_ssp = false` skips `system.ssp` (the co-simulation runs do not need it).
pub fn export_with(
    model: &Model,
    coupling: &CouplingConfig,
    out: &Path,
    with_ssp: bool,
) -> Result<Exported, String> {
    // JSON has no NaN or infinity (serde would write null): refuse before writing anything.
    if let Some(what) = model.bridge.first_non_finite() {
        return Err(format!(
            "the bridge model has a number that is not finite ({what}); nothing was exported"
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let libs = library_dir()?;
    // The GUID digests what determines the track record; the record itself is written only
    // when the FMU is (re)packaged.
    let track_identity = model.track.record_identity();
    let bridge_res = BridgeResources {
        modal: model.bridge.clone(),
        probes: model
            .probes
            .iter()
            .map(|(n, x)| ProbeSpec {
                name: n.clone(),
                x_m: *x,
            })
            .collect(),
        n_wheelsets: model.train.n_wheelsets(),
        has_track_record: track_identity.is_some(),
    };
    let bridge_layout = BridgeLayout::of(&bridge_res);
    let bridge_json = serde_json::to_vec_pretty(&bridge_res).map_err(|e| e.to_string())?;
    let mut bridge_bytes = bridge_json.clone();
    if let Some(identity) = &track_identity {
        bridge_bytes.extend_from_slice(identity);
    }
    let bridge_files = || {
        let mut files = vec![(BRIDGE_RESOURCE.to_string(), bridge_json)];
        if let Some(csv) = model.track.to_record_csv() {
            files.push((TRACK_RESOURCE.to_string(), csv.into_bytes()));
        }
        files
    };
    let train_res = model.train_res.clone();
    let train_layout = TrainLayout::of(&train_res);
    let train_json = serde_json::to_vec_pretty(&train_res).map_err(|e| e.to_string())?;
    let bridge_guid = fmi_export::guid(BRIDGE_ID, BUILD_ID, &bridge_bytes);
    let train_guid = fmi_export::guid(TRAIN_ID, BUILD_ID, &train_json);
    let stop = model.t_end();
    let bridge_path = out.join(Side::Bridge.fmu_file());
    let train_path = out.join(Side::Train.fmu_file());
    let experiment = (stop, model.dt);
    let package = Packaging {
        libs: &libs,
        experiment,
    };
    // The two archives are independent: the train's is packaged on a second thread while
    // the bridge's (the larger) is on this one.
    std::thread::scope(|scope| {
        let train = scope.spawn(|| {
            package.fmu::<fmu_train::TrainFmu>(
                &train_path,
                (TRAIN_ID, &train_guid, fmu_train::layout::DESCRIPTION),
                &train_layout.variables(&train_res),
                || fmu_train::TrainFmu::dependencies(&train_res),
                || vec![(TRAIN_RESOURCE.to_string(), train_json)],
            )
        });
        let bridge = package.fmu::<fmu_bridge::BridgeFmu>(
            &bridge_path,
            (BRIDGE_ID, &bridge_guid, fmu_bridge::layout::DESCRIPTION),
            &bridge_layout.variables(&bridge_res),
            || fmu_bridge::BridgeFmu::dependencies(&bridge_res, model.track.clone() as _),
            bridge_files,
        );
        let train = train
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        bridge.and(train)
    })?;
    let wind = match &model.bridge.buffeting {
        Some(spec) => {
            let res = WindResources {
                mean_speed_m_s: spec.mean_speed_m_s,
                turbulence: spec.turbulence.clone(),
                points_m: spec
                    .points_on(model.bridge.x_start_m, model.bridge.x_end_m)
                    .0,
                duration_s: spec.duration_s,
                n_vehicles: model.train_res.spec.n_vehicles(),
                record: None,
                admittance: spec.admittance.map(|c| (c, spec.width_m)),
            };
            let res = WindResources {
                record: spec
                    .record
                    .as_ref()
                    .map(|_| spec.generate(&res.points_m))
                    .transpose()?,
                ..res
            };
            let layout = WindLayout::of(&res);
            let json = serde_json::to_vec_pretty(&res).map_err(|e| e.to_string())?;
            let guid = fmi_export::guid(WIND_ID, BUILD_ID, &json);
            let path = out.join(Side::Wind.fmu_file());
            package.fmu::<fmu_wind::WindFmu>(
                &path,
                (WIND_ID, &guid, fmu_wind::layout::DESCRIPTION),
                &layout.variables(&res),
                || fmu_wind::WindFmu::dependencies(&res),
                || vec![(WIND_RESOURCE.to_string(), json)],
            )?;
            Some((path, res, layout))
        }
        None => None,
    };
    let ssp = out.join("system.ssp");
    let mut ssd = String::new();
    if with_ssp {
        let mut parts = vec![
            (
                Side::Bridge,
                bridge_path.clone(),
                bridge_layout.variables(&bridge_res),
            ),
            (
                Side::Train,
                train_path.clone(),
                train_layout.variables(&train_res),
            ),
        ];
        if let Some((path, res, layout)) = &wind {
            parts.push((Side::Wind, path.clone(), layout.variables(res)));
        }
        let links = connections(&bridge_layout, &train_layout, wind.as_ref().map(|w| &w.2))?;
        let probe_names: Vec<String> = model.probes.iter().map(|p| p.0.clone()).collect();
        let outputs = system_outputs(&parts, &probe_names);
        ssd = write_ssp(
            &ssp,
            &parts,
            &links,
            &outputs,
            stop,
            (coupling, model.dt, model.output_every),
        )?;
    }
    Ok(Exported {
        bridge: bridge_path,
        train: train_path,
        ssp,
        ssd,
        bridge_guid,
        train_guid,
        bridge_resources: bridge_res,
        train_resources: train_res,
        bridge_layout,
        train_layout,
        wind,
    })
}

/// Where the FMUs' shared objects are and the default experiment (stop time, step) their
/// descriptions declare.
struct Packaging<'a> {
    libs: &'a Path,
    experiment: (f64, f64),
}

impl Packaging<'_> {
    /// Write the FMU `(id, guid, description)` with these variables, dependencies and
    /// resource files (both made only when it is written) to `path`, unless the file there
    /// has this GUID and shared object already.
    fn fmu<M: fmi_export::FmuModel>(
        &self,
        path: &Path,
        (id, guid, what): (&str, &str, &str),
        vars: &[Var],
        dependencies: impl FnOnce() -> Result<Declared, String>,
        files: impl FnOnce() -> Vec<(String, Vec<u8>)>,
    ) -> Result<(), String> {
        let so = self.libs.join(format!("lib{id}.so"));
        if is_current(path, guid, id, &so) {
            return Ok(());
        }
        let (stop, step) = self.experiment;
        let caps = fmi_export::capabilities_of::<M>();
        let xml = description_xml(id, guid, what, vars, &dependencies()?, (stop, step), caps)?;
        let doc = DOC.replace("{TITLE}", id).replace("{WHAT}", what);
        // the error names the file
        write_fmu(path, &xml, id, &so, &files(), Some(&doc)).map_err(|e| e.to_string())
    }
}

/// Whether `fmu` exists with this GUID and this shared object (so a rebuilt library is
/// always repackaged). The packed library is compared by its length and by the CRC-32 the
/// archive's directory records, so nothing is inflated.
fn is_current(fmu: &Path, guid: &str, id: &str, so: &Path) -> bool {
    use std::io::Read;
    let Ok(f) = std::fs::File::open(fmu) else {
        return false;
    };
    let Ok(mut z) = zip::ZipArchive::new(f) else {
        return false;
    };
    let mut s = String::new();
    match z.by_name("modelDescription.xml") {
        Ok(mut md) => {
            if md.read_to_string(&mut s).is_err() {
                return false;
            }
        }
        Err(_) => return false,
    }
    if !s.contains(&format!("guid=\"{guid}\"")) {
        return false;
    }
    let (size, crc) = match z.by_name(&format!("binaries/linux64/{id}.so")) {
        Ok(b) => (b.size(), b.crc32()),
        Err(_) => return false,
    };
    length_and_crc(so)
        .map(|(len, c)| len == size && c == crc)
        .unwrap_or(false)
}

/// The FMUs of the coupled system, in the order of [`tbi_coupling::System`]'s
/// participants (the wind last, in a turbulent wind only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Bridge = 0,
    Train = 1,
    Wind = 2,
}

/// The folder of the system archive that holds the FMUs (its components' `source`).
pub const SSP_FMU_FOLDER: &str = "resources/";

impl Side {
    /// The SSP component name.
    pub fn name(self) -> &'static str {
        match self {
            Side::Bridge => "bridge",
            Side::Train => "train",
            Side::Wind => "wind",
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

/// One connection: an output of one FMU feeds an input of the other; the variable has the
/// same name on both sides.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Link {
    pub from: Side,
    pub from_vr: u32,
    pub to: Side,
    pub to_vr: u32,
    pub name: String,
}

/// The connections of the coupled system, from the layouts: per wheelset, its
/// [`WHEEL_CHANNELS`](fmu_contract::WHEEL_CHANNELS) train → bridge, then its
/// [`RAIL_CHANNELS`](fmu_contract::RAIL_CHANNELS) bridge → train; with a wind
/// FMU, per car body its position train → wind and its along-wind turbulence wind → train,
/// then per deck point its turbulence wind → bridge.
pub fn connections(
    b: &BridgeLayout,
    t: &TrainLayout,
    wind: Option<&WindLayout>,
) -> Result<Vec<Link>, String> {
    if b.n_wheelsets() != t.n_wheelsets() {
        return Err(format!(
            "the bridge FMU has {} wheelsets, the train FMU {}",
            b.n_wheelsets(),
            t.n_wheelsets()
        ));
    }
    let mut c = Vec::new();
    for w in 0..b.n_wheelsets() {
        for k in 0..b.wheel_in.width() {
            c.push(Link {
                from: Side::Train,
                from_vr: t.wheel_out.vr(w, k),
                to: Side::Bridge,
                to_vr: b.wheel_in.vr(w, k),
                name: b.wheel_in.name(w, k),
            });
        }
        for k in 0..b.rail_out.width() {
            c.push(Link {
                from: Side::Bridge,
                from_vr: b.rail_out.vr(w, k),
                to: Side::Train,
                to_vr: t.rail_in.vr(w, k),
                name: b.rail_out.name(w, k),
            });
        }
    }
    if let Some(wl) = wind {
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
                from: Side::Train,
                from_vr: t.body_x_out.vr(i, 0),
                to: Side::Wind,
                to_vr: wl.body_in.vr(i, 0),
                name: wl.body_in.name(i, 0),
            });
            c.push(Link {
                from: Side::Wind,
                from_vr: wl.body_out.vr(i, 0),
                to: Side::Train,
                to_vr: t.wind_in.vr(i, 0),
                name: t.wind_in.name(i, 0),
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
fn system_outputs(
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
                (Side::Train, "veh") => format!("veh{k}.{channel}"),
                _ => continue,
            };
            out.push((name, *side, v.name.clone()));
        }
    }
    out
}

/// Writes the system archive (unless the one at `path` is current) and returns its
/// description.
fn write_ssp(
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
        let name = xml_escape(&link.name);
        conns.push_str(&format!(
            "      <ssd:Connection startElement=\"{}\" startConnector=\"{name}\" endElement=\"{}\" endConnector=\"{name}\"/>\n",
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
        crate::ssp::COUPLING_ANNOTATION,
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
        crate::outdir::replace_atomically(path, |tmp| write_ssp_zip(tmp, &ssd, &fmus))?;
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
fn length_and_crc(path: &Path) -> std::io::Result<(u64, u32)> {
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
