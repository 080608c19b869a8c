//! Train–bridge interaction dynamics after Xia, Xu & Chan (2000), "Dynamic interaction of
//! long suspension bridges with running trains", J. Sound Vib. 237(2).
//!
//! * [`vehicle`]: vehicles as constant linear systems driven by the rail under their
//!   wheelsets (moving force, sprung mass, the 27-DOF coach), derived from element lists;
//! * [`bridge`]: the modal bridge (analytic spans or mode files) and the rail map Ψ(x);
//! * [`track`]: rail irregularity profiles and wheel hunting;
//! * [`solver`]: Newmark integration — the monolithic eq. (14) and its two partitions;
//! * [`newmark`]: the integrator's coefficients.
//!
//! Axes (used everywhere): x along the track in the direction of travel, y lateral to the
//! right, z vertical downward; rotations right-handed about x (roll, right side down), y
//! (pitch, nose up) and z (yaw, nose right). SI units throughout.

// Index loops mirror the equations (q_n, ω_n, rows k of Ψ) and are kept on purpose.
#![allow(clippy::needless_range_loop)]

pub mod bridge;
/// Input errors (defined with the modes file format, which needs them first).
pub mod error {
    pub use tbi_modes::error::*;
}
pub mod en1991;
pub mod hslm;
pub mod newmark;
pub mod response;
pub use tbi_numerics::simd;
pub mod solver;
pub mod sparse;
pub mod track;
pub mod train;
pub mod trig;
pub mod vehicle;

pub use error::InputError;
