//! The EN 1991-2 dynamic design check: `tbi sweep SCENARIO --trains hslm-a`.
//!
//! 1. **Cases** ([`cases`]): every train at every speed of its grid, each the scenario with
//!    its train replaced and its speed set, read as `tbi run` reads a scenario file.
//! 2. **Speeds** ([`refine`]): the grid plus each train's resonance speeds f₁ D / i, then a
//!    golden-section refinement around every local maximum of the train's deck
//!    acceleration envelope.
//! 3. **Outputs sized for sweeps**: a case keeps its maxima (a row of `envelope.csv`);
//!    full runs (`history.csv`, plots, `summary.json` in `OUT/<train>/v<speed>/`) only for
//!    each train's case of largest deck acceleration and for the governing case of each
//!    check (`--keep-histories`: every case). The disk use is estimated before the first
//!    run and refused past `tbi run`'s limit (`--allow-large`).
//! 4. **Governing cases** as scenario files, `OUT/governing/<check>.toml`: `tbi run` of one
//!    reproduces the reported value.
//! 5. **Checks**: the deck acceleration against EN 1990 A2.4.4.2.1 (3.5 m/s² ballasted,
//!    5 m/s² direct fastening) with the modes up to max(30 Hz, 1.5 f₁, f₃); with vehicles,
//!    the car-body acceleration against EN 1990 Table A2.9; and the EN 1991-2 §6.4.6.5
//!    comparison with LM71 ([`en`]).
//!
//! φ'dyn = max y_dyn / max y_stat − 1 (§6.4.6.5, Annex C) uses the modal static response
//! Σₙ φₙ(x_p) Σⱼ Pⱼ ψₙ(xⱼ)/ωₙ² with the modes kept, maximised over the train's positions,
//! at the probe where it is largest.

pub mod cases;
pub mod en;
pub mod refine;
pub mod report;

use crate::design::SweepOptions;
use crate::model::Limits;
use crate::text::num;
use cases::{Case, Source};
use rayon::prelude::*;
use refine::Point;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The trains `--trains` names: `hslm-a` for A1–A10, or names such as `A1`.
pub fn train_names(items: &[String]) -> Result<Vec<String>, String> {
    let mut names: Vec<String> = Vec::new();
    for item in items {
        let item = item.trim();
        let add: Vec<String> = if item.eq_ignore_ascii_case("hslm-a") {
            tbi_dynamics::hslm::HSLM_A
                .iter()
                .map(|t| t.name.to_owned())
                .collect()
        } else {
            tbi_dynamics::hslm::hslm_a(item).map_err(|e| format!("--trains {item}: {e}"))?;
            vec![item.to_ascii_uppercase()]
        };
        for n in add {
            if names.contains(&n) {
                return Err(format!("--trains: {n} is given twice"));
            }
            names.push(n);
        }
    }
    Ok(names)
}

/// EN 1990 Table A2.9: the car-body vertical acceleration b_v of each comfort level, m/s².
pub fn comfort_limit(level: &str) -> Result<f64, String> {
    match level {
        "very-good" => Ok(1.0),
        "good" => Ok(1.3),
        "acceptable" => Ok(2.0),
        other => Err(format!(
            "--comfort {other}: expected very-good (1.0 m/s²), good (1.3 m/s²) or acceptable (2.0 m/s²)"
        )),
    }
}

/// One case's result: a row of `envelope.csv`.
#[derive(Debug, Clone)]
pub struct Row {
    pub train: String,
    pub speed_kmh: f64,
    pub point: Point,
    /// Deck vertical acceleration, largest over the probes, m/s².
    pub acceleration: f64,
    /// Deck vertical displacement, largest over the probes, m.
    pub displacement: f64,
    /// The static displacement of the train crossing, largest over the probes, m.
    pub static_displacement: f64,
    /// φ'dyn at the probe where it is largest, –.
    pub phi: f64,
    /// Car-body vertical acceleration, largest over the vehicles, m/s² (vehicles only).
    pub body: Option<f64>,
}

/// A check's quantity of the envelope.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    DeckAcceleration,
    DeckDisplacement,
    CarBodyAcceleration,
}

