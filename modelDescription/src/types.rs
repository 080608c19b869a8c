//! The in-memory form of an FMI 2.0 `modelDescription.xml`.
//!
//! Attribute values are stored as the XML states them, with two exceptions that make the
//! types easier to use and round-trip losslessly all the same: `causality` and
//! `variability` hold their FMI 2.0 defaults (`local`, `continuous`) when the attribute is
//! absent, and are always written back explicitly. `initial` stays optional because its
//! default depends on the other two; [`ScalarVariable::initial_or_default`] resolves it.

use std::fmt;
use std::str::FromStr;

/// The root element `<fmiModelDescription>`.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelDescription {
    /// `fmiVersion`; `"2.0"` for every description this crate reads successfully.
    pub fmi_version: String,
    pub model_name: String,
    pub guid: String,
    pub description: Option<String>,
    pub author: Option<String>,
    pub version: Option<String>,
    pub copyright: Option<String>,
    pub license: Option<String>,
    pub generation_tool: Option<String>,
    pub generation_date_and_time: Option<String>,
    pub variable_naming_convention: VariableNamingConvention,
    pub number_of_event_indicators: Option<u32>,
    pub model_exchange: Option<ModelExchange>,
    pub co_simulation: Option<CoSimulation>,
    pub unit_definitions: Vec<Unit>,
    pub type_definitions: Vec<SimpleType>,
    pub log_categories: Vec<LogCategory>,
    pub default_experiment: Option<DefaultExperiment>,
    /// The complete `<VendorAnnotations>…</VendorAnnotations>` element exactly as it was
    /// read (opaque: tools put arbitrary XML there). Written back verbatim.
    pub vendor_annotations: Option<String>,
    pub model_variables: Vec<ScalarVariable>,
    pub model_structure: ModelStructure,
    /// Where the elements stood in the text this description was read from (empty for a
    /// description built in code); error and validation messages name these lines.
    pub source_lines: SourceLines,
}

impl ModelDescription {
    /// A description with the given identity and nothing else: no interface, variables,
    /// units or structure (the naming convention flat, as FMI's default).
    pub(crate) fn empty(fmi_version: &str, model_name: &str, guid: &str) -> ModelDescription {
        ModelDescription {
            fmi_version: fmi_version.to_owned(),
            model_name: model_name.to_owned(),
            guid: guid.to_owned(),
            description: None,
            author: None,
            version: None,
            copyright: None,
            license: None,
            generation_tool: None,
            generation_date_and_time: None,
            variable_naming_convention: VariableNamingConvention::default(),
            number_of_event_indicators: None,
            model_exchange: None,
            co_simulation: None,
            unit_definitions: Vec::new(),
            type_definitions: Vec::new(),
            log_categories: Vec::new(),
            default_experiment: None,
            vendor_annotations: None,
            model_variables: Vec::new(),
            model_structure: ModelStructure::default(),
            source_lines: SourceLines::default(),
        }
    }
}

/// 1-based line numbers of the elements of a description read from text, each list in
/// document order (the `i`-th `<ScalarVariable>` at `variables[i]`, …). Not part of a
/// description's value: two descriptions differing only in their lines are equal.
#[derive(Debug, Clone, Default)]
pub struct SourceLines {
    pub root: Option<usize>,
    pub model_exchange: Option<usize>,
    pub co_simulation: Option<usize>,
    pub default_experiment: Option<usize>,
    pub model_structure: Option<usize>,
    pub units: Vec<usize>,
    pub types: Vec<usize>,
    pub categories: Vec<usize>,
    pub variables: Vec<usize>,
    pub outputs: Vec<usize>,
    pub derivatives: Vec<usize>,
    pub initial_unknowns: Vec<usize>,
}

impl PartialEq for SourceLines {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl SourceLines {
    /// `", line N"` for an element at `line`, else nothing: the suffix messages append
    /// inside their parenthesis.
    pub fn suffix(line: Option<usize>) -> String {
        line.map(|l| format!(", line {l}")).unwrap_or_default()
    }

    /// `"line N: "` for an element at `line`, else nothing: the prefix of a message.
    pub fn prefix(line: Option<usize>) -> String {
        line.map(|l| format!("line {l}: ")).unwrap_or_default()
    }
}

impl ModelDescription {
    /// The variable with this name, if any.
    pub fn variable(&self, name: &str) -> Option<&ScalarVariable> {
        self.model_variables.iter().find(|v| v.name == name)
    }

