//! `tbi bench`: speed measurements, reported as ratios measured in one run.
//!
//! 1. Monolithic solver: 8 `xia2000` coaches over a 2000 m, 20-mode modal bridge (simply
//!    supported, vertical, lateral and torsional modes, track off the shear centre) at
//!    70 km/h with dt = 0.005 s: wall time, steps per second, simulated/wall time.
//! 2. The same case by implicit co-simulation of the two FMUs: wall time over the
//!    monolithic wall time.
//! 3. The Tsing Ma finite-element model: assembly plus the lowest 50 modes.
//! 4. The four-speed sweep of the embedded Tsing Ma case (20, 40, 70, 120 km/h).

use crate::run::run_scenario;
use crate::scenario::Scenario;
use crate::summary::Summary;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Command-line arguments of `tbi bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Scratch folder for the runs.
    #[arg(long, default_value = "tbi-out/bench")]
    pub out: PathBuf,
    /// Skip the Tsing Ma parts (FE modes and the four-speed sweep).
    #[arg(long)]
    pub quick: bool,
}

/// The benchmark scenario (see the module docs).
pub const BENCH_SCENARIO: &str = r#"
name = "bench-2000m"
[run]
speed_kmh = 70.0
dt_s = 0.005
solver = "monolithic"
free_vibration_s = 0.0
output_every = 1000000
[bridge]
kind = "simply_supported"
span_m = 2000.0
youngs_modulus_pa = 2.1e11
inertia_vertical_m4 = 50.0
inertia_lateral_m4 = 500.0
shear_modulus_pa = 8.1e10
torsion_constant_m4 = 20.0
polar_inertia_kg_m = 5.0e6
mass_per_length_kg_m = 3.0e4
modes = 20
damping_ratio = 0.01
damping_ratio_torsional = 0.005
track_eccentricity_m = 2.05
track_height_m = 1.25
[train]
kind = "coach_27dof"
preset = "xia2000"
vehicles = 8
[track]
irregularity = { spectrum = "chinese-main-line", seed = 1, lambda_min_m = 2.0, lambda_max_m = 80.0 }
[[probe]]
name = "mid"
x_m = 1000.0
[coupling]
scheme = "implicit"
acceleration = "iqn-ils"
relaxation = 1.0
reuse_steps = 2
atol = 1e-8
"#;

fn timed(s: &Scenario, out: &Path) -> Result<(f64, Summary), Box<dyn std::error::Error>> {
    let t = Instant::now();
    let summary = run_scenario(s, out, false, &crate::model::Limits::default())?;
    Ok((t.elapsed().as_secs_f64(), summary))
}

pub fn main(args: BenchArgs) -> Result<(), Box<dyn std::error::Error>> {
    let mut s = Scenario::from_toml(BENCH_SCENARIO, "<bench scenario>", Path::new("."))?;
    let sim_time = crate::model::build(&s)?.t_end();
    let (mono_wall, mono) = timed(&s, &args.out.join("monolithic"))?;
    let steps = mono.steps as f64;
    println!("monolithic: 8 coaches, 2000 m bridge, 20 modes, 70 km/h, dt 0.005 s");
    println!(
        "  steps {steps}, wall {mono_wall:.3} s, {:.0} steps/s, simulated/wall = {:.0}",
        steps / mono_wall,
        sim_time / mono_wall
    );
    s.run.solver = crate::scenario::SolverKind::Cosim;
    let (co_wall, co) = timed(&s, &args.out.join("cosim"))?;
    let coupling = co
        .coupling
        .ok_or("the co-simulation run reported no coupling")?;
    println!(
        "co-simulation ({}, {}): wall {co_wall:.3} s, {:.2} iterations/step, cosim/monolithic wall = {:.2}",
        coupling.scheme,
        coupling.acceleration,
        coupling.iterations_mean,
        co_wall / mono_wall
    );
    if args.quick {
        return Ok(());
    }
    let t = Instant::now();
    let params = crate::suspension::preset_params(crate::scenario::SuspensionPreset::TsingMa);
    let fe = tbi_fe::FeModel::build(&params).map_err(|e| e.to_string())?;
    let assembled = t.elapsed().as_secs_f64();
    fe.modes(50).map_err(|e| e.to_string())?;
    let fe_total = t.elapsed().as_secs_f64();
    println!("Tsing Ma FE model: assembly {assembled:.3} s, assembly + 50 modes {fe_total:.2} s");
    let t = Instant::now();
    crate::sweep::main(crate::sweep::SweepArgs {
        scenario: None,
        speeds: vec![20.0, 40.0, 70.0, 120.0],
        solver: None,
        out: args.out.join("sweep"),
        allow_large: false,
    })?;
    println!(
        "Tsing Ma four-speed sweep (co-simulation, in parallel): {:.1} s",
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