impl Quantity {
    /// The file name of its governing case (`governing/<name>.toml`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::DeckAcceleration => "deck-acceleration",
            Quantity::DeckDisplacement => "deck-displacement",
            Quantity::CarBodyAcceleration => "car-body-acceleration",
        }
    }

    pub fn of(self, r: &Row) -> f64 {
        match self {
            Quantity::DeckAcceleration => r.acceleration,
            Quantity::DeckDisplacement => r.displacement,
            Quantity::CarBodyAcceleration => r.body.unwrap_or(0.0),
        }
    }
}

/// What the check was asked to do (the options of `tbi sweep --trains`).
pub struct Options {
    pub limit_m_s2: f64,
    pub track: &'static str,
    pub comfort: Option<(f64, String)>,
    pub keep_histories: bool,
    pub limits: Limits,
    pub en: en::Options,
}

/// The result of a check, for the report.
pub struct Outcome {
    /// The first case's scenario: the bridge, damping, time step and probes of every case.
    pub scenario: crate::scenario::Scenario,
    pub rows: Vec<Row>,
    pub bridge: tbi_dynamics::bridge::ModalBridge,
    /// Per train, in the order asked for: its resonance speeds in the range, km/h.
    pub resonances: Vec<(String, Vec<f64>)>,
    /// Per quantity: the governing row's index and the scenario file written for it.
    pub governing: Vec<(Quantity, usize, PathBuf)>,
    pub refined_runs: usize,
    pub grid_runs: usize,
    /// The disk use estimated before the first run, bytes.
    pub estimated_bytes: f64,
    pub speeds: Vec<f64>,
    pub en: Option<en::Comparison>,
}

/// `tbi sweep --trains`: the check, its summary printed; exit code 3 when a check FAILs.
pub fn main(args: &SweepOptions, speeds: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    let done = run(args, speeds)?;
    for line in done.text.lines() {
        crate::say!("{line}");
    }
    if !done.passed {
        crate::output::console::check_failed();
    }
    eprintln!(
        "tbi: {} cases ({} on the grid with the resonance speeds, {} refining peaks); envelope.csv, report.html, summary.txt and governing/ in {}",
        done.outcome.rows.len(),
        done.outcome.grid_runs,
        done.outcome.refined_runs,
        args.out.display()
    );
    Ok(())
}

/// A check done: its outcome, the summary's text (also `summary.txt`) and whether every
/// check passed.
pub struct Done {
    pub outcome: Outcome,
    pub text: String,
    pub passed: bool,
}

/// The check of `args` over `speeds` into `args.out` (`envelope.csv`, `summary.txt`,
/// `report.html`, `governing/`, the kept runs), printing nothing: for `tbi sweep` and the
/// Python package.
pub fn run(args: &SweepOptions, speeds: &[f64]) -> Result<Done, Box<dyn std::error::Error>> {
    let trains = train_names(&args.trains)?;
    let (limit_m_s2, track) = match args.track.as_str() {
        "ballasted" => (3.5, "ballasted track"),
        "direct" => (5.0, "direct fastening"),
        other => return Err(format!("--track {other}: expected ballasted or direct").into()),
    };
    let mut source = Source::load(args.scenario.as_deref())?;
    source.solver = args.solver.clone();
    source.all_modes = args.all_modes;
    let first = source.scenario(&Case {
        train: trains[0].clone(),
        speed_kmh: speeds[0],
    })?;
    let comfort = match first.train.axle_vehicle {
        Some(_) => Some((comfort_limit(&args.comfort)?, args.comfort.clone())),
        None => None,
    };
    let options = Options {
        limit_m_s2,
        track,
        comfort,
        keep_histories: args.keep_histories,
        limits: if args.allow_large {
            Limits::none()
        } else {
            Limits::default()
        },
        en: en::Options::from_args(args)?,
    };
    let started = std::time::Instant::now();
    let out = crate::output::outdir::OutputDir::claim(&args.out)?;
    let outcome = check(&source, &first, &trains, speeds, &options, out.path())?;
    let text = summary_text(&source, &outcome, &options, out.path());
    crate::output::outdir::write_atomically(&out.path().join("summary.txt"), text.as_bytes())?;
    let html = report::html(&source, &outcome, &options, out.path(), started)?;
    crate::output::outdir::write_atomically(&out.path().join("report.html"), html.as_bytes())?;
    let passed = checks(&outcome, &options).iter().all(|c| c.passed);
    Ok(Done {
        outcome,
        text,
        passed,
    })
}

