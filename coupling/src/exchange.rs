//! Routing of connection values between participants.
//!
//! Every distinct source `(participant, output value reference)` of a connection is one *slot*;
//! its current value lives in [`Exchange::values`]. A connection `from → to` is *forward* when
//! `from < to` (the source is stepped earlier in the sweep) and *feedback* when `from ≥ to`.
//! The distinct sources of feedback connections are the interface unknowns `x` of the implicit
//! scheme, numbered in the order of their first appearance in [`System::connections`].

use super::system::{CouplingError, System};

/// Where an input takes its value from.
#[derive(Debug, Clone, Copy)]
pub(super) struct Route {
    pub(super) slot: usize,
    /// Index into the interface unknowns when the connection is a feedback connection.
    pub(super) unknown: Option<usize>,
}

/// The outputs of one participant read as one run of consecutive value references `vrs`
/// that holds every connected one (an FMU copies such a run at once instead of looking up each
/// value reference), and the position in the run of each connected output.
#[derive(Debug, Clone)]
struct ReadRun {
    vrs: Vec<u32>,
    at: Vec<usize>,
}

impl ReadRun {
    /// How the connected outputs `vrs` of participant `p` are read: as the run from the lowest
    /// to the highest when it is at most twice as long as they are many and every value
    /// reference in it is a declared Real variable
    /// ([`super::system::Participant::variable_name`]; fmi2GetReal may read any variable),
    /// otherwise as they are (one by one, `at` the identity).
    fn of(sys: &System, p: usize, vrs: &[u32]) -> ReadRun {
        let as_they_are = || ReadRun {
            vrs: vrs.to_vec(),
            at: (0..vrs.len()).collect(),
        };
        let (Some(&lo), Some(&hi)) = (vrs.iter().min(), vrs.iter().max()) else {
            return as_they_are();
        };
        let len = (hi - lo) as usize + 1;
        let part = &sys.participants[p];
        if vrs.len() >= 2
            && len <= 2 * vrs.len()
            && (lo..=hi).all(|vr| part.variable_name(vr).is_some())
        {
            ReadRun {
                vrs: (lo..=hi).collect(),
                at: vrs.iter().map(|&vr| (vr - lo) as usize).collect(),
            }
        } else {
            as_they_are()
        }
    }
}

/// The first of `n` consecutive indices that `indices` is, if it is such a run.
fn run_start(indices: impl Iterator<Item = usize>) -> Option<usize> {
    let mut start = None;
    for (k, i) in indices.enumerate() {
        match start {
            None => start = Some(i),
            Some(s) if i == s + k => {}
            Some(_) => return None,
        }
    }
    start
}

/// Runs of a participant's inputs and outputs that are copied at once instead of element by
/// element ([`run_start`] of their unknowns and slots; None where they are no run).
#[derive(Debug, Clone, Default)]
struct Runs {
    /// Every input fed by unknown `u0 + k`, input k.
    inputs_from_unknowns: Option<usize>,
    /// Every input from slot `s0 + k` and none from an unknown.
    inputs_from_slots: Option<usize>,
    /// Output k (of `out_vrs`) into slot `s0 + k`, read as position k of the run.
    outputs_to_slots: Option<usize>,
}

/// The connection topology of a [`System`] compiled into per-participant batches.
#[derive(Debug, Clone)]
pub(crate) struct Exchange {
    /// Output value references read from each participant, and the slot each one fills.
    pub(super) out_vrs: Vec<Vec<u32>>,
    pub(super) out_slots: Vec<Vec<usize>>,
    /// Per participant, how its outputs are read (a run, or as they are).
    out_runs: Vec<ReadRun>,
    /// Per participant, what is copied at once.
    runs: Vec<Runs>,
    /// The first slot of the unknowns' slots when they are consecutive.
    feedback_run: Option<usize>,
    run_values: Vec<f64>,
    /// Input value references written to each participant, and where each takes its value.
    pub(super) in_vrs: Vec<Vec<u32>>,
    pub(super) in_routes: Vec<Vec<Route>>,
    /// Source `(participant, output vr)` of each slot, and the source output's declared unit.
    pub(super) slot_source: Vec<(usize, u32)>,
    pub(super) slot_unit: Vec<Option<String>>,
    /// Current value of each slot.
    pub values: Vec<f64>,
    /// Slot of each interface unknown (distinct feedback sources).
    pub feedback_slots: Vec<usize>,
    /// `(from, to)` participants of the first feedback connection of each unknown.
    pub feedback_pairs: Vec<(usize, usize)>,
    scratch: Vec<f64>,
    participants: usize,
    connections: usize,
}

