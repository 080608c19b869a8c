//! `SystemStructure.ssd` and `.ssv` documents parsed into an [`Ssd`]: components,
//! connections, parameter bindings, the default experiment and the coupling annotation,
//! each malformed element refused with its line.

use super::{COUPLING_ANNOTATION, PROCESS_ANNOTATION};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

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
    /// The component's process annotation (`<tbi:Process in_process="true"/>`): run its FMU
    /// in the master's process even when the others run in workers. `None` when absent.
    pub in_process: Option<bool>,
}

/// One `ssd:Connection`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SspConnection {
    pub start_element: String,
    pub start_connector: String,
    pub end_element: String,
    pub end_connector: String,
}

pub(crate) fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.local_name().as_ref() == key)
        .and_then(|a| {
            a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .ok()
                .map(|v| v.into_owned())
        })
}

/// The namespace of SSP 1.0 System Structure Descriptions.
pub const SSD_NAMESPACE: &str = "http://ssp-standard.org/SSP1/SystemStructureDescription";
/// The namespace of SSP 1.0 parameter values (`.ssv`).
pub const SSV_NAMESPACE: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";
/// The one component type the master runs: an FMU (SSP 1.0's default).
pub const FMU_COMPONENT_TYPE: &str = "application/x-fmu-sharedlibrary";

/// Refuses a root element that is not SSP 1.0's `<local>` in `namespace` with
/// `version="1.0"`.
fn check_root(e: &BytesStart<'_>, local: &str, namespace: &str) -> Result<(), String> {
    let name = e.name().as_ref().to_owned();
    if e.local_name().as_ref() != local {
        return Err(format!(
            "<{name}> is not an SSP 1.0 document (expected <{local}> as its root)"
        ));
    }
    let declaration = match e.name().prefix() {
        Some(p) => format!("xmlns:{}", p.as_ref()),
        None => "xmlns".to_owned(),
    };
    let ns = e
        .attributes()
        .flatten()
        .find(|a| a.key.as_ref() == declaration)
        .and_then(|a| {
            a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .ok()
                .map(|v| v.into_owned())
        });
    if ns.as_deref() != Some(namespace) {
        return Err(format!(
            "<{name}> is in namespace {}, not SSP 1.0's \"{namespace}\"",
            ns.map_or("(none)".to_owned(), |n| format!("\"{n}\""))
        ));
    }
    match attr(e, "version") {
        Some(v) if v == "1.0" => Ok(()),
        v => Err(format!(
            "<{name} version={}>: only SSP version \"1.0\" is read",
            v.map_or("(missing)".to_owned(), |v| format!("\"{v}\""))
        )),
    }
}

pub(crate) fn line_of(text: &str, pos: usize) -> usize {
    text[..pos.min(text.len())].matches('\n').count() + 1
}

/// A `<Component>` of `<Elements>`: only FMUs, named and with a source.
fn component(e: &BytesStart<'_>) -> Result<Component, String> {
    if let Some(t) = attr(e, "type").filter(|t| t != FMU_COMPONENT_TYPE) {
        return Err(format!(
            "component \"{}\" has type \"{t}\": only FMUs ({FMU_COMPONENT_TYPE}) are run; nested SSP packages and other component types are not supported",
            attr(e, "name").unwrap_or_default()
        ));
    }
    Ok(Component {
        name: attr(e, "name").ok_or("<Component> has no name")?,
        source: attr(e, "source").ok_or("<Component> has no source")?,
        ..Default::default()
    })
}

/// The `in_process` of a component's `<tbi:Process>`: `true` or `false`.
fn process_flag(e: &BytesStart<'_>, component: &str) -> Result<bool, String> {
    match attr(e, "in_process").as_deref() {
        Some("true") => Ok(true),
        Some("false") => Ok(false),
        v => Err(format!(
            "component \"{component}\": <tbi:Process in_process={}>: expected \"true\" or \"false\"",
            v.map_or("(missing)".to_owned(), |v| format!("\"{v}\""))
        )),
    }
}

