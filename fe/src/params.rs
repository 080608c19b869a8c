//! Parameters of a three-span suspension bridge and the Tsing Ma preset.
//!
//! Coordinates: x along the deck from the left abutment, y lateral (to the right looking
//! in +x), z vertical **downward**. Elevations in this struct are measured **upward** from
//! the deck shear centre (the deck is straight and level at z = 0); the model converts them
//! to z = −elevation.

use crate::error::FeError;
use crate::structure::BeamSection;
use serde::{Deserialize, Serialize};

/// Main-cable properties (one cable; the bridge has two).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CableParams {
    /// Young's modulus of the cable (parallel wire), Pa. Default 1.96e11.
    pub e: f64,
    /// Steel area of one cable in the main span, m². Default 0.759.
    pub area_main: f64,
    /// Steel area of one cable in the side spans and back-stays, m². Default 0.801.
    pub area_side: f64,
    /// Mass per unit length of one cable in the main span (steel + wrapping, bands), kg/m.
    /// Default 6 400 (0.759 m² × 7 850 kg/m³ × 1.074).
    pub mass_per_length_main: f64,
    /// Mass per unit length of one cable in the side spans, kg/m. Default 6 750.
    pub mass_per_length_side: f64,
}

impl Default for CableParams {
    fn default() -> Self {
        Self {
            e: 1.96e11,
            area_main: 0.759,
            area_side: 0.801,
            mass_per_length_main: 6_400.0,
            mass_per_length_side: 6_750.0,
        }
    }
}

/// Hanger (suspender) properties; one hanger per cable at every hanger station.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HangerParams {
    /// Young's modulus of the hanger ropes, Pa. Default 1.4e11.
    pub e: f64,
    /// Metallic area of one hanger (all its ropes), m². Default 0.011.
    pub area: f64,
    /// Mass per unit length of one hanger, kg/m. Default 95.
    pub mass_per_length: f64,
}

impl Default for HangerParams {
    fn default() -> Self {
        Self {
            e: 1.4e11,
            area: 0.011,
            mass_per_length: 95.0,
        }
    }
}

/// Where the deck is restrained longitudinally (everywhere else it slides on its bearings).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum LongitudinalRestraint {
    /// At the left abutment (x = `deck_start_x`).
    LeftAbutment,
    /// At the right abutment (x = `deck_end_x`).
    RightAbutment,
}