impl Exchange {
    /// Compiles the connections of `sys`, rejecting indices out of range and inputs fed by more
    /// than one connection.
    pub fn new(sys: &System) -> Result<Self, CouplingError> {
        let np = sys.participants.len();
        let mut ex = Exchange {
            out_vrs: vec![Vec::new(); np],
            out_slots: vec![Vec::new(); np],
            out_runs: Vec::new(),
            runs: Vec::new(),
            feedback_run: None,
            run_values: Vec::new(),
            in_vrs: vec![Vec::new(); np],
            in_routes: vec![Vec::new(); np],
            slot_source: Vec::new(),
            slot_unit: Vec::new(),
            values: Vec::new(),
            feedback_slots: Vec::new(),
            feedback_pairs: Vec::new(),
            scratch: Vec::new(),
            participants: np,
            connections: sys.connections.len(),
        };
        for (i, c) in sys.connections.iter().enumerate() {
            if c.from >= np || c.to >= np {
                return Err(CouplingError::Wiring(format!(
                    "connection {i} ({} vr {} -> {} vr {}) refers to a participant that does not \
                     exist (the system has {np})",
                    c.from, c.from_vr, c.to, c.to_vr
                )));
            }
            if ex.in_vrs[c.to].contains(&c.to_vr) {
                return Err(CouplingError::Wiring(format!(
                    "input vr {} of participant '{}' is fed by more than one connection",
                    c.to_vr,
                    sys.participants[c.to].name()
                )));
            }
            let slot = match ex
                .slot_source
                .iter()
                .position(|&s| s == (c.from, c.from_vr))
            {
                Some(s) => s,
                None => {
                    ex.slot_source.push((c.from, c.from_vr));
                    ex.slot_unit
                        .push(sys.participants[c.from].unit(c.from_vr).map(str::to_owned));
                    ex.out_vrs[c.from].push(c.from_vr);
                    ex.out_slots[c.from].push(ex.slot_source.len() - 1);
                    ex.slot_source.len() - 1
                }
            };
            let unknown = if c.from >= c.to {
                Some(match ex.feedback_slots.iter().position(|&s| s == slot) {
                    Some(u) => u,
                    None => {
                        ex.feedback_slots.push(slot);
                        ex.feedback_pairs.push((c.from, c.to));
                        ex.feedback_slots.len() - 1
                    }
                })
            } else {
                None
            };
            ex.in_vrs[c.to].push(c.to_vr);
            ex.in_routes[c.to].push(Route { slot, unknown });
        }
        ex.values = vec![0.0; ex.slot_source.len()];
        ex.number_slots_by_participant();
        ex.out_runs = (0..np)
            .map(|p| ReadRun::of(sys, p, &ex.out_vrs[p]))
            .collect();
        ex.runs = (0..np)
            .map(|p| {
                let routes = &ex.in_routes[p];
                let run = &ex.out_runs[p];
                let at_identity = run.at.iter().enumerate().all(|(k, &i)| i == k);
                Runs {
                    inputs_from_unknowns: if routes.iter().all(|r| r.unknown.is_some()) {
                        run_start(routes.iter().filter_map(|r| r.unknown))
                    } else {
                        None
                    },
                    inputs_from_slots: if routes.iter().all(|r| r.unknown.is_none()) {
                        run_start(routes.iter().map(|r| r.slot))
                    } else {
                        None
                    },
                    outputs_to_slots: if at_identity {
                        run_start(ex.out_slots[p].iter().copied())
                    } else {
                        None
                    },
                }
            })
            .collect();
        ex.feedback_run = run_start(ex.feedback_slots.iter().copied());
        Ok(ex)
    }

