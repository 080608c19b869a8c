//! An open system wired for the coupling library: FMUs loaded and instantiated, parameter
//! bindings and `--set` values applied, connections resolved to value references, the
//! inputs settled from the outputs they are connected to.

use super::open::OpenSystem;
use super::read::Component;
use fmi_import::remote::{RemoteInstance, WorkerOptions};
use fmi_import::{AnyFmu, FmiCalls, Fmu, FmuParticipant, InstantiateOptions};
use model_description::{Causality, ModelDescription, Variability, VariableKind};
use std::collections::HashMap;
use std::sync::Arc;
use tbi_coupling::{Connection, Discrete, DiscreteConnection, System};

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
    /// The components' model descriptions (participant order), for name look-ups.
    pub fmus: Vec<Arc<ModelDescription>>,
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
            fmi_import::names::did_you_mean(
                name,
                md.model_variables.iter().map(|x| x.name.as_str())
            )
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
pub fn exchanged_kind(kind: &VariableKind) -> Option<Option<Discrete>> {
    match kind {
        VariableKind::Real(_) => Some(None),
        VariableKind::Integer(_) | VariableKind::Enumeration(_) => Some(Some(Discrete::Integer)),
        VariableKind::Boolean(_) => Some(Some(Discrete::Boolean)),
        VariableKind::String(_) => None,
    }
}

/// A component's FMU, ready to instantiate: loaded in this process, or described only (its
/// library is loaded by its worker).
enum Ready {
    Loaded(AnyFmu),
    Described(Box<ModelDescription>),
}