/// A three-span suspension bridge: left side span with the cable over a pier saddle and a
/// back-stay to the left anchorage, main span between two towers, right side span to the
/// right anchorage; a continuous deck spine with bearings at the abutments, piers and towers.
///
/// All fields are public; [`SuspensionBridgeParams::default`] is the Tsing Ma preset
/// ([`tsing_ma`]). Calibrated values are listed in the crate docs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SuspensionBridgeParams {
    // ---------------------------------------------------------------- layout (x, m)
    /// x of the left cable anchorage, m. Default 0.0 (Ma Wan abutment).
    pub left_anchorage_x: f64,
    /// x of the pier that carries the left cable saddles and a deck bearing, m.
    /// Default 97.0 (pier M2).
    pub left_pier_x: f64,
    /// x of the left tower, m. Default 452.5 (Ma Wan tower; 355.5 m side span).
    pub left_tower_x: f64,
    /// x of the right tower, m. Default 1829.5 (Tsing Yi tower; 1377 m main span).
    pub right_tower_x: f64,
    /// x of the right cable anchorage, m. Default 2129.5 (300 m Tsing Yi side span).
    pub right_anchorage_x: f64,
    /// x of the deck's left end (abutment bearing), m. Default 0.0.
    pub deck_start_x: f64,
    /// x of the deck's right end (abutment bearing), m. Default 2160.0 (overall length).
    pub deck_end_x: f64,
    /// x of further deck piers (bearings only, no cable), m. Default: three piers evenly
    /// spaced between the right tower and the right abutment (1912.125, 1994.75, 2077.375).
    pub deck_piers_x: Vec<f64>,
    /// Whether the deck between the left pier and the left tower hangs from the cables.
    /// Default true.
    pub left_side_span_suspended: bool,
    /// Whether the deck of the right side span hangs from the cables. Default false (the
    /// deck rests on the piers and the cables span free to the anchorage).
    pub right_side_span_suspended: bool,
    /// Longitudinal deck restraint. Default [`LongitudinalRestraint::LeftAbutment`].
    pub longitudinal_restraint: LongitudinalRestraint,

    // ------------------------------------------------------------- elevations (m)
    /// Tower height from its base to the saddle, m. Default 206.
    pub tower_height: f64,
    /// Height of the deck shear centre above the tower base, m. Default 75.
    pub deck_level_above_tower_base: f64,
    /// Main-span cable sag over span, f/L (–). Default 1/11.
    pub main_sag_ratio: f64,
    /// Elevation of the left pier saddle above the deck shear centre, m. Default 50.
    pub left_pier_saddle_elevation: f64,
    /// Elevation of the left anchorage (splay saddle) above the deck shear centre, m. Default 0.
    pub left_anchorage_elevation: f64,
    /// Elevation of the right anchorage above the deck shear centre, m. Default 0.
    pub right_anchorage_elevation: f64,

    // -------------------------------------------------------- discretisation (m)
    /// Distance between the two cable planes, m. Default 36.
    pub cable_spacing: f64,
    /// Elevation of the hanger anchor points on the deck above the shear centre, m. The
    /// rigid arm from the spine to a hanger is (0, ∓cable_spacing/2, −this). Default 0 when
    /// absent from a file; Tsing Ma 3.8 (see [`tsing_ma`]).
    #[serde(default)]
    pub hanger_anchor_elevation: f64,
    /// Target hanger spacing, m; the actual spacing divides each suspended span into an
    /// integer number of equal bays (an even number in the main span). Default 18.
    pub hanger_spacing: f64,
    /// Target element length where hangers do not fix the mesh (unsuspended deck, free
    /// cables, back-stays, tower legs), m. Default 18.
    pub element_length: f64,
    /// Gravitational acceleration, m/s². Default 9.81.
    pub gravity: f64,

    // -------------------------------------------------------------- members
    /// Deck spine at the shear centre (local y′ = lateral y, z′ = vertical z: `iy` is the
    /// vertical-bending inertia, `iz` the lateral one; `mass_per_length` is the full deck
    /// dead load (structure, railway, surfacing) / g, `mass_moment_per_length` its polar mass
    /// moment about the shear centre). Default: calibrated Tsing Ma deck.
    pub deck: BeamSection,
    /// Main cables. Default [`CableParams::default`].
    pub cable: CableParams,
    /// Hangers. Default [`HangerParams::default`].
    pub hanger: HangerParams,
    /// Tower leg (local x′ up, y′ = lateral y, z′ = longitudinal x: `iy` resists longitudinal
    /// bending, `iz` lateral bending). Default: hollow concrete leg.
    pub tower_leg: BeamSection,
    /// Tower portal beam between the legs (local x′ = y, y′ up, z′ = −x: `iz` resists vertical
    /// bending, `iy` horizontal bending). Default: prestressed concrete box.
    pub tower_crossbeam: BeamSection,
    /// Elevations of the portal beams above the deck shear centre, m. One must be 0: that
    /// beam carries the deck bearings at the tower. Default [0, 40, 80, 115].
    pub crossbeam_elevations: Vec<f64>,

    // ---------------------------------------------------------- track (consumer)
    /// Lateral offset e of the track centre from the deck shear centre (+ to the right), m.
    /// Default 2.05 (paper, Table 1). Not used by the model itself.
    pub track_eccentricity: f64,
    /// Height h4 of the rail/track reference above the deck shear centre, m. Default 1.25
    /// (paper, Table 1). Not used by the model itself.
    pub track_height: f64,
}

impl Default for SuspensionBridgeParams {
    fn default() -> Self {
        tsing_ma()
    }
}

