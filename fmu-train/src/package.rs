//! The train FMU's [`Contract`]: its resource (`train.json`), layout, dependencies and
//! capabilities.

use crate::layout::{TrainLayout, DESCRIPTION};
use crate::{TrainFmu, TRAIN_ID, TRAIN_RESOURCE};
use fmi_export::dependencies::Declared;
use fmi_export::CoSimulationCapabilities;
use fmu_contract::{Contract, Var, BUILD_ID};
use tbi_dynamics::train::TrainDescription;

/// A train FMU to package.
pub struct TrainPackage {
    pub resources: TrainDescription,
    pub layout: TrainLayout,
    json: Vec<u8>,
}

impl TrainPackage {
    pub fn new(resources: TrainDescription) -> Result<Self, String> {
        let json = serde_json::to_vec_pretty(&resources).map_err(|e| e.to_string())?;
        Ok(TrainPackage {
            layout: TrainLayout::of(&resources),
            resources,
            json,
        })
    }
}

impl Contract for TrainPackage {
    fn id(&self) -> &'static str {
        TRAIN_ID
    }
    fn description(&self) -> &'static str {
        DESCRIPTION
    }
    fn guid(&self) -> String {
        fmi_export::guid(TRAIN_ID, BUILD_ID, &self.json)
    }
    fn variables(&self) -> Vec<Var> {
        self.layout.variables(&self.resources)
    }
    fn dependencies(&self) -> Result<Declared, String> {
        TrainFmu::dependencies(&self.resources)
    }
    fn capabilities(&self) -> CoSimulationCapabilities {
        fmi_export::capabilities_of::<TrainFmu>()
    }
    fn resources(&self) -> Result<Vec<(String, Vec<u8>)>, String> {
        Ok(vec![(TRAIN_RESOURCE.to_string(), self.json.clone())])
    }
}