    /// The variable at a 1-based ModelStructure index, if the index is in range.
    pub fn variable_at_index(&self, index: u32) -> Option<&ScalarVariable> {
        let i = usize::try_from(index).ok()?.checked_sub(1)?;
        self.model_variables.get(i)
    }

    /// The 1-based ModelStructure index of the variable with this name.
    pub fn index_of(&self, name: &str) -> Option<u32> {
        self.model_variables
            .iter()
            .position(|v| v.name == name)
            .and_then(|i| u32::try_from(i + 1).ok())
    }

    /// The variables with `causality="output"`, in ModelVariables order.
    pub fn outputs(&self) -> impl Iterator<Item = &ScalarVariable> {
        self.model_variables
            .iter()
            .filter(|v| v.causality == Causality::Output)
    }

    /// The type definition named `name`, if any.
    pub fn type_definition(&self, name: &str) -> Option<&SimpleType> {
        self.type_definitions.iter().find(|t| t.name == name)
    }

    /// The unit definition named `name`, if any.
    pub fn unit_definition(&self, name: &str) -> Option<&Unit> {
        self.unit_definitions.iter().find(|u| u.name == name)
    }
}

/// `variableNamingConvention`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VariableNamingConvention {
    #[default]
    Flat,
    Structured,
}

/// `<CoSimulation>`: the capability flags of the Co-Simulation interface.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CoSimulation {
    pub model_identifier: String,
    pub needs_execution_tool: bool,
    pub can_handle_variable_communication_step_size: bool,
    pub can_interpolate_inputs: bool,
    pub max_output_derivative_order: u32,
    pub can_run_asynchronuously: bool,
    pub can_be_instantiated_only_once_per_process: bool,
    pub can_not_use_memory_management_functions: bool,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    pub provides_directional_derivative: bool,
    /// `<SourceFiles><File name=…/></SourceFiles>`.
    pub source_files: Vec<String>,
}

impl CoSimulation {
    /// A Co-Simulation interface with every capability flag `false`.
    pub fn new(model_identifier: impl Into<String>) -> Self {
        Self {
            model_identifier: model_identifier.into(),
            ..Self::default()
        }
    }
}

/// `<ModelExchange>`: read and written so that descriptions offering both interfaces
/// survive a round trip; this project only uses Co-Simulation.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelExchange {
    pub model_identifier: String,
    pub needs_execution_tool: bool,
    pub completed_integrator_step_not_needed: bool,
    pub can_be_instantiated_only_once_per_process: bool,
    pub can_not_use_memory_management_functions: bool,
    pub can_get_and_set_fmu_state: bool,
    pub can_serialize_fmu_state: bool,
    pub provides_directional_derivative: bool,
    pub source_files: Vec<String>,
}

/// `<Unit>` in `<UnitDefinitions>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Unit {
    pub name: String,
    pub base_unit: Option<BaseUnit>,
    pub display_units: Vec<DisplayUnit>,
}

impl Unit {
    /// A unit without base-unit information or display units.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            ..Self::default()
        }
    }
}

/// `<BaseUnit>`: the SI exponents, factor and offset of a unit.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseUnit {
    pub kg: i32,
    pub m: i32,
    pub s: i32,
    pub a: i32,
    pub k: i32,
    pub mol: i32,
    pub cd: i32,
    pub rad: i32,
    pub factor: f64,
    pub offset: f64,
}

impl Default for BaseUnit {
    fn default() -> Self {
        Self {
            kg: 0,
            m: 0,
            s: 0,
            a: 0,
            k: 0,
            mol: 0,
            cd: 0,
            rad: 0,
            factor: 1.0,
            offset: 0.0,
        }
    }
}

/// `<DisplayUnit>`.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplayUnit {
    pub name: String,
    pub factor: f64,
    pub offset: f64,
}

/// `<SimpleType>` in `<TypeDefinitions>`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimpleType {
    pub name: String,
    pub description: Option<String>,
    pub kind: SimpleTypeKind,
}

/// The element inside a `<SimpleType>`.
#[derive(Debug, Clone, PartialEq)]
pub enum SimpleTypeKind {
    Real(RealAttributes),
    Integer(IntegerAttributes),
    Boolean,
    String,
    Enumeration {
        attributes: IntegerAttributes,
        items: Vec<EnumerationItem>,
    },
}

