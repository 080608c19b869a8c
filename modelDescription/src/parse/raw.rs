//! Pass 2 of reading: the private "raw" serde structs quick-xml's deserializer fills.
//! Every attribute is an optional string so that pass 3 can give precise messages;
//! unknown attributes and elements are ignored by serde.

use serde::Deserialize;

#[derive(Deserialize)]
pub(super) struct RawModelDescription {
    #[serde(rename = "@fmiVersion")]
    pub(super) fmi_version: Option<String>,
    #[serde(rename = "@modelName")]
    pub(super) model_name: Option<String>,
    #[serde(rename = "@guid")]
    pub(super) guid: Option<String>,
    #[serde(rename = "@description")]
    pub(super) description: Option<String>,
    #[serde(rename = "@author")]
    pub(super) author: Option<String>,
    #[serde(rename = "@version")]
    pub(super) version: Option<String>,
    #[serde(rename = "@copyright")]
    pub(super) copyright: Option<String>,
    #[serde(rename = "@license")]
    pub(super) license: Option<String>,
    #[serde(rename = "@generationTool")]
    pub(super) generation_tool: Option<String>,
    #[serde(rename = "@generationDateAndTime")]
    pub(super) generation_date_and_time: Option<String>,
    #[serde(rename = "@variableNamingConvention")]
    pub(super) variable_naming_convention: Option<String>,
    #[serde(rename = "@numberOfEventIndicators")]
    pub(super) number_of_event_indicators: Option<String>,
    #[serde(rename = "ModelExchange")]
    pub(super) model_exchange: Option<RawInterface>,
    #[serde(rename = "CoSimulation")]
    pub(super) co_simulation: Option<RawInterface>,
    #[serde(rename = "UnitDefinitions")]
    pub(super) unit_definitions: Option<RawUnitDefinitions>,
    #[serde(rename = "TypeDefinitions")]
    pub(super) type_definitions: Option<RawTypeDefinitions>,
    #[serde(rename = "LogCategories")]
    pub(super) log_categories: Option<RawLogCategories>,
    #[serde(rename = "DefaultExperiment")]
    pub(super) default_experiment: Option<RawDefaultExperiment>,
    #[serde(rename = "ModelVariables")]
    pub(super) model_variables: Option<RawModelVariables>,
    #[serde(rename = "ModelStructure")]
    pub(super) model_structure: Option<RawModelStructure>,
}

/// `<ModelExchange>` and `<CoSimulation>` share one raw shape.
#[derive(Deserialize)]
pub(super) struct RawInterface {
    #[serde(rename = "@modelIdentifier")]
    pub(super) model_identifier: Option<String>,
    #[serde(rename = "@needsExecutionTool")]
    pub(super) needs_execution_tool: Option<String>,
    #[serde(rename = "@completedIntegratorStepNotNeeded")]
    pub(super) completed_integrator_step_not_needed: Option<String>,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    pub(super) can_handle_variable_communication_step_size: Option<String>,
    #[serde(rename = "@canInterpolateInputs")]
    pub(super) can_interpolate_inputs: Option<String>,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    pub(super) max_output_derivative_order: Option<String>,
    #[serde(rename = "@canRunAsynchronuously")]
    pub(super) can_run_asynchronuously: Option<String>,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    pub(super) can_be_instantiated_only_once_per_process: Option<String>,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    pub(super) can_not_use_memory_management_functions: Option<String>,
    #[serde(rename = "@canGetAndSetFMUstate")]
    pub(super) can_get_and_set_fmu_state: Option<String>,
    #[serde(rename = "@canSerializeFMUstate")]
    pub(super) can_serialize_fmu_state: Option<String>,
    #[serde(rename = "@providesDirectionalDerivative")]
    pub(super) provides_directional_derivative: Option<String>,
    #[serde(rename = "SourceFiles")]
    pub(super) source_files: Option<RawSourceFiles>,
}

#[derive(Deserialize)]
pub(super) struct RawSourceFiles {
    #[serde(rename = "File", default)]
    pub(super) files: Vec<RawNamed>,
}

#[derive(Deserialize)]
pub(super) struct RawNamed {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "@description")]
    pub(super) description: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct RawUnitDefinitions {
    #[serde(rename = "Unit", default)]
    pub(super) units: Vec<RawUnit>,
}

#[derive(Deserialize)]
pub(super) struct RawUnit {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "BaseUnit")]
    pub(super) base_unit: Option<RawBaseUnit>,
    #[serde(rename = "DisplayUnit", default)]
    pub(super) display_units: Vec<RawDisplayUnit>,
}

#[derive(Deserialize)]
pub(super) struct RawBaseUnit {
    #[serde(rename = "@kg")]
    pub(super) kg: Option<String>,
    #[serde(rename = "@m")]
    pub(super) m: Option<String>,
    #[serde(rename = "@s")]
    pub(super) s: Option<String>,
    #[serde(rename = "@A")]
    pub(super) a: Option<String>,
    #[serde(rename = "@K")]
    pub(super) k: Option<String>,
    #[serde(rename = "@mol")]
    pub(super) mol: Option<String>,
    #[serde(rename = "@cd")]
    pub(super) cd: Option<String>,
    #[serde(rename = "@rad")]
    pub(super) rad: Option<String>,
    #[serde(rename = "@factor")]
    pub(super) factor: Option<String>,
    #[serde(rename = "@offset")]
    pub(super) offset: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct RawDisplayUnit {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "@factor")]
    pub(super) factor: Option<String>,
    #[serde(rename = "@offset")]
    pub(super) offset: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct RawTypeDefinitions {
    #[serde(rename = "SimpleType", default)]
    pub(super) types: Vec<RawSimpleType>,
}