    /// Numbers the slots participant by participant, each one's in the order of its
    /// `out_vrs`, so that a participant's outputs, and inputs fed from one participant's
    /// outputs in their order, are runs of slots ([`Runs`]).
    fn number_slots_by_participant(&mut self) {
        let mut new_of = vec![0; self.slot_source.len()];
        for (k, &old) in self.out_slots.iter().flatten().enumerate() {
            new_of[old] = k;
        }
        let mut source = self.slot_source.clone();
        let mut unit = vec![None; self.slot_unit.len()];
        for (old, &new) in new_of.iter().enumerate() {
            source[new] = self.slot_source[old];
            unit[new] = self.slot_unit[old].take();
        }
        (self.slot_source, self.slot_unit) = (source, unit);
        for s in self.out_slots.iter_mut().flatten() {
            *s = new_of[*s];
        }
        for r in self.in_routes.iter_mut().flatten() {
            r.slot = new_of[r.slot];
        }
        for s in &mut self.feedback_slots {
            *s = new_of[*s];
        }
    }

    /// Compile the plan for `sys` and pass the current outputs to the inputs once (the
    /// initial exchange of the explicit schemes).
    pub fn initial(sys: &mut System) -> Result<Self, CouplingError> {
        let mut ex = Exchange::new(sys)?;
        ex.read_all(sys)?;
        ex.write_all(sys)?;
        Ok(ex)
    }

    /// The plan in `slot`, recompiled if `sys` changed shape since it was made.
    pub fn current<'a>(
        slot: &'a mut Option<Exchange>,
        sys: &System,
    ) -> Result<&'a mut Exchange, CouplingError> {
        match slot {
            Some(ex) if ex.matches(sys) => Ok(slot.as_mut().expect("matched Some")),
            _ => Ok(slot.insert(Exchange::new(sys)?)),
        }
    }

    /// Whether `sys` still has the shape this plan was compiled for.
    pub fn matches(&self, sys: &System) -> bool {
        self.participants == sys.participants.len() && self.connections == sys.connections.len()
    }

    /// Number of interface unknowns (distinct feedback sources).
    pub fn unknowns(&self) -> usize {
        self.feedback_slots.len()
    }

    /// Reads the outputs of participant `p` that feed any connection into their slots.
    pub fn read_outputs(&mut self, sys: &mut System, p: usize) -> Result<(), CouplingError> {
        let vrs = &self.out_vrs[p];
        if vrs.is_empty() {
            return Ok(());
        }
        let part = &mut sys.participants[p];
        let run = &self.out_runs[p];
        self.run_values.resize(run.vrs.len(), 0.0);
        part.get_real(&run.vrs, &mut self.run_values)
            .map_err(|e| CouplingError::call(part.name(), "get_real", e))?;
        // connected output k is run_values[at[k]]
        let values = &self.run_values;
        if !part.get_real_refuses_non_finite() && values.iter().any(|v| !v.is_finite()) {
            if let Some(k) = (0..vrs.len()).find(|&k| !values[run.at[k]].is_finite()) {
                return Err(CouplingError::NonFinite {
                    participant: part.name().to_owned(),
                    vr: vrs[k],
                    value: values[run.at[k]],
                });
            }
        }
        match self.runs[p].outputs_to_slots {
            Some(s0) => {
                let n = self.out_slots[p].len();
                self.values[s0..s0 + n].copy_from_slice(&values[..n]);
            }
            None => {
                for (&slot, &i) in self.out_slots[p].iter().zip(&run.at) {
                    self.values[slot] = values[i];
                }
            }
        }
        Ok(())
    }

    /// Reads the connected outputs of every participant.
    pub fn read_all(&mut self, sys: &mut System) -> Result<(), CouplingError> {
        (0..self.participants).try_for_each(|p| self.read_outputs(sys, p))
    }

    /// Writes the inputs of participant `p`: feedback inputs from `x` when given, all others
    /// (and all inputs when `x` is `None`) from the current slot values.
    pub fn write_inputs(
        &mut self,
        sys: &mut System,
        p: usize,
        x: Option<&[f64]>,
    ) -> Result<(), CouplingError> {
        let vrs = &self.in_vrs[p];
        if vrs.is_empty() {
            return Ok(());
        }
        let n = vrs.len();
        let values: &[f64] = match (x, &self.runs[p]) {
            (
                Some(x),
                Runs {
                    inputs_from_unknowns: Some(u0),
                    ..
                },
            ) => &x[*u0..u0 + n],
            (
                _,
                Runs {
                    inputs_from_slots: Some(s0),
                    ..
                },
            ) => &self.values[*s0..s0 + n],
            _ => {
                self.scratch.clear();
                self.scratch
                    .extend(self.in_routes[p].iter().map(|r| match (r.unknown, x) {
                        (Some(u), Some(x)) => x[u],
                        _ => self.values[r.slot],
                    }));
                &self.scratch
            }
        };
        let part = &mut sys.participants[p];
        part.set_real(vrs, values)
            .map_err(|e| CouplingError::call(part.name(), "set_real", e))
    }

    /// Writes every participant's inputs from the current slot values.
    pub fn write_all(&mut self, sys: &mut System) -> Result<(), CouplingError> {
        (0..self.participants).try_for_each(|p| self.write_inputs(sys, p, None))
    }

    /// `participant.variable` (or `participant vr N`) of the source of interface unknown `u`.
    pub fn unknown_name(&self, sys: &System, u: usize) -> String {
        let (p, vr) = self.slot_source[self.feedback_slots[u]];
        let part = &sys.participants[p];
        match part.variable_name(vr) {
            Some(v) => format!("{}.{v}", part.name()),
            None => format!("{} vr {vr}", part.name()),
        }
    }

    /// Number of slots (distinct connected outputs).
    pub fn slots(&self) -> usize {
        self.slot_source.len()
    }

    /// The convergence groups ([`super::convergence::Groups`]) of the values of `slots`:
    /// outputs of the same participant with the same declared unit share a group; an output
    /// without a unit is a group of its own.
    pub fn groups(&self, slots: impl Iterator<Item = usize>) -> super::convergence::Groups {
        super::convergence::Groups::by_key(
            slots.map(|s| (self.slot_source[s].0, self.slot_unit[s].as_deref().ok_or(s))),
        )
    }

    /// Copies the current values of the interface unknowns into `x`.
    pub fn feedback_values(&self, x: &mut Vec<f64>) {
        x.clear();
        match self.feedback_run {
            Some(s0) => x.extend_from_slice(&self.values[s0..s0 + self.feedback_slots.len()]),
            None => x.extend(self.feedback_slots.iter().map(|&s| self.values[s])),
        }
    }
}

