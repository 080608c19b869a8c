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
//!
//! # Structure, kept across steps ([`StepJacobian`])
//!
//! The first Jacobian moves every input alone and records which outputs each one moves (its
//! *pattern*). Later Jacobians use what was learnt:
//!
//! * **Colouring.** Inputs whose patterns share no output are moved together in one probe
//!   (greedy colouring in input order); each output that moves is credited to the one input
//!   of the colour whose pattern holds it. The train's map is block-diagonal by vehicle, so
//!   its inputs need as many probes as one vehicle has inputs. An output that moves outside
//!   every member's pattern shows a new dependency: the colour's inputs are then moved alone
//!   again and their patterns extended. Inputs that moved nothing (a wheelset's force before
//!   it reaches the deck) share a colour of their own, so their first effect is seen. A new
//!   dependency on an output already credited to another member of a colour would go
//!   unseen: colouring assumes that outputs depending on different inputs stay apart (true of
//!   the train's vehicles; the bridge's forces all meet in the deck and are never coloured
//!   together). The patterns are learnt again when the step size changes.
//! * **Reuse.** A participant's local Jacobian `J_p` is kept with the step size it was taken
//!   for. Before reusing it, one probe moves all its inputs at once by `sᵢ εᵢ` (fixed
//!   pseudo-random signs `sᵢ = ±1`) and compares the outputs' change with `Σᵢ J_p[:, i] sᵢ εᵢ`
//!   (to `10⁻⁷` of `Σᵢ |J_p[o, i]| εᵢ` in every output `o`): a participant whose step is linear
//!   with constant coefficients (the train) then costs one probe per Jacobian, one whose map
//!   moved (the bridge, as the wheelsets travel) is differentiated again.
//! * **Constant unknowns.** Until it is known whether a participant's outputs that are
//!   unknowns respond to its inputs, its Jacobians move every one of its inputs, also those
//!   that do not depend on `x` there (a rail before the deck). Once every input could be moved
//!   on the scale of its kind (its group not all zero), an unknown whose source output moved
//!   with none of them (it does not respond to anything within a step: the train's wheelset
//!   positions and speeds) is not moved afterwards, its column taken as zero. Its Newton
//!   update is then its own residual, exact after one sweep; the others' update misses
//!   `J[:, u] r_u`, which the next sweep corrects should `r_u` not be negligible.
//! * **The operating point's outputs** are those of the sweep just made at `x` (no probe).

use super::exchange::Exchange;
use super::scheme::do_step;
use super::system::{CouplingError, StepStatus, System};
use nalgebra::DMatrix;

/// What the master has learnt of the participants' step maps, kept from step to step (see
/// the module documentation).
#[derive(Debug, Clone, Default)]
pub struct StepJacobian {
    /// The step size the local Jacobians were taken for.
    h: Option<f64>,
    parts: Vec<Local>,
    /// Per unknown: whether its source output is constant within a step (None: not yet
    /// known).
    constant: Vec<Option<bool>>,
    /// Participant steps spent on Jacobians so far.
    probes: usize,
    /// Local Jacobians are reused when the check allows (default); else re-differentiated
    /// (coloured) every time.
    no_reuse: bool,
}

/// One participant's local Jacobian `∂y_p/∂u_p` and its structure.
#[derive(Debug, Clone, Default)]
struct Local {
    /// Per input: the outputs it moved when probed alone (None: never probed alone).
    pattern: Vec<Option<Vec<usize>>>,
    /// Per input: the non-zero entries `(output, ∂y/∂u)` of its column, for the step size
    /// [`StepJacobian::h`] (None: not taken).
    columns: Vec<Option<Vec<(usize, f64)>>>,
}

impl StepJacobian {
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether local Jacobians may be reused across steps (default true).
    pub fn reuse(mut self, on: bool) -> Self {
        self.no_reuse = !on;
        self
    }

    /// Participant steps spent on Jacobians so far.
    pub fn probes(&self) -> usize {
        self.probes
    }

