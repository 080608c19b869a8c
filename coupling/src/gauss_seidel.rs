//! Explicit Gauss–Seidel coupling.
//!
//! Participants step in their order in [`System::participants`]; before its step, participant
//! `p` receives the outputs at `t + h` of the participants `q < p` (already stepped) and the
//! outputs at `t` of the participants `q ≥ p`. Only the feedback connections (`from ≥ to`) are
//! lagged, and the coupling error is first order in `h`. No state is saved.

use super::convergence::{Groups, WeightedRms};
use super::exchange::Exchange;
use super::scheme::{discard_error, do_step, CouplingScheme, StepReport};
use super::system::{CouplingError, StepStatus, System};

/// Explicit (single-sweep) Gauss–Seidel scheme.
#[derive(Debug, Clone)]
pub struct GaussSeidel {
    measure: WeightedRms,
    /// Groups of the values the defect is measured over ([`Exchange::groups`]).
    groups: Groups,
    exchange: Option<Exchange>,
    lagged: Vec<f64>,
    fresh: Vec<f64>,
}

impl GaussSeidel {
    /// `measure` only scales the reported interface defect ([`super::scheme::StepReport`]).
    pub fn new(measure: WeightedRms) -> Self {
        Self {
            measure,
            groups: Groups::default(),
            exchange: None,
            lagged: Vec::new(),
            fresh: Vec::new(),
        }
    }
}

impl CouplingScheme for GaussSeidel {
    fn name(&self) -> &str {
        "gauss-seidel"
    }

    fn initialize(&mut self, sys: &mut System) -> Result<(), CouplingError> {
        let ex = Exchange::initial(sys)?;
        sys.pass_discrete(None)?;
        self.groups = ex.groups(ex.feedback_slots.iter().copied());
        self.exchange = Some(ex);
        Ok(())
    }

    fn step(&mut self, sys: &mut System, t: f64, h: f64) -> Result<StepReport, CouplingError> {
        let ex = Exchange::current(&mut self.exchange, sys)?;
        if self.groups.len() != ex.unknowns() {
            self.groups = ex.groups(ex.feedback_slots.iter().copied());
        }
        ex.read_all(sys)?;
        ex.feedback_values(&mut self.lagged);
        for p in 0..sys.participants.len() {
            // Slots of participants q < p already hold their outputs at t + h.
            ex.write_inputs(sys, p, None)?;
            // Integer and Boolean inputs from the sources' current values, with the same
            // timing as the Real ones.
            sys.pass_discrete(Some(p))?;
            if do_step(sys, p, t, h)? == StepStatus::Discard {
                return Err(discard_error(sys, "gauss-seidel", p, t, h));
            }
            ex.read_outputs(sys, p)?;
        }
        ex.feedback_values(&mut self.fresh);
        Ok(StepReport {
            iterations: 1,
            residual: self
                .measure
                .evaluate_lag(&self.lagged, &self.fresh, &mut self.groups),
            converged: true,
            discarded_by: None,
            diagnosis: None,
            jacobian_probes: 0,
        })
    }
}