/// Tolerance for recognising two communication points as the same.
pub(crate) fn same_time(a: f64, b: f64, h: f64) -> bool {
    (a - b).abs() <= 1e-6 * h.abs().max(f64::MIN_POSITIVE)
}

/// Sets every connected input from the output it is connected to, before the first step:
/// every connected output read, then every input set (one call per participant and
/// direction), Real and Integer/Boolean alike, until a pass reads what the pass before it did
/// or after 50 passes (an FMU in initialisation mode may recompute all its outputs when one is
/// read after an input has changed).
pub fn settle_inputs(system: &mut System) -> Result<(), CouplingError> {
    let mut ex = Exchange::new(system)?;
    let mut last: Vec<f64> = Vec::new();
    for _ in 0..50 {
        ex.read_all(system)?;
        let System {
            participants,
            discrete,
            ..
        } = &mut *system;
        let mut levels = vec![0; discrete.len()];
        for (c, v) in discrete.iter().zip(&mut levels) {
            participants[c.from].get_discrete(c.kind, &[c.from_vr], std::slice::from_mut(v))?;
        }
        ex.write_all(system)?;
        for (c, &v) in system.discrete.iter().zip(&levels) {
            system.participants[c.to].set_discrete(c.kind, &[c.to_vr], &[v])?;
        }
        let now: Vec<f64> = (ex.values.iter().copied())
            .chain(levels.iter().map(|&v| f64::from(v)))
            .collect();
        if now == last {
            break;
        }
        last = now;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{Connection, Participant, StepStatus};
    use std::cell::RefCell;
    use std::rc::Rc;

    /// The `(vr, value)` of every input a table was given, in order.
    type Given = Rc<RefCell<Vec<(u32, f64)>>>;

    /// Outputs `vr ↦ offset + 10 vr` (NaN for those in `nan`); the value references it
    /// declares; the lists it was asked for; the inputs it was given.
    #[derive(Default)]
    struct Table {
        declared: Vec<u32>,
        nan: Vec<u32>,
        offset: f64,
        asked: Rc<RefCell<Vec<Vec<u32>>>>,
        given: Given,
    }

    impl Participant for Table {
        fn name(&self) -> &str {
            "table"
        }
        fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
            let mut given = self.given.borrow_mut();
            given.extend(vrs.iter().copied().zip(values.iter().copied()));
            Ok(())
        }
        fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
            self.asked.borrow_mut().push(vrs.to_vec());
            for (&vr, v) in vrs.iter().zip(values) {
                if !self.declared.contains(&vr) {
                    return Err(CouplingError::new(format!("vr {vr} is not declared")));
                }
                *v = if self.nan.contains(&vr) {
                    f64::NAN
                } else {
                    self.offset + 10.0 * vr as f64
                };
            }
            Ok(())
        }
        fn do_step(&mut self, _t: f64, _h: f64) -> Result<StepStatus, CouplingError> {
            Ok(StepStatus::Ok)
        }
        fn save_state(&mut self) -> Result<(), CouplingError> {
            Ok(())
        }
        fn restore_state(&mut self) -> Result<(), CouplingError> {
            Ok(())
        }
        fn variable_name(&self, vr: u32) -> Option<String> {
            self.declared.contains(&vr).then(|| format!("v{vr}"))
        }
    }

    /// Reads the outputs `from_vrs` of a table declaring `declared` (each connected to an
    /// input of a second table); returns the slot values and the lists asked for.
    fn read(declared: Vec<u32>, from_vrs: &[u32]) -> (Vec<f64>, Vec<Vec<u32>>) {
        let (values, asked) = read_with_nan(declared, Vec::new(), from_vrs);
        (values.unwrap(), asked)
    }

    /// [`read`] from a table whose outputs `nan` are NaN: the slot values or the error.
    fn read_with_nan(
        declared: Vec<u32>,
        nan: Vec<u32>,
        from_vrs: &[u32],
    ) -> (Result<Vec<f64>, String>, Vec<Vec<u32>>) {
        let asked = Rc::new(RefCell::new(Vec::new()));
        let source = Table {
            declared,
            nan,
            asked: asked.clone(),
            ..Default::default()
        };
        let sink = Table::default();
        let connections = (from_vrs.iter().enumerate())
            .map(|(i, &vr)| Connection {
                from: 0,
                from_vr: vr,
                to: 1,
                to_vr: i as u32,
            })
            .collect();
        let mut sys = System::new(vec![Box::new(source), Box::new(sink)], connections);
        let mut ex = Exchange::new(&sys).unwrap();
        let read = ex.read_outputs(&mut sys, 0).map_err(|e| e.to_string());
        let asked = asked.borrow().clone();
        (read.map(|()| ex.values.clone()), asked)
    }

    /// A NaN among the connected outputs is an error naming its value reference, whether it
    /// is read in a run or alone; one in the run that is not connected is no error.
    #[test]
    fn a_non_finite_connected_output_is_an_error_naming_it() {
        let (read, asked) = read_with_nan((10..=18).collect(), vec![15], &[12, 10, 15, 16]);
        assert_eq!(asked, vec![(10..=16).collect::<Vec<u32>>()]);
        let e = read.unwrap_err();
        assert!(e.contains("output vr 15 is not finite (NaN)"), "{e}");
        let (read, _) = read_with_nan((10..=30).collect(), vec![30], &[10, 20, 30]);
        let e = read.unwrap_err();
        assert!(e.contains("output vr 30 is not finite (NaN)"), "{e}");
        // vr 11 is read with the run 10..=13 but is not connected
        let (read, asked) = read_with_nan((10..=18).collect(), vec![11], &[10, 12, 13]);
        assert_eq!(asked, vec![(10..=13).collect::<Vec<u32>>()]);
        assert_eq!(read.unwrap(), vec![100.0, 120.0, 130.0]);
    }

    #[test]
    fn outputs_close_together_are_read_as_one_run_of_declared_variables() {
        // 5 of the 9 declared value references 10..=18, out of order: one run, picked right
        let (values, asked) = read((10..=18).collect(), &[12, 10, 11, 16, 15]);
        assert_eq!(values, vec![120.0, 100.0, 110.0, 160.0, 150.0]);
        assert_eq!(asked, vec![(10..=16).collect::<Vec<u32>>()]);
    }

    #[test]
    fn outputs_far_apart_or_around_undeclared_ones_are_read_one_by_one() {
        // the run 10..=30 would be more than twice as long as the three outputs
        let (values, asked) = read((10..=30).collect(), &[10, 20, 30]);
        assert_eq!(values, vec![100.0, 200.0, 300.0]);
        assert_eq!(asked, vec![vec![10, 20, 30]]);
        // vr 11 lies in the run but is not a declared variable
        let (values, asked) = read(vec![10, 12, 13], &[10, 12, 13]);
        assert_eq!(values, vec![100.0, 120.0, 130.0]);
        assert_eq!(asked, vec![vec![10, 12, 13]]);
    }

    /// Every input gets its source's value, or its unknown's when the unknowns are given,
    /// whether the plan copies runs of slots or of unknowns (connections interleaved between
    /// the participants, as an SSP lists them) or gathers them one by one (an input fed from
    /// two participants).
    #[test]
    fn inputs_get_their_sources_values_copied_as_runs_or_one_by_one() {
        let table = |offset: f64, given: &Given| Table {
            declared: (1..=4).collect(),
            offset,
            given: given.clone(),
            ..Default::default()
        };
        let given: Vec<Given> = (0..3).map(|_| Rc::default()).collect();
        let c = |from, from_vr, to, to_vr| Connection {
            from,
            from_vr,
            to,
            to_vr,
        };
        // A.k -> B.k and B.k -> A.k interleaved; C takes A.2 and B.3
        let connections = vec![
            c(0, 1, 1, 10),
            c(1, 1, 0, 10),
            c(0, 2, 1, 11),
            c(1, 2, 0, 11),
            c(0, 3, 1, 12),
            c(1, 3, 0, 12),
            c(0, 2, 2, 10),
            c(1, 3, 2, 11),
        ];
        let parts: Vec<Box<dyn Participant>> = (0..3)
            .map(|p| Box::new(table(1000.0 * p as f64, &given[p])) as Box<dyn Participant>)
            .collect();
        let mut sys = System::new(parts, connections.clone());
        let mut ex = Exchange::new(&sys).unwrap();
        assert_eq!(ex.runs[0].inputs_from_unknowns, Some(0));
        assert!(ex.runs[1].inputs_from_slots.is_some());
        assert!(ex.runs[0].outputs_to_slots.is_some() && ex.runs[1].outputs_to_slots.is_some());
        assert_eq!(ex.runs[2].inputs_from_slots, None);
        ex.read_all(&mut sys).unwrap();
        let x: Vec<f64> = (0..ex.unknowns()).map(|u| -1.0 - u as f64).collect();
        for with_x in [false, true] {
            for (p, given) in given.iter().enumerate() {
                given.borrow_mut().clear();
                ex.write_inputs(&mut sys, p, with_x.then_some(&x[..]))
                    .unwrap();
                let mut expected: Vec<(u32, f64)> = Vec::new();
                for k in connections.iter().filter(|k| k.to == p) {
                    let slot = ex
                        .slot_source
                        .iter()
                        .position(|&s| s == (k.from, k.from_vr));
                    let unknown = ex.feedback_slots.iter().position(|&s| Some(s) == slot);
                    let value = match unknown {
                        Some(u) if with_x && k.from >= k.to => x[u],
                        _ => 1000.0 * k.from as f64 + 10.0 * k.from_vr as f64,
                    };
                    expected.push((k.to_vr, value));
                }
                assert_eq!(
                    *given.borrow(),
                    expected,
                    "participant {p}, unknowns {with_x}"
                );
            }
        }
        let mut fed = Vec::new();
        ex.feedback_values(&mut fed);
        assert_eq!(fed, vec![1010.0, 1020.0, 1030.0]);
    }
}
