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

use crate::fmus::package::{write_fmu, write_fmu3, FMI3_PLATFORM};
use crate::fmus::ssd::{connections, length_and_crc, system_outputs, write_ssp, Side};
use crate::model::Model;
use fmi_export::dependencies::Declared;
use fmu_bridge::layout::BridgeLayout;
use fmu_bridge::package::BridgePackage;
use fmu_bridge::{BridgeResources, ProbeSpec};
use fmu_contract::{Causality, Contract, Var};
use fmu_train::layout::TrainLayout;
use fmu_train::package::TrainPackage;
use fmu_wind::layout::WindLayout;
use fmu_wind::package::WindPackage;
use fmu_wind::WindResources;
use model_description::builder::{ModelDescriptionBuilder, RealBuilder};
use model_description::{
    DefaultExperiment, DependencyKind, Initial, ModelDescription, Unknown, Variability,
    VariableNamingConvention,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tbi_coupling::CouplingConfig;
use tbi_dynamics::train::TrainDescription;

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
    /// The trains after the first (`train2.fmu`, …), each its own FMU.
    pub more_trains: Vec<ExportedTrain>,
    /// The wind FMU, its resources and layout, in a turbulent wind.
    pub wind: Option<(PathBuf, WindResources, WindLayout)>,
}

/// A train FMU of an export.
#[derive(Debug, Clone)]
pub struct ExportedTrain {
    pub path: PathBuf,
    pub guid: String,
    pub resources: TrainDescription,
    pub layout: TrainLayout,
}

