//! Quick timing of the monolithic solver on the benchmark case (see `tbi bench`).
use std::sync::Arc;
use std::time::Instant;
use tbi_dynamics::bridge::SimplySupported;
use tbi_dynamics::solver::Monolithic;
use tbi_dynamics::train::{Train, TrainVehicle};
use tbi_dynamics::vehicle::coach::CoachParams;

fn main() {
    let bridge = SimplySupported {
        span_m: 2000.0,
        youngs_modulus_pa: 2.1e11,
        inertia_vertical_m4: 50.0,
        inertia_lateral_m4: Some(500.0),
        shear_modulus_pa: Some(8.1e10),
        torsion_constant_m4: Some(20.0),
        polar_inertia_kg_m: Some(5.0e6),
        mass_per_length_kg_m: 3.0e4,
        modes: 20,
        damping_ratio: 0.01,
        damping_ratio_torsional: 0.005,
        e_m: 2.05,
        h4_m: 1.25,
        x_start_m: 0.0,
    }
    .modal();
    let p = CoachParams::xia2000();
    let c = Arc::new(p.build().unwrap());
    let vehicles: Vec<TrainVehicle> = (0..8)
        .map(|k| TrainVehicle {
            model: c.clone(),
            offset_m: k as f64 * p.length_m,
        })
        .collect();
    let train = Train {
        vehicles,
        speed_m_s: 70.0 / 3.6,
        x0_m: 0.0,
        hunting: tbi_track::WheelHunting::new(&Default::default(), 32).unwrap(),
    };
    let dt = 0.005;
    let mut sol = Monolithic::new(bridge, train, Arc::new(tbi_dynamics::track::Smooth), dt);
    let steps = ((2000.0 + 180.0) / (70.0 / 3.6) / dt) as usize;
    let t = Instant::now();
    for _ in 0..steps {
        sol.step();
    }
    let wall = t.elapsed().as_secs_f64();
    println!(
        "iterative steps, CG iterations: {:?}",
        sol.iterative_steps()
    );
    println!(
        "{steps} steps in {wall:.3} s: {:.0} steps/s, {:.0}x real time",
        steps as f64 / wall,
        steps as f64 * dt / wall
    );
}
