//! `tbi cosim SYSTEM.ssp`: run any SSP 1.0 system of FMI 2.0 Co-Simulation FMUs with the
//! coupling algorithms of [`tbi_coupling`] (see [`crate::ssp`] for what is read).
//!
//! Times and step: the command line, else the SSD (`DefaultExperiment`, and `step_size`
//! of the coupling annotation); the step size is required. Coupling options: the
//! command line over the annotation over the defaults of [`CouplingConfig`].
//!
//! Output: a CSV (default `<SYSTEM stem>_out.csv`) with `time`, then the system's own
//! outputs by name (the annotation's `tbi:Output`s: `tbi export` declares each probe's deck
//! response and each car body's accelerations), or with `--record-all` (or a system that
//! declares none) every connected output as `component.variable` (in connection order;
//! Integer and Boolean values as integers, Booleans 0/1), then the `--record` variables. Its
//! size is estimated first and refused past 2 GiB (`--allow-large`); a row
//! after initialisation and one after each communication step (with `--output-interval`,
//! after each step ending at a multiple of the interval, and after the last), every number in full
//! precision (shortest round-trip form, scientific notation as in `history.csv`). Beside it `<CSV>.json`: steps, iterations per step
//! (mean, max), the largest final residual of the interface iteration (explicit schemes:
//! the interface defect, also printed, with a word when it passes
//! [`EXPLICIT_DEFECT_NOTICE`]) in tolerances and relative, with its measure named, the
//! options used (the acceleration `null` for an explicit scheme), and the connections the scheme lagged by one
//! step per pair of components (`lagged_connections`: for Gauss–Seidel the connections
//! that close a cycle in the SSD's component order).

use std::io::Write;
use std::path::PathBuf;
use std::str::FromStr;
use tbi_coupling::CouplingStatistics;
use tbi_coupling::{
    advance_into, build_scheme, AccelerationKind, CouplingConfig, Discrete, SchemeKind,
};

/// Command-line arguments of `tbi cosim`.
#[derive(Debug, Clone, clap::Args)]
pub struct CosimArgs {
    /// The system: a `.ssp` archive or a `SystemStructure.ssd` file.
    pub system: PathBuf,
    /// Start time, s (default: DefaultExperiment startTime, else 0).
    #[arg(long, allow_negative_numbers = true)]
    pub start_time: Option<f64>,
    /// Stop time, s (default: DefaultExperiment stopTime).
    #[arg(long, allow_negative_numbers = true)]
    pub stop_time: Option<f64>,
    /// Communication step, s (default: the annotation's step_size).
    #[arg(long, allow_negative_numbers = true)]
    pub step_size: Option<f64>,
    /// Coupling scheme: `implicit` (the interface iterated in every step until it converges:
    /// the monolithic solution), `gauss-seidel` or `jacobi` (explicit: one pass, inputs
    /// lagged). Default: the annotation's, else `implicit`.
    #[arg(long)]
    pub scheme: Option<String>,
    /// Acceleration of the implicit scheme: `iqn-ils`, `aitken`, `newton` or `constant`.
    /// Default: the annotation's, else `iqn-ils` reusing the last 8 steps' columns. Refused
    /// with an explicit scheme.
    #[arg(long)]
    pub acceleration: Option<String>,
    /// Relative tolerance of the interface: a step converges when the weighted RMS of the
    /// change of the exchanged values, each over rtol·max|value of its group| + atol, is ≤ 1.
    /// Default: the annotation's, else 1e-10.
    #[arg(long, allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Absolute tolerance of the interface, in the units of the exchanged values (> 0).
    /// Default: the annotation's, else 1e-12.
    #[arg(long, allow_negative_numbers = true)]
    pub atol: Option<f64>,
    /// Most sweeps of the implicit scheme in one step. Default: the annotation's, else 50.
    #[arg(long)]
    pub max_iterations: Option<usize>,
    /// Set a parameter or input before initialisation: `COMPONENT.VARIABLE=VALUE`.
    #[arg(long = "set", value_name = "COMPONENT.VARIABLE=VALUE")]
    pub set: Vec<String>,
    /// Also record `COMPONENT.VARIABLE` (repeatable).
    #[arg(long = "record", value_name = "COMPONENT.VARIABLE")]
    pub record: Vec<String>,
    /// Record every connected output, not only the system's own outputs (the probes and car
    /// bodies `tbi export` declares). A system that declares none records every connected
    /// output anyway.
    #[arg(long)]
    pub record_all: bool,
    /// Result CSV. Default: `<SYSTEM stem>_out.csv` in the working folder.
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Time between result rows, s: a whole multiple of the step size. Default: the
    /// annotation's `output_interval` (`tbi export` writes the scenario's
    /// `dt_s × output_every`) where it is a whole multiple of the step, else a row after
    /// every step. The last step always has a row.
    #[arg(long, allow_negative_numbers = true)]
    pub output_interval: Option<f64>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Write the CSV even when its estimated size passes 2 GiB (the limit of `tbi run`).
    #[arg(long)]
    pub allow_large: bool,
}

