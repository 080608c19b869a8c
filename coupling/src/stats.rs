//! Per-run statistics of the coupling iteration.

use std::fmt;

use super::advance::AdvanceReport;
use super::scheme::StepReport;

/// Counters over a run, fed with [`CouplingStatistics::record`] after every
/// [`advance`](super::advance::advance).
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingStatistics {
    /// Steps kept (a split step counts each part).
    pub steps: usize,
    /// Sweeps over the kept steps.
    pub iterations: usize,
    /// Largest number of sweeps in one kept step.
    pub max_iterations: usize,
    /// Kept steps by their number of sweeps: entry `k` counts the steps that took `k + 1`.
    pub steps_by_iterations: Vec<usize>,
    /// Largest residual of a kept step (weighted RMS; ≤ 1 when converged).
    pub max_residual: f64,
    /// Kept steps that did not converge (policy `Accept`).
    pub accepted_unconverged: usize,
    /// Attempts rolled back and split (policy `Retry`).
    pub rejected: usize,
    /// Sweeps spent in rejected attempts.
    pub rejected_iterations: usize,
    /// Smallest step kept (s); `f64::INFINITY` before the first.
    pub min_step: f64,
    /// Participant steps spent on interface Jacobians (kept steps).
    pub jacobian_probes: usize,
}

impl Default for CouplingStatistics {
    fn default() -> Self {
        Self {
            steps: 0,
            iterations: 0,
            max_iterations: 0,
            steps_by_iterations: Vec::new(),
            max_residual: 0.0,
            accepted_unconverged: 0,
            rejected: 0,
            rejected_iterations: 0,
            min_step: f64::INFINITY,
            jacobian_probes: 0,
        }
    }
}

impl CouplingStatistics {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the steps of one [`advance`](super::advance::advance).
    pub fn record(&mut self, report: &AdvanceReport) {
        for s in &report.steps {
            self.record_step(s.h, &s.report);
        }
        self.rejected += report.rejected.len();
        self.rejected_iterations += report
            .rejected
            .iter()
            .map(|s| s.report.iterations)
            .sum::<usize>();
    }

    /// Adds one kept step of size `h`.
    pub fn record_step(&mut self, h: f64, report: &StepReport) {
        self.steps += 1;
        self.iterations += report.iterations;
        self.max_iterations = self.max_iterations.max(report.iterations);
        if let Some(k) = report.iterations.checked_sub(1) {
            if self.steps_by_iterations.len() <= k {
                self.steps_by_iterations.resize(k + 1, 0);
            }
            self.steps_by_iterations[k] += 1;
        }
        self.max_residual = self.max_residual.max(report.residual);
        self.min_step = self.min_step.min(h);
        self.jacobian_probes += report.jacobian_probes;
        if !report.converged {
            self.accepted_unconverged += 1;
        }
    }

    /// Mean sweeps per kept step (0 before the first).
    pub fn mean_iterations(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.iterations as f64 / self.steps as f64
        }
    }
}

impl fmt::Display for CouplingStatistics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} steps, iterations mean {:.2} max {}, max residual {:.3e}",
            self.steps,
            self.mean_iterations(),
            self.max_iterations,
            self.max_residual
        )?;
        if self.rejected > 0 {
            write!(
                f,
                ", {} rejected attempts ({} iterations), smallest step {} s",
                self.rejected, self.rejected_iterations, self.min_step
            )?;
        }
        if self.accepted_unconverged > 0 {
            write!(
                f,
                ", {} steps accepted WITHOUT convergence",
                self.accepted_unconverged
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(iterations: usize) -> StepReport {
        StepReport {
            iterations,
            residual: 0.5,
            converged: true,
            discarded_by: None,
            diagnosis: None,
            jacobian_probes: 0,
        }
    }

    #[test]
    fn steps_are_counted_by_their_sweeps() {
        let mut stats = CouplingStatistics::new();
        for k in [2, 2, 3, 5, 2, 1] {
            stats.record_step(0.01, &step(k));
        }
        assert_eq!(stats.steps_by_iterations, vec![1, 3, 1, 0, 1]);
        assert_eq!(stats.steps_by_iterations.iter().sum::<usize>(), stats.steps);
        assert_eq!(stats.max_iterations, stats.steps_by_iterations.len());
        assert_eq!(stats.iterations, 15);
    }
}
