//! The bridge FMU's identity and resources: its model identifier, the files it carries and
//! what they hold.

use serde::{Deserialize, Serialize};
use tbi_dynamics::bridge::ModalBridge;

/// Model identifier (and shared-object stem) of the bridge FMU.
pub const BRIDGE_ID: &str = "bridge";
/// Resource file of the bridge FMU (JSON of [`BridgeResources`]).
pub const BRIDGE_RESOURCE: &str = "bridge.json";
/// Resource file with the track irregularity record (optional).
pub const TRACK_RESOURCE: &str = "track.csv";

/// A probe: name (for descriptions) and position, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProbeSpec {
    pub name: String,
    pub x_m: f64,
}

/// Everything the bridge FMU reads from its resources.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BridgeResources {
    pub modal: ModalBridge,
    pub probes: Vec<ProbeSpec>,
    pub n_wheelsets: usize,
    /// The track each wheelset slot runs on, 0 the first (empty: all on the first; not
    /// written then).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wheelset_tracks: Vec<usize>,
    /// Whether `track.csv` holds an irregularity record (else the track is smooth).
    pub has_track_record: bool,
}

impl BridgeResources {
    /// Refuse a track list that does not give one existing track per wheelset slot.
    pub fn check_tracks(&self) -> Result<(), String> {
        let tracks = &self.wheelset_tracks;
        if tracks.is_empty() {
            return Ok(());
        }
        if tracks.len() != self.n_wheelsets {
            return Err(format!(
                "wheelset_tracks has {} entries for {} wheelsets",
                tracks.len(),
                self.n_wheelsets
            ));
        }
        let n = self.modal.n_tracks();
        match tracks.iter().position(|&k| k >= n) {
            Some(w) => Err(format!(
                "wheelset_tracks[{w}] = {}: the deck has {n} track(s), numbered from 0",
                tracks[w]
            )),
            None => Ok(()),
        }
    }
}
