//! Co-simulation coupling algorithms.
//!
//! # Setting
//!
//! A [`System`] holds participants `P₀, …, P_{m−1}` in their sweep order and scalar
//! connections `to.to_vr := from.from_vr`. Each participant advances its own model from `t` to
//! `t + h` in [`Participant::do_step`] and interprets its inputs as values at the end of the
//! step. A connection is *forward* if `from < to` and *feedback* if `from ≥ to`; for the
//! train–bridge system, bridge (0) → train (1) carries displacements (forward) and
//! train → bridge carries wheel forces (feedback).
//!
//! # Schemes ([`CouplingScheme`])
//!
//! * [`Jacobi`]: every input is the output at `t`; all participants step. First order in `h`.
//! * [`GaussSeidel`]: one sweep in order; forward inputs are fresh (at `t + h`), feedback inputs
//!   are the outputs at `t`. First order in `h`.
//! * [`Implicit`]: the sweep is iterated to the fixed point. With `x ∈ ℝⁿ` the feedback values
//!   at `t + h`, one sweep (after restoring all participants to `t`) is the map
//!
//!   ```text
//!   x̃ = H(x),    r = x̃ − x,
//!   ```
//!
//!   whose fixed point is the monolithic solution of the step (for participants that
//!   integrate with the same method as the monolithic model, the two are identical). The
//!   iteration stops when the weighted RMS of [`WeightedRms`],
//!
//!   ```text
//!   sqrt( (1/n) Σᵢ ((x̃ᵢ − xᵢ) / (rtol·|x̃ᵢ| + atol))² ) ≤ 1 ,
//!   ```
//!
//!   holds, keeping the state of the last sweep, or after `max_iterations` sweeps.
//!
//! # Accelerations ([`acceleration::Acceleration`])
//!
//! With `D = diag(1 / (rtol·X + atol))` a per-variable scaling by the magnitude `X` of each
//! block of interface values (normalised to a largest entry of 1, fixed within a step):
//!
//! * constant relaxation: `xₖ₊₁ = xₖ + ω rₖ`;
//! * Aitken: `xₖ₊₁ = xₖ + ωₖ rₖ`, `ωₖ = −ωₖ₋₁ rₖ₋₁ᵀD²(rₖ − rₖ₋₁) / ‖D(rₖ − rₖ₋₁)‖²`;
//! * IQN-ILS: `xₖ₊₁ = x̃ₖ + W c`, `c = argmin ‖D(V c + rₖ)‖₂`, where the columns of `V` and `W`
//!   are the differences of successive residuals and outputs of the step (and optionally of
//!   previous steps), solved by a filtered QR factorisation.
//!
//! # Master loop
//!
//! [`advance()`] performs one macro step and applies [`OnNonConvergence`] (stop, retry with
//! halved steps after rollback, or accept and report); [`CouplingStatistics`] accumulates the
//! iteration counts of a run. [`CouplingConfig`] mirrors the scenario keys and
//! [`build_scheme`] constructs the configured scheme.

pub mod acceleration;
pub mod advance;
pub mod config;
pub mod convergence;
pub(crate) mod exchange;
pub mod gauss_seidel;
pub mod implicit;
pub mod jacobi;
pub mod jacobian;
pub mod scheme;
pub mod stats;
pub mod system;

pub use advance::{advance, advance_into, AdvanceReport, OnNonConvergence, Substep};
pub use config::{
    build_acceleration, build_scheme, AccelerationKind, CouplingConfig, NonConvergenceAction,
    SchemeKind,
};
pub use convergence::WeightedRms;
pub use exchange::settle_inputs;
pub use gauss_seidel::GaussSeidel;
pub use implicit::{Implicit, Predictor};
pub use jacobi::Jacobi;
pub use scheme::{restore_all, save_all, CouplingScheme, StepReport};
pub use stats::CouplingStatistics;
pub use system::{
    Connection, CouplingError, Discrete, DiscreteConnection, Participant, StepStatus, System,
};
