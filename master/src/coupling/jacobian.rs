//! The interface Jacobian of one step, `J = ∂H/∂x`, by finite differences through rollback.
//!
//! FMI 2.0 gives a Co-Simulation FMU's directional derivatives only at a communication
//! point, not of its step, so the step map of each participant `p` (its connected outputs at
//! `t + h` as a function of its connected inputs for the step) is differentiated by stepping
//! it again from its saved state at `t` with one input moved:
//!
//! ```text
//! J_p[:, i] = (y_p(u + εᵢ eᵢ) − y_p(u)) / εᵢ ,   εᵢ = 10⁻⁶ · max(|uᵢ|, Uᵢ, 10⁻³⁰⁰) ,
//! ```
//!
//! with `Uᵢ` the largest magnitude among the values of the input's source group (same
//! participant and unit), so that an input passing through zero is moved by an amount on the
//! scale of its kind. On maps linear in the moved input the difference is exact up to
//! rounding; in a wheelset position it is accurate to about 10⁻⁶.
//!
//! The sweep visits the participants in order, so the chain rule gives `J` slot by slot:
//! an input of `p` is either an unknown `x_u` (a feedback connection: `∂/∂x = e_u`) or the
//! output of a participant stepped before it in the sweep (`∂/∂x` already known), and
//!
//! ```text
//! ∂y_p/∂x = J_p · ∂u_p/∂x ,      J = rows of ∂y/∂x of the unknowns' sources.
//! ```
//!
//! Only inputs whose `∂u/∂x` row is non-zero are moved. Every participant is left at a
//! probed state: the caller restores them before the next sweep.

use super::exchange::Exchange;
use super::scheme::do_step;
use super::system::{CouplingError, StepStatus, System};
use nalgebra::DMatrix;

impl Exchange {
    /// `J = ∂H/∂x` of the step `t → t + h` at the guess `x`, with the slot values of the
    /// last sweep at `x` as the operating point of the forward connections.
    pub(crate) fn step_jacobian(
        &mut self,
        sys: &mut System,
        t: f64,
        h: f64,
        x: &[f64],
    ) -> Result<DMatrix<f64>, CouplingError> {
        let n = self.unknowns();
        // ∂(slot value)/∂x, for the slots of participants already differentiated
        let mut d_slot: Vec<Option<Vec<f64>>> = vec![None; self.slots()];
        let group_max = self.group_magnitudes();
        for p in 0..sys.participants.len() {
            if self.out_vrs[p].is_empty() {
                continue;
            }
            // ∂u/∂x of each input, and its value at the operating point
            let mut rows: Vec<Vec<f64>> = Vec::with_capacity(self.in_vrs[p].len());
            let mut base: Vec<f64> = Vec::with_capacity(self.in_vrs[p].len());
            for r in &self.in_routes[p] {
                match r.unknown {
                    Some(u) => {
                        let mut e = vec![0.0; n];
                        e[u] = 1.0;
                        rows.push(e);
                        base.push(x[u]);
                    }
                    None => {
                        rows.push(d_slot[r.slot].clone().unwrap_or_else(|| vec![0.0; n]));
                        base.push(self.values[r.slot]);
                    }
                }
            }
            let moved: Vec<usize> = (0..rows.len())
                .filter(|&i| rows[i].iter().any(|&v| v != 0.0))
                .collect();
            let y0 = self.probe_step(sys, p, t, h, &base)?;
            let mut dy = vec![vec![0.0; n]; self.out_vrs[p].len()];
            for &i in &moved {
                let r = &self.in_routes[p][i];
                let scale = group_max[r.slot];
                let eps = 1e-6 * base[i].abs().max(scale).max(1e-300);
                let mut u = base.clone();
                u[i] += eps;
                let y = self.probe_step(sys, p, t, h, &u)?;
                for (o, (yo, y0o)) in y.iter().zip(&y0).enumerate() {
                    let jp = (yo - y0o) / eps;
                    if jp != 0.0 {
                        for (d, &ri) in dy[o].iter_mut().zip(&rows[i]) {
                            *d += jp * ri;
                        }
                    }
                }
            }
            for (o, &slot) in self.out_slots[p].iter().enumerate() {
                d_slot[slot] = Some(std::mem::take(&mut dy[o]));
            }
        }
        let mut j = DMatrix::zeros(n, n);
        for (u, &slot) in self.feedback_slots.iter().enumerate() {
            if let Some(row) = &d_slot[slot] {
                for (c, &v) in row.iter().enumerate() {
                    j[(u, c)] = v;
                }
            }
        }
        Ok(j)
    }