/// The size an explicit scheme's interface defect may reach, relative to the values, before
/// `tbi cosim` suggests the implicit scheme: 1e-3 (0.1 %).
pub const EXPLICIT_DEFECT_NOTICE: f64 = 1e-3;

/// The connections an explicit scheme lags by one step, counted per pair of components:
/// Jacobi lags every connection; Gauss–Seidel (components stepped in SSD order) lags those
/// from a component to itself or to one stepped before it, the connections that close a
/// cycle of the connection graph; the implicit scheme iterates them all, lagging none.
fn lagged_connections(
    sys: &tbi_coupling::System,
    scheme: SchemeKind,
    components: &[crate::ssp::Component],
) -> Vec<serde_json::Value> {
    let pairs = sys
        .connections
        .iter()
        .map(|c| (c.from, c.to))
        .chain(sys.discrete.iter().map(|c| (c.from, c.to)));
    let mut counts: Vec<((usize, usize), usize)> = Vec::new();
    for (from, to) in pairs {
        let lagged = match scheme {
            SchemeKind::Jacobi => true,
            SchemeKind::GaussSeidel => from >= to,
            SchemeKind::Implicit => false,
        };
        if !lagged {
            continue;
        }
        match counts.iter_mut().find(|(p, _)| *p == (from, to)) {
            Some((_, n)) => *n += 1,
            None => counts.push(((from, to), 1)),
        }
    }
    counts
        .into_iter()
        .map(|((from, to), n)| {
            serde_json::json!({
                "from": components[from].name,
                "to": components[to].name,
                "connections": n,
            })
        })
        .collect()
}

/// How the side-car's residuals are measured.
const RESIDUAL_MEASURE: &str = "weighted RMS of the change of the exchanged values in a step's last sweep (implicit) or of the defect between the lagged inputs and the outputs they stand for (explicit), each value over rtol·max|value of its group| + atol: 1 is the tolerance; the relative figure is that times rtol";

fn split_name(item: &str, option: &str) -> Result<(String, String), String> {
    item.split_once('.')
        .map(|(c, v)| (c.to_owned(), v.to_owned()))
        .ok_or_else(|| format!("{option} {item}: expected COMPONENT.VARIABLE"))
}

