//! `tbi bench`: speed measurements, reported as ratios measured in one run.
//!
//! 1. Monolithic solver: 8 `xia2000` coaches over a 2000 m, 20-mode modal bridge (simply
//!    supported, vertical, lateral and torsional modes, track off the shear centre) at
//!    70 km/h with dt = 0.005 s: wall time, steps per second, simulated/wall time.
//! 2. The same case by implicit co-simulation of the two FMUs: wall time over the
//!    monolithic wall time; then its exported system as `tbi cosim` runs it, each FMU in
//!    a worker process against both in process (alternating, the fastest of each): the
//!    wall-time ratio, the round trips per step and the cost of each.
//! 3. The scale case: the Tsing Ma finite-element model's lowest 200 modes under 32 coaches
//!    (128 wheelsets) at 70 km/h with dt = 0.005 s, the track and coupling of the bench case,
//!    both solvers, simulated/wall time (the modes computed before the clock starts; item 5
//!    measures the eigen-solution).
//! 4. Cost growth: seconds of wall time per simulated second for modes 20/50/100/200 ×
//!    coaches 1/8/32, both solvers (the bench case at 300 km/h, so each run is short).
//! 5. The Tsing Ma finite-element model: assembly plus the lowest 50 modes.
//! 6. The four-speed sweep of the embedded Tsing Ma case (20, 40, 70, 120 km/h).
//! 7. The design check of a 20 m span: the ten HSLM-A trains from 140 to 420 km/h in
//!    2.5 km/h steps (1130 grid runs, moving forces, modes to 57 Hz) with the default
//!    outputs, the resonance speeds and the refinement of the peaks: wall time, runs per
//!    second, the runs of each kind and the bytes written.
//! 8. The Tsing Ma meeting case (`tbi run --meeting`, two 8-coach trains, 64 wheelsets)
//!    against the default case (one train, 32), both solvers: wall time per simulated
//!    second, meeting over one train, and the co-simulations' sweeps per step.
//!
//! The bench case (1 and 2) is run `--repeat` times (default 3), the two solvers alternating,
//! and each solver's figures come from its fastest run: on a shared machine the least
//! disturbed run is the closest to the cost itself, and alternating exposes both solvers to
//! the same load. Every wall time is printed and written (`monolithic_walls_s`,
//! `cosim_walls_s`), and for each monolithic run the share of its steps whose geometry a
//! second core made ahead (`monolithic_steps_ahead_fraction`; `tbi run` times both ways as
//! it goes and keeps the faster, see `run::AheadChoice`).
//!
//! `--quick` runs 1 and 2 only. `--json FILE` writes every figure measured under the stable
//! names `monolithic_realtime_factor`, `cosim_realtime_factor`, `cosim_over_monolithic`,
//! `isolated_over_in_process`, `isolated_round_trips_per_step`, `isolated_round_trip_us`,
//! `cosim_iterations_per_step`, `cosim_steps_by_iterations` (entry k: the bench case's steps
//! that took k + 1 sweeps), `scale_monolithic_realtime_factor`,
//! `scale_cosim_realtime_factor`, `growth` (rows of modes, coaches, solver, wall seconds
//! per simulated second), `fe_modes_50_s`, `tsing_ma_wind_over_still_air`,
//! `meeting_monolithic_over_one_train`, `meeting_cosim_over_one_train`,
//! `one_train_cosim_iterations_per_step`, `meeting_cosim_iterations_per_step`,
//! `sweep_tsing_ma_4_speeds_s`, `hslm_sweep_s`, `hslm_runs_per_s`, `hslm_grid_runs`,
//! `hslm_resonance_runs`, `hslm_refined_runs`, `hslm_bytes_written`, and with them the conditions: `load_average_before` and
//! `load_average_after` (the one-minute load average at the start and at the end, where the
//! system reports one; `null` elsewhere) and `cores` (the cores the process may use).

