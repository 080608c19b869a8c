//! The wind FMU's identity and resources: its model identifier, the file it carries and what
//! it holds.

use serde::{Deserialize, Serialize};

/// Model identifier (and shared-object stem) of the wind FMU.
pub const WIND_ID: &str = "wind";
/// Resource file of the wind FMU (JSON of [`WindResources`]).
pub const WIND_RESOURCE: &str = "wind.json";

/// Everything the wind FMU reads from its resources: the turbulence, generated from its seed
/// at the deck points (the same field the monolithic solver generates).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindResources {
    /// Mean wind speed U at deck level, m/s (> 0).
    pub mean_speed_m_s: f64,
    pub turbulence: tbi_wind::Turbulence,
    /// The deck points, m (strictly increasing).
    pub points_m: Vec<f64>,
    /// Duration the field covers, s (it repeats beyond).
    pub duration_s: f64,
    /// Number of vehicles whose car bodies it gives the wind at.
    pub n_vehicles: usize,
    /// A measured record at the deck points, used instead of generating `turbulence`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<tbi_wind::WindField>,
    /// Davenport's admittance `(c, B)` of the deck forces: the deck outputs are the field
    /// through it ([`tbi_dynamics::bridge::buffeting::admittance_gain`]), the car bodies' the field.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub admittance: Option<(f64, f64)>,
}
