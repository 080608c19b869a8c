//! An FMU of either standard: [`AnyFmu`] loads an FMI 2.0 or FMI 3.0 Co-Simulation FMU,
//! as its description says, and makes instances a master calls through [`FmiCalls`].

use crate::error::FmiError;
use crate::fmi3::Fmu3;
use crate::participant::FmiCalls;
use crate::{Fmu, InstantiateOptions, LocalInstance, UnpackLimits};
use model_description::ModelDescription;
use std::path::Path;
use std::sync::Arc;

/// A loaded FMU, FMI 2.0 or FMI 3.0.
#[derive(Clone)]
pub enum AnyFmu {
    V2(Arc<Fmu>),
    V3(Arc<Fmu3>),
}

impl AnyFmu {
    /// Unpack `path` once, read its description and load it as the version it declares.
    pub fn load(path: impl AsRef<Path>) -> Result<AnyFmu, FmiError> {
        let (name, dir, md, relative) = Fmu::read(path.as_ref(), &UnpackLimits::default())?;
        if md.fmi_version.starts_with('3') {
            Fmu3::from_read(name, dir, md, relative).map(AnyFmu::V3)
        } else {
            Fmu::from_read(name, dir, md, relative).map(AnyFmu::V2)
        }
    }

    /// The FMU's file name, used in every message.
    pub fn name(&self) -> &str {
        match self {
            AnyFmu::V2(f) => f.name(),
            AnyFmu::V3(f) => f.name(),
        }
    }

    /// The description (an FMI 3.0 one in FMI 2.0's terms, `fmi_version` "3.0").
    pub fn model_description(&self) -> &ModelDescription {
        match self {
            AnyFmu::V2(f) => f.model_description(),
            AnyFmu::V3(f) => f.model_description(),
        }
    }

    /// A new instance, called through [`FmiCalls`].
    pub fn instantiate_calls(
        &self,
        options: &InstantiateOptions,
    ) -> Result<Box<dyn FmiCalls>, FmiError> {
        Ok(match self {
            AnyFmu::V2(f) => Box::new(LocalInstance::new(f.instantiate(options)?)),
            AnyFmu::V3(f) => Box::new(f.instantiate(options)?),
        })
    }
}