pub fn main(args: CosimArgs) -> Result<(), Box<dyn std::error::Error>> {
    let open = crate::ssp::open(&args.system)?;
    let (mut cfg, annotated_step): (CouplingConfig, Option<f64>) = open.coupling()?;
    if let Some(s) = &args.scheme {
        cfg.scheme = SchemeKind::from_str(s).map_err(|e| format!("--scheme {s}: {e}"))?;
    }
    if let Some(a) = &args.acceleration {
        cfg.acceleration =
            AccelerationKind::from_str(a).map_err(|e| format!("--acceleration {a}: {e}"))?;
        if cfg.scheme != SchemeKind::Implicit {
            return Err(crate::console::UsageError(format!(
                "--acceleration {a} with --scheme {}: an explicit scheme makes one pass per step and accelerates nothing; drop --acceleration or use --scheme implicit",
                cfg.scheme.as_str()
            ))
            .into());
        }
    }
    if let Some(v) = args.rtol {
        cfg.rtol = v;
    }
    if let Some(v) = args.atol {
        cfg.atol = v;
    }
    if let Some(v) = args.max_iterations {
        cfg.max_iterations = v;
    }
    cfg.validate()
        .map_err(|e| format!("coupling options: {e}"))?;
    let start = args.start_time.or(open.ssd.start_time).unwrap_or(0.0);
    let stop = args
        .stop_time
        .or(open.ssd.stop_time)
        .ok_or_else(|| format!("{}: no stop time (give --stop-time)", open.origin))?;
    let h = args
        .step_size
        .or(annotated_step)
        .ok_or_else(|| format!("{}: no communication step (give --step-size)", open.origin))?;
    if !(start.is_finite() && stop.is_finite() && stop > start) {
        return Err(format!(
            "start time {start} s and stop time {stop} s: the stop must come after the start"
        )
        .into());
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(format!("--step-size {h}: must be a positive number").into());
    }
    let steps = ((stop - start) / h - 1e-9).ceil().max(1.0);
    if steps > 1e7 {
        return Err(format!(
            "the run would take {steps:.3e} communication steps, more than the limit of 1e7"
        )
        .into());
    }
    let steps = steps as usize;
    let every = match (args.output_interval, open.output_interval()?) {
        (Some(dt), _) => steps_per_row(dt, h)?,
        // the annotation's, where it is a whole number of this run's steps
        (None, Some(dt)) => steps_per_row(dt, h).unwrap_or(1),
        (None, None) => 1,
    };
    let mut sets = Vec::new();
    for item in &args.set {
        let (name, value) = item
            .split_once('=')
            .ok_or_else(|| format!("--set {item}: expected COMPONENT.VARIABLE=VALUE"))?;
        let (c, v) = split_name(name.trim(), "--set")?;
        // typed by the variable when it is set (a number, an integer, true/false)
        sets.push((c, v, value.trim().to_owned()));
    }
    let mut wired = crate::ssp::wire(&open, &sets, start, stop)?;
    if cfg.scheme == SchemeKind::Implicit {
        // The interface iteration repeats each step after rolling the FMUs back.
        for (c, fmu) in open.ssd.components.iter().zip(&wired.fmus) {
            let can = fmu
                .model_description()
                .co_simulation
                .as_ref()
                .is_some_and(|cs| cs.can_get_and_set_fmu_state);
            if !can {
                return Err(format!(
                    "{}: component \"{}\" ({}) cannot roll back (canGetAndSetFMUstate is not true), which the implicit scheme needs; use --scheme gauss-seidel or jacobi",
                    open.origin, c.name, c.source
                )
                .into());
            }
        }
        if let Some(c) = wired.system.discrete.first() {
            return Err(format!(
                "{}: the connection {} is {}; the implicit scheme iterates Real connections only, use --scheme gauss-seidel or jacobi",
                open.origin, c.name, c.kind
            )
            .into());
        }
    }
    // the system's own outputs by default; every connected output with --record-all or
    // when the system declares none
    let all = args.record_all || wired.recorded.is_empty();
    let mut columns: Vec<(String, usize, u32, Option<Discrete>)> =
        if all { &wired.outputs } else { &wired.recorded }
            .iter()
            .map(|o| (o.name.clone(), o.participant, o.vr, o.kind))
            .collect();
    for r in &args.record {
        let (c, v) = split_name(r, "--record")?;
        let i = open
            .ssd
            .components
            .iter()
            .position(|x| x.name == c)
            .ok_or_else(|| {
                format!(
                    "--record {r}: the system has no component \"{c}\"{}",
                    crate::suggest::did_you_mean(
                        &c,
                        open.ssd.components.iter().map(|x| x.name.as_str())
                    )
                )
            })?;
        let md = wired.fmus[i].model_description();
        let var = md.variable(&v).ok_or_else(|| {
            format!(
                "--record {r}: component \"{c}\" has no variable \"{v}\"{}",
                crate::suggest::did_you_mean(
                    &v,
                    md.model_variables.iter().map(|x| x.name.as_str())
                )
            )
        })?;
        let kind = crate::ssp::exchanged_kind(&var.kind)
            .ok_or_else(|| format!("--record {r}: a String variable cannot be recorded"))?;
        columns.push((r.clone(), i, var.value_reference, kind));
    }
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = args
            .system
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "system".into());
        PathBuf::from(format!("{stem}_out.csv"))
    });
    let rows_total = (steps / every + 2) as f64;
    let estimate = rows_total * (1 + columns.len()) as f64 * crate::model::VALUE_BYTES;
    let limit = crate::model::Limits::default().max_history_bytes;
    if estimate > limit && !args.allow_large {
        return Err(format!(
            "{}: the CSV would grow to about {:.0} MiB ({} columns × {rows_total:.0} rows), more than the limit of {:.0} MiB; record fewer signals (without --record-all), raise --output-interval, or give --allow-large",
            output.display(),
            estimate / (1u64 << 20) as f64,
            columns.len() + 1,
            limit / (1u64 << 20) as f64
        )
        .into());
    }
    let partial = crate::outdir::with_suffix(&output, ".partial");
    let sidecar = crate::outdir::with_suffix(&output, ".json");
    let failure = crate::outdir::with_suffix(&partial, ".json");
    crate::outdir::refuse_inputs(
        &[
            output.clone(),
            sidecar.clone(),
            partial.clone(),
            failure.clone(),
        ],
        &system_inputs(&args, &open),
    )?;
    // rows stream into <output>.partial, renamed at success: a failed run leaves an earlier
    // result and its side-car as they were, and says what it computed beside its .partial
    let mut csv = crate::outdir::NamedFile::create(&partial)?;
    let stepped = step_and_record(
        &mut wired.system,
        &columns,
        &cfg,
        (start, stop, h, steps, every),
        &mut csv,
        args.quiet,
    )
    .and_then(|stats| {
        csv.flush()?;
        Ok(stats)
    });
    let stats = match stepped {
        Ok(stats) => stats,
        Err(e) => {
            let _ = csv.flush();
            let said = serde_json::json!({
                "system": open.origin,
                "status": "failed",
                "error": e.to_string(),
                "rows": partial.display().to_string(),
            });
            let _ = crate::outdir::write_atomically(
                &failure,
                serde_json::to_string_pretty(&said)?.as_bytes(),
            );
            return Err(format!(
                "{e} (the rows computed so far are in {}; {} is left as it was)",
                partial.display(),
                output.display()
            )
            .into());
        }
    };
    let lagged = lagged_connections(&wired.system, cfg.scheme, &open.ssd.components);
    let summary = serde_json::json!({
        "system": open.origin,
        "start_time_s": start,
        "stop_time_s": stop,
        "step_size_s": h,
        "scheme": cfg.scheme.as_str(),
        "acceleration": (cfg.scheme == SchemeKind::Implicit).then(|| cfg.acceleration.as_str()),
        "rtol": cfg.rtol,
        "atol": cfg.atol,
        "recorded": if all { "every connected output" } else { "the system's outputs" },
        "steps": stats.steps,
        "iterations_mean": stats.mean_iterations(),
        "iterations_max": stats.max_iterations,
        "steps_by_iterations": stats.steps_by_iterations,
        "jacobian_probes": stats.jacobian_probes,
        "residual_measure": RESIDUAL_MEASURE,
        "max_residual_in_tolerances": stats.max_residual,
        "max_residual_relative": stats.max_residual * cfg.rtol,
        "accepted_unconverged": stats.accepted_unconverged,
        "lagged_connections": lagged,
    });
    // the side-car and the CSV replace an earlier pair together: the side-car written whole
    // under a temporary name, the CSV renamed, then the side-car
    let staged = crate::outdir::with_suffix(&sidecar, &format!(".tmp-{}", std::process::id()));
    std::fs::write(&staged, serde_json::to_string_pretty(&summary)?)
        .map_err(|e| format!("{}: {e}", staged.display()))?;
    std::fs::rename(&partial, &output).map_err(|e| format!("{}: {e}", output.display()))?;
    std::fs::rename(&staged, &sidecar).map_err(|e| format!("{}: {e}", sidecar.display()))?;
    let _ = std::fs::remove_file(&failure);
    if cfg.scheme != SchemeKind::Implicit {
        let relative = stats.max_residual * cfg.rtol;
        eprintln!(
            "tbi: {} scheme: interface defect up to {relative:.3e} relative ({:.3e} tolerances): how far the inputs each FMU stepped with, lagged by the scheme, were from the outputs they stand for{}",
            cfg.scheme.as_str(),
            stats.max_residual,
            if relative > EXPLICIT_DEFECT_NOTICE {
                "; above 0.1 %: the results differ from the coupled solution by about that much, use --scheme implicit"
            } else {
                ""
            }
        );
    }
    if !args.quiet {
        eprintln!(
            "tbi: {} steps, {:.2} iterations per step; results in {}",
            stats.steps,
            stats.mean_iterations(),
            output.display()
        );
    }
    Ok(())
}

