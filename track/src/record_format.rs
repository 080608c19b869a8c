//! Names of the CSV record format (described in [`crate::record`]): the header columns and
//! the periodic directive, shared by the record reader ([`crate::Record`]) and the profile
//! writer ([`crate::Profile::write_csv`]).

/// Required header columns.
pub const HEADER: [&str; 4] = ["x_m", "lateral_m", "vertical_m", "cross_level_rad"];
/// Optional slope columns following [`HEADER`].
pub const SLOPE_HEADER: [&str; 3] = ["lateral_slope", "vertical_slope", "cross_level_slope"];
/// Comment text that declares a record periodic.
pub const PERIODIC_DIRECTIVE: &str = "periodic";
