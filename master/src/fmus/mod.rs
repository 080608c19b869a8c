//! The scenario's FMUs (bridge, train and wind) exported, packaged and checked, and the SSP
//! system ([`ssd`]) that couples them.

pub mod export;
pub mod package;
pub mod ssd;