/// The files a run reads, which no output may replace: the system file, and for an `.ssd`
/// given directly the components' FMUs and `.ssv` files beside it (an `.ssp`'s are inside
/// it).
fn system_inputs(args: &CosimArgs, open: &crate::ssp::OpenSystem) -> Vec<(PathBuf, String)> {
    let mut inputs = vec![(args.system.clone(), "the system".to_string())];
    let archive = args
        .system
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ssp"));
    if !archive {
        for c in &open.ssd.components {
            inputs.push((
                open.base.join(&c.source),
                format!("the FMU of component \"{}\"", c.name),
            ));
            for f in &c.parameter_files {
                inputs.push((
                    open.base.join(f),
                    format!("a parameter file of component \"{}\"", c.name),
                ));
            }
        }
    }
    inputs
}

/// Initialise the coupling, then step from `start` to `stop` by `h`, writing a row after
/// initialisation and every `every` steps (and after the last) into `csv`.
fn step_and_record(
    sys: &mut tbi_coupling::System,
    columns: &[(String, usize, u32, Option<Discrete>)],
    cfg: &CouplingConfig,
    (start, stop, h, steps, every): (f64, f64, f64, usize, usize),
    csv: &mut crate::outdir::NamedFile,
    quiet: bool,
) -> Result<CouplingStatistics, Box<dyn std::error::Error>> {
    let header: Vec<&str> = std::iter::once("time")
        .chain(columns.iter().map(|c| c.0.as_str()))
        .collect();
    writeln!(csv, "{}", header.join(","))?;
    let mut rows = Rows::new(columns, sys.participants.len());
    let mut scheme = build_scheme(cfg)?;
    scheme.initialize(sys)?;
    rows.write(sys, start, csv)?;
    let mut stats = CouplingStatistics::new();
    let mut report = tbi_coupling::AdvanceReport::default();
    let pb = crate::progress::bar(steps, !quiet);
    for k in 1..=steps {
        let (t, t1, hk) = communication_step(start, stop, h, k, steps);
        crate::interrupt::check(t)?;
        advance_into(scheme.as_mut(), sys, t, hk, cfg.policy(hk), &mut report)
            .map_err(|e| format!("co-simulation stopped at t = {t} s: {e}"))?;
        stats.record(&report);
        if k.is_multiple_of(every) || k == steps {
            rows.write(sys, t1, csv)?;
        }
        if k % 256 == 0 {
            pb.set_position(k as u64);
        }
    }
    pb.finish_and_clear();
    Ok(stats)
}