/// The Tsing Ma Bridge as used by Xia, Xu & Chan (2000), with deck properties calibrated on
/// the six measured frequencies and the static deflection under the project's train (paper,
/// Table 1 masses). See the crate docs for the calibration table.
pub fn tsing_ma() -> SuspensionBridgeParams {
    let right_tower_x = 1829.5;
    let deck_end_x = 2160.0;
    let bay = (deck_end_x - right_tower_x) / 4.0;
    SuspensionBridgeParams {
        left_anchorage_x: 0.0,
        left_pier_x: 97.0,
        left_tower_x: 452.5,
        right_tower_x,
        right_anchorage_x: 2129.5,
        deck_start_x: 0.0,
        deck_end_x,
        deck_piers_x: (1..4).map(|k| right_tower_x + k as f64 * bay).collect(),
        left_side_span_suspended: true,
        right_side_span_suspended: false,
        longitudinal_restraint: LongitudinalRestraint::LeftAbutment,
        tower_height: 206.0,
        deck_level_above_tower_base: 75.0,
        main_sag_ratio: 1.0 / 11.0,
        left_pier_saddle_elevation: 50.0,
        left_anchorage_elevation: 0.0,
        right_anchorage_elevation: 0.0,
        cable_spacing: 36.0,
        hanger_anchor_elevation: 3.8,
        hanger_spacing: 18.0,
        element_length: 18.0,
        gravity: 9.81,
        deck: BeamSection {
            e: 2.0e11,
            g: 8.0e10,
            area: 1.2,
            iy: 18.5,
            iz: 205.0,
            j: 34.0,
            mass_per_length: 32_000.0,
            mass_moment_per_length: 6.4e6,
        },
        cable: CableParams::default(),
        hanger: HangerParams::default(),
        tower_leg: BeamSection {
            e: 3.4e10,
            g: 1.4e10,
            area: 40.0,
            iy: 200.0,
            iz: 900.0,
            j: 500.0,
            mass_per_length: 100_000.0,
            mass_moment_per_length: 2.75e6,
        },
        tower_crossbeam: BeamSection {
            e: 3.4e10,
            g: 1.4e10,
            area: 20.0,
            iy: 60.0,
            iz: 100.0,
            j: 80.0,
            mass_per_length: 50_000.0,
            mass_moment_per_length: 4.0e5,
        },
        crossbeam_elevations: vec![0.0, 40.0, 80.0, 115.0],
        track_eccentricity: 2.05,
        track_height: 1.25,
    }
}

impl SuspensionBridgeParams {
    /// The Tsing Ma preset (same as [`tsing_ma`]).
    pub fn tsing_ma() -> Self {
        tsing_ma()
    }

    /// Main span length, m.
    pub fn main_span(&self) -> f64 {
        self.right_tower_x - self.left_tower_x
    }

    /// Main-span cable sag f, m.
    pub fn main_sag(&self) -> f64 {
        self.main_sag_ratio * self.main_span()
    }

    /// Elevation of the tower saddles above the deck shear centre, m.
    pub fn saddle_elevation(&self) -> f64 {
        self.tower_height - self.deck_level_above_tower_base
    }

    /// Length of a hanger from a cable node at `cable_z` (z down, m) to its anchor on the
    /// deck, `hanger_anchor_elevation` above the shear centre, m.
    pub fn hanger_length(&self, cable_z: f64) -> f64 {
        -cable_z - self.hanger_anchor_elevation
    }

