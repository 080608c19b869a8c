//! The scenario bridge's modes as a [`ModeSet`] and their table beside the measured Tsing Ma
//! frequencies.

use std::fmt::Write as _;
use tbi_dynamics::bridge::{Mode, ModeSet, FORMAT_TAG};

/// Measured Tsing Ma frequencies (domain reference §3), Hz, by mode label.
pub const TSING_MA_TARGETS: [(&str, &str, f64); 6] = [
    ("L-S-1", "1st lateral symmetric", 0.069),
    ("V-A-1", "1st vertical antisymmetric", 0.113),
    ("V-S-1", "1st vertical symmetric", 0.139),
    ("L-A-1", "1st lateral antisymmetric", 0.164),
    ("V-S-2", "2nd vertical symmetric", 0.184),
    ("T-S-1", "1st torsional", 0.267),
];

/// The scenario bridge's modes as a [`ModeSet`] (analytic shapes sampled at 401 nodes).
pub fn mode_set(s: &crate::scenario::Scenario) -> Result<ModeSet, String> {
    match crate::model::nodal_modes(s).map_err(|e| e.to_string())? {
        Some((mut set, modal, _)) => {
            set.modes.truncate(modal.modes);
            Ok(set)
        }
        None => {
            let modal = crate::model::build_bridge(s).map_err(|e| e.to_string())?;
            let n = 401;
            let xs: Vec<f64> = (0..n)
                .map(|i| modal.x_start_m + modal.length_m() * i as f64 / (n - 1) as f64)
                .collect();
            let nb = modal.n_modes();
            let mut modes: Vec<Mode> = (0..nb)
                .map(|k| Mode {
                    label: modal.labels[k].clone(),
                    frequency_hz: modal.frequencies_hz[k],
                    damping_ratio: Some(modal.damping[k]),
                    lateral: Vec::with_capacity(n),
                    vertical: Vec::with_capacity(n),
                    torsion: Vec::with_capacity(n),
                })
                .collect();
            let mut sh = vec![[0.0; 3]; nb];
            for &x in &xs {
                modal.deck_shapes(x, &mut sh);
                for (m, v) in modes.iter_mut().zip(&sh) {
                    m.lateral.push(v[0]);
                    m.vertical.push(v[1]);
                    m.torsion.push(v[2]);
                }
            }
            Ok(ModeSet {
                format: FORMAT_TAG.to_string(),
                x_m: xs,
                modes,
            })
        }
    }
}

/// The table of modes (Markdown), with the Tsing Ma targets when they apply.
pub fn table(set: &ModeSet, targets: bool) -> String {
    let mut t = String::from("| mode | frequency (Hz) | type |\n|---:|---:|---|\n");
    for (k, m) in set.modes.iter().enumerate() {
        let _ = writeln!(t, "| {} | {:.4} | {} |", k + 1, m.frequency_hz, m.label);
    }
    if targets {
        t.push_str(
            "\n| target | measured (Hz) | model (Hz) | difference |\n|---|---:|---:|---:|\n",
        );
        for (label, name, f) in TSING_MA_TARGETS {
            match set.modes.iter().find(|m| m.label == label) {
                Some(m) => {
                    let _ = writeln!(
                        t,
                        "| {name} ({label}) | {f:.3} | {:.4} | {:+.1} % |",
                        m.frequency_hz,
                        100.0 * (m.frequency_hz / f - 1.0)
                    );
                }
                None => {
                    let _ = writeln!(t, "| {name} ({label}) | {f:.3} | not among the modes | |");
                }
            }
        }
    }
    t
}