/// Run the check into `out`: the cases, the refinement, the kept runs, `envelope.csv` and
/// the governing scenario files. `first` is the first case's scenario (its bridge is every
/// case's).
pub fn check(
    source: &Source,
    first: &crate::scenario::Scenario,
    trains: &[String],
    speeds: &[f64],
    o: &Options,
    out: &Path,
) -> Result<Outcome, Box<dyn std::error::Error>> {
    let bridge = crate::model::build_bridge(first)?;
    let (lo, hi) = speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let f1 = bridge.frequencies_hz[0];
    let mut resonances = Vec::new();
    let mut grid = Vec::new();
    for t in trains {
        let d = tbi_dynamics::hslm::HSLM_A
            .iter()
            .find(|h| h.name == t)
            .map_or(0.0, |h| h.coach_length_m);
        let r = refine::resonance_speeds(f1, d, lo, hi);
        for (v, point) in refine::with_resonances(speeds, &r) {
            grid.push((t.clone(), v, point));
        }
        resonances.push((t.clone(), r));
    }
    let statics = statics(trains, &bridge, first)?;
    let estimated_bytes = estimate_disk(source, trains, &grid, o, out)?;
    let pb = crate::output::progress::counted(grid.len(), "cases", true);
    let evaluate = |t: &str, v: f64, point: Point| -> Result<Row, String> {
        let case = Case {
            train: t.to_string(),
            speed_kmh: v,
        };
        let s = source.scenario(&case)?;
        let summary = crate::solve::run_maxima(&s, &o.limits)
            .map_err(|e| format!("{t} at {} km/h: {e}", num(v)))?;
        Ok(row(&case, point, &summary, &statics[t]))
    };
    let mut rows: Vec<Row> = grid
        .par_iter()
        .map(|(t, v, point)| {
            let r = evaluate(t, *v, *point);
            pb.inc(1);
            r
        })
        .collect::<Result<_, _>>()?;
    pb.finish_and_clear();
    let grid_runs = rows.len();
    let refined = refine_peaks(trains, &rows, &evaluate)?;
    let refined_runs = refined.len();
    rows.extend(refined);
    rows.sort_by(|a, b| {
        trains
            .iter()
            .position(|t| *t == a.train)
            .cmp(&trains.iter().position(|t| *t == b.train))
            .then(a.speed_kmh.total_cmp(&b.speed_kmh))
    });
    let quantities: Vec<Quantity> = [
        Quantity::DeckAcceleration,
        Quantity::DeckDisplacement,
        Quantity::CarBodyAcceleration,
    ]
    .into_iter()
    .filter(|q| *q != Quantity::CarBodyAcceleration || o.comfort.is_some())
    .collect();
    let governing = write_governing(source, &rows, &quantities, out)?;
    crate::output::outdir::write_atomically(
        &out.join("envelope.csv"),
        envelope_csv(&rows, &governing).as_bytes(),
    )?;
    keep_runs(source, trains, &rows, &governing, o, out)?;
    let en = en::compare(first, &bridge, trains, &rows, &o.en)?;
    Ok(Outcome {
        scenario: first.clone(),
        rows,
        bridge,
        resonances,
        governing,
        refined_runs,
        grid_runs,
        estimated_bytes,
        speeds: speeds.to_vec(),
        en,
    })
}

/// Per train and probe: the largest static displacement of the train crossing, m.
pub type Statics = BTreeMap<String, BTreeMap<String, f64>>;

fn statics(
    trains: &[String],
    bridge: &tbi_dynamics::bridge::ModalBridge,
    first: &crate::scenario::Scenario,
) -> Result<Statics, String> {
    let mut all = Statics::new();
    for t in trains {
        let axles = tbi_dynamics::hslm::hslm_a(t)?;
        let per_probe = first
            .probes
            .iter()
            .map(|p| {
                (
                    p.name.clone(),
                    static_displacement_max(bridge, &axles, p.x_m, 0.05),
                )
            })
            .collect();
        all.insert(t.clone(), per_probe);
    }
    Ok(all)
}

