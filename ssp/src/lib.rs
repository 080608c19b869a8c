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
//! outputs they are connected to. With [`wire_with`] and worker options, each FMU is
//! instead described here (its library never loaded in this process) and instantiated in a
//! worker process of its own ([`fmi_import::remote`]), except a component that asks to run
//! in the master's process (a trusted FMU, whose calls then cost no round trip):
//!
//! ```xml
//! <ssd:Component name="bridge" source="resources/bridge.fmu" type="application/x-fmu-sharedlibrary">
//!   <ssd:Annotations>
//!     <ssc:Annotation type="org.tbi.process"><tbi:Process in_process="true"/></ssc:Annotation>
//!   </ssd:Annotations>
//! </ssd:Component>
//! ```

pub mod open;
pub mod read;
pub mod wire;

pub use open::{open, open_exported, OpenSystem};
pub use read::{parse_ssd, parse_ssv, Component, RecordedOutput, Ssd, SspConnection};
pub use wire::{exchanged_kind, wire, wire_with, Output, Wired};

/// The folder of a system archive that holds its FMUs (its components' `source`), as
/// `tbi export` writes it.
pub const SSP_FMU_FOLDER: &str = "resources/";

/// The annotation type of the coupling options.
pub const COUPLING_ANNOTATION: &str = "org.tbi.coupling";

/// The annotation type of a component's process (`<tbi:Process in_process="true"/>`).
pub const PROCESS_ANNOTATION: &str = "org.tbi.process";