impl SimpleTypeKind {
    /// The base type name (`Real`, `Integer`, …).
    pub fn type_name(&self) -> &'static str {
        match self {
            SimpleTypeKind::Real(_) => "Real",
            SimpleTypeKind::Integer(_) => "Integer",
            SimpleTypeKind::Boolean => "Boolean",
            SimpleTypeKind::String => "String",
            SimpleTypeKind::Enumeration { .. } => "Enumeration",
        }
    }
}

/// The attributes shared by a Real type definition and a Real variable.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RealAttributes {
    pub quantity: Option<String>,
    pub unit: Option<String>,
    pub display_unit: Option<String>,
    pub relative_quantity: Option<bool>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub nominal: Option<f64>,
    pub unbounded: Option<bool>,
}

/// The attributes shared by Integer and Enumeration types and variables.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IntegerAttributes {
    pub quantity: Option<String>,
    pub min: Option<i32>,
    pub max: Option<i32>,
}

/// `<Item>` of an enumeration type.
#[derive(Debug, Clone, PartialEq)]
pub struct EnumerationItem {
    pub name: String,
    pub value: i32,
    pub description: Option<String>,
}

/// `<Category>` in `<LogCategories>`.
#[derive(Debug, Clone, PartialEq)]
pub struct LogCategory {
    pub name: String,
    pub description: Option<String>,
}

/// `<DefaultExperiment>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DefaultExperiment {
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    pub tolerance: Option<f64>,
    pub step_size: Option<f64>,
}

/// `causality`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    #[default]
    Local,
    Independent,
}

/// `variability`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    #[default]
    Continuous,
}

/// `initial`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

/// `dependenciesKind` entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DependencyKind {
    Dependent,
    Constant,
    Fixed,
    Tunable,
    Discrete,
}

macro_rules! keyword_enum {
    ($ty:ident, $what:literal, { $($variant:ident => $text:literal),+ $(,)? }) => {
        impl $ty {
            /// The attribute value as written in the XML.
            pub fn as_str(self) -> &'static str {
                match self { $($ty::$variant => $text),+ }
            }
            /// Every value, in the order the standard lists them.
            pub const ALL: &'static [$ty] = &[$($ty::$variant),+];
        }
        impl fmt::Display for $ty {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }
        impl FromStr for $ty {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($text => Ok($ty::$variant),)+
                    _ => Err(format!(
                        concat!($what, " \"{}\" is not one of {}"),
                        s,
                        [$($text),+].join(", ")
                    )),
                }
            }
        }
    };
}

keyword_enum!(Causality, "causality", {
    Parameter => "parameter",
    CalculatedParameter => "calculatedParameter",
    Input => "input",
    Output => "output",
    Local => "local",
    Independent => "independent",
});
keyword_enum!(Variability, "variability", {
    Constant => "constant",
    Fixed => "fixed",
    Tunable => "tunable",
    Discrete => "discrete",
    Continuous => "continuous",
});
keyword_enum!(Initial, "initial", {
    Exact => "exact",
    Approx => "approx",
    Calculated => "calculated",
});
keyword_enum!(DependencyKind, "dependenciesKind", {
    Dependent => "dependent",
    Constant => "constant",
    Fixed => "fixed",
    Tunable => "tunable",
    Discrete => "discrete",
});
keyword_enum!(VariableNamingConvention, "variableNamingConvention", {
    Flat => "flat",
    Structured => "structured",
});

/// `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalarVariable {
    pub name: String,
    pub value_reference: u32,
    pub description: Option<String>,
    pub causality: Causality,
    pub variability: Variability,
    /// As written; `None` means "the default for this causality and variability".
    pub initial: Option<Initial>,
    pub can_handle_multiple_set_per_time_instant: Option<bool>,
    pub kind: VariableKind,
}

impl ScalarVariable {
    /// `initial`, or the FMI 2.0 default for this causality/variability combination
    /// (standard, table in section 2.2.7). `None` for combinations without an `initial`
    /// (independent) and for illegal combinations.
    pub fn initial_or_default(&self) -> Option<Initial> {
        self.initial
            .or_else(|| default_initial(self.causality, self.variability))
    }

