//! A scenario run into its output folder: the model built, its cost checked, the monolithic
//! solver or the co-simulation of its FMUs stepped, the history recorded and the summary and
//! plots written.

use crate::model::{build, Limits, Model};
use crate::output::outdir::{NamedFile, OutputDir};
use crate::output::summary::Summary;
use crate::scenario::{Scenario, SolverKind};
use std::path::Path;
use std::time::Instant;
use tbi_dynamics::response::{Layout, Recorder};
use tbi_dynamics::solver::sample::ProbeShapes;
use tbi_dynamics::solver::Monolithic;

/// The record layout of a model.
pub fn layout(model: &Model) -> Layout {
    Layout {
        probe_names: model.probes.iter().map(|p| p.0.clone()).collect(),
        vehicles: model
            .train
            .vehicles
            .iter()
            .map(|v| {
                [
                    v.model.body.lateral.is_some(),
                    v.model.body.vertical.is_some(),
                ]
            })
            .collect(),
        wheelsets: model
            .train
            .wheelsets()
            .iter()
            .map(|w| {
                let m = &model.train.vehicles[w.vehicle].model;
                (
                    m.wheelsets[w.local].reference_load_n(),
                    m.contact_distance_m,
                )
            })
            .collect(),
        trains: match model.trains.len() {
            1 => Vec::new(),
            _ => (model.trains.iter())
                .map(|t| [t.spec.n_vehicles(), t.spec.n_wheelsets()])
                .collect(),
        },
    }
}

/// Run a scenario into `out` (co-simulation keeps its FMUs in `out/fmus`); returns the
/// summary (also written as `summary.json`). The folder is claimed for the run
/// ([`OutputDir`]) and the run's cost checked against `limits` before any step.
pub fn run_scenario(
    scenario: &Scenario,
    out: &Path,
    show_progress: bool,
    limits: &Limits,
) -> Result<Summary, Box<dyn std::error::Error>> {
    let model = build(scenario)?;
    limits.check(scenario, &model.estimate())?;
    let claim = OutputDir::claim(out)?;
    let out = claim.path();
    let history = out.join("history.csv");
    let mut rec = Recorder::new(
        layout(&model),
        &model.probes.iter().map(|p| p.1).collect::<Vec<_>>(),
        Some(NamedFile::create(&history)?),
    )?;
    let _in_flight = InFlight::enter();
    let start = Instant::now();
    let mut steps_ahead = None;
    let result = match scenario.run.solver {
        SolverKind::Monolithic => run_monolithic(&model, &mut rec, show_progress).map(|n| {
            steps_ahead = Some(n);
            None
        }),
        SolverKind::Cosim => crate::solve::cosim::run_cosim(
            &scenario.coupling,
            &model,
            (&out.join("fmus"), scenario.run.fmi_version),
            &mut rec,
            show_progress,
        )
        .map(Some),
    };
    let wall = start.elapsed().as_secs_f64();
    rec.finish()?;
    let mut summary = Summary::new(scenario, &model, &rec, wall);
    summary.steps_ahead = steps_ahead;
    // The plots come before the summary, so that `"status": "ok"` is only ever written for
    // a run that succeeded as a whole.
    let result = result.and_then(|coupling| {
        crate::output::plots::write_run_plots(
            out,
            &model,
            &history,
            &format!(
                "{}, {} km/h",
                scenario.name,
                crate::text::num(scenario.run.speed_kmh)
            ),
        )
        .map_err(|e| format!("plots in {}: {e}", out.display()))?;
        Ok(coupling)
    });
    match result {
        Ok(coupling) => {
            summary.coupling = coupling;
            summary.write(out)?;
            Ok(summary)
        }
        Err(e) => {
            summary.status = "failed".into();
            summary.error = Some(e.to_string());
            summary.write(out)?;
            Err(format!(
                "{e} (partial results up to the failure are in {})",
                out.display()
            )
            .into())
        }
    }
}

