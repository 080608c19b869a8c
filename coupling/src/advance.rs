//! One macro step of the master loop with a policy for steps that do not converge.
//!
//! [`advance`] calls [`CouplingScheme::step`] and applies [`OnNonConvergence`] when the step
//! reports `converged == false` or a discard:
//!
//! * [`OnNonConvergence::Stop`]: an error naming the step, the residual and the iterations.
//! * [`OnNonConvergence::Retry`]: restore every participant to `t` and take two steps of
//!   `h/2` (recursively) while `h/2 ≥ min_step`; an error once that would go below `min_step`.
//!   The rejected attempts are listed in [`AdvanceReport::rejected`].
//! * [`OnNonConvergence::Accept`]: keep the non-converged step; it stays visible in the report
//!   ([`AdvanceReport::accepted_unconverged`]). A discarded step or one with a non-finite
//!   residual is never accepted.

use std::fmt;

use super::scheme::{restore_all, CouplingScheme, StepReport};
use super::system::{CouplingError, System};

/// What to do when a coupling step does not converge within `max_iterations`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum OnNonConvergence {
    /// Fail with an error (default).
    #[default]
    Stop,
    /// Roll back and split the step in halves, down to `min_step` (s).
    Retry { min_step: f64 },
    /// Keep the result and report it. Only when explicitly configured.
    Accept,
}

impl fmt::Display for OnNonConvergence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Stop => f.write_str("stop"),
            Self::Retry { min_step } => write!(f, "retry (min_step = {min_step} s)"),
            Self::Accept => f.write_str("accept"),
        }
    }
}

/// One step attempted by [`advance`].
#[derive(Debug, Clone, PartialEq)]
pub struct Substep {
    /// Start time (s).
    pub t: f64,
    /// Step size (s).
    pub h: f64,
    pub report: StepReport,
}

/// The outcome of [`advance`] over `[t, t + h]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AdvanceReport {
    /// The steps kept, in time order; they cover `[t, t + h]`. One unless the step was split.
    pub steps: Vec<Substep>,
    /// Attempts that did not converge and were rolled back (policy `Retry`).
    pub rejected: Vec<Substep>,
}

impl AdvanceReport {
    /// Sweeps over all kept steps.
    pub fn iterations(&self) -> usize {
        self.steps.iter().map(|s| s.report.iterations).sum()
    }

    /// Number of kept steps that did not converge (policy `Accept`).
    pub fn accepted_unconverged(&self) -> usize {
        self.steps.iter().filter(|s| !s.report.converged).count()
    }

    /// Whether the step had to be split.
    pub fn retried(&self) -> bool {
        !self.rejected.is_empty()
    }
}

/// Advances `sys` from `t` to `t + h` with `scheme`, applying `policy` to steps that do not
/// converge.
pub fn advance(
    scheme: &mut dyn CouplingScheme,
    sys: &mut System,
    t: f64,
    h: f64,
    policy: OnNonConvergence,
) -> Result<AdvanceReport, CouplingError> {
    let mut report = AdvanceReport::default();
    advance_into(scheme, sys, t, h, policy, &mut report)?;
    Ok(report)
}

/// [`advance`] into `report`, emptied first (a master loop keeps one report for the run, so
/// a step allocates nothing for it).
pub fn advance_into(
    scheme: &mut dyn CouplingScheme,
    sys: &mut System,
    t: f64,
    h: f64,
    policy: OnNonConvergence,
    report: &mut AdvanceReport,
) -> Result<(), CouplingError> {
    report.steps.clear();
    report.rejected.clear();
    if !(h > 0.0 && h.is_finite() && t.is_finite()) {
        return Err(CouplingError::Step(format!(
            "invalid coupling step t = {t} s, h = {h} s"
        )));
    }
    attempt(scheme, sys, t, h, policy, report)
}

fn attempt(
    scheme: &mut dyn CouplingScheme,
    sys: &mut System,
    t: f64,
    h: f64,
    policy: OnNonConvergence,
    report: &mut AdvanceReport,
) -> Result<(), CouplingError> {
    let r = scheme.step(sys, t, h)?;
    if r.converged && r.discarded_by.is_none() {
        report.steps.push(Substep { t, h, report: r });
        return Ok(());
    }
    let what = failure(scheme.name(), t, h, &r);
    match policy {
        OnNonConvergence::Stop => Err(CouplingError::Step(format!("{what}; policy: stop"))),
        OnNonConvergence::Accept => {
            if r.discarded_by.is_some() || !r.residual.is_finite() {
                return Err(CouplingError::Step(format!(
                    "{what}; policy: accept, but a discarded or non-finite step cannot be kept"
                )));
            }
            report.steps.push(Substep { t, h, report: r });
            Ok(())
        }
        OnNonConvergence::Retry { min_step } => {
            let half = 0.5 * h;
            if half < min_step {
                return Err(CouplingError::Step(format!(
                    "{what}; policy: retry, but h/2 = {half} s is below min_step = {min_step} s"
                )));
            }
            restore_all(sys)?;
            report.rejected.push(Substep { t, h, report: r });
            attempt(scheme, sys, t, half, policy, report)?;
            attempt(scheme, sys, t + half, half, policy, report)
        }
    }
}

fn failure(scheme: &str, t: f64, h: f64, r: &StepReport) -> String {
    match &r.discarded_by {
        Some(name) => format!(
            "coupling step t = {t} s, h = {h} s ({scheme}): {name} discarded the step in \
             iteration {}",
            r.iterations
        ),
        None => format!(
            "coupling step t = {t} s, h = {h} s ({scheme}) did not converge: residual {:.3e} \
             (weighted RMS, converged when ≤ 1) after {} iterations{}",
            r.residual,
            r.iterations,
            r.diagnosis
                .as_deref()
                .map(|d| format!("; {d}"))
                .unwrap_or_default()
        ),
    }
}