/// `tbi export`: the scenario's FMUs and SSP into `out`, each FMU instantiated once as an
/// importer would; when one does not instantiate nothing is left exported.
pub fn export_scenario(
    scenario: &crate::scenario::Scenario,
    out: &Path,
    version: FmiVersion,
) -> Result<Exported, Box<dyn std::error::Error>> {
    let model = crate::model::build(scenario)?;
    let e = export_with(&model, &scenario.coupling, out, true, version)?;
    if version == FmiVersion::V3 {
        // the importer loads FMI 2.0 FMUs only: the FMI 3.0 ones are checked by their tests
        // (FMPy validates and simulates them)
        return Ok(e);
    }
    let mut fmus = vec![&e.bridge, &e.train];
    fmus.extend(e.more_trains.iter().map(|t| &t.path));
    for fmu in &fmus {
        if let Err(why) = check_instantiates(fmu) {
            for f in fmus.iter().chain([&&e.ssp]) {
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
) -> Result<ModelDescription, String> {
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
    Ok(md)
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

/// The FMI version of the FMUs written: 2.0 (the default) or 3.0, from the same models,
/// binaries and variables (FMI 3.0 adds the independent variable `time`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FmiVersion {
    #[default]
    V2,
    V3,
}

impl FmiVersion {
    /// `2` → 2.0, `3` → 3.0.
    pub fn from_major(major: u8) -> Result<FmiVersion, String> {
        match major {
            2 => Ok(FmiVersion::V2),
            3 => Ok(FmiVersion::V3),
            _ => Err(format!("FMI version {major}: expected 2 or 3")),
        }
    }
}

/// Package the model's FMUs and SSP into `out`. Existing files with the same GUIDs are reused.
pub fn export(model: &Model, coupling: &CouplingConfig, out: &Path) -> Result<Exported, String> {
    export_with(model, coupling, out, true, FmiVersion::V2)
}

/// As [`export`]; `with_ssp = false` skips `system.ssp` (the co-simulation runs do not need
/// it), and `version` chooses FMI 2.0 or 3.0 FMUs.
pub fn export_with(
    model: &Model,
    coupling: &CouplingConfig,
    out: &Path,
    with_ssp: bool,
    version: FmiVersion,
) -> Result<Exported, String> {
    // JSON has no NaN or infinity (serde would write null): refuse before writing anything.
    if let Some(what) = model.bridge.first_non_finite() {
        return Err(format!(
            "the bridge model has a number that is not finite ({what}); nothing was exported"
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let libs = library_dir()?;
    let bridge = BridgePackage::new(bridge_resources(model), model.track.clone())?;
    let trains = (model.trains.iter())
        .map(|t| TrainPackage::new(t.clone()))
        .collect::<Result<Vec<_>, _>>()?;
    let wind = wind_resources(model)?.map(WindPackage::new).transpose()?;
    let mut fmus: Vec<(Side, &dyn Contract)> = vec![(Side::Bridge, &bridge)];
    for (k, t) in trains.iter().enumerate() {
        fmus.push((Side::Train(k), t));
    }
    if let Some(w) = &wind {
        fmus.push((Side::Wind, w));
    }
    let packaging = Packaging {
        libs: &libs,
        experiment: (model.t_end(), model.dt),
        version,
    };
    // The archives are independent: each is packaged on a thread of its own.
    std::thread::scope(|scope| {
        let jobs: Vec<_> = (fmus.iter())
            .map(|&(side, contract)| {
                let path = out.join(side.fmu_file());
                scope.spawn(move || packaging.fmu(&path, contract))
            })
            .collect();
        (jobs.into_iter())
            .map(|job| job.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect::<Result<Vec<()>, String>>()
    })?;
    let ssp = out.join("system.ssp");
    let mut ssd = String::new();
    if with_ssp {
        let parts: Vec<(Side, PathBuf, Vec<Var>)> = (fmus.iter())
            .map(|&(side, c)| (side, out.join(side.fmu_file()), c.variables()))
            .collect();
        let layouts: Vec<&TrainLayout> = trains.iter().map(|t| &t.layout).collect();
        let links = connections(&bridge.layout, &layouts, wind.as_ref().map(|w| &w.layout))?;
        let probe_names: Vec<String> = model.probes.iter().map(|p| p.0.clone()).collect();
        let outputs = system_outputs(&parts, &probe_names);
        ssd = write_ssp(
            &ssp,
            &parts,
            &links,
            &outputs,
            model.t_end(),
            (coupling, model.dt, model.output_every),
        )?;
    }
    let mut trains = trains.into_iter().enumerate().map(|(k, t)| ExportedTrain {
        path: out.join(Side::Train(k).fmu_file()),
        guid: t.guid(),
        resources: t.resources,
        layout: t.layout,
    });
    let train = trains.next().expect("a train");
    Ok(Exported {
        bridge: out.join(Side::Bridge.fmu_file()),
        train: train.path,
        ssp,
        ssd,
        bridge_guid: bridge.guid(),
        train_guid: train.guid,
        bridge_resources: bridge.resources,
        train_resources: train.resources,
        bridge_layout: bridge.layout,
        train_layout: train.layout,
        more_trains: trains.collect(),
        wind: wind.map(|w| (out.join(Side::Wind.fmu_file()), w.resources, w.layout)),
    })
}

/// The bridge FMU's resources: the model's modal bridge, probes and wheelsets.
fn bridge_resources(model: &Model) -> BridgeResources {
    BridgeResources {
        modal: model.bridge.clone(),
        probes: (model.probes.iter())
            .map(|(n, x)| ProbeSpec {
                name: n.clone(),
                x_m: *x,
            })
            .collect(),
        n_wheelsets: model.train.n_wheelsets(),
        wheelset_tracks: wheelset_tracks(&model.train),
        has_track_record: false,
    }
}

/// The track of each wheelset of `train`, empty when all run on the first (as a one-track
/// bridge's resources have always been).
fn wheelset_tracks(train: &tbi_dynamics::train::Train) -> Vec<usize> {
    let tracks: Vec<usize> = (train.wheelsets().iter())
        .map(|w| train.runs[w.run].track)
        .collect();
    if tracks.iter().all(|&k| k == 0) {
        return Vec::new();
    }
    tracks
}

/// The wind FMU's resources in a turbulent wind (a measured record resampled at the deck
/// points), or `None` in still air or a steady wind.
fn wind_resources(model: &Model) -> Result<Option<WindResources>, String> {
    let Some(spec) = &model.bridge.buffeting else {
        return Ok(None);
    };
    let res = WindResources {
        mean_speed_m_s: spec.mean_speed_m_s,
        turbulence: spec.turbulence.clone(),
        points_m: spec
            .points_on(model.bridge.x_start_m, model.bridge.x_end_m)
            .0,
        duration_s: spec.duration_s,
        n_vehicles: model.trains[0].spec.n_vehicles(),
        record: None,
        admittance: spec.admittance.map(|c| (c, spec.width_m)),
    };
    Ok(Some(WindResources {
        record: spec
            .record
            .as_ref()
            .map(|_| spec.generate(&res.points_m))
            .transpose()?,
        ..res
    }))
}

/// Where the FMUs' shared objects are and the default experiment (stop time, step) their
/// descriptions declare.
#[derive(Clone, Copy)]
struct Packaging<'a> {
    libs: &'a Path,
    experiment: (f64, f64),
    version: FmiVersion,
}

impl Packaging<'_> {
    /// Write the FMU of `contract` to `path`, unless the file there has its GUID and shared
    /// object already (its dependencies and resources are made only when it is written).
    fn fmu(&self, path: &Path, contract: &dyn Contract) -> Result<(), String> {
        let (id, guid, what) = (contract.id(), contract.guid(), contract.description());
        let so = self.libs.join(format!("lib{id}.so"));
        if is_current(path, &guid, id, &so, self.version) {
            return Ok(());
        }
        let declared = contract.dependencies()?;
        let vars = contract.variables();
        let caps = contract.capabilities();
        let md = description_xml(id, &guid, what, &vars, &declared, self.experiment, caps)?;
        let doc = DOC.replace("{TITLE}", id).replace("{WHAT}", what);
        let resources = contract.resources()?;
        // the error names the file
        match self.version {
            FmiVersion::V2 => write_fmu(path, &md.to_xml_string(), id, &so, &resources, Some(&doc)),
            FmiVersion::V3 => {
                let doc = doc.replace("fmi2DoStep", "fmi3DoStep");
                write_fmu3(path, &md, id, &so, &resources, Some(&doc))
            }
        }
        .map_err(|e| e.to_string())
    }
}

/// Whether `fmu` exists with this GUID (FMI 3.0: instantiation token), FMI version and
/// shared object (so a rebuilt library is always repackaged). The packed library is
/// compared by its length and by the CRC-32 the archive's directory records, so nothing is
/// inflated.
fn is_current(fmu: &Path, guid: &str, id: &str, so: &Path, version: FmiVersion) -> bool {
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
    let (token, platform) = match version {
        FmiVersion::V2 => ("guid", fmi_import::PLATFORM),
        FmiVersion::V3 => ("instantiationToken", FMI3_PLATFORM),
    };
    if !s.contains(&format!("{token}=\"{guid}\"")) {
        return false;
    }
    let (size, crc) = match z.by_name(&format!("binaries/{platform}/{id}.so")) {
        Ok(b) => (b.size(), b.crc32()),
        Err(_) => return false,
    };
    length_and_crc(so)
        .map(|(len, c)| len == size && c == crc)
        .unwrap_or(false)
}