/// Run a scenario for its maxima alone (a case of a sweep): no folder, no `history.csv`,
/// no plots; the summary as [`run_scenario`] would write it (the maxima take every step, so
/// they equal those of a run with files). The run's steps and memory are checked against
/// `limits`. Co-simulation needs a folder for its FMUs: it runs in a temporary one that is
/// removed afterwards.
pub fn run_maxima(
    scenario: &Scenario,
    limits: &Limits,
) -> Result<Summary, Box<dyn std::error::Error>> {
    let model = build(scenario)?;
    let mut estimate = model.estimate();
    estimate.history_bytes = 0.0;
    limits.check(scenario, &estimate)?;
    let mut rec = Recorder::new(
        layout(&model),
        &model.probes.iter().map(|p| p.1).collect::<Vec<_>>(),
        None::<std::io::Sink>,
    )?;
    let _in_flight = InFlight::enter();
    let start = Instant::now();
    let mut steps_ahead = None;
    let coupling = match scenario.run.solver {
        SolverKind::Monolithic => {
            steps_ahead = Some(run_monolithic(&model, &mut rec, false)?);
            None
        }
        SolverKind::Cosim => {
            let tmp = crate::output::outdir::TempDir::new("tbi-case")?;
            Some(crate::solve::cosim::run_cosim(
                &scenario.coupling,
                &model,
                (&tmp.path().join("fmus"), scenario.run.fmi_version),
                &mut rec,
                false,
            )?)
        }
    };
    let wall = start.elapsed().as_secs_f64();
    rec.finish()?;
    let mut summary = Summary::new(scenario, &model, &rec, wall);
    summary.steps_ahead = steps_ahead;
    summary.coupling = coupling;
    Ok(summary)
}

/// The runs in progress in this process ([`run_scenario`]).
static RUNS_IN_FLIGHT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// A run in progress (counted in [`RUNS_IN_FLIGHT`] while it lives).
struct InFlight;

impl InFlight {
    fn enter() -> Self {
        RUNS_IN_FLIGHT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        InFlight
    }