use crate::design::SweepOptions;
use crate::output::summary::Summary;
use crate::scenario::Scenario;
use crate::solve::run_scenario;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Command-line arguments of `tbi bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Scratch folder for the runs.
    #[arg(long, default_value = "tbi-out/bench")]
    pub out: PathBuf,
    /// Only the bench case (skip the scale case, the growth table and the Tsing Ma parts).
    #[arg(long)]
    pub quick: bool,
    /// Also write every figure as JSON (stable names, see `tbi bench` docs).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Runs of the bench case per solver, alternating; the fastest of each counts.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=20))]
    pub repeat: u32,
}

/// A scenario of the bench's kind: `name`, the `[bridge]` table's own lines, the number of
/// coaches and the probe's position; the run, the bridge's damping and track position, the
/// coaches, the track and the coupling are the bench case's.
macro_rules! bench_like {
    ($name:literal, $bridge:literal, $vehicles:literal, $probe_x_m:literal) => {
        concat!(
            "name = \"",
            $name,
            r#""
[run]
speed_kmh = 70.0
dt_s = 0.005
solver = "monolithic"
free_vibration_s = 0.0
output_every = 1000000
[bridge]
"#,
            $bridge,
            r#"damping_ratio = 0.01
damping_ratio_torsional = 0.005
track_eccentricity_m = 2.05
track_height_m = 1.25
[train]
kind = "coach_27dof"
preset = "xia2000"
vehicles = "#,
            $vehicles,
            r#"
[[probe]]
name = "mid"
x_m = "#,
            $probe_x_m,
            r#"
[track]
irregularity = { spectrum = "chinese-main-line", seed = 1, lambda_min_m = 2.0, lambda_max_m = 80.0 }
[coupling]
scheme = "implicit"
acceleration = "iqn-ils"
relaxation = 1.0
reuse_steps = 8
atol = 1e-8
"#
        )
    };
}

/// The benchmark scenario (see the module docs).
pub const BENCH_SCENARIO: &str = bench_like!(
    "bench-2000m",
    r#"kind = "simply_supported"
span_m = 2000.0
youngs_modulus_pa = 2.1e11
inertia_vertical_m4 = 50.0
inertia_lateral_m4 = 500.0
shear_modulus_pa = 8.1e10
torsion_constant_m4 = 20.0
polar_inertia_kg_m = 5.0e6
mass_per_length_kg_m = 3.0e4
modes = 20
"#,
    "8",
    "1000.0"
);

/// The scale case (item 3 of the module docs): the bench case's run, track and coupling.
pub const SCALE_SCENARIO: &str = bench_like!(
    "scale-tsing-ma-200",
    r#"kind = "suspension"
preset = "tsing-ma"
modes = 200
"#,
    "32",
    "1141.0"
);

fn timed(s: &Scenario, out: &Path) -> Result<(f64, Summary), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let summary = run_scenario(s, out, false, &crate::model::Limits::default())?;
    Ok((t.elapsed().as_secs_f64(), summary))
}

/// The bench scenario with `modes` modes, `coaches` coaches at `speed_kmh`.
fn variant(
    modes: usize,
    coaches: usize,
    speed_kmh: f64,
) -> Result<Scenario, Box<dyn std::error::Error>> {
    let text = BENCH_SCENARIO
        .replace("modes = 20", &format!("modes = {modes}"))
        .replace("vehicles = 8", &format!("vehicles = {coaches}"))
        .replace("speed_kmh = 70.0", &format!("speed_kmh = {speed_kmh:?}"));
    Ok(Scenario::from_toml(
        &text,
        "<bench scenario>",
        Path::new("."),
    )?)
}

/// Wall seconds and simulated seconds of `s` with `solver`.
fn measure(
    s: &Scenario,
    solver: crate::scenario::SolverKind,
    out: &Path,
) -> Result<(f64, f64, Summary), Box<dyn std::error::Error>> {
    let mut s = s.clone();
    s.run.solver = solver;
    let sim = crate::model::build(&s)?.t_end();
    let (wall, summary) = timed(&s, out)?;
    Ok((wall, sim, summary))
}

/// The figures `--json` writes, by name.
type Figures = serde_json::Map<String, serde_json::Value>;

pub fn main(args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    let load_before = load_average();
    let mut figures = serde_json::Map::new();
    default_case(&args, &mut figures)?;
    isolated_case(&args, &mut figures)?;
    if args.quick {
        return write_figures(&args, figures, load_before);
    }
    scale_and_growth(&args, &mut figures)?;
    tsing_ma_fe_and_wind(&args, &mut figures)?;
    meeting_case(&args, &mut figures)?;
    design_checks(&args, &mut figures)?;
    write_figures(&args, figures, load_before)
}

/// The bench case, monolithic against co-simulation, `args.repeat` times alternating.
fn default_case(args: &BenchArgs, figures: &mut Figures) -> Result<(), Box<dyn std::error::Error>> {
    let s = Scenario::from_toml(BENCH_SCENARIO, "<bench scenario>", Path::new("."))?;
    let sim_time = crate::model::build(&s)?.t_end();
    let mut cosim = s.clone();
    cosim.run.solver = crate::scenario::SolverKind::Cosim;
    let (mut mono_walls, mut co_walls) = (Vec::new(), Vec::new());
    let mut mono_ahead = Vec::new();
    let (mut mono, mut co) = (None, None);
    for _ in 0..args.repeat {
        let (wall, summary) = timed(&s, &args.out.join("monolithic"))?;
        mono_walls.push(wall);
        let ahead = summary.steps_ahead.unwrap_or(0) as f64 / summary.steps.max(1) as f64;
        mono_ahead.push(ahead);
        mono = Some(summary);
        let (wall, summary) = timed(&cosim, &args.out.join("cosim"))?;
        co_walls.push(wall);
        co = Some(summary);
    }
    let (mono, co) = (mono.expect("repeat ≥ 1"), co.expect("repeat ≥ 1"));
    let fastest = |walls: &[f64]| walls.iter().copied().fold(f64::INFINITY, f64::min);
    let list = |walls: &[f64]| {
        let w: Vec<String> = walls.iter().map(|w| format!("{w:.3}")).collect();
        w.join(", ")
    };
    let (mono_wall, co_wall) = (fastest(&mono_walls), fastest(&co_walls));
    figures.insert(
        "monolithic_realtime_factor".into(),
        (sim_time / mono_wall).into(),
    );
    figures.insert("monolithic_walls_s".into(), mono_walls.clone().into());
    figures.insert("cosim_walls_s".into(), co_walls.clone().into());
    figures.insert(
        "monolithic_steps_ahead_fraction".into(),
        mono_ahead.clone().into(),
    );
    let steps = mono.steps as f64;
    crate::say!(
        "monolithic: 8 coaches, 2000 m bridge, 20 modes, 70 km/h, dt 0.005 s (fastest of {} runs, alternating with the co-simulation)",
        args.repeat
    );
    crate::say!(
        "  steps {steps}, wall {mono_wall:.3} s ({} s), {:.0} steps/s, simulated/wall = {:.0}",
        list(&mono_walls),
        steps / mono_wall,
        sim_time / mono_wall
    );
    let shares: Vec<String> = mono_ahead
        .iter()
        .map(|a| format!("{:.0} %", 100.0 * a))
        .collect();
    crate::say!(
        "  steps with the geometry made ahead on a second core: {}",
        shares.join(", ")
    );
    let coupling = co
        .coupling
        .ok_or("the co-simulation run reported no coupling")?;
    crate::say!(
        "co-simulation ({}, {}): wall {co_wall:.3} s ({} s), {:.2} iterations/step, cosim/monolithic wall = {:.2}",
        coupling.scheme,
        coupling.acceleration,
        list(&co_walls),
        coupling.iterations_mean,
        co_wall / mono_wall
    );
    figures.insert("cosim_realtime_factor".into(), (sim_time / co_wall).into());
    figures.insert("cosim_over_monolithic".into(), (co_wall / mono_wall).into());
    figures.insert(
        "cosim_iterations_per_step".into(),
        coupling.iterations_mean.into(),
    );
    let by = &coupling.steps_by_iterations;
    let shares: Vec<String> = (by.iter().enumerate())
        .filter(|(_, &n)| n > 0)
        .map(|(k, &n)| {
            format!(
                "{}: {:.1} %",
                k + 1,
                100.0 * n as f64 / coupling.steps as f64
            )
        })
        .collect();
    crate::say!("  steps by their sweeps: {}", shares.join(", "));
    figures.insert(
        "cosim_steps_by_iterations".into(),
        serde_json::to_value(by)?,
    );
    Ok(())
}

/// The bench case's exported system as `tbi cosim` runs it (wiring included), each FMU in
/// a worker process against both in process, `args.repeat` times alternating.
fn isolated_case(
    args: &BenchArgs,
    figures: &mut Figures,
) -> Result<(), Box<dyn std::error::Error>> {
    use crate::solve::system::step_and_record;
    use fmi_import::remote::{round_trips, WorkerOptions};
    let s = Scenario::from_toml(BENCH_SCENARIO, "<bench scenario>", Path::new("."))?;
    let model = crate::model::build(&s)?;
    let dir = args.out.join("isolated");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let exported =
        crate::fmus::export::export_with(&model, &s.coupling, &dir, true, Default::default())?;
    let open = tbi_ssp::open_exported(&exported.ssd, &exported.ssp)?;
    let (t_end, steps) = (model.t_end(), model.steps);
    let times = (0.0, t_end, model.dt, steps, steps);
    let workers = super::workers::options(false, None)?;
    let run =
        |isolation: Option<&WorkerOptions>| -> Result<(f64, u64), Box<dyn std::error::Error>> {
            let (trips, started) = (round_trips(), Instant::now());
            let mut wired = tbi_ssp::wire_with(&open, &[], 0.0, t_end, isolation)?;
            let mut csv = crate::output::outdir::NamedFile::create(&dir.join("last_row.csv"))?;
            step_and_record(&mut wired.system, &[], &s.coupling, times, &mut csv, true)?;
            drop(wired);
            Ok((started.elapsed().as_secs_f64(), round_trips() - trips))
        };
    let (mut here, mut isolated, mut trips) = (Vec::new(), Vec::new(), 0);
    for _ in 0..args.repeat {
        here.push(run(None)?.0);
        let (wall, n) = run(workers.as_ref())?;
        isolated.push(wall);
        trips = n;
    }
    let fastest = |walls: &[f64]| walls.iter().copied().fold(f64::INFINITY, f64::min);
    let (here, isolated) = (fastest(&here), fastest(&isolated));
    let per_step = trips as f64 / steps as f64;
    let cost_us = 1e6 * (isolated - here).max(0.0) / trips.max(1) as f64;
    crate::say!(
        "isolated FMUs (tbi cosim's default) against in process: wall {isolated:.3} s against {here:.3} s = {:.2}, {per_step:.2} round trips per step, {cost_us:.1} µs each",
        isolated / here
    );
    figures.insert("isolated_over_in_process".into(), (isolated / here).into());
    figures.insert("isolated_round_trips_per_step".into(), per_step.into());
    figures.insert("isolated_round_trip_us".into(), cost_us.into());
    Ok(())
}

/// The scale case and the cost growth with modes and coaches.
fn scale_and_growth(
    args: &BenchArgs,
    figures: &mut Figures,
) -> Result<(), Box<dyn std::error::Error>> {
    use crate::scenario::SolverKind::{Cosim, Monolithic};
    let scale = Scenario::from_toml(SCALE_SCENARIO, "<scale scenario>", Path::new("."))?;
    let (mw, ms, _) = measure(&scale, Monolithic, &args.out.join("scale-monolithic"))?;
    let (cw, cs, _) = measure(&scale, Cosim, &args.out.join("scale-cosim"))?;
    crate::say!(
        "scale case (Tsing Ma, 200 modes, 32 coaches = 128 wheelsets): simulated/wall monolithic {:.1}, co-simulation {:.1}",
        ms / mw,
        cs / cw
    );
    figures.insert("scale_monolithic_realtime_factor".into(), (ms / mw).into());
    figures.insert("scale_cosim_realtime_factor".into(), (cs / cw).into());
    crate::say!("cost growth at 300 km/h, wall s per simulated s:");
    crate::say!("  modes  coaches  monolithic  co-simulation");
    let mut growth = Vec::new();
    for modes in [20, 50, 100, 200] {
        for coaches in [1, 8, 32] {
            let v = variant(modes, coaches, 300.0)?;
            let dir = args.out.join(format!("growth-{modes}-{coaches}"));
            let (mw, ms, _) = measure(&v, Monolithic, &dir.join("monolithic"))?;
            let (cw, cs, _) = measure(&v, Cosim, &dir.join("cosim"))?;
            crate::say!(
                "  {modes:>5}  {coaches:>7}  {:>10.4}  {:>13.4}",
                mw / ms,
                cw / cs
            );
            for (solver, per) in [("monolithic", mw / ms), ("cosim", cw / cs)] {
                growth.push(serde_json::json!({
                    "modes": modes,
                    "coaches": coaches,
                    "solver": solver,
                    "wall_s_per_simulated_s": per,
                }));
            }
        }
    }
    figures.insert("growth".into(), growth.into());
    Ok(())
}

/// The Tsing Ma FE model's assembly and modes, and the default case with and without wind.
fn tsing_ma_fe_and_wind(
    args: &BenchArgs,
    figures: &mut Figures,
) -> Result<(), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let params =
        crate::model::suspension::preset_params(crate::scenario::SuspensionPreset::TsingMa);
    let fe = tbi_fe::FeModel::build(&params).map_err(|e| e.to_string())?;
    let assembled = t.elapsed().as_secs_f64();
    fe.modes(50).map_err(|e| e.to_string())?;
    let fe_total = t.elapsed().as_secs_f64();
    crate::say!(
        "Tsing Ma FE model: assembly {assembled:.3} s, assembly + 50 modes {fe_total:.2} s"
    );
    figures.insert("fe_modes_50_s".into(), fe_total.into());
    // the default case with and without a turbulent 20 m/s wind (200 deck points), monolithic
    let mut still = Scenario::default_case();
    still.run.solver = crate::scenario::SolverKind::Monolithic;
    let mut windy = still.clone();
    windy.set_wind_speed(20.0)?;
    if let Some(w) = windy.wind.as_mut() {
        w.turbulence = Some(Default::default());
    }
    // both from the FE modes cached in the process (else the first run alone would pay
    // the eigen-solution)
    crate::model::build(&still)?;
    let (still_wall, _) = timed(&still, &args.out.join("tsing-ma-still"))?;
    let (windy_wall, _) = timed(&windy, &args.out.join("tsing-ma-wind"))?;
    crate::say!(
        "Tsing Ma case, monolithic: still air {still_wall:.2} s, turbulent 20 m/s wind (200 deck points, field generated in the run) {windy_wall:.2} s, ratio {:.2}",
        windy_wall / still_wall
    );
    figures.insert(
        "tsing_ma_wind_over_still_air".into(),
        (windy_wall / still_wall).into(),
    );
    Ok(())
}

/// The Tsing Ma meeting case (two 8-coach trains, `tbi run --meeting`) against the default
/// case (one train), both solvers: the cost per simulated second, meeting over one train,
/// and the sweeps per step of each co-simulation.
fn meeting_case(args: &BenchArgs, figures: &mut Figures) -> Result<(), Box<dyn std::error::Error>> {
    use crate::scenario::SolverKind;
    let (one, two) = (Scenario::default_case(), Scenario::meeting_case());
    // the FE modes cached in the process before any clock starts
    crate::model::build(&one)?;
    for solver in [SolverKind::Monolithic, SolverKind::Cosim] {
        let name = solver.as_str();
        let (w1, s1, r1) = measure(&one, solver, &args.out.join(format!("one-{name}")))?;
        let (w2, s2, r2) = measure(&two, solver, &args.out.join(format!("meeting-{name}")))?;
        let ratio = (w2 / s2) / (w1 / s1);
        crate::say!(
            "Tsing Ma, {name}: one train {:.3} s wall per simulated s, two trains meeting {:.3} (ratio {ratio:.2}; wheelsets 64 against 32)",
            w1 / s1,
            w2 / s2
        );
        figures.insert(format!("meeting_{name}_over_one_train"), ratio.into());
        if let (Some(c1), Some(c2)) = (r1.coupling, r2.coupling) {
            crate::say!(
                "  sweeps per step: one train {:.2}, two trains {:.2}",
                c1.iterations_mean,
                c2.iterations_mean
            );
            figures.insert(
                "one_train_cosim_iterations_per_step".into(),
                c1.iterations_mean.into(),
            );
            figures.insert(
                "meeting_cosim_iterations_per_step".into(),
                c2.iterations_mean.into(),
            );
        }
    }
    Ok(())
}

/// The four-speed Tsing Ma sweep and the HSLM-A check of a 20 m span.
fn design_checks(
    args: &BenchArgs,
    figures: &mut Figures,
) -> Result<(), Box<dyn std::error::Error>> {
    let t = Instant::now();
    crate::design::run(&SweepOptions {
        speeds: ["20", "40", "70", "120"].map(String::from).to_vec(),
        out: args.out.join("sweep"),
        ..SweepOptions::default()
    })?;
    let sweep = t.elapsed().as_secs_f64();
    crate::say!("Tsing Ma four-speed sweep (co-simulation, in parallel): {sweep:.1} s");
    figures.insert("sweep_tsing_ma_4_speeds_s".into(), sweep.into());
    std::fs::create_dir_all(&args.out)?;
    let span = args.out.join("hslm-20m.toml");
    std::fs::write(&span, HSLM_SPAN)?;
    let t = Instant::now();
    crate::design::run(&SweepOptions {
        scenario: Some(span),
        speeds: vec!["140:420:2.5".into()],
        trains: vec!["hslm-a".into()],
        out: args.out.join("hslm"),
        ..SweepOptions::default()
    })?;
    let hslm = t.elapsed().as_secs_f64();
    // the check's verdicts are the span's, not the bench's: they set no exit code here
    crate::output::console::clear_check_failed();
    let envelope = std::fs::read_to_string(args.out.join("hslm/envelope.csv"))?;
    let count = |point: &str| {
        envelope
            .lines()
            .filter(|l| l.split(',').nth(2) == Some(point))
            .count()
    };
    let (grid, resonance, refined) = (count("grid"), count("resonance"), count("refined"));
    let runs = grid + resonance + refined;
    crate::say!(
        "HSLM-A design check of a 20 m span (10 trains × 113 speeds = {grid} grid runs, {resonance} at resonance speeds, {refined} refining peaks; default outputs): {hslm:.1} s, {:.0} runs/s",
        runs as f64 / hslm
    );
    figures.insert("hslm_sweep_s".into(), hslm.into());
    figures.insert("hslm_runs_per_s".into(), (runs as f64 / hslm).into());
    figures.insert("hslm_grid_runs".into(), grid.into());
    figures.insert("hslm_resonance_runs".into(), resonance.into());
    figures.insert("hslm_refined_runs".into(), refined.into());
    figures.insert(
        "hslm_bytes_written".into(),
        dir_bytes(&args.out.join("hslm")).into(),
    );
    Ok(())
}

/// A 20 m simply supported concrete span (f₁ = 6.4 Hz, three modes to 57 Hz) for the HSLM
/// design check of the bench.
const HSLM_SPAN: &str = r#"name = "span-20m"
[run]
speed_kmh = 300.0
dt_s = 0.001
solver = "monolithic"
free_vibration_s = 0.0
output_every = 1
[bridge]
kind = "simply_supported"
span_m = 20.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 0.9
mass_per_length_kg_m = 12000.0
modes = 3
damping = { rule = "en1991-2", structure = "prestressed_concrete" }
[train]
kind = "hslm_a"
name = "A1"
[track]
irregularity = "none"
[[probe]]
name = "mid"
x_m = 10.0
"#;

/// Bytes of the files below `dir`.
fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| match e.metadata() {
            Ok(m) if m.is_dir() => dir_bytes(&e.path()),
            Ok(m) => m.len(),
            Err(_) => 0,
        })
        .sum()
}

/// The one-minute load average, where the system reports one (`/proc/loadavg`).
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|text| parse_load_average(&text))
}

/// The first field of `/proc/loadavg` (`"1.14 1.68 1.50 2/345 12345"`), if it is a number.
fn parse_load_average(text: &str) -> Option<f64> {
    text.split_whitespace()
        .next()?
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && *v >= 0.0)
}

/// Prints the conditions of the run (load average before and after, cores) and writes
/// every figure with them to `--json`.
fn write_figures(
    args: &BenchArgs,
    mut figures: serde_json::Map<String, serde_json::Value>,
    load_before: Option<f64>,
) -> Result<(), Box<dyn std::error::Error>> {
    let load_after = load_average();
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let shown = |l: Option<f64>| l.map_or("unknown".to_owned(), |v| format!("{v:.2}"));
    crate::say!(
        "load average (1 min): {} before, {} after; {cores} cores",
        shown(load_before),
        shown(load_after)
    );
    figures.insert("load_average_before".into(), load_before.into());
    figures.insert("load_average_after".into(), load_after.into());
    figures.insert("cores".into(), cores.into());
    if let Some(path) = &args.json {
        crate::output::outdir::write_atomically(
            path,
            serde_json::to_string_pretty(&serde_json::Value::Object(figures))?.as_bytes(),
        )?;
        crate::say!("figures in {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The load average is the first field of `/proc/loadavg`; anything else is none.
    #[test]
    fn the_load_average_is_the_first_field() {
        assert_eq!(
            parse_load_average("1.14 1.68 1.50 2/345 12345\n"),
            Some(1.14)
        );
        assert_eq!(parse_load_average("0.00 0.01 0.05 1/80 7"), Some(0.0));
        assert_eq!(parse_load_average(""), None);
        assert_eq!(parse_load_average("busy 1.0"), None);
        assert_eq!(parse_load_average("-1 0 0"), None);
        assert_eq!(parse_load_average("NaN 0 0"), None);
    }

    /// The embedded scenarios are valid: a mistake in one would otherwise surface only in a
    /// bench run.
    #[test]
    fn the_bench_scenarios_are_valid() {
        for (name, text) in [
            ("bench", BENCH_SCENARIO),
            ("scale", SCALE_SCENARIO),
            ("hslm", HSLM_SPAN),
        ] {
            if let Err(e) = Scenario::from_toml(text, name, Path::new(".")) {
                panic!("{name}: {e}");
            }
        }
    }
}
