//! Errors of model generation and analysis.

/// Anything that can go wrong while building or analysing a finite-element model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeError {
    /// A parameter has a value that is not allowed.
    #[error("parameter `{name}` = {value}: {reason}")]
    Parameter {
        name: &'static str,
        value: String,
        reason: String,
    },
    /// The parameters describe an impossible geometry (e.g. a cable below the deck).
    #[error("geometry: {0}")]
    Geometry(String),
    /// A node, element or support refers to something that does not exist.
    #[error("model definition: {0}")]
    Definition(String),
    /// A matrix that must be symmetric positive definite is not (mechanism, missing mass).
    #[error("{matrix} is not positive definite: {hint}")]
    NotPositiveDefinite { matrix: &'static str, hint: String },
    /// The eigensolver failed or returned something unusable.
    #[error("eigen-solution: {0}")]
    Eigen(String),
    /// More modes were requested than the model has degrees of freedom.
    #[error(
        "{requested} modes requested but the model has only {available} free degrees of freedom"
    )]
    TooManyModes { requested: usize, available: usize },
    /// Fewer modes with deck participation (labels other than `C-k`) than requested among
    /// the modes that were computed.
    #[error(
        "{requested} deck modes requested but only {found} of the lowest {computed} modes have deck participation"
    )]
    TooFewDeckModes {
        requested: usize,
        found: usize,
        computed: usize,
    },
    /// A static load or output position lies outside the deck.
    #[error("deck position x = {x} m lies outside the deck [{start}, {end}] m")]
    OutsideDeck { x: f64, start: f64, end: f64 },
}

impl FeError {
    pub(crate) fn parameter(
        name: &'static str,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        FeError::Parameter {
            name,
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}
