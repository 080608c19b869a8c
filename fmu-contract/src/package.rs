//! What one FMU puts into its archive beside its shared object, stated by the FMU's own crate
//! ([`Contract`]): its identity, description text, variables, dependencies, capabilities and
//! resource files. The exporter loops over the FMUs' contracts; it knows no FMU by name.

use crate::Var;
use fmi_export::dependencies::Declared;
use fmi_export::CoSimulationCapabilities;

/// One FMU's contract, from the resources of one export.
pub trait Contract: Sync {
    /// Model identifier, also the shared object's stem (`lib<id>.so`).
    fn id(&self) -> &'static str;
    /// `<fmiModelDescription description>`.
    fn description(&self) -> &'static str;
    /// The GUID: a digest of the identifier, the build and everything the model reads from
    /// its resources (so an FMU on disk with this GUID holds these resources).
    fn guid(&self) -> String;
    /// The variables, in value-reference order.
    fn variables(&self) -> Vec<Var>;
    /// The dependencies `<ModelStructure>` declares (made only when the FMU is written).
    fn dependencies(&self) -> Result<Declared, String>;
    /// The `<CoSimulation>` capabilities.
    fn capabilities(&self) -> CoSimulationCapabilities;
    /// The resource files `(name, bytes)` (made only when the FMU is written).
    fn resources(&self) -> Result<Vec<(String, Vec<u8>)>, String>;
}