/// Parse SSD text; `origin` names it in messages (with the line).
pub fn parse_ssd(xml: &str, origin: &str) -> Result<Ssd, String> {
    let mut r = Reader::from_str(xml);
    let mut ssd = Ssd::default();
    let mut stack: Vec<String> = Vec::new();
    let mut in_annotation = false;
    let mut in_process_annotation = false;
    let mut parameter: Option<String> = None;
    let (mut root_seen, mut seen_system, mut seen_elements) = (false, false, false);
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
                if stack.is_empty() && !root_seen {
                    check_root(e, "SystemStructureDescription", SSD_NAMESPACE).map_err(at)?;
                    root_seen = true;
                }
                seen_system |= name == "System" && stack.len() == 1;
                seen_elements |= name == "Elements" && inside("System");
                match name.as_str() {
                    "SystemStructureDescription" => {
                        ssd.name = attr(e, "name").unwrap_or_default();
                    }
                    "Component" if inside("Elements") => {
                        let c = component(e).map_err(at)?;
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
                        in_process_annotation =
                            attr(e, "type").as_deref() == Some(PROCESS_ANNOTATION);
                    }
                    "Process"
                        if in_process_annotation
                            && inside("Component")
                            && inside("Elements")
                            && !ssd.components.is_empty() =>
                    {
                        let c = ssd.components.last_mut().expect("checked above");
                        c.in_process = Some(process_flag(e, &c.name).map_err(at)?);
                    }
                    "Coupling" if in_annotation => ssd.coupling = attributes(e),
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
                    "ParameterBinding" if inside("Component") && inside("Elements") => {
                        if let Some(src) = attr(e, "source") {
                            let c = ssd.components.last_mut().expect("inside a component");
                            c.parameter_files.push(src);
                        }
                    }
                    "Parameter" if inside("Component") && inside("Elements") => {
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
                    "Annotation" => {
                        in_annotation = false;
                        in_process_annotation = false;
                    }
                    "Parameter" => parameter = None,
                    _ => {}
                }
                stack.pop();
            }
            Event::Eof => {
                if let Some(open) = stack.last() {
                    return Err(format!(
                        "{origin}:{}: the document ends inside <{open}>: it is not a whole SSD",
                        line_of(xml, xml.len())
                    ));
                }
                break;
            }
            _ => {}
        }
    }
    whole(origin, root_seen, seen_system, seen_elements, &ssd)?;
    Ok(ssd)
}

/// Every attribute of `e`, by local name, as written.
fn attributes(e: &BytesStart<'_>) -> Vec<(String, String)> {
    e.attributes()
        .flatten()
        .map(|a| {
            (
                a.key.local_name().as_ref().to_owned(),
                a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                    .map(|v| v.into_owned())
                    .unwrap_or_default(),
            )
        })
        .collect()
}

/// Refuses a document without a root, `<System>`, `<Elements>` or components.
fn whole(origin: &str, root: bool, system: bool, elements: bool, ssd: &Ssd) -> Result<(), String> {
    if !root {
        return Err(format!("{origin}: no XML element: it is not an SSD"));
    }
    if !system || !elements {
        return Err(format!(
            "{origin}: the SSD has no <System>{}",
            if system { " <Elements>" } else { "" }
        ));
    }
    if ssd.components.is_empty() {
        return Err(format!("{origin}: the system has no components"));
    }
    Ok(())
}