    /// Whether another run is in progress beside this one.
    fn others() -> bool {
        RUNS_IN_FLIGHT.load(std::sync::atomic::Ordering::Relaxed) > 1
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        RUNS_IN_FLIGHT.fetch_sub(1, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Whether a monolithic run may take a second core for its geometry
/// ([`Monolithic::run_ahead`]): the machine (or the process's CPU quota) has two or more,
/// the run is not one of a parallel sweep (a rayon worker, or runs in other threads of the
/// process), and neither `RAYON_NUM_THREADS` nor `OMP_NUM_THREADS` is 1 (the way schedulers
/// and Dask's workers ask a process to keep to one core).
fn may_use_second_core() -> bool {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let one = |var: &str| std::env::var(var).is_ok_and(|v| v.trim() == "1");
    cores > 1
        && rayon::current_thread_index().is_none()
        && !InFlight::others()
        && !one("RAYON_NUM_THREADS")
        && !one("OMP_NUM_THREADS")
}

/// Whether the monolithic run makes its geometry ahead on a second core
/// ([`Monolithic::run_ahead`]), chosen by timing both ways again and again through the run:
/// the hand-over of the shapes between the cores costs what the cores' placement makes it
/// (on a virtual machine of two cores the Tsing Ma case ran 35 % faster ahead in one
/// placement and 13 % slower in another, and the host moves the cores).
///
/// A choice times four windows of [`AheadChoice::PARTS`] × [`AheadChoice::PART`] steps:
/// the way of the moment, the other, the other again and the first again (so that a cost
/// changing steadily along the run, as the train moves onto the bridge, weighs on both
/// alike). Each window follows [`AheadChoice::SETTLE`] steps untimed (the worker's start,
/// the caches) and is counted by the faster half of its parts (so that another process
/// taking the core for a while does not decide). The way ahead is taken only when it was
/// [`AheadChoice::MARGIN`] faster, and the choice is kept for [`AheadChoice::KEEP_MIN`]
/// steps, four times as long each time it is made again, up to [`AheadChoice::KEEP_MAX`]:
/// the first steps of a run are not those of a train on the bridge (the Tsing Ma case,
/// timed at 2.3 s, ran 14 % faster ahead, and from 37 s on 5–10 % slower).
///
/// A step that waits for the worker longer than [`tbi_dynamics::solver::MAX_LAG`] (another
/// process has taken its core) ends the way ahead at once, and a choice whose windows on
/// one core saw another process running at every look (one per part, [`procs_running`])
/// keeps one core: with one busy process on a machine of two cores, runs that timed the
/// way ahead took 1.6–2.5 times as long. Either ends as a choice of one core made again.
/// The values are the same either way, bit for bit.
struct AheadChoice {
    /// Steps left in this phase, the coming one included.
    left: usize,
    /// The window being timed (0–3; 4 while keeping), and its part being timed (1 to
    /// `PARTS`; 0 while settling), with the parts' seconds.
    window: usize,
    part: usize,
    parts: [f64; AheadChoice::PARTS],
    start: Instant,
    /// Seconds of the timed windows: the way of the moment's, the other's.
    first: f64,
    other: f64,
    /// Steps the last choice is kept for.
    keep: usize,
    /// The longest a step waits for the worker ([`Monolithic::run_ahead`]).
    give_up: Option<std::time::Duration>,
    /// The fewest threads running on the machine at the looks during this choice's
    /// windows on one core (this run's own included; `usize::MAX` before the first look).
    running: usize,
    /// How it looks: [`procs_running`].
    look: fn() -> Option<usize>,
}

impl AheadChoice {
    const SETTLE: usize = 16;
    const PART: usize = 32;
    const PARTS: usize = 6;
    const KEEP_MIN: usize = 512;
    const KEEP_MAX: usize = 32768;
    const MARGIN: f64 = 0.03;

    fn new(give_up: Option<std::time::Duration>, look: fn() -> Option<usize>) -> Self {
        AheadChoice {
            give_up,
            running: usize::MAX,
            look,
            left: Self::SETTLE,
            window: 0,
            part: 0,
            parts: [0.0; Self::PARTS],
            start: Instant::now(),
            first: 0.0,
            other: 0.0,
            keep: Self::KEEP_MIN / 4,
        }
    }

    /// Before each step: start or end a window where a phase ends.
    fn before_step(&mut self, sol: &mut Monolithic) {
        if sol.take_ahead_lost() {
            // the worker fell behind (another process has its core)
            self.keep_one_core();
        }
        if self.left == 0 {
            self.next_phase(sol);
        }
        self.left -= 1;
    }

    /// Whether another process was running at every look during this choice's windows on
    /// one core (the way ahead would share a core with it).
    fn busy(&self) -> bool {
        self.running != usize::MAX && self.running >= 2
    }

    /// One core, kept as a choice made again (the worker, if any, already stopped).
    fn keep_one_core(&mut self) {
        self.window = 4;
        self.keep = (4 * self.keep).min(Self::KEEP_MAX);
        self.left = self.keep;
    }

    fn switch(&self, sol: &mut Monolithic) {
        if sol.runs_ahead() {
            sol.stop_ahead();
        } else {
            sol.run_ahead(self.give_up);
        }
    }

    fn next_phase(&mut self, sol: &mut Monolithic) {
        if self.window == 4 {
            // the choice kept long enough: time again
            (self.window, self.first, self.other) = (0, 0.0, 0.0);
            (self.part, self.left) = (0, Self::SETTLE);
            self.running = usize::MAX;
            return;
        }
        if self.part > 0 {
            self.parts[self.part - 1] = self.start.elapsed().as_secs_f64();
            if !sol.runs_ahead() {
                self.running = self.running.min((self.look)().unwrap_or(1));
            }
        }
        if self.part < Self::PARTS {
            (self.part, self.left) = (self.part + 1, Self::PART);
            self.start = Instant::now();
            return;
        }
        // the window's faster half of its parts: a part the machine took the core from (a
        // scheduler's tick is milliseconds, a part a fraction of one) is left out
        self.parts.sort_by(f64::total_cmp);
        let took: f64 = self.parts[..Self::PARTS / 2].iter().sum();
        if self.window == 0 || self.window == 3 {
            self.first += took;
        } else {
            self.other += took;
        }
        self.window += 1;
        if self.busy() && !sol.runs_ahead() {
            // another process runs all along: the worker would share a core with it
            self.keep_one_core();
            return;
        }
        if self.window < 4 {
            // the middle two windows are the other way's
            if self.window != 2 {
                self.switch(sol);
            }
            (self.part, self.left) = (0, Self::SETTLE);
            return;
        }
        let (ahead, plain) = if sol.runs_ahead() {
            (self.first, self.other)
        } else {
            (self.other, self.first)
        };
        let was = sol.runs_ahead();
        if (ahead < (1.0 - Self::MARGIN) * plain && !self.busy()) != was {
            self.switch(sol);
        }
        // the same choice again: kept four times as long; another: kept shortly
        self.keep = if sol.runs_ahead() == was {
            (4 * self.keep).min(Self::KEEP_MAX)
        } else {
            Self::KEEP_MIN
        };
        self.left = self.keep;
    }
}

/// The threads running on the machine at this moment (Linux: `procs_running` of
/// `/proc/stat`, the reader included); None where the system does not say.
fn procs_running() -> Option<usize> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let line = stat.lines().find(|l| l.starts_with("procs_running "))?;
    line["procs_running ".len()..].trim().parse().ok()
}

/// Integrate the model with the monolithic solver of eq. (14); the number of steps whose
/// geometry was made ahead on a second core (`AheadChoice`).
pub fn run_monolithic<W: std::io::Write>(
    model: &Model,
    rec: &mut Recorder<W>,
    show_progress: bool,
) -> Result<usize, Box<dyn std::error::Error>> {
    let mut sol = Monolithic::new(
        model.bridge.clone(),
        model.train.clone(),
        model.track.clone(),
        model.dt,
    );
    // the geometry of the coming steps on a core of its own, for a run alone in the process
    // on a machine with cores to spare (not in a sweep, whose runs take the cores)
    let mut ahead = (may_use_second_core() && sol.ahead_may_pay())
        .then(|| AheadChoice::new(Some(tbi_dynamics::solver::MAX_LAG), procs_running));
    let mut steps_ahead = 0;
    let probe_x: Vec<f64> = model.probes.iter().map(|p| p.1).collect();
    let shapes = ProbeShapes::new(&model.bridge, &probe_x);
    let mut sample = sol.sample(&shapes);
    rec.record(&sample, true)?;
    let pb = crate::output::progress::bar(model.steps, show_progress);
    for k in 1..=model.steps {
        crate::interrupt::check(sol.t)?;
        if let Some(c) = &mut ahead {
            if InFlight::others() {
                sol.stop_ahead();
                ahead = None;
            } else {
                c.before_step(&mut sol);
            }
        }
        sol.step();
        // still ahead after the step: this step's geometry was the worker's
        steps_ahead += usize::from(sol.runs_ahead());
        if !sol.q.iter().all(|v| v.is_finite()) {
            return Err(format!(
                "monolithic solver: non-finite bridge response at t = {} s",
                sol.t
            )
            .into());
        }
        sol.sample_into(&shapes, &mut sample);
        rec.record(&sample, k % model.output_every == 0 || k == model.steps)?;
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(steps_ahead)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solver(model: &Model) -> Monolithic {
        Monolithic::new(
            model.bridge.clone(),
            model.train.clone(),
            model.track.clone(),
            model.dt,
        )
    }

    /// The choice times the sequential way, the way ahead twice and the sequential way again,
    /// each window after its settling steps, keeps one way for `KEEP_MIN` steps and times again
    /// from the way kept; every step's values are those of the run without it.
    #[test]
    fn the_choice_times_both_ways_in_turn_and_changes_no_value() {
        let model = build(&Scenario::default_case()).unwrap();
        let (mut sol, mut plain) = (solver(&model), solver(&model));
        assert!(sol.ahead_may_pay());
        // a machine that runs nothing else, and a step that waits for the worker as long
        // as it takes (the tests run side by side)
        let mut c = AheadChoice::new(None, || Some(1));
        let w = AheadChoice::SETTLE + AheadChoice::PARTS * AheadChoice::PART;
        let mut ways = Vec::new();
        for _ in 0..(4 * w + AheadChoice::KEEP_MIN + 2 * w) {
            c.before_step(&mut sol);
            ways.push(sol.runs_ahead());
            sol.step();
            plain.step();
            assert_eq!(sol.q, plain.q);
            assert_eq!(sol.forces, plain.forces);
        }
        let all = |r: std::ops::Range<usize>, ahead: bool| ways[r].iter().all(|&a| a == ahead);
        // sequential, ahead, ahead, sequential
        assert!(all(0..w, false) && all(w..3 * w, true) && all(3 * w..4 * w, false));
        // then one way kept, timed again from it, and the other way timed
        let kept = ways[4 * w];
        let timed = 4 * w + AheadChoice::KEEP_MIN;
        assert!(all(4 * w..timed + w, kept));
        assert!(all(timed + w..timed + 2 * w, !kept));
    }

    /// With another process running at every look, the choice keeps one core after its
    /// first window and never starts the worker.
    #[test]
    fn a_busy_machine_keeps_one_core() {
        let mut sol = solver(&build(&Scenario::default_case()).unwrap());
        let mut c = AheadChoice::new(None, || Some(2));
        for _ in 0..3 * AheadChoice::KEEP_MIN {
            c.before_step(&mut sol);
            assert!(!sol.runs_ahead());
            sol.step();
        }
        let mut idle = AheadChoice::new(None, || Some(1));
        let mut started = false;
        for _ in 0..3 * AheadChoice::KEEP_MIN {
            idle.before_step(&mut sol);
            started |= sol.runs_ahead();
            sol.step();
        }
        assert!(started, "an idle machine times the way ahead");
    }
}