/// The steps per result row of `--output-interval dt` with step size `h`: `dt / h`, which must
/// be a positive whole number (to 1e-9 of it).
fn steps_per_row(dt: f64, h: f64) -> Result<usize, String> {
    let ratio = dt / h;
    let whole = ratio.round();
    if !(dt.is_finite() && dt > 0.0 && whole >= 1.0 && (ratio - whole).abs() <= 1e-9 * whole) {
        return Err(format!(
            "--output-interval {dt}: must be a positive whole multiple of the step size {h} s"
        ));
    }
    if whole > 1e9 {
        return Err(format!(
            "--output-interval {dt}: more than 1e9 steps of {h} s between rows"
        ));
    }
    Ok(whole as usize)
}

/// Step `k` (1-based) of `steps`: its start `t = start + (k − 1) h`, its end `t₁` and its size.
///
/// The size is the nominal `h` itself, not `t₁ − t`: that difference jitters with the
/// rounding of `t` (by about 1e-11 of h at t = 100 s with h = 2 ms), so every FMU would see a
/// new step size in every step and redo what it keeps per step size (and the iteration then
/// takes more sweeps). Only a last step that ends at `stop` more than round-off short of a
/// whole step is shorter.
fn communication_step(start: f64, stop: f64, h: f64, k: usize, steps: usize) -> (f64, f64, f64) {
    let t = start + (k - 1) as f64 * h;
    let t1 = (start + k as f64 * h).min(stop);
    let short = k == steps && (t1 - t) < h * (1.0 - 1e-9);
    (t, t1, if short { t1 - t } else { h })
}

