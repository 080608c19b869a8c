//! FMI 2.0 `modelDescription.xml`: types, reading, writing, validation and a builder.
//!
//! - [`ModelDescription`] and the types in [`types`] mirror the FMI 2.0 schema
//!   (`fmiModelDescription` attributes, UnitDefinitions, TypeDefinitions, LogCategories,
//!   DefaultExperiment, ModelExchange / CoSimulation, VendorAnnotations, ModelVariables,
//!   ModelStructure).
//! - Reading ([`ModelDescription::from_path`], [`ModelDescription::parse`], and
//!   `str::parse` via [`std::str::FromStr`]) uses quick-xml's serde deserializer over
//!   private raw structs, then converts every value with an error that names the origin
//!   and the element (see [`parse`] for the passes). Unknown elements and
//!   attributes — vendor extensions, `<Annotations>`, later 2.0.x additions — are skipped;
//!   `<VendorAnnotations>` is kept verbatim.
//! - Writing ([`ModelDescription::to_xml_string`]) emits schema order; reading what was
//!   written gives back an equal value.
//! - [`ModelDescription::validate`] checks the FMI 2.0 rules FMPy's validation checks and
//!   returns every problem found (see [`validate`]).
//! - An FMI 3.0 description (`fmiVersion="3.0"`) is read into the same types, in FMI 2.0's
//!   terms, for the Co-Simulation FMUs the importer runs (see `fmi3_read`).
//! - [`ModelDescription::to_fmi3_xml_string`] writes the FMI 3.0 description of the same
//!   Co-Simulation FMU (see [`fmi3`]).
//! - [`ModelDescriptionBuilder`] creates Co-Simulation descriptions with Real variables and
//!   derives ModelStructure and unit declarations (see [`builder`]).

pub mod builder;
mod error;
pub mod fmi3;
mod fmi3_read;
pub mod parse;
pub mod types;
pub mod validate;
mod write;

pub use builder::{BuildError, ModelDescriptionBuilder, RealBuilder};
pub use error::Error;
pub use types::*;