    /// `J = ∂H/∂x` of the step `t → t + h` at the guess `x`. The slot values of `ex` must be
    /// those of the sweep just made at `x` (the operating point); the participants must have
    /// saved their states at `t`, and are left at probed states.
    pub(crate) fn compute(
        &mut self,
        ex: &mut Exchange,
        sys: &mut System,
        t: f64,
        h: f64,
        x: &[f64],
    ) -> Result<DMatrix<f64>, CouplingError> {
        let np = sys.participants.len();
        let n = ex.unknowns();
        if self.parts.len() != np || self.constant.len() != n {
            self.parts = vec![Local::default(); np];
            self.constant = vec![None; n];
        }
        if !self.h.is_some_and(|h0| (h - h0).abs() <= 1e-9 * h0.abs()) {
            self.h = Some(h);
            for l in &mut self.parts {
                *l = Local::default();
            }
            self.constant = vec![None; n];
        }
        // ∂(slot value)/∂x, for the slots of participants already differentiated
        let mut d_slot: Vec<Option<Vec<f64>>> = vec![None; ex.slots()];
        let group_max = ex.group_magnitudes();
        for p in 0..np {
            if ex.out_vrs[p].is_empty() {
                continue;
            }
            let ni = ex.in_vrs[p].len();
            // ∂u/∂x of each input, and its value at the operating point
            let mut rows: Vec<Vec<f64>> = Vec::with_capacity(ni);
            let mut base: Vec<f64> = Vec::with_capacity(ni);
            for r in &ex.in_routes[p] {
                match r.unknown {
                    Some(u) => {
                        let mut e = vec![0.0; n];
                        if self.constant[u] != Some(true) {
                            e[u] = 1.0;
                        }
                        rows.push(e);
                        base.push(x[u]);
                    }
                    None => {
                        rows.push(d_slot[r.slot].clone().unwrap_or_else(|| vec![0.0; n]));
                        base.push(ex.values[r.slot]);
                    }
                }
            }
            // While it is not known whether the outputs of p that are unknowns are constant,
            // every input of p is moved, also those that do not depend on x at this point (a
            // rail before the deck).
            let sources = (ex.feedback_slots.iter().enumerate())
                .filter(|(_, &slot)| ex.slot_source[slot].0 == p)
                .map(|(u, _)| u)
                .collect::<Vec<usize>>();
            let learning = sources.iter().any(|&u| self.constant[u].is_none());
            let moved: Vec<usize> = (0..ni)
                .filter(|&i| learning || rows[i].iter().any(|&v| v != 0.0))
                .collect();
            let scales: Vec<f64> = (0..ni)
                .map(|i| base[i].abs().max(group_max[ex.in_routes[p][i].slot]))
                .collect();
            let eps: Vec<f64> = scales.iter().map(|s| 1e-6 * s.max(1e-300)).collect();
            let y0: Vec<f64> = ex.out_slots[p].iter().map(|&s| ex.values[s]).collect();
            let local = &mut self.parts[p];
            local.pattern.resize(ni, None);
            local.columns.resize(ni, None);
            let mut probe = Probe {
                ex,
                sys,
                p,
                t,
                h,
                base: &base,
                y0: &y0,
                count: &mut self.probes,
            };
            if self.no_reuse || !local.reusable(&mut probe, &moved, &eps)? {
                local.differentiate(&mut probe, &moved, &eps)?;
            }
            // Decided once every input was moved by a step on the scale of its kind (an
            // input whose group is all zero moves by 1e-306 and may show nothing).
            if learning && scales.iter().all(|&s| s > 0.0) {
                for u in sources {
                    let o = ex.out_slots[p]
                        .iter()
                        .position(|&s| s == ex.feedback_slots[u])
                        .expect("a slot is an output of its source");
                    let moves = (local.columns.iter().flatten())
                        .any(|col| col.iter().any(|&(oo, _)| oo == o));
                    self.constant[u] = Some(!moves);
                }
            }
            // chain rule: ∂y_p/∂x = J_p · ∂u_p/∂x
            let mut dy = vec![vec![0.0; n]; ex.out_vrs[p].len()];
            for &i in &moved {
                for &(o, jp) in local.columns[i].as_deref().unwrap_or_default() {
                    for (d, &ri) in dy[o].iter_mut().zip(&rows[i]) {
                        *d += jp * ri;
                    }
                }
            }
            for (o, &slot) in ex.out_slots[p].iter().enumerate() {
                d_slot[slot] = Some(std::mem::take(&mut dy[o]));
            }
        }
        let mut j = DMatrix::zeros(n, n);
        for (u, &slot) in ex.feedback_slots.iter().enumerate() {
            if let Some(row) = &d_slot[slot] {
                for (c, &v) in row.iter().enumerate() {
                    j[(u, c)] = v;
                }
            }
        }
        Ok(j)
    }
}

