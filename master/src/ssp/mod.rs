//! SSP 1.0 systems: read `SystemStructure.ssd` (from a `.ssp` archive or a folder) and wire
//! its FMUs into a coupling [`System`].
//!
//! Read: the components (FMUs inside the archive or next to the `.ssd`, by `source`), their
//! connections (an output feeding one or more inputs), parameter bindings (inline
//! `ssv:ParameterValues`, or `.ssv` files by `source`), `DefaultExperiment` start and stop
//! times, and this project's annotation for the coupling options:
//!
//! ```xml
//! <ssd:System name="…"> …
//!   <ssd:Annotations>
//!     <ssc:Annotation type="org.tbi.coupling">
//!       <tbi:Coupling step_size="0.002" scheme="implicit" acceleration="iqn-ils" rtol="1e-10">
//!         <tbi:Output name="mid.z" element="bridge" connector="probe[1].z"/>
//!       </tbi:Coupling>
//!     </ssc:Annotation>
//!   </ssd:Annotations>
//! </ssd:System>
//! ```
//!
//! whose attributes are the keys of a scenario's `[coupling]` table plus `step_size` (s)
//! and `output_interval` (s, the rows `tbi cosim` writes by default);
//! command-line options override them. The `tbi:Output`s name the system's own outputs
//! (`tbi export` declares the scenario's probes and car bodies), which `tbi cosim` records
//! by default. (An annotation rather than SSD System connectors: libcosim refuses a
//! connection without an `endElement`; the outputs sit inside `tbi:Coupling`, as the SSP
//! schema takes one element in an annotation.) Real connections are coupled by every scheme;
//! Integer (and Enumeration) and Boolean connections by the explicit schemes only (passed
//! once per step, never iterated); a String connection is refused naming it. The
//! participants are stepped in the order of the SSD's components (the Gauss–Seidel order).
//!
//! Initialisation: the FMUs are unpacked and their libraries loaded side by side (as many at
//! once as there are cores), then instantiated in order; every FMU enters initialisation
//! mode, the parameter bindings (then `--set` values) are applied, and the connected values
//! are exchanged until they no longer change (at most 50 rounds), so inputs start from the
//! outputs they are connected to.

use fmi_import::archive::UnpackedDir;
use fmi_import::FmuParticipant;
use fmi_import::{Fmu, InstantiateOptions, UnpackLimits};
use model_description::{Causality, ModelDescription, Variability, VariableKind};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tbi_coupling::{Connection, CouplingConfig, Discrete, DiscreteConnection, System};

/// The annotation type of the coupling options.
pub const COUPLING_ANNOTATION: &str = "org.tbi.coupling";

/// A parsed `SystemStructure.ssd`.
#[derive(Debug, Clone, Default)]
pub struct Ssd {
    pub name: String,
    pub components: Vec<Component>,
    pub connections: Vec<SspConnection>,
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    /// The attributes of the coupling annotation, as written.
    pub coupling: Vec<(String, String)>,
    /// The system's own outputs of the annotation (`<tbi:Output name element connector/>`):
    /// what `tbi cosim` records by default, by name (`mid.z` for the bridge's
    /// `probe[1].z`).
    pub recorded: Vec<RecordedOutput>,
}

/// A system output the annotation names: `name` is `element.connector`'s.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecordedOutput {
    pub name: String,
    pub element: String,
    pub connector: String,
}

/// One `ssd:Component`.
#[derive(Debug, Clone, Default)]
pub struct Component {
    pub name: String,
    /// `source`: the FMU, relative to the archive or the `.ssd`'s folder.
    pub source: String,
    /// Inline parameter values, then those of `.ssv` files (`source`), in order.
    pub parameters: Vec<(String, String)>,
    /// `.ssv` files bound to the component.
    pub parameter_files: Vec<String>,
}

/// One `ssd:Connection`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SspConnection {
    pub start_element: String,
    pub start_connector: String,
    pub end_element: String,
    pub end_connector: String,
}

fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.local_name().as_ref() == key)
        .and_then(|a| {
            a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .ok()
                .map(|v| v.into_owned())
        })
}

fn line_of(text: &str, pos: usize) -> usize {
    text[..pos.min(text.len())].matches('\n').count() + 1
}

/// Parse SSD text; `origin` names it in messages (with the line).
pub fn parse_ssd(xml: &str, origin: &str) -> Result<Ssd, String> {
    let mut r = Reader::from_str(xml);
    let mut ssd = Ssd::default();
    let mut stack: Vec<String> = Vec::new();
    let mut in_annotation = false;
    let mut parameter: Option<String> = None;
    loop {
        let pos = r.buffer_position() as usize;
        let event = r.read_event().map_err(|e| {
            format!(
                "{origin}:{}: malformed XML: {e}",
                line_of(xml, r.error_position() as usize)
            )
        })?;
        let at = |what: String| format!("{origin}:{}: {what}", line_of(xml, pos));
        match event {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let name = e.local_name().as_ref().to_owned();
                let inside = |n: &str| stack.iter().any(|s| s == n);
                match name.as_str() {
                    "SystemStructureDescription" => {
                        ssd.name = attr(e, "name").unwrap_or_default();
                    }
                    "Component" if inside("Elements") => {
                        let c = Component {
                            name: attr(e, "name")
                                .ok_or_else(|| at("<Component> has no name".into()))?,
                            source: attr(e, "source")
                                .ok_or_else(|| at("<Component> has no source".into()))?,
                            ..Default::default()
                        };
                        if ssd.components.iter().any(|o| o.name == c.name) {
                            return Err(at(format!("component \"{}\" is defined twice", c.name)));
                        }
                        ssd.components.push(c);
                    }
                    "Connection" if inside("Connections") => {
                        let get = |k: &str| {
                            attr(e, k).ok_or_else(|| at(format!("<Connection> has no {k}")))
                        };
                        ssd.connections.push(SspConnection {
                            start_element: get("startElement")?,
                            start_connector: get("startConnector")?,
                            end_element: get("endElement")?,
                            end_connector: get("endConnector")?,
                        });
                    }
                    "DefaultExperiment" => {
                        let num = |k: &str| -> Result<Option<f64>, String> {
                            attr(e, k)
                                .map(|v| {
                                    v.parse::<f64>().map_err(|_| {
                                        at(format!(
                                            "<DefaultExperiment {k}=\"{v}\"> is not a number"
                                        ))
                                    })
                                })
                                .transpose()
                        };
                        ssd.start_time = num("startTime")?;
                        ssd.stop_time = num("stopTime")?;
                    }
                    "Annotation" => {
                        in_annotation = attr(e, "type").as_deref() == Some(COUPLING_ANNOTATION);
                    }
                    "Coupling" if in_annotation => {
                        ssd.coupling = e
                            .attributes()
                            .flatten()
                            .map(|a| {
                                (
                                    a.key.local_name().as_ref().to_owned(),
                                    a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                                        .map(|v| v.into_owned())
                                        .unwrap_or_default(),
                                )
                            })
                            .collect();
                    }
                    "Output" if in_annotation => {
                        let get = |k: &str| {
                            attr(e, k).ok_or_else(|| at(format!("<tbi:Output> has no {k}")))
                        };
                        ssd.recorded.push(RecordedOutput {
                            name: get("name")?,
                            element: get("element")?,
                            connector: get("connector")?,
                        });
                    }
                    "ParameterBinding" if inside("Component") => {
                        if let Some(src) = attr(e, "source") {
                            let c = ssd.components.last_mut().expect("inside a component");
                            c.parameter_files.push(src);
                        }
                    }
                    "Parameter" if inside("Component") => {
                        parameter = Some(
                            attr(e, "name").ok_or_else(|| at("<Parameter> has no name".into()))?,
                        );
                    }
                    "Real" | "Integer" | "Boolean" | "String" if parameter.is_some() => {
                        let value = attr(e, "value")
                            .ok_or_else(|| at(format!("<{name}> of a parameter has no value")))?;
                        let c = ssd.components.last_mut().expect("inside a component");
                        c.parameters
                            .push((parameter.clone().expect("checked"), value));
                    }
                    _ => {}
                }
                if matches!(event, Event::Start(_)) {
                    stack.push(name);
                }
            }
            Event::End(ref e) => {
                let name = e.local_name().as_ref().to_owned();
                match name.as_str() {
                    "Annotation" => in_annotation = false,
                    "Parameter" => parameter = None,
                    _ => {}
                }
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if ssd.components.is_empty() {
        return Err(format!("{origin}: the system has no components"));
    }
    Ok(ssd)
}

/// Parameter values of an `.ssv` file (`ssv:ParameterSet`).
fn parse_ssv(xml: &str, origin: &str) -> Result<Vec<(String, String)>, String> {
    let wrapped = format!(
        "<ssd:SystemStructureDescription><ssd:System><ssd:Elements><ssd:Component name=\"ssv\" source=\"-\">{}</ssd:Component></ssd:Elements></ssd:System></ssd:SystemStructureDescription>",
        xml.trim_start_matches(|c| c != '<')
            .split_once("?>")
            .map_or(xml, |(_, rest)| rest)
    );
    Ok(parse_ssd(&wrapped, origin)?.components.remove(0).parameters)
}

/// An SSP system on disk: its description and where its files are.
pub struct OpenSystem {
    pub ssd: Ssd,
    /// Where `source` paths are resolved.
    pub base: PathBuf,
    /// The unpacked archive (removed on drop), if it was one.
    _unpacked: Option<UnpackedDir>,
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

/// The system just exported to `ssp` with description `ssd` (the text the archive holds),
/// its components' FMUs read where the exporter wrote them beside the archive (the archive's
/// [`crate::export::Side::ssp_source`] is [`crate::export::Side::fmu_file`] in the archive's
/// folder), so that the archive is not unpacked only to copy them out again. Everything
/// after the opening is the path `open` leads to.
pub fn open_exported(ssd: &str, ssp: &Path) -> Result<OpenSystem, String> {
    let origin = ssp.display().to_string();
    let mut ssd = parse_ssd(ssd, &format!("{origin}: SystemStructure.ssd"))?;
    for c in &mut ssd.components {
        let Some(file) = c.source.strip_prefix(crate::export::SSP_FMU_FOLDER) else {
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

/// A connected output, for the result CSV.
#[derive(Debug, Clone)]
pub struct Output {
    /// `component.variable`.
    pub name: String,
    pub participant: usize,
    pub vr: u32,
    /// `None` for a Real output.
    pub kind: Option<Discrete>,
}

/// The wired system and what to record.
pub struct Wired {
    pub system: System,
    /// Every connected output, once, in connection order.
    pub outputs: Vec<Output>,
    /// The system's own outputs ([`Ssd::recorded`]), by their names.
    pub recorded: Vec<Output>,
    /// The loaded FMUs (participant order), for name look-ups.
    pub fmus: Vec<Arc<Fmu>>,
}

/// The variable a connection names, and its kind (`None`: Real; Enumerations connect as
/// Integers); String variables are refused.
fn connectable_variable<'a>(
    md: &'a ModelDescription,
    component: &str,
    name: &str,
    origin: &str,
) -> Result<(&'a model_description::ScalarVariable, Option<Discrete>), String> {
    let v = md.variable(name).ok_or_else(|| {
        format!(
            "{origin}: component \"{component}\" has no variable \"{name}\"{}",
            crate::suggest::did_you_mean(name, md.model_variables.iter().map(|x| x.name.as_str()))
        )
    })?;
    let kind = exchanged_kind(&v.kind).ok_or_else(|| {
        format!(
            "{origin}: {component}.{name} is a String variable; Real, Integer and Boolean connections are coupled"
        )
    })?;
    Ok((v, kind))
}

/// How a variable's values are exchanged: `Some(None)` as Reals, `Some(Some(kind))` as
/// Integers (Enumerations too) or Booleans, `None` not at all (Strings).
pub(crate) fn exchanged_kind(kind: &VariableKind) -> Option<Option<Discrete>> {
    match kind {
        VariableKind::Real(_) => Some(None),
        VariableKind::Integer(_) | VariableKind::Enumeration(_) => Some(Some(Discrete::Integer)),
        VariableKind::Boolean(_) => Some(Some(Discrete::Boolean)),
        VariableKind::String(_) => None,
    }
}

/// Unpacks the components' FMUs, reads their model descriptions and loads their libraries,
/// as many side by side as the machine has cores (the archives are independent; no code of
/// an FMU runs but its library's initialisers), each result in component order. They are
/// instantiated afterwards, in order, on the calling thread.
fn load_all(open: &OpenSystem) -> Vec<Result<std::sync::Arc<Fmu>, String>> {
    let origin = &open.origin;
    let load = |c: &Component| -> Result<std::sync::Arc<Fmu>, String> {
        let path = open.base.join(&c.source);
        if !path.is_file() {
            return Err(format!(
                "{origin}: component \"{}\": its FMU {} does not exist",
                c.name, c.source
            ));
        }
        Fmu::load(&path).map_err(|e| format!("{origin}: component \"{}\": {e}", c.name))
    };
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let mut loaded = Vec::new();
    for group in open.ssd.components.chunks(cores.max(1)) {
        std::thread::scope(|s| {
            let threads: Vec<_> = group.iter().map(|c| s.spawn(|| load(c))).collect();
            loaded.extend(threads.into_iter().zip(group).map(|(t, c)| {
                t.join().unwrap_or_else(|_| {
                    Err(format!(
                        "{origin}: component \"{}\": loading its FMU panicked",
                        c.name
                    ))
                })
            }));
        });
    }
    loaded
}

/// Load, instantiate and initialise the system's FMUs, apply the parameter bindings and
/// `sets` (`component.variable = value`), and exchange the connected values until they
/// settle.
pub fn wire(
    open: &OpenSystem,
    sets: &[(String, String, String)],
    start: f64,
    stop: f64,
) -> Result<Wired, String> {
    let origin = &open.origin;
    let mut fmus = Vec::new();
    let mut instances = Vec::new();
    let mut index = HashMap::new();
    for (i, (c, fmu)) in (open.ssd.components.iter()).zip(load_all(open)).enumerate() {
        let fmu = fmu?;
        let inst = fmu
            .instantiate(&InstantiateOptions {
                instance_name: Some(c.name.clone()),
                visible: false,
                logging_on: false,
                echo_log: true,
            })
            .map_err(|e| e.to_string())?;
        index.insert(c.name.clone(), i);
        fmus.push(fmu);
        instances.push(inst);
    }
    let mut connections = Vec::new();
    let mut discrete = Vec::new();
    let mut outputs: Vec<Output> = Vec::new();
    for c in &open.ssd.connections {
        let find = |element: &str| {
            index.get(element).copied().ok_or_else(|| {
                format!("{origin}: a connection names the unknown component \"{element}\"")
            })
        };
        let (from, to) = (find(&c.start_element)?, find(&c.end_element)?);
        let (src, src_kind) = connectable_variable(
            fmus[from].model_description(),
            &c.start_element,
            &c.start_connector,
            origin,
        )?;
        let (dst, dst_kind) = connectable_variable(
            fmus[to].model_description(),
            &c.end_element,
            &c.end_connector,
            origin,
        )?;
        if src_kind != dst_kind {
            let name = |k: Option<Discrete>| match k {
                None => "a Real",
                Some(Discrete::Integer) => "an Integer",
                Some(Discrete::Boolean) => "a Boolean",
            };
            return Err(format!(
                "{origin}: connection {}.{} → {}.{}: {} output cannot feed {} input",
                c.start_element,
                c.start_connector,
                c.end_element,
                c.end_connector,
                name(src_kind),
                name(dst_kind)
            ));
        }
        if src.causality != Causality::Output {
            return Err(format!(
                "{origin}: connection {}.{} → {}.{}: the start is not an output",
                c.start_element, c.start_connector, c.end_element, c.end_connector
            ));
        }
        if dst.causality != Causality::Input {
            return Err(format!(
                "{origin}: connection {}.{} → {}.{}: the end is not an input",
                c.start_element, c.start_connector, c.end_element, c.end_connector
            ));
        }
        let name = format!("{}.{}", c.start_element, c.start_connector);
        match src_kind {
            None => connections.push(Connection {
                from,
                from_vr: src.value_reference,
                to,
                to_vr: dst.value_reference,
            }),
            Some(kind) => discrete.push(DiscreteConnection {
                kind,
                from,
                from_vr: src.value_reference,
                to,
                to_vr: dst.value_reference,
                name: format!("{name} → {}.{}", c.end_element, c.end_connector),
            }),
        }
        if !outputs.iter().any(|o| o.name == name) {
            outputs.push(Output {
                name,
                participant: from,
                vr: src.value_reference,
                kind: src_kind,
            });
        }
    }
    for inst in &mut instances {
        inst.setup_experiment(None, start, Some(stop * (1.0 + 1e-12) + 1e-9))
            .map_err(|e| e.to_string())?;
        inst.enter_initialization_mode()
            .map_err(|e| e.to_string())?;
    }
    // (component, variable, value as written, where it was written)
    let mut values: Vec<(usize, &str, &str, String)> = Vec::new();
    for (i, c) in open.ssd.components.iter().enumerate() {
        for (name, text) in &c.parameters {
            let at = format!("{origin}: component \"{}\": parameter {name}", c.name);
            values.push((i, name, text, at));
        }
    }
    for (component, name, text) in sets {
        let i = *index.get(component).ok_or_else(|| {
            format!(
                "--set {component}.{name}: the system has no component \"{component}\"{}",
                crate::suggest::did_you_mean(
                    component,
                    open.ssd.components.iter().map(|c| c.name.as_str())
                )
            )
        })?;
        values.push((i, name, text, format!("--set {component}.{name}")));
    }
    for (i, name, text, at) in values {
        let c = &open.ssd.components[i].name;
        let md = fmus[i].model_description();
        let var = md.variable(name).ok_or_else(|| {
            format!(
                "{at}: component \"{c}\" has no variable \"{name}\"{}",
                crate::suggest::did_you_mean(
                    name,
                    md.model_variables.iter().map(|x| x.name.as_str())
                )
            )
        })?;
        let settable = var.causality == Causality::Parameter
            && matches!(var.variability, Variability::Fixed | Variability::Tunable)
            || var.causality == Causality::Input;
        if !settable {
            return Err(format!(
                "{at}: {c}.{name} is not a parameter or input and cannot be set"
            ));
        }
        let vr = var.value_reference;
        let text = text.trim();
        let refused = |what: &str| format!("{at} = \"{text}\" is not {what}");
        let inst = &mut instances[i];
        match var.kind {
            VariableKind::Real(_) => {
                let v: f64 = text.parse().map_err(|_| refused("a number"))?;
                inst.set_real(&[vr], &[v]).map(drop)
            }
            VariableKind::Integer(_) | VariableKind::Enumeration(_) => {
                let v: i32 = text.parse().map_err(|_| refused("an integer"))?;
                inst.set_integer(&[vr], &[v]).map(drop)
            }
            VariableKind::Boolean(_) => {
                let v = match text {
                    "true" | "1" => true,
                    "false" | "0" => false,
                    _ => return Err(refused("true, false, 1 or 0")),
                };
                inst.set_boolean(&[vr], &[v]).map(drop)
            }
            VariableKind::String(_) => inst.set_string(&[vr], &[text]).map(drop),
        }
        .map_err(|e| format!("{at}: {e}"))?;
    }
    let mut system = System {
        participants: instances
            .into_iter()
            .zip(&fmus)
            .map(|(inst, fmu)| {
                Box::new(FmuParticipant::new(fmu, inst)) as Box<dyn tbi_coupling::Participant>
            })
            .collect(),
        connections,
        discrete,
    };
    let text = |e: tbi_coupling::CouplingError| e.to_string();
    tbi_coupling::settle_inputs(&mut system).map_err(text)?;
    for p in &mut system.participants {
        p.exit_initialization().map_err(text)?;
    }
    let recorded = recorded_outputs(open, &index, &fmus)?;
    Ok(Wired {
        system,
        outputs,
        recorded,
        fmus,
    })
}

/// The annotation's system outputs ([`Ssd::recorded`]) as outputs to record.
fn recorded_outputs(
    open: &OpenSystem,
    index: &HashMap<String, usize>,
    fmus: &[Arc<Fmu>],
) -> Result<Vec<Output>, String> {
    let origin = &open.origin;
    open.ssd
        .recorded
        .iter()
        .map(|r| {
            let i = *index.get(&r.element).ok_or_else(|| {
                format!(
                    "{origin}: the system output \"{}\" names the unknown component \"{}\"",
                    r.name, r.element
                )
            })?;
            let (v, kind) = connectable_variable(
                fmus[i].model_description(),
                &r.element,
                &r.connector,
                origin,
            )?;
            Ok(Output {
                name: r.name.clone(),
                participant: i,
                vr: v.value_reference,
                kind,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SSD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="c" xmlns:ssd="d" xmlns:ssv="v" xmlns:tbi="t" version="1.0" name="s">
  <ssd:System name="s">
    <ssd:Elements>
      <ssd:Component name="a" source="resources/a.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet version="1.0" name="p"><ssv:Parameters>
          <ssv:Parameter name="k"><ssv:Real value="2.5"/></ssv:Parameter>
        </ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>
      </ssd:Component>
      <ssd:Component name="b" source="resources/b.fmu"/>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="a" startConnector="y" endElement="b" endConnector="u"/>
    </ssd:Connections>
    <ssd:Annotations><ssc:Annotation type="org.tbi.coupling"><tbi:Coupling step_size="0.01" scheme="jacobi" rtol="1e-9"/></ssc:Annotation></ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="2.5"/>
</ssd:SystemStructureDescription>"#;

    #[test]
    fn reads_components_connections_parameters_experiment_and_coupling() {
        let s = parse_ssd(SSD, "t.ssd").unwrap();
        assert_eq!(s.components.len(), 2);
        assert_eq!(s.components[0].parameters, vec![("k".into(), "2.5".into())]);
        assert_eq!(s.connections[0].end_connector, "u");
        assert_eq!((s.start_time, s.stop_time), (Some(0.0), Some(2.5)));
        assert_eq!(s.coupling[0], ("step_size".into(), "0.01".into()));
        let open = OpenSystem {
            ssd: s,
            base: PathBuf::new(),
            _unpacked: None,
            origin: "t.ssp".into(),
        };
        let (cfg, step) = open.coupling().unwrap();
        assert_eq!(step, Some(0.01));
        assert_eq!(cfg.scheme.as_str(), "jacobi");
        assert_eq!(cfg.rtol, 1e-9);
    }

    #[test]
    fn malformed_and_duplicate_elements_are_refused_with_the_line() {
        let e = parse_ssd("<a><b></a>", "x.ssd").unwrap_err();
        assert!(e.starts_with("x.ssd:1: malformed XML"), "{e}");
        let twice = SSD.replace("name=\"b\"", "name=\"a\"");
        let e = parse_ssd(&twice, "x.ssd").unwrap_err();
        assert!(
            e.contains("x.ssd:10: component \"a\" is defined twice"),
            "{e}"
        );
    }
}
