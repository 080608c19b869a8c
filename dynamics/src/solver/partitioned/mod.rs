//! The two partitions of eq. (14), each advanced by its own Newmark step with the coupling
//! quantities of the *end* of the step as inputs.
//!
//! * [`BridgeSide`] (bridge plus track): inputs per wheelset — position `x`, speed `ẋ` and the
//!   force on the rail `f = (F_y, M_x, F_z)`; it integrates `q̈ + 2ζω q̇ + ω² q = Σ Ψ(x)ᵀ f` and
//!   outputs the rail motion under each wheelset, deck plus irregularity:
//!   `u = Ψ(x) q + r(x)`, `u̇ = Ψ q̇ + ẋ r′`, `ü = Ψ q̈ + ẋ² r″`. It forms `Σ Ψᵀ f` and
//!   `Ψ (q, q̇, q̈)` through the shapes' own basis, `Ψ(x) = R Σ_b β_b(x) φ_b` (`R` the rail
//!   map): the nodes of the Lagrange stencil at `x` (nodal shapes, `β` its weights) or the
//!   half-wave numbers (sine shapes, `β_k = sin(kπ(x − x₀)/L)`), each basis function in use
//!   once per sweep instead of every mode under every wheelset.
//! * [`TrainSide`]: inputs per wheelset — that rail motion; it adds wheel hunting, integrates
//!   every vehicle and outputs positions and the wheel forces of eq. (6).
//!
//! When an interface iteration converges, both partitions satisfy their equations at
//! `t + h` with the same interface values, which is exactly the monolithic Newmark step of
//! eq. (14): the co-simulation and the monolithic solution coincide to the iteration
//! tolerance.
//!
//! **Where the parts sit.** The bridge side in `bridge_side`, with the shapes' basis at the
//! wheelsets and its kernels (the speed-ups of its sums over the wheelsets) in `basis`; the
//! train side in `train_side`; the values the two exchange per wheelset and the bridge's probe
//! output in `interface`.

mod basis;
mod bridge_side;
mod interface;
mod train_side;

pub use bridge_side::{BridgeSide, ModalState};
pub use interface::{ProbeValues, WheelInput};
pub use train_side::TrainSide;