/// Parameter values of an `.ssv` file (`ssv:ParameterSet`).
pub fn parse_ssv(xml: &str, origin: &str) -> Result<Vec<(String, String)>, String> {
    let mut r = Reader::from_str(xml);
    loop {
        let pos = r.buffer_position() as usize;
        match r.read_event() {
            Err(e) => {
                return Err(format!(
                    "{origin}:{}: malformed XML: {e}",
                    line_of(xml, r.error_position() as usize)
                ))
            }
            Ok(Event::Start(ref e) | Event::Empty(ref e)) => {
                check_root(e, "ParameterSet", SSV_NAMESPACE)
                    .map_err(|m| format!("{origin}:{}: {m}", line_of(xml, pos)))?;
                break;
            }
            Ok(Event::Eof) => return Err(format!("{origin}: no XML element: it is not an SSV")),
            Ok(Event::Text(t)) if !t.as_ref().trim().is_empty() => {
                return Err(format!(
                    "{origin}:{}: text before any element: it is not an SSV document",
                    line_of(xml, pos)
                ))
            }
            Ok(_) => {}
        }
    }
    let wrapped = format!(
        "<ssd:SystemStructureDescription xmlns:ssd=\"{SSD_NAMESPACE}\" version=\"1.0\"><ssd:System><ssd:Elements><ssd:Component name=\"ssv\" source=\"-\">{}</ssd:Component></ssd:Elements></ssd:System></ssd:SystemStructureDescription>",
        xml.trim_start_matches(|c| c != '<')
            .split_once("?>")
            .map_or(xml, |(_, rest)| rest)
    );
    Ok(parse_ssd(&wrapped, origin)?.components.remove(0).parameters)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OpenSystem;
    use std::path::PathBuf;

    const SSD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="c" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssv="v" xmlns:tbi="t" version="1.0" name="s">
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
    fn only_whole_ssp_1_0_documents_are_read() {
        let refused = |text: &str, needle: &str| {
            let e = parse_ssd(text, "x.ssd").unwrap_err();
            assert!(
                e.starts_with("x.ssd") && e.contains(needle),
                "{needle}: {e}"
            );
        };
        refused(
            &SSD[..SSD.find("<ssd:Connections>").unwrap()],
            "the document ends inside <System>",
        );
        refused(&SSD[..SSD.len() / 2], "malformed XML");
        refused("plain text", "no XML element");
        refused(
            &SSD.replace("<ssd:Elements>", "<ssd:Items>")
                .replace("</ssd:Elements>", "</ssd:Items>"),
            "no <System> <Elements>",
        );
        refused(
            &SSD.replace(SSD_NAMESPACE, "urn:x"),
            "namespace \"urn:x\", not SSP 1.0's",
        );
        refused(
            &SSD.replace("version=\"1.0\" name=\"s\"", "version=\"2.0\" name=\"s\""),
            "only SSP version \"1.0\"",
        );
        refused(
            &SSD.replace(
                "name=\"b\"",
                "name=\"b\" type=\"application/x-ssp-package\"",
            ),
            "x.ssd:10: component \"b\" has type \"application/x-ssp-package\"",
        );
        let ssv = format!("<ssv:ParameterSet xmlns:ssv=\"{SSV_NAMESPACE}\" version=\"1.0\" name=\"p\"><ssv:Parameters><ssv:Parameter name=\"k\"><ssv:Real value=\"3\"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>");
        assert_eq!(
            parse_ssv(&ssv, "p.ssv").unwrap(),
            vec![("k".into(), "3".into())]
        );
        for (text, needle) in [
            ("myhost\n", "p.ssv:1: text before any element"),
            ("", "p.ssv: no XML element"),
            ("<a/>", "p.ssv:1: <a> is not an SSP 1.0 document"),
        ] {
            let e = parse_ssv(text, "p.ssv").unwrap_err();
            assert!(e.contains(needle), "{needle}: {e}");
        }
        let e = parse_ssv(&ssv.replace(SSV_NAMESPACE, "v"), "p.ssv").unwrap_err();
        assert!(e.contains("namespace \"v\""), "{e}");
    }

    #[test]
    fn malformed_and_duplicate_elements_are_refused_with_the_line() {
        let e = parse_ssd(
            &SSD.replace("</ssd:Connections>", "</ssd:Connection>"),
            "x.ssd",
        )
        .unwrap_err();
        assert!(e.starts_with("x.ssd:14: malformed XML"), "{e}");
        let twice = SSD.replace("name=\"b\"", "name=\"a\"");
        let e = parse_ssd(&twice, "x.ssd").unwrap_err();
        assert!(
            e.contains("x.ssd:10: component \"a\" is defined twice"),
            "{e}"
        );
    }
}