/// One participant's step from its saved state with moved inputs.
struct Probe<'a> {
    ex: &'a mut Exchange,
    sys: &'a mut System,
    p: usize,
    t: f64,
    h: f64,
    base: &'a [f64],
    /// Outputs at the operating point.
    y0: &'a [f64],
    count: &'a mut usize,
}

impl Probe<'_> {
    /// The outputs' change when the inputs `moved[k].0` move by `moved[k].1`.
    fn change(&mut self, moved: &[(usize, f64)]) -> Result<Vec<f64>, CouplingError> {
        let mut u = self.base.to_vec();
        for &(i, d) in moved {
            u[i] += d;
        }
        *self.count += 1;
        let part = &mut self.sys.participants[self.p];
        part.restore_state()?;
        part.set_real(&self.ex.in_vrs[self.p], &u)?;
        if do_step(self.sys, self.p, self.t, self.h)? == StepStatus::Discard {
            return Err(CouplingError::Discarded(format!(
                "{} discarded a step while its Jacobian was probed at t = {} s",
                self.sys.participants[self.p].name(),
                self.t
            )));
        }
        let mut y = vec![0.0; self.ex.out_vrs[self.p].len()];
        self.sys.participants[self.p].get_real(&self.ex.out_vrs[self.p], &mut y)?;
        for (yo, y0) in y.iter_mut().zip(self.y0) {
            *yo -= y0;
        }
        Ok(y)
    }
}

/// The fixed sign of input `i` in the reuse check (a Weyl sequence's parity).
fn sign(i: usize) -> f64 {
    if ((i as f64 * 0.618_033_988_749_894_9).fract()) < 0.5 {
        1.0
    } else {
        -1.0
    }
}

impl Local {
    /// Whether the kept columns of `moved` still hold: one probe moving all of them.
    fn reusable(
        &self,
        probe: &mut Probe,
        moved: &[usize],
        eps: &[f64],
    ) -> Result<bool, CouplingError> {
        if moved.is_empty() || moved.iter().any(|&i| self.columns[i].is_none()) {
            return Ok(moved.is_empty());
        }
        let no = probe.y0.len();
        let (mut predicted, mut size) = (vec![0.0; no], vec![0.0; no]);
        for &i in moved {
            for &(o, v) in self.columns[i].as_deref().unwrap_or_default() {
                predicted[o] += v * sign(i) * eps[i];
                size[o] += (v * eps[i]).abs();
            }
        }
        let step: Vec<(usize, f64)> = moved.iter().map(|&i| (i, sign(i) * eps[i])).collect();
        let dy = probe.change(&step)?;
        Ok(dy
            .iter()
            .zip(&predicted)
            .zip(&size)
            .all(|((d, p), s)| (d - p).abs() <= 1e-7 * s))
    }