    /// Step participant `p` from its saved state with inputs `u`; its connected outputs.
    fn probe_step(
        &mut self,
        sys: &mut System,
        p: usize,
        t: f64,
        h: f64,
        u: &[f64],
    ) -> Result<Vec<f64>, CouplingError> {
        sys.participants[p].restore_state()?;
        sys.participants[p].set_real(&self.in_vrs[p], u)?;
        if do_step(sys, p, t, h)? == StepStatus::Discard {
            return Err(CouplingError::new(format!(
                "{} discarded a step while its Jacobian was probed at t = {t} s",
                sys.participants[p].name()
            )));
        }
        let mut y = vec![0.0; self.out_vrs[p].len()];
        sys.participants[p].get_real(&self.out_vrs[p], &mut y)?;
        Ok(y)
    }

    /// For each slot, the largest magnitude among the current values of its group (same
    /// source participant and unit; a slot without a unit is its own group).
    fn group_magnitudes(&self) -> Vec<f64> {
        let groups = self.groups(0..self.slots());
        let mut max = vec![0.0_f64; self.slots()];
        let of = groups.of();
        let mut by_group = vec![0.0_f64; of.iter().copied().max().map_or(0, |m| m + 1)];
        for (s, &g) in of.iter().enumerate() {
            by_group[g] = by_group[g].max(self.values[s].abs());
        }
        for (s, &g) in of.iter().enumerate() {
            max[s] = by_group[g];
        }
        max
    }
}

/// One sweep of the step `t → t + h` from the participants' saved states with the interface
/// unknowns at `x`: `H(x)`. The participants must have saved their states at `t`
/// ([`super::scheme::save_all`]); they are left at `t + h`.
pub fn sweep(sys: &mut System, t: f64, h: f64, x: &[f64]) -> Result<Vec<f64>, CouplingError> {
    let mut ex = Exchange::new(sys)?;
    sweep_with(&mut ex, sys, t, h, x)
}

fn sweep_with(
    ex: &mut Exchange,
    sys: &mut System,
    t: f64,
    h: f64,
    x: &[f64],
) -> Result<Vec<f64>, CouplingError> {
    super::scheme::restore_all(sys)?;
    ex.read_all(sys)?;
    for p in 0..sys.participants.len() {
        ex.write_inputs(sys, p, Some(x))?;
        if do_step(sys, p, t, h)? == StepStatus::Discard {
            return Err(CouplingError::new(format!(
                "{} discarded the step at t = {t} s",
                sys.participants[p].name()
            )));
        }
        ex.read_outputs(sys, p)?;
    }
    let mut out = Vec::new();
    ex.feedback_values(&mut out);
    Ok(out)
}

/// The interface Jacobian `J = ∂H/∂x` of the step `t → t + h` at `x`, as the Newton update
/// computes it (participant by participant, chain rule). The participants must have saved
/// their states at `t`; they are left at probed states.
pub fn step_jacobian(
    sys: &mut System,
    t: f64,
    h: f64,
    x: &[f64],
) -> Result<DMatrix<f64>, CouplingError> {
    let mut ex = Exchange::new(sys)?;
    sweep_with(&mut ex, sys, t, h, x)?;
    ex.step_jacobian(sys, t, h, x)
}
