//! Explicit Gauss–Jacobi coupling.
//!
//! All inputs of the step `t → t + h` are the outputs at `t`; then every participant steps
//! (conceptually in parallel). Every connection is lagged by one step, so the coupling error is
//! first order in `h`. No state is saved and nothing is iterated.

use super::convergence::{Groups, WeightedRms};
use super::exchange::Exchange;
use super::scheme::{discard_error, step_all, CouplingScheme, StepReport};
use super::system::{CouplingError, System};

/// Explicit Gauss–Jacobi scheme.
#[derive(Debug, Clone)]
pub struct Jacobi {
    measure: WeightedRms,
    /// Groups of the values the defect is measured over ([`Exchange::groups`]).
    groups: Groups,
    exchange: Option<Exchange>,
    lagged: Vec<f64>,
    fresh: Vec<f64>,
}

impl Jacobi {
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

impl CouplingScheme for Jacobi {
    fn name(&self) -> &str {
        "jacobi"
    }

    fn initialize(&mut self, sys: &mut System) -> Result<(), CouplingError> {
        let ex = Exchange::initial(sys)?;
        sys.pass_discrete(None)?;
        self.groups = ex.groups(0..ex.slots());
        self.exchange = Some(ex);
        Ok(())
    }

    fn step(&mut self, sys: &mut System, t: f64, h: f64) -> Result<StepReport, CouplingError> {
        let ex = Exchange::current(&mut self.exchange, sys)?;
        if self.groups.len() != ex.slots() {
            self.groups = ex.groups(0..ex.slots());
        }
        ex.read_all(sys)?;
        self.lagged.clone_from(&ex.values);
        ex.write_all(sys)?;
        sys.pass_discrete(None)?;
        if let Some(p) = step_all(sys, t, h)? {
            return Err(discard_error(sys, "jacobi", p, t, h));
        }
        ex.read_all(sys)?;
        self.fresh.clone_from(&ex.values);
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