/// One CSV row per communication point: every recorded Real output of a participant read by
/// one `get_real` call, the row formatted into one reused line.
struct Rows {
    /// Per participant: the value references of its recorded Real outputs and their columns.
    reals: Vec<(Vec<u32>, Vec<usize>)>,
    /// `(column, participant, vr, kind)` of the recorded Integer/Boolean outputs.
    discrete: Vec<(usize, usize, u32, Discrete)>,
    /// The cells of the row being written, and its text.
    cells: Vec<Cell>,
    buffer: Vec<f64>,
    line: String,
}

#[derive(Clone, Copy)]
enum Cell {
    Real(f64),
    Discrete(i32),
}

impl Rows {
    fn new(columns: &[(String, usize, u32, Option<Discrete>)], participants: usize) -> Self {
        let mut reals = vec![(Vec::new(), Vec::new()); participants];
        let mut discrete = Vec::new();
        for (col, &(_, p, vr, kind)) in columns.iter().enumerate() {
            match kind {
                None => {
                    reals[p].0.push(vr);
                    reals[p].1.push(col);
                }
                Some(kind) => discrete.push((col, p, vr, kind)),
            }
        }
        Rows {
            reals,
            discrete,
            cells: vec![Cell::Real(0.0); columns.len()],
            buffer: Vec::new(),
            line: String::new(),
        }
    }

    fn write(
        &mut self,
        sys: &mut tbi_coupling::System,
        t: f64,
        csv: &mut crate::outdir::NamedFile,
    ) -> Result<(), Box<dyn std::error::Error>> {
        use std::fmt::Write as _;
        for (p, (vrs, cols)) in self.reals.iter().enumerate() {
            if vrs.is_empty() {
                continue;
            }
            self.buffer.resize(vrs.len(), 0.0);
            sys.participants[p].get_real(vrs, &mut self.buffer)?;
            for (&col, &v) in cols.iter().zip(&self.buffer) {
                self.cells[col] = Cell::Real(v);
            }
        }
        for &(col, p, vr, kind) in &self.discrete {
            let mut v = [0];
            sys.participants[p].get_discrete(kind, &[vr], &mut v)?;
            self.cells[col] = Cell::Discrete(v[0]);
        }
        self.line.clear();
        write!(self.line, "{t:e}")?;
        for cell in &self.cells {
            match cell {
                Cell::Real(v) => write!(self.line, ",{v:e}")?,
                Cell::Discrete(v) => write!(self.line, ",{v}")?,
            }
        }
        self.line.push('\n');
        csv.write_all(self.line.as_bytes())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::communication_step;

    #[test]
    fn output_intervals_are_whole_multiples_of_the_step() {
        use super::steps_per_row;
        assert_eq!(steps_per_row(0.002, 0.002), Ok(1));
        assert_eq!(steps_per_row(0.01, 0.002), Ok(5));
        assert_eq!(steps_per_row(0.1, 0.001), Ok(100));
        for bad in [0.003, 0.001, 0.0, -0.01, f64::NAN, f64::INFINITY] {
            let e = steps_per_row(bad, 0.002).unwrap_err();
            assert!(
                e.contains("--output-interval") && e.contains("0.002"),
                "{e}"
            );
        }
    }

    /// Every step of the Tsing Ma run (65 059 steps of 2 ms to 130.118 s) has the nominal size
    /// bit for bit, although `t₁ − t` differs from it in most steps; a run whose end is not a
    /// whole number of steps ends with the short remainder.
    #[test]
    fn steps_have_the_nominal_size_except_a_short_last_one() {
        let (h, stop) = (0.002, 130.118);
        let steps = ((stop - 0.0) / h - 1e-9_f64).ceil() as usize;
        assert_eq!(steps, 65_059);
        let mut jittered = 0;
        for k in 1..=steps {
            let (t, t1, hk) = communication_step(0.0, stop, h, k, steps);
            assert_eq!(hk.to_bits(), h.to_bits(), "step {k}");
            jittered += usize::from((t1 - t).to_bits() != h.to_bits());
        }
        assert!(jittered > steps / 2, "{jittered} of {steps}");
        let stop = 1.0005;
        let steps = (stop / h - 1e-9_f64).ceil() as usize;
        assert_eq!(steps, 501);
        let (t, t1, hk) = communication_step(0.0, stop, h, steps, steps);
        assert_eq!((t, t1), (1.0, stop));
        assert!((hk - 0.0005).abs() < 1e-12, "{hk}");
    }
}