/// A case's row of the envelope from its summary.
fn row(
    case: &Case,
    point: Point,
    summary: &crate::output::summary::Summary,
    statics: &BTreeMap<String, f64>,
) -> Row {
    let max = |f: fn(&tbi_dynamics::response::ProbeMax) -> f64| {
        summary.probes.values().map(f).fold(0.0, f64::max)
    };
    let phi = summary
        .probes
        .iter()
        .filter_map(|(name, p)| {
            let st = statics.get(name).copied().unwrap_or(0.0);
            (st > 0.0).then(|| p.vertical_displacement_max_m / st - 1.0)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    Row {
        train: case.train.clone(),
        speed_kmh: case.speed_kmh,
        point,
        acceleration: max(|p| p.vertical_acceleration_max_m_s2),
        displacement: max(|p| p.vertical_displacement_max_m),
        static_displacement: statics.values().copied().fold(0.0, f64::max),
        phi,
        body: summary
            .vehicles
            .as_ref()
            .map(|v| v.vertical_acceleration_max_m_s2),
    }
}

/// The refinement of every train's peaks of the deck acceleration ([`refine`]), the peaks
/// in parallel.
fn refine_peaks(
    trains: &[String],
    rows: &[Row],
    evaluate: &(dyn Fn(&str, f64, Point) -> Result<Row, String> + Sync),
) -> Result<Vec<Row>, String> {
    let mut jobs = Vec::new();
    for t in trains {
        let mine: Vec<&Row> = rows.iter().filter(|r| &r.train == t).collect();
        let points: Vec<(f64, f64)> = mine.iter().map(|r| (r.speed_kmh, r.acceleration)).collect();
        let value = |v: f64| points.iter().find(|p| p.0 == v).map_or(f64::NAN, |p| p.1);
        for (a, c, b) in refine::peaks(&points) {
            jobs.push((t.clone(), (a, c, b), (value(a), value(c), value(b))));
        }
    }
    let found: Vec<Vec<Row>> = jobs
        .par_iter()
        .map(|(t, bracket, values)| {
            let mut new = Vec::new();
            refine::refine(*bracket, *values, |v| {
                let r = evaluate(t, v, Point::Refined)?;
                let a = r.acceleration;
                new.push(r);
                Ok::<f64, String>(a)
            })?;
            Ok(new)
        })
        .collect::<Result<_, String>>()?;
    Ok(found.into_iter().flatten().collect())
}

/// `envelope.csv`: one row per case; displacements in mm, accelerations in m/s²; the
/// last column names the checks a row governs (their `governing/<check>.toml`).
fn envelope_csv(rows: &[Row], governing: &[(Quantity, usize, PathBuf)]) -> String {
    let mut csv = String::from(
        "train,speed_kmh,point,deck_acceleration_max_m_s2,deck_displacement_max_mm,deck_static_displacement_max_mm,phi_dyn,car_body_acceleration_max_m_s2,governing\n",
    );
    for (i, r) in rows.iter().enumerate() {
        let body = r.body.map(|b| format!("{b:e}")).unwrap_or_default();
        let governs: Vec<&str> = governing
            .iter()
            .filter(|g| g.1 == i)
            .map(|g| g.0.name())
            .collect();
        let _ = writeln!(
            csv,
            "{},{},{},{:e},{:e},{:e},{:e},{body},{}",
            r.train,
            r.speed_kmh,
            r.point.as_str(),
            r.acceleration,
            1000.0 * r.displacement,
            1000.0 * r.static_displacement,
            r.phi,
            governs.join(";")
        );
    }
    csv
}

/// The index of the row with the largest `q`.
pub fn governing_row(rows: &[Row], q: Quantity) -> usize {
    (0..rows.len())
        .max_by(|&a, &b| q.of(&rows[a]).total_cmp(&q.of(&rows[b])))
        .expect("at least one case")
}

/// `governing/<quantity>.toml` for each quantity's governing case.
fn write_governing(
    source: &Source,
    rows: &[Row],
    quantities: &[Quantity],
    out: &Path,
) -> Result<Vec<(Quantity, usize, PathBuf)>, String> {
    let dir = out.join("governing");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut written = Vec::new();
    for &q in quantities {
        let i = governing_row(rows, q);
        let r = &rows[i];
        let case = Case {
            train: r.train.clone(),
            speed_kmh: r.speed_kmh,
        };
        let base: String = source.name.chars().take(70).collect();
        let name = format!("{base}-{}", q.name());
        let mut text = format!(
            "# The governing case of the {} check of `tbi sweep {} --trains`: {} at {} km/h.\n# `tbi run` of this file reproduces the value of envelope.csv.\n",
            q.name().replace('-', " "),
            source.origin,
            r.train,
            r.speed_kmh
        );
        text.push_str(&source.case_text(&case, Some(&name)));
        let path = dir.join(format!("{}.toml", q.name()));
        crate::output::outdir::write_atomically(&path, text.as_bytes())?;
        written.push((q, i, path));
    }
    Ok(written)
}

/// The folder of a case's full run.
pub fn case_dir(out: &Path, train: &str, speed_kmh: f64) -> PathBuf {
    out.join(train).join(format!("v{}", num(speed_kmh)))
}

/// The cases whose full runs are kept: each train's case of largest deck acceleration, the
/// governing case of each quantity (`--keep-histories`: every case), each once.
fn kept_cases(
    trains: &[String],
    rows: &[Row],
    governing: &[(Quantity, usize, PathBuf)],
    all: bool,
) -> Vec<usize> {
    let mut keep: Vec<usize> = if all {
        (0..rows.len()).collect()
    } else {
        trains
            .iter()
            .filter_map(|t| {
                (0..rows.len())
                    .filter(|&i| &rows[i].train == t)
                    .max_by(|&a, &b| rows[a].acceleration.total_cmp(&rows[b].acceleration))
            })
            .collect()
    };
    for (_, i, _) in governing {
        if !keep.contains(i) {
            keep.push(*i);
        }
    }
    keep
}

fn keep_runs(
    source: &Source,
    trains: &[String],
    rows: &[Row],
    governing: &[(Quantity, usize, PathBuf)],
    o: &Options,
    out: &Path,
) -> Result<(), String> {
    let keep = kept_cases(trains, rows, governing, o.keep_histories);
    keep.par_iter()
        .map(|&i| {
            let r = &rows[i];
            let case = Case {
                train: r.train.clone(),
                speed_kmh: r.speed_kmh,
            };
            let s = source.scenario(&case)?;
            crate::solve::run_scenario(&s, &case_dir(out, &r.train, r.speed_kmh), false, &o.limits)
                .map(|_| ())
                .map_err(|e| format!("{} at {} km/h: {e}", r.train, num(r.speed_kmh)))
        })
        .collect::<Result<Vec<()>, String>>()?;
    Ok(())
}

/// Bytes a full run of `s` writes: `history.csv` as [`crate::model::Model::estimate`]
/// gives it, the plots (about [`PLOT_BYTES_PER_ROW`] per history row and probe, capped as
/// the plots thin their points) and `summary.json`.
fn run_bytes(s: &crate::scenario::Scenario) -> Result<f64, String> {
    let model = crate::model::build(s).map_err(|e| e.to_string())?;
    let e = model.estimate();
    let rows = model.steps as f64 / model.output_every as f64 + 1.0;
    Ok(e.history_bytes + PLOT_BYTES_PER_ROW * rows * model.probes.len().max(1) as f64 + 20_000.0)
}

/// The plots' bytes per history row and probe (SVG path points).
const PLOT_BYTES_PER_ROW: f64 = 30.0;

/// Estimate the disk use of the check and refuse it past `tbi run`'s history limit.
fn estimate_disk(
    source: &Source,
    trains: &[String],
    grid: &[(String, f64, Point)],
    o: &Options,
    out: &Path,
) -> Result<f64, String> {
    // the mean bytes of a run over the train's speeds: a run's steps go as a + b / v (the
    // crossing, then the free vibration), fitted to the lowest and highest speeds
    let mut total = 0.0;
    let checks = 2.0 + f64::from(u8::from(o.comfort.is_some()));
    for t in trains {
        let mine: Vec<f64> = grid.iter().filter(|g| &g.0 == t).map(|g| g.1).collect();
        let (lo, hi) = (mine[0], mine[mine.len() - 1]);
        let bytes = |v: f64| {
            run_bytes(&source.scenario(&Case {
                train: t.clone(),
                speed_kmh: v,
            })?)
        };
        let (at_lo, at_hi) = (bytes(lo)?, bytes(hi)?);
        let mean = if hi > lo {
            let b = (at_lo - at_hi) / (1.0 / lo - 1.0 / hi);
            let a = at_hi - b / hi;
            mine.iter().map(|v| a + b / v).sum::<f64>() / mine.len() as f64
        } else {
            at_lo
        };
        let kept = if o.keep_histories {
            mine.len() as f64
        } else {
            1.0
        };
        total += kept * mean + 200.0 * mine.len() as f64;
        if !o.keep_histories {
            // the governing cases of the other checks, shared among the trains
            total += (checks - 1.0) * mean / trains.len() as f64;
        }
    }
    let limit = o.limits.max_history_bytes;
    if total > limit {
        return Err(format!(
            "{}: the check would write about {:.0} MiB ({} cases{}), more than the limit of {:.0} MiB; give --allow-large to run it anyway",
            out.display(),
            total / (1u64 << 20) as f64,
            grid.len(),
            if o.keep_histories { ", every history kept" } else { "" },
            limit / (1u64 << 20) as f64
        ));
    }
    Ok(total)
}

/// The largest static deck vertical displacement at `x_probe` of the moving forces `axles`
/// crossing the bridge (modal static response with the modes kept), over first-axle
/// positions every `dx` metres.
pub fn static_displacement_max(
    bridge: &tbi_dynamics::bridge::ModalBridge,
    axles: &[tbi_dynamics::vehicle::simple::MovingForceAxle],
    x_probe: f64,
    dx: f64,
) -> f64 {
    let n = bridge.n_modes();
    let omega2: Vec<f64> = bridge.omegas().iter().map(|w| w * w).collect();
    let mut probe = vec![[0.0; 3]; n];
    bridge.deck_shapes(x_probe, &mut probe);
    let mut psi = vec![[0.0; 3]; n];
    let length = axles.iter().map(|a| a.offset_m).fold(0.0, f64::max);
    let (start, end) = (bridge.x_start_m, bridge.x_end_m + length);
    let steps = ((end - start) / dx).ceil() as usize;
    let mut best = 0.0_f64;
    let mut force = vec![0.0; n];
    for k in 0..=steps {
        let head = start + k as f64 * dx;
        force.iter_mut().for_each(|f| *f = 0.0);
        for a in axles {
            if bridge.rail_shapes(head - a.offset_m, &mut psi) {
                for (f, p) in force.iter_mut().zip(&psi) {
                    *f += a.load_n * p[2];
                }
            }
        }
        let y: f64 = (0..n).map(|m| probe[m][1] * force[m] / omega2[m]).sum();
        best = best.max(y.abs());
    }
    best
}

/// A speed for people, km/h: whole numbers as they are, others to 0.01 km/h (the
/// governing scenario files keep every digit).
pub fn kmh(v: f64) -> String {
    if v.fract() == 0.0 {
        num(v)
    } else {
        format!("{v:.2}")
    }
}

/// One check's verdict, for the summary and the report.
pub struct Verdict {
    pub name: String,
    pub clause: &'static str,
    pub passed: bool,
    /// Value and limit, with units.
    pub value: String,
    pub limit: String,
    /// Where it governs, and how to reproduce it.
    pub governing: String,
    pub command: Option<String>,
}

/// The checks of an outcome.
pub fn checks(outcome: &Outcome, o: &Options) -> Vec<Verdict> {
    let rows = &outcome.rows;
    let mut v = Vec::new();
    let reproduce = |q: Quantity| {
        outcome
            .governing
            .iter()
            .find(|g| g.0 == q)
            .map(|g| format!("tbi run {}", g.2.display()))
    };
    let at = |i: usize| format!("{} at {} km/h", rows[i].train, kmh(rows[i].speed_kmh));
    let a = governing_row(rows, Quantity::DeckAcceleration);
    v.push(Verdict {
        name: format!("deck vertical acceleration ({})", o.track),
        clause: "EN 1990 A2.4.4.2.1",
        passed: rows[a].acceleration <= o.limit_m_s2,
        value: format!("{:.3} m/s²", rows[a].acceleration),
        limit: format!("{} m/s²", o.limit_m_s2),
        governing: at(a),
        command: reproduce(Quantity::DeckAcceleration),
    });
    let f = &outcome.bridge.frequencies_hz;
    let (_, needed) = tbi_dynamics::en1991::modes_considered(f);
    let kept = f.iter().copied().fold(0.0, f64::max);
    v.push(Verdict {
        name: "modes considered up to max(30 Hz, 1.5 f₁, f₃)".into(),
        clause: "EN 1990 A2.4.4.2.1",
        passed: kept >= needed,
        value: format!("{} modes up to {kept:.1} Hz", f.len()),
        limit: format!("{needed:.1} Hz"),
        governing: if kept >= needed {
            "the modes reach the frequency".into()
        } else {
            "raise bridge.modes".into()
        },
        command: None,
    });
    if let Some((limit, level)) = &o.comfort {
        let b = governing_row(rows, Quantity::CarBodyAcceleration);
        v.push(Verdict {
            name: format!("car-body vertical acceleration ({level} comfort)"),
            clause: "EN 1990 A2.4.4.3.2, Table A2.9",
            passed: rows[b].body.unwrap_or(0.0) <= *limit,
            value: format!("{:.3} m/s²", rows[b].body.unwrap_or(0.0)),
            limit: format!("{limit} m/s²"),
            governing: at(b),
            command: reproduce(Quantity::CarBodyAcceleration),
        });
    }
    if let Some(c) = &outcome.en {
        v.extend(c.verdicts());
    }
    v
}

/// The lines printed at the end of a check (and `summary.txt`).
fn summary_text(source: &Source, outcome: &Outcome, o: &Options, out: &Path) -> String {
    let rows = &outcome.rows;
    let mut t = String::new();
    let f = &outcome.bridge.frequencies_hz;
    let _ = writeln!(
        t,
        "{}: {} modes kept, up to {:.1} Hz (f₁ = {:.3} Hz); {} cases: {} on the grid with the resonance speeds, {} refining the peaks",
        source.name,
        f.len(),
        f.iter().copied().fold(0.0, f64::max),
        f[0],
        rows.len(),
        outcome.grid_runs,
        outcome.refined_runs
    );
    let d = governing_row(rows, Quantity::DeckDisplacement);
    let _ = writeln!(
        t,
        "deck vertical displacement: largest {:.3} mm ({} at {} km/h)",
        1000.0 * rows[d].displacement,
        rows[d].train,
        kmh(rows[d].speed_kmh)
    );
    let p = (0..rows.len())
        .max_by(|&a, &b| rows[a].phi.total_cmp(&rows[b].phi))
        .expect("a case");
    let _ = writeln!(
        t,
        "dynamic enhancement φ'dyn: largest {:.3} ({} at {} km/h)",
        rows[p].phi,
        rows[p].train,
        kmh(rows[p].speed_kmh)
    );
    for c in checks(outcome, o) {
        let _ = writeln!(
            t,
            "{}: {}: {} (limit {}, {}; {}){}",
            if c.passed { "PASS" } else { "FAIL" },
            c.name,
            c.value,
            c.limit,
            c.clause,
            c.governing,
            c.command
                .map(|cmd| format!("; reproduce: {cmd}"))
                .unwrap_or_default()
        );
    }
    if let Some(c) = &outcome.en {
        for line in c.lines() {
            let _ = writeln!(t, "{line}");
        }
    }
    let _ = write!(
        t,
        "files: {} (about {:.1} MiB estimated before the run)",
        out.display(),
        outcome.estimated_bytes / (1u64 << 20) as f64
    );
    t
}
