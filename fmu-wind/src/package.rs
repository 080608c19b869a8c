//! The wind FMU's [`Contract`]: its resource (`wind.json`), layout, dependencies and
//! capabilities.

use crate::layout::{WindLayout, DESCRIPTION};
use crate::{WindFmu, WindResources, WIND_ID, WIND_RESOURCE};
use fmi_export::dependencies::Declared;
use fmi_export::CoSimulationCapabilities;
use fmu_contract::{Contract, Var, BUILD_ID};

/// A wind FMU to package.
pub struct WindPackage {
    pub resources: WindResources,
    pub layout: WindLayout,
    json: Vec<u8>,
}

impl WindPackage {
    pub fn new(resources: WindResources) -> Result<Self, String> {
        let json = serde_json::to_vec_pretty(&resources).map_err(|e| e.to_string())?;
        Ok(WindPackage {
            layout: WindLayout::of(&resources),
            resources,
            json,
        })
    }
}

impl Contract for WindPackage {
    fn id(&self) -> &'static str {
        WIND_ID
    }
    fn description(&self) -> &'static str {
        DESCRIPTION
    }
    fn guid(&self) -> String {
        fmi_export::guid(WIND_ID, BUILD_ID, &self.json)
    }
    fn variables(&self) -> Vec<Var> {
        self.layout.variables(&self.resources)
    }
    fn dependencies(&self) -> Result<Declared, String> {
        WindFmu::dependencies(&self.resources)
    }
    fn capabilities(&self) -> CoSimulationCapabilities {
        fmi_export::capabilities_of::<WindFmu>()
    }
    fn resources(&self) -> Result<Vec<(String, Vec<u8>)>, String> {
        Ok(vec![(WIND_RESOURCE.to_string(), self.json.clone())])
    }
}