    /// The base type name (`Real`, `Integer`, `Boolean`, `String`, `Enumeration`).
    pub fn type_name(&self) -> &'static str {
        self.kind.type_name()
    }

    /// Whether the variable has a `start` attribute.
    pub fn has_start(&self) -> bool {
        match &self.kind {
            VariableKind::Real(r) => r.start.is_some(),
            VariableKind::Integer(i) => i.start.is_some(),
            VariableKind::Boolean(b) => b.start.is_some(),
            VariableKind::String(s) => s.start.is_some(),
            VariableKind::Enumeration(e) => e.start.is_some(),
        }
    }

    /// The `declaredType` attribute, if any.
    pub fn declared_type(&self) -> Option<&str> {
        match &self.kind {
            VariableKind::Real(r) => r.declared_type.as_deref(),
            VariableKind::Integer(i) => i.declared_type.as_deref(),
            VariableKind::Boolean(b) => b.declared_type.as_deref(),
            VariableKind::String(s) => s.declared_type.as_deref(),
            VariableKind::Enumeration(e) => Some(&e.declared_type),
        }
    }

    /// The Real `start` value, if this is a Real variable with one.
    pub fn real_start(&self) -> Option<f64> {
        match &self.kind {
            VariableKind::Real(r) => r.start,
            _ => None,
        }
    }
}

/// The FMI 2.0 default of `initial` (`None` where the standard defines none).
pub fn default_initial(causality: Causality, variability: Variability) -> Option<Initial> {
    use Causality as C;
    use Variability as V;
    match (variability, causality) {
        (V::Constant, C::Output | C::Local) => Some(Initial::Exact),
        (V::Fixed | V::Tunable, C::Parameter) => Some(Initial::Exact),
        (V::Fixed | V::Tunable, C::CalculatedParameter | C::Local) => Some(Initial::Calculated),
        (V::Discrete | V::Continuous, C::Input) => Some(Initial::Exact),
        (V::Discrete | V::Continuous, C::Output | C::Local) => Some(Initial::Calculated),
        _ => None,
    }
}

/// The type element of a `<ScalarVariable>` with its type-specific attributes.
#[derive(Debug, Clone, PartialEq)]
pub enum VariableKind {
    Real(RealVariable),
    Integer(IntegerVariable),
    Boolean(BooleanVariable),
    String(StringVariable),
    Enumeration(EnumerationVariable),
}

impl VariableKind {
    /// The element name (`Real`, `Integer`, …).
    pub fn type_name(&self) -> &'static str {
        match self {
            VariableKind::Real(_) => "Real",
            VariableKind::Integer(_) => "Integer",
            VariableKind::Boolean(_) => "Boolean",
            VariableKind::String(_) => "String",
            VariableKind::Enumeration(_) => "Enumeration",
        }
    }
}

/// `<Real>` inside a `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RealVariable {
    pub declared_type: Option<String>,
    pub attributes: RealAttributes,
    pub start: Option<f64>,
    /// 1-based index of the state variable this variable is the derivative of.
    pub derivative: Option<u32>,
    pub reinit: Option<bool>,
}

/// `<Integer>` inside a `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IntegerVariable {
    pub declared_type: Option<String>,
    pub attributes: IntegerAttributes,
    pub start: Option<i32>,
}

/// `<Boolean>` inside a `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BooleanVariable {
    pub declared_type: Option<String>,
    pub start: Option<bool>,
}

/// `<String>` inside a `<ScalarVariable>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StringVariable {
    pub declared_type: Option<String>,
    pub start: Option<String>,
}

/// `<Enumeration>` inside a `<ScalarVariable>` (`declaredType` is required).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EnumerationVariable {
    pub declared_type: String,
    pub attributes: IntegerAttributes,
    pub start: Option<i32>,
}

/// `<ModelStructure>`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelStructure {
    pub outputs: Vec<Unknown>,
    pub derivatives: Vec<Unknown>,
    pub initial_unknowns: Vec<Unknown>,
}

/// `<Unknown>`: a 1-based index into ModelVariables and its dependencies.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Unknown {
    pub index: u32,
    /// `None`: attribute absent (depends on all knowns); `Some(vec![])`: depends on none.
    pub dependencies: Option<Vec<u32>>,
    pub dependencies_kind: Option<Vec<DependencyKind>>,
}

impl Unknown {
    /// An unknown without dependency information.
    pub fn new(index: u32) -> Self {
        Self {
            index,
            ..Self::default()
        }
    }
}