#[derive(Deserialize)]
pub(super) struct RawSimpleType {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "@description")]
    pub(super) description: Option<String>,
    #[serde(rename = "Real")]
    pub(super) real: Option<RawTypeElement>,
    #[serde(rename = "Integer")]
    pub(super) integer: Option<RawTypeElement>,
    #[serde(rename = "Boolean")]
    pub(super) boolean: Option<RawTypeElement>,
    #[serde(rename = "String")]
    pub(super) string: Option<RawTypeElement>,
    #[serde(rename = "Enumeration")]
    pub(super) enumeration: Option<RawTypeElement>,
}

/// The type element of a `<SimpleType>` or a `<ScalarVariable>` (one raw shape for all
/// five base types; pass 3 reads the attributes that belong to the type).
#[derive(Deserialize)]
pub(super) struct RawTypeElement {
    #[serde(rename = "@declaredType")]
    pub(super) declared_type: Option<String>,
    #[serde(rename = "@quantity")]
    pub(super) quantity: Option<String>,
    #[serde(rename = "@unit")]
    pub(super) unit: Option<String>,
    #[serde(rename = "@displayUnit")]
    pub(super) display_unit: Option<String>,
    #[serde(rename = "@relativeQuantity")]
    pub(super) relative_quantity: Option<String>,
    #[serde(rename = "@min")]
    pub(super) min: Option<String>,
    #[serde(rename = "@max")]
    pub(super) max: Option<String>,
    #[serde(rename = "@nominal")]
    pub(super) nominal: Option<String>,
    #[serde(rename = "@unbounded")]
    pub(super) unbounded: Option<String>,
    #[serde(rename = "@start")]
    pub(super) start: Option<String>,
    #[serde(rename = "@derivative")]
    pub(super) derivative: Option<String>,
    #[serde(rename = "@reinit")]
    pub(super) reinit: Option<String>,
    #[serde(rename = "Item", default)]
    pub(super) items: Vec<RawItem>,
}

#[derive(Deserialize)]
pub(super) struct RawItem {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "@value")]
    pub(super) value: Option<String>,
    #[serde(rename = "@description")]
    pub(super) description: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct RawLogCategories {
    #[serde(rename = "Category", default)]
    pub(super) categories: Vec<RawNamed>,
}

#[derive(Deserialize)]
pub(super) struct RawDefaultExperiment {
    #[serde(rename = "@startTime")]
    pub(super) start_time: Option<String>,
    #[serde(rename = "@stopTime")]
    pub(super) stop_time: Option<String>,
    #[serde(rename = "@tolerance")]
    pub(super) tolerance: Option<String>,
    #[serde(rename = "@stepSize")]
    pub(super) step_size: Option<String>,
}

#[derive(Deserialize)]
pub(super) struct RawModelVariables {
    #[serde(rename = "ScalarVariable", default)]
    pub(super) variables: Vec<RawScalarVariable>,
}

#[derive(Deserialize)]
pub(super) struct RawScalarVariable {
    #[serde(rename = "@name")]
    pub(super) name: Option<String>,
    #[serde(rename = "@valueReference")]
    pub(super) value_reference: Option<String>,
    #[serde(rename = "@description")]
    pub(super) description: Option<String>,
    #[serde(rename = "@causality")]
    pub(super) causality: Option<String>,
    #[serde(rename = "@variability")]
    pub(super) variability: Option<String>,
    #[serde(rename = "@initial")]
    pub(super) initial: Option<String>,
    #[serde(rename = "@canHandleMultipleSetPerTimeInstant")]
    pub(super) can_handle_multiple_set_per_time_instant: Option<String>,
    #[serde(rename = "Real")]
    pub(super) real: Option<RawTypeElement>,
    #[serde(rename = "Integer")]
    pub(super) integer: Option<RawTypeElement>,
    #[serde(rename = "Boolean")]
    pub(super) boolean: Option<RawTypeElement>,
    #[serde(rename = "String")]
    pub(super) string: Option<RawTypeElement>,
    #[serde(rename = "Enumeration")]
    pub(super) enumeration: Option<RawTypeElement>,
}

#[derive(Deserialize)]
pub(super) struct RawModelStructure {
    #[serde(rename = "Outputs")]
    pub(super) outputs: Option<RawUnknowns>,
    #[serde(rename = "Derivatives")]
    pub(super) derivatives: Option<RawUnknowns>,
    #[serde(rename = "InitialUnknowns")]
    pub(super) initial_unknowns: Option<RawUnknowns>,
}

#[derive(Deserialize)]
pub(super) struct RawUnknowns {
    #[serde(rename = "Unknown", default)]
    pub(super) unknowns: Vec<RawUnknown>,
}

#[derive(Deserialize)]
pub(super) struct RawUnknown {
    #[serde(rename = "@index")]
    pub(super) index: Option<String>,
    #[serde(rename = "@dependencies")]
    pub(super) dependencies: Option<String>,
    #[serde(rename = "@dependenciesKind")]
    pub(super) dependencies_kind: Option<String>,
}
