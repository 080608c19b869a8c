//! What the partitions exchange per wheelset ([`WheelInput`]: where it is, how fast it
//! goes and its force on the rail, the bridge's inputs) and the bridge's output at a probe
//! ([`ProbeValues`]).

use serde::{Deserialize, Serialize};

/// The inputs of one wheelset to the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct WheelInput {
    /// Position along the track, m.
    pub x: f64,
    /// Speed along the track, m/s.
    pub vx: f64,
    /// Force on the rail (F_y N, M_x N·m, F_z N).
    pub f: [f64; 3],
}

/// Deck response at a probe (shear centre).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ProbeValues {
    /// Lateral displacement, m.
    pub y: f64,
    /// Vertical displacement, m (+ down).
    pub z: f64,
    /// Torsion, rad.
    pub theta: f64,
    /// Lateral acceleration, m/s².
    pub y_dd: f64,
    /// Vertical acceleration, m/s².
    pub z_dd: f64,
}

impl ProbeValues {
    /// Deck response from the deck shapes `(φ_h, φ_v, φ_θ)` at the probe and the modal
    /// displacements and accelerations.
    pub fn from_shapes(shapes: &[[f64; 3]], q: &[f64], qdd: &[f64]) -> Self {
        let mut p = ProbeValues::default();
        for (n, sh) in shapes.iter().enumerate() {
            p.y += sh[0] * q[n];
            p.z += sh[1] * q[n];
            p.theta += sh[2] * q[n];
            p.y_dd += sh[0] * qdd[n];
            p.z_dd += sh[1] * qdd[n];
        }
        p
    }
}
