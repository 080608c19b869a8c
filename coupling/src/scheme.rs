//! The interface every coupling algorithm implements, and the helpers they share.

use super::system::{CouplingError, Participant, StepStatus, System};

/// What one coupling step did.
#[derive(Debug, Clone, PartialEq)]
pub struct StepReport {
    /// Gauss–Seidel sweeps (participant `do_step` rounds) performed; 1 for explicit schemes.
    pub iterations: usize,
    /// Implicit scheme: the weighted RMS interface change of the last sweep (converged when
    /// ≤ 1, see [`super::convergence::WeightedRms`], grouped by source and unit). Explicit
    /// schemes: the interface defect, how far the values the lagged inputs used (outputs at
    /// `t`) are from the outputs they stand for (at `t + h`), in the same tolerances against
    /// each group's largest magnitude so far ([`super::convergence::WeightedRms::evaluate_lag`]);
    /// ≤ 1 would mean the lag is within the implicit tolerance; for information only.
    pub residual: f64,
    /// The convergence criterion holds (always `true` for explicit schemes).
    pub converged: bool,
    /// The participant that answered `do_step` with [`StepStatus::Discard`]. The step did not
    /// complete and must be retried from `t` or abandoned, never accepted.
    pub discarded_by: Option<String>,
    /// When the step did not converge: where the last sweep changed most (the connection's
    /// source, its value and change) and whether the acceleration broke down.
    pub diagnosis: Option<String>,
    /// Participant steps spent on the interface Jacobian in this step (finite differences
    /// through rollback; not counted in `iterations`).
    pub jacobian_probes: usize,
}

/// One co-simulation master algorithm (MasterSim: a master algorithm; preCICE: a coupling
/// scheme). The scheme owns how values move between participants within a step; the caller
/// ([`super::advance::advance`]) owns the time loop and what happens when a step fails.
pub trait CouplingScheme {
    /// Human-readable name, e.g. `"implicit (iqn-ils)"`.
    fn name(&self) -> &str;

    /// Binds the scheme to `sys` and exchanges the initial values: every connected output is
    /// read and then written to the inputs it feeds.
    fn initialize(&mut self, sys: &mut System) -> Result<(), CouplingError>;

    /// Advances every participant from `t` to `t + h`.
    ///
    /// On return (`Ok`) all participants are at `t + h`, except when
    /// [`StepReport::discarded_by`] is set. A scheme that can return `converged == false` or a
    /// discard leaves each participant's rollback slot holding its state at `t`, so the caller
    /// may restore all participants and retry; schemes that never do so need not save states.
    fn step(&mut self, sys: &mut System, t: f64, h: f64) -> Result<StepReport, CouplingError>;
}

/// `do_step` of participant `p`, with the participant and time named in errors.
pub(crate) fn do_step(
    sys: &mut System,
    p: usize,
    t: f64,
    h: f64,
) -> Result<StepStatus, CouplingError> {
    let part = &mut sys.participants[p];
    part.do_step(t, h)
        .map_err(|e| CouplingError::call(part.name(), format!("do_step(t = {t}, h = {h})"), e))
}

/// Steps every participant from `t` to `t + h` on the inputs already written, starting all
/// before waiting for any ([`Participant::start_step`]): participants in processes of their
/// own step side by side. Returns the first that discarded its step, if any (the others have
/// stepped all the same).
pub(crate) fn step_all(sys: &mut System, t: f64, h: f64) -> Result<Option<usize>, CouplingError> {
    let named = |part: &dyn Participant, e| {
        CouplingError::call(part.name(), format!("do_step(t = {t}, h = {h})"), e)
    };
    let mut done = Vec::with_capacity(sys.participants.len());
    for part in sys.participants.iter_mut() {
        done.push(part.start_step(t, h).map_err(|e| named(part.as_ref(), e))?);
    }
    let mut discarded = None;
    for (p, (part, status)) in sys.participants.iter_mut().zip(done).enumerate() {
        let status = match status {
            Some(s) => s,
            None => part.finish_step().map_err(|e| named(part.as_ref(), e))?,
        };
        if status == StepStatus::Discard && discarded.is_none() {
            discarded = Some(p);
        }
    }
    Ok(discarded)
}

/// Saves the state of every participant into its rollback slot.
pub fn save_all(sys: &mut System) -> Result<(), CouplingError> {
    for part in sys.participants.iter_mut() {
        part.save_state()
            .map_err(|e| CouplingError::call(part.name(), "save_state", e))?;
    }
    Ok(())
}

/// Restores every participant from its rollback slot.
pub fn restore_all(sys: &mut System) -> Result<(), CouplingError> {
    for part in sys.participants.iter_mut() {
        part.restore_state()
            .map_err(|e| CouplingError::call(part.name(), "restore_state", e))?;
    }
    Ok(())
}

/// Error for a discard in a scheme that keeps no state to roll back to.
pub(crate) fn discard_error(sys: &System, scheme: &str, p: usize, t: f64, h: f64) -> CouplingError {
    CouplingError::Discarded(format!(
        "{} discarded the step t = {t} s, h = {h} s; the {scheme} scheme keeps no saved state \
         to retry from (use the implicit scheme for rollback)",
        sys.participants[p].name()
    ))
}
