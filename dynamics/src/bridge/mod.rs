//! The bridge as a modal model.
pub mod aeroelastic;
pub mod buffeting;
mod lanes;
pub mod modal;
/// The modes file format (crate `tbi-modes`).
pub use tbi_modes as modes_file;
pub mod simply_supported;

pub use lanes::{LaneScratch, SHAPE_LANES};
pub use modal::{ModalBridge, Shapes};
pub use simply_supported::SimplySupported;
pub use tbi_modes::{Mode, ModeSet, FORMAT_TAG};

impl ModalBridge {
    /// A modal bridge from the first `modes` modes of `set`. Modes without a damping
    /// ratio get `damping` (bending) or `damping_torsional` (labels starting with `T`).
    /// The deck starts at the first node; shapes are interpolated through `order` nodes.
    pub fn from_mode_set(
        set: &ModeSet,
        modes: usize,
        damping: f64,
        damping_torsional: f64,
        e_m: f64,
        h4_m: f64,
        order: usize,
    ) -> ModalBridge {
        let modes = modes.min(set.modes.len());
        let used = &set.modes[..modes];
        let nn = set.x_m.len();
        let mut values = Vec::with_capacity(nn * modes);
        for j in 0..nn {
            for m in used {
                values.push([m.lateral[j], m.vertical[j], m.torsion[j]]);
            }
        }
        ModalBridge {
            x_start_m: set.x_m[0],
            x_end_m: *set.x_m.last().expect("validated: at least two nodes"),
            frequencies_hz: used.iter().map(|m| m.frequency_hz).collect(),
            damping: used
                .iter()
                .map(|m| {
                    m.damping_ratio.unwrap_or(if m.label.starts_with('T') {
                        damping_torsional
                    } else {
                        damping
                    })
                })
                .collect(),
            labels: used.iter().map(|m| m.label.clone()).collect(),
            e_m,
            h4_m,
            other_tracks: Vec::new(),
            shapes: Shapes::Nodal {
                x_m: set.x_m.clone(),
                values,
                order,
            },
            steady_modal_force: Vec::new(),
            buffeting: None,
        }
    }
}