    /// The columns of `moved`, by colours of inputs with disjoint patterns.
    fn differentiate(
        &mut self,
        probe: &mut Probe,
        moved: &[usize],
        eps: &[f64],
    ) -> Result<(), CouplingError> {
        for c in &mut self.columns {
            *c = None;
        }
        for colour in self.colours(moved, probe.y0.len()) {
            let step: Vec<(usize, f64)> = colour.iter().map(|&i| (i, eps[i])).collect();
            let dy = probe.change(&step)?;
            if let [i] = colour[..] {
                self.record_alone(i, &dy, eps[i]);
                continue;
            }
            // credit each moved output to the member whose pattern holds it
            let mut owner = vec![usize::MAX; dy.len()];
            for &i in &colour {
                for &o in self.pattern[i].as_deref().unwrap_or_default() {
                    owner[o] = i;
                }
            }
            if dy
                .iter()
                .zip(&owner)
                .any(|(&d, &w)| d != 0.0 && w == usize::MAX)
            {
                // a dependency outside the known patterns: every member alone
                for &i in &colour {
                    let dy = probe.change(&[(i, eps[i])])?;
                    self.record_alone(i, &dy, eps[i]);
                }
                continue;
            }
            for &i in &colour {
                self.columns[i] = Some(Vec::new());
            }
            for (o, (&d, &w)) in dy.iter().zip(&owner).enumerate() {
                if d != 0.0 {
                    self.columns[w]
                        .as_mut()
                        .expect("set above")
                        .push((o, d / eps[w]));
                }
            }
        }
        Ok(())
    }

    /// The column of input `i` moved alone by `eps`, and its pattern.
    fn record_alone(&mut self, i: usize, dy: &[f64], eps: f64) {
        let col: Vec<(usize, f64)> = (dy.iter().enumerate())
            .filter(|(_, &d)| d != 0.0)
            .map(|(o, &d)| (o, d / eps))
            .collect();
        let mut pattern = self.pattern[i].take().unwrap_or_default();
        pattern.extend(col.iter().map(|&(o, _)| o));
        pattern.sort_unstable();
        pattern.dedup();
        self.pattern[i] = Some(pattern);
        self.columns[i] = Some(col);
    }

    /// Greedy colouring of `moved` (in order): an input joins the first colour none of whose
    /// members' patterns meets its own; an input never probed alone is a colour of its own,
    /// and inputs that moved nothing share one colour (any change there is news).
    fn colours(&self, moved: &[usize], outputs: usize) -> Vec<Vec<usize>> {
        let mut colours: Vec<(Vec<usize>, Vec<bool>)> = Vec::new();
        let mut alone = Vec::new();
        let mut silent = Vec::new();
        for &i in moved {
            let Some(pattern) = &self.pattern[i] else {
                alone.push(vec![i]);
                continue;
            };
            if pattern.is_empty() {
                silent.push(i);
                continue;
            }
            match colours
                .iter_mut()
                .find(|(_, used)| pattern.iter().all(|&o| !used[o]))
            {
                Some((members, used)) => {
                    members.push(i);
                    pattern.iter().for_each(|&o| used[o] = true);
                }
                None => {
                    let mut used = vec![false; outputs];
                    pattern.iter().for_each(|&o| used[o] = true);
                    colours.push((vec![i], used));
                }
            }
        }
        alone.extend(colours.into_iter().map(|(m, _)| m));
        if !silent.is_empty() {
            alone.push(silent);
        }
        alone
    }
}

impl Exchange {
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
            return Err(CouplingError::Discarded(format!(
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
/// computes it (participant by participant, chain rule), with the structure `known` has
/// learnt (a new [`StepJacobian`] moves every input alone). The participants must have
/// saved their states at `t`; they are left at probed states.
pub fn step_jacobian(
    known: &mut StepJacobian,
    sys: &mut System,
    t: f64,
    h: f64,
    x: &[f64],
) -> Result<DMatrix<f64>, CouplingError> {
    let mut ex = Exchange::new(sys)?;
    sweep_with(&mut ex, sys, t, h, x)?;
    known.compute(&mut ex, sys, t, h, x)
}