/// Unpacks the components' FMUs and reads their model descriptions, and in process loads
/// their libraries, as many side by side as the machine has cores (the archives are
/// independent; no code of an FMU runs but its library's initialisers), each result in
/// component order. They are instantiated afterwards, in order, on the calling thread.
fn load_all(open: &OpenSystem, isolated: bool) -> Vec<Result<Ready, String>> {
    let origin = &open.origin;
    let load = |c: &Component| -> Result<Ready, String> {
        let isolated = isolated && c.in_process != Some(true);
        let path = open.base.join(&c.source);
        if !path.is_file() {
            return Err(format!(
                "{origin}: component \"{}\": its FMU {} does not exist",
                c.name, c.source
            ));
        }
        let named = |e: fmi_import::FmiError| format!("{origin}: component \"{}\": {e}", c.name);
        if isolated {
            Fmu::describe(&path)
                .map(|md| Ready::Described(Box::new(md)))
                .map_err(named)
        } else {
            AnyFmu::load(&path).map(Ready::Loaded).map_err(named)
        }
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
    wire_with(open, sets, start, stop, None)
}

/// [`wire`], each FMU in a worker process started with `isolation` when given (its
/// library is never loaded in this process) unless its component's process annotation
/// says `in_process="true"`; without `isolation`, all in this process.
pub fn wire_with(
    open: &OpenSystem,
    sets: &[(String, String, String)],
    start: f64,
    stop: f64,
    isolation: Option<&WorkerOptions>,
) -> Result<Wired, String> {
    let (fmus, mut instances, index) = instantiate_all(open, isolation)?;
    let (connections, discrete, outputs) = resolve_connections(open, &index, &fmus)?;
    for inst in &mut instances {
        inst.setup_experiment(None, start, Some(stop * (1.0 + 1e-12) + 1e-9))?;
        inst.enter_initialization_mode()?;
    }
    apply_values(open, sets, &index, &fmus, &mut instances)?;
    let mut system = System {
        participants: instances
            .into_iter()
            .zip(&fmus)
            .map(|(calls, md)| {
                Box::new(FmuParticipant::new(md, calls)) as Box<dyn tbi_coupling::Participant>
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

/// The components' FMUs loaded (or described) and instantiated in order, in this process
/// or each in a worker started with `isolation`, and each component's index by name.
#[allow(clippy::type_complexity)]
fn instantiate_all(
    open: &OpenSystem,
    isolation: Option<&WorkerOptions>,
) -> Result<
    (
        Vec<Arc<ModelDescription>>,
        Vec<Box<dyn FmiCalls>>,
        HashMap<String, usize>,
    ),
    String,
> {
    let mut fmus = Vec::new();
    let mut instances: Vec<Box<dyn FmiCalls>> = Vec::new();
    let mut index = HashMap::new();
    for (i, (c, ready)) in (open.ssd.components.iter())
        .zip(load_all(open, isolation.is_some()))
        .enumerate()
    {
        let (md, calls): (ModelDescription, Box<dyn FmiCalls>) = match (ready?, isolation) {
            (Ready::Loaded(fmu), _) => {
                let calls = fmu
                    .instantiate_calls(&InstantiateOptions::component(&c.name))
                    .map_err(|e| e.to_string())?;
                (fmu.model_description().clone(), calls)
            }
            (Ready::Described(md), Some(options)) => {
                let path = open.base.join(&c.source);
                let remote = RemoteInstance::start(&path, &c.name, options)
                    .map_err(|e| format!("{}: {e}", open.origin))?;
                (*md, Box::new(remote))
            }
            (Ready::Described(_), None) => unreachable!("described only when isolated"),
        };
        index.insert(c.name.clone(), i);
        fmus.push(Arc::new(md));
        instances.push(calls);
    }
    Ok((fmus, instances, index))
}

/// The SSD's connections resolved to value references: the Real ones, the Integer/Boolean
/// ones, and every connected output once (by `component.connector`).
#[allow(clippy::type_complexity)]
fn resolve_connections(
    open: &OpenSystem,
    index: &HashMap<String, usize>,
    fmus: &[Arc<ModelDescription>],
) -> Result<(Vec<Connection>, Vec<DiscreteConnection>, Vec<Output>), String> {
    let origin = &open.origin;
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
        let (src, src_kind) =
            connectable_variable(&fmus[from], &c.start_element, &c.start_connector, origin)?;
        let (dst, dst_kind) =
            connectable_variable(&fmus[to], &c.end_element, &c.end_connector, origin)?;
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
    Ok((connections, discrete, outputs))
}

/// Applies the parameter bindings of the SSD (and its `.ssv` files), then the `--set`
/// values, each checked against the variable's causality and type; a value that is not a
/// finite number for a Real, or lies outside its declared `min`/`max`, is refused naming
/// the binding or option.
fn apply_values(
    open: &OpenSystem,
    sets: &[(String, String, String)],
    index: &HashMap<String, usize>,
    fmus: &[Arc<ModelDescription>],
    instances: &mut [Box<dyn FmiCalls>],
) -> Result<(), String> {
    let origin = &open.origin;
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
                fmi_import::names::did_you_mean(
                    component,
                    open.ssd.components.iter().map(|c| c.name.as_str())
                )
            )
        })?;
        values.push((i, name, text, format!("--set {component}.{name}")));
    }
    for (i, name, text, at) in values {
        let c = &open.ssd.components[i].name;
        let md = &fmus[i];
        let var = md.variable(name).ok_or_else(|| {
            format!(
                "{at}: component \"{c}\" has no variable \"{name}\"{}",
                fmi_import::names::did_you_mean(
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
        match &var.kind {
            VariableKind::Real(r) => {
                let v: f64 = (text.parse().ok())
                    .filter(|v: &f64| v.is_finite())
                    .ok_or_else(|| refused("a finite number"))?;
                let declared =
                    r.declared_type
                        .as_deref()
                        .and_then(|t| match &md.type_definition(t)?.kind {
                            model_description::SimpleTypeKind::Real(a) => Some(a),
                            _ => None,
                        });
                let min = r.attributes.min.or(declared.and_then(|a| a.min));
                let max = r.attributes.max.or(declared.and_then(|a| a.max));
                within(v, min, max).map_err(|bound| refused(&bound))?;
                inst.set_real(&[vr], &[v])
            }
            VariableKind::Integer(_) | VariableKind::Enumeration(_) => {
                let v: i32 = text.parse().map_err(|_| refused("an integer"))?;
                inst.set_integer(&[vr], &[v])
            }
            VariableKind::Boolean(_) => {
                let v = match text {
                    "true" | "1" => true,
                    "false" | "0" => false,
                    _ => return Err(refused("true, false, 1 or 0")),
                };
                inst.set_boolean(&[vr], &[v])
            }
            VariableKind::String(_) => inst.set_string(&[vr], &[text]),
        }
        .map_err(|e| format!("{at}: {e}"))?;
    }
    Ok(())
}

/// `Ok` when `v` lies within the variable's declared `min` and `max`, else what it should be.
fn within(v: f64, min: Option<f64>, max: Option<f64>) -> Result<(), String> {
    match (min, max) {
        (Some(lo), _) if v < lo => Err(format!("at least the variable's min = {lo}")),
        (_, Some(hi)) if v > hi => Err(format!("at most the variable's max = {hi}")),
        _ => Ok(()),
    }
}

/// The annotation's system outputs ([`Ssd::recorded`]) as outputs to record.
fn recorded_outputs(
    open: &OpenSystem,
    index: &HashMap<String, usize>,
    fmus: &[Arc<ModelDescription>],
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
            let (v, kind) = connectable_variable(&fmus[i], &r.element, &r.connector, origin)?;
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
    #[test]
    fn values_outside_min_and_max_are_refused() {
        assert!(super::within(0.5, Some(0.0), Some(1.0)).is_ok());
        assert!(super::within(0.5, None, None).is_ok());
        assert_eq!(
            super::within(-1.0, Some(0.0), None).unwrap_err(),
            "at least the variable's min = 0"
        );
        assert_eq!(
            super::within(2.0, None, Some(1.0)).unwrap_err(),
            "at most the variable's max = 1"
        );
    }
}
