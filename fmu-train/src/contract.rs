//! The train FMU's identity and resources: its model identifier and the file it carries (the
//! JSON of a [`tbi_dynamics::train::TrainDescription`]).

pub use tbi_dynamics::train::{Crosswind, TrainDescription, TrainSpec};

/// Model identifier (and shared-object stem) of the train FMU.
pub const TRAIN_ID: &str = "train";
/// Resource file of the train FMU (JSON of [`TrainDescription`]).
pub const TRAIN_RESOURCE: &str = "train.json";