    /// Check ranges and ordering; returns the first problem found.
    pub fn validate(&self) -> Result<(), FeError> {
        let pos = |name: &'static str, v: f64| -> Result<(), FeError> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(FeError::parameter(name, v, "must be positive and finite"))
            }
        };
        pos("tower_height", self.tower_height)?;
        pos(
            "deck_level_above_tower_base",
            self.deck_level_above_tower_base,
        )?;
        pos("main_sag_ratio", self.main_sag_ratio)?;
        pos("cable_spacing", self.cable_spacing)?;
        pos("hanger_spacing", self.hanger_spacing)?;
        if !self.hanger_anchor_elevation.is_finite() {
            return Err(FeError::parameter(
                "hanger_anchor_elevation",
                self.hanger_anchor_elevation,
                "must be finite",
            ));
        }
        pos("element_length", self.element_length)?;
        pos("gravity", self.gravity)?;
        pos("cable.e", self.cable.e)?;
        pos("cable.area_main", self.cable.area_main)?;
        pos("cable.area_side", self.cable.area_side)?;
        pos(
            "cable.mass_per_length_main",
            self.cable.mass_per_length_main,
        )?;
        pos(
            "cable.mass_per_length_side",
            self.cable.mass_per_length_side,
        )?;
        pos("hanger.e", self.hanger.e)?;
        pos("hanger.area", self.hanger.area)?;
        if !(self.hanger.mass_per_length >= 0.0 && self.hanger.mass_per_length.is_finite()) {
            return Err(FeError::parameter(
                "hanger.mass_per_length",
                self.hanger.mass_per_length,
                "must be non-negative and finite",
            ));
        }
        self.deck.validate("deck")?;
        self.tower_leg.validate("tower_leg")?;
        self.tower_crossbeam.validate("tower_crossbeam")?;
        let order = [
            ("left_anchorage_x", self.left_anchorage_x),
            ("left_pier_x", self.left_pier_x),
            ("left_tower_x", self.left_tower_x),
            ("right_tower_x", self.right_tower_x),
            ("right_anchorage_x", self.right_anchorage_x),
        ];
        for (name, v) in order.iter().chain(&[
            ("deck_start_x", self.deck_start_x),
            ("deck_end_x", self.deck_end_x),
        ]) {
            if !v.is_finite() {
                return Err(FeError::parameter(name, v, "must be finite"));
            }
        }
        for w in order.windows(2) {
            if w[1].1 <= w[0].1 {
                return Err(FeError::parameter(
                    w[1].0,
                    w[1].1,
                    format!("must be greater than {} = {}", w[0].0, w[0].1),
                ));
            }
        }
        if self.deck_start_x > self.left_pier_x {
            return Err(FeError::parameter(
                "deck_start_x",
                self.deck_start_x,
                "the deck must start at or before the left pier",
            ));
        }
        if self.deck_end_x <= self.right_tower_x {
            return Err(FeError::parameter(
                "deck_end_x",
                self.deck_end_x,
                "the deck must end beyond the right tower",
            ));
        }
        if self.right_side_span_suspended && self.deck_end_x < self.right_anchorage_x {
            return Err(FeError::parameter(
                "deck_end_x",
                self.deck_end_x,
                "a suspended right side span needs the deck to reach the right anchorage",
            ));
        }
        for &x in &self.deck_piers_x {
            let inside = x > self.deck_start_x && x < self.deck_end_x;
            let clear = (x - self.left_tower_x).abs() > 1e-6
                && (x - self.right_tower_x).abs() > 1e-6
                && (x - self.left_pier_x).abs() > 1e-6;
            let in_suspended = (x > self.left_tower_x && x < self.right_tower_x)
                || (self.left_side_span_suspended && x > self.left_pier_x && x < self.left_tower_x)
                || (self.right_side_span_suspended
                    && x > self.right_tower_x
                    && x < self.right_anchorage_x);
            if !inside || !clear || in_suspended {
                return Err(FeError::parameter(
                    "deck_piers_x",
                    x,
                    "deck piers must lie inside the deck, outside suspended spans, away from towers and the cable pier",
                ));
            }
        }
        if !self.crossbeam_elevations.contains(&0.0) {
            return Err(FeError::parameter(
                "crossbeam_elevations",
                format!("{:?}", self.crossbeam_elevations),
                "one portal beam must be at the deck level (elevation 0)",
            ));
        }
        let top = self.saddle_elevation();
        for &e in &self.crossbeam_elevations {
            if !(e >= 0.0 && e < top) {
                return Err(FeError::parameter(
                    "crossbeam_elevations",
                    e,
                    format!("must lie in [0, saddle elevation = {top}) m"),
                ));
            }
        }
        if top <= 0.0 {
            return Err(FeError::parameter(
                "tower_height",
                self.tower_height,
                "the saddle must be above the deck",
            ));
        }
        Ok(())
    }
}
