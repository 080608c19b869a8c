//! The bridge FMU's [`Contract`]: its resources (`bridge.json`, and `track.csv` when the
//! track has an irregularity record), layout, dependencies and capabilities.

use crate::layout::{BridgeLayout, DESCRIPTION};
use crate::{BridgeFmu, BridgeResources, BRIDGE_ID, BRIDGE_RESOURCE, TRACK_RESOURCE};
use fmi_export::dependencies::Declared;
use fmi_export::CoSimulationCapabilities;
use fmu_contract::{Contract, Var, BUILD_ID};
use std::sync::Arc;
use tbi_track::Irregularity;

/// A bridge FMU to package: its resources and the track it carries.
pub struct BridgePackage {
    pub resources: BridgeResources,
    pub layout: BridgeLayout,
    track: Arc<Irregularity>,
    json: Vec<u8>,
    /// What determines the track record (digested into the GUID; the record itself is made
    /// only when the FMU is written).
    track_identity: Option<Vec<u8>>,
}

impl BridgePackage {
    /// The package of `resources` on `track`; `resources.has_track_record` is set from the
    /// track.
    pub fn new(mut resources: BridgeResources, track: Arc<Irregularity>) -> Result<Self, String> {
        let track_identity = track.record_identity();
        resources.has_track_record = track_identity.is_some();
        let json = serde_json::to_vec_pretty(&resources).map_err(|e| e.to_string())?;
        Ok(BridgePackage {
            layout: BridgeLayout::of(&resources),
            resources,
            track,
            json,
            track_identity,
        })
    }
}

impl Contract for BridgePackage {
    fn id(&self) -> &'static str {
        BRIDGE_ID
    }
    fn description(&self) -> &'static str {
        DESCRIPTION
    }
    fn guid(&self) -> String {
        let mut bytes = self.json.clone();
        if let Some(identity) = &self.track_identity {
            bytes.extend_from_slice(identity);
        }
        fmi_export::guid(BRIDGE_ID, BUILD_ID, &bytes)
    }
    fn variables(&self) -> Vec<Var> {
        self.layout.variables(&self.resources)
    }
    fn dependencies(&self) -> Result<Declared, String> {
        BridgeFmu::dependencies(&self.resources, self.track.clone() as _)
    }
    fn capabilities(&self) -> CoSimulationCapabilities {
        fmi_export::capabilities_of::<BridgeFmu>()
    }
    fn resources(&self) -> Result<Vec<(String, Vec<u8>)>, String> {
        let mut files = vec![(BRIDGE_RESOURCE.to_string(), self.json.clone())];
        if let Some(csv) = self.track.to_record_csv() {
            files.push((TRACK_RESOURCE.to_string(), csv.into_bytes()));
        }
        Ok(files)
    }
}
