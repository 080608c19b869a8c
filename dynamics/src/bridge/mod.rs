//! The bridge as a modal model.
pub mod modes_file;

pub use modes_file::{Mode, ModeSet};
