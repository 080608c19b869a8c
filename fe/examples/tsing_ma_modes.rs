//! Build the Tsing Ma model, print its lowest modes and the static deflection under the
//! paper's 8-coach train; optionally write the deck modes to a file.
//!
//! `cargo run -p tbi-fe --release --example tsing_ma_modes -- [n_modes] [out.csv|out.json]`

use std::time::Instant;
use tbi_fe::{tsing_ma, DeckLoad, FeModel};

/// Axle offsets behind the train front of the paper's 8 identical coaches, m.
fn axle_offsets() -> Vec<f64> {
    let (coach, bogie_half, axle_half) = (22.5, 7.8, 1.25);
    (0..8)
        .flat_map(|c| {
            let centre = c as f64 * coach + 0.5 * coach;
            [-bogie_half, bogie_half].into_iter().flat_map(move |b| {
                [-axle_half, axle_half]
                    .into_iter()
                    .map(move |a| centre + b + a)
            })
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(50);
    let params = tsing_ma();
    let t0 = Instant::now();
    let model = FeModel::build(&params)?;
    let t1 = Instant::now();
    let modal = model.modes(n)?;
    let t2 = Instant::now();
    println!(
        "{} free DOFs; build {:.2} s, {} modes {:.2} s",
        model.system().dof_count(),
        (t1 - t0).as_secs_f64(),
        n,
        (t2 - t1).as_secs_f64()
    );
    let dl = model.dead_load();
    println!("H = {:.4e} N per cable", dl.horizontal_tension);
    println!(" #  f (Hz)   label    deck_lat deck_ver deck_tor cables other");
    for (i, m) in modal.modes.iter().enumerate() {
        let e = m.energy;
        println!(
            "{:2} {:.4}  {:8} {:.3}    {:.3}    {:.3}    {:.3}  {:.3}",
            i + 1,
            m.frequency_hz,
            m.label,
            e.deck_lateral,
            e.deck_vertical,
            e.deck_torsion,
            e.cables,
            e.other
        );
    }
    let solver = model.static_solver()?;
    let axle_load = 13_250.0 * 9.81;
    let offsets = axle_offsets();
    for &xp in &[1012.5, 1138.0, 1174.0, 1498.5] {
        let mut best = (0.0f64, 0.0, 0.0);
        let mut front = xp - 20.0;
        while front <= xp + 200.0 {
            let loads: Vec<DeckLoad> = offsets
                .iter()
                .map(|&o| DeckLoad {
                    x: front - o,
                    lateral: 0.0,
                    vertical: axle_load,
                    torque: params.track_eccentricity * axle_load,
                })
                .collect();
            let d = solver.deck_deflection(&loads, &[xp])?[0];
            if d.vertical > best.0 {
                best = (
                    d.vertical,
                    front,
                    d.vertical + params.track_eccentricity * d.torsion,
                );
            }
            front += 1.0;
        }
        println!(
            "x = {xp:7.1} m: max vertical deflection {:.4} m (train front at {:.1} m; at the track {:.4} m)",
            best.0, best.1, best.2
        );
    }
    if let Some(path) = args.get(2) {
        modal.to_mode_set().write(std::path::Path::new(path))?;
        println!("wrote {path}");
    }
    Ok(())
}
