//! Build the Tsing Ma model, print its lowest modes, the lowest 20 modes with deck
//! participation and the static deflection under the project's 8-coach train (paper,
//! Table 1, crush masses); optionally write the deck modes to a file.
//!
//! `cargo run -p tbi-fe --release --example tsing_ma_modes -- [n_modes] [out.csv|out.json]`

use std::time::Instant;
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_fe::{tsing_ma, DeckLoad, FeModel};

/// Deck modes the paper's case uses.
const DECK_MODES: usize = 20;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(50);
    let params = tsing_ma();
    let t0 = Instant::now();
    let model = FeModel::build(&params)?;
    let t1 = Instant::now();
    let modal = model.modes(n)?;
    let t2 = Instant::now();
    let deck = model.deck_modes(DECK_MODES)?;
    let t3 = Instant::now();
    println!(
        "{} free DOFs; build {:.2} s, {} modes {:.2} s, {} deck modes {:.2} s",
        model.system().dof_count(),
        (t1 - t0).as_secs_f64(),
        n,
        (t2 - t1).as_secs_f64(),
        DECK_MODES,
        (t3 - t2).as_secs_f64()
    );
    let dl = model.dead_load();
    let t_max = dl.segment_tension.iter().cloned().fold(0.0, f64::max);
    println!(
        "H = {:.4e} N per cable, largest cable tension {:.4e} N",
        dl.horizontal_tension, t_max
    );
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
    println!("lowest {DECK_MODES} deck modes:");
    for (i, m) in deck.modes.iter().enumerate() {
        println!("{:2} {:.4}  {}", i + 1, m.frequency_hz, m.label);
    }

    // The train: 8 identical coaches, `length_m` apart, static wheelset loads from Table 1.
    let coach = CoachParams::xia2000();
    let vehicle = coach.build()?;
    let axles: Vec<(f64, f64)> = (0..8)
        .flat_map(|c| {
            let start = c as f64 * coach.length_m;
            vehicle
                .wheelsets
                .iter()
                .map(move |w| (start + w.offset_m, w.p0.z))
        })
        .collect();
    println!(
        "train: {} axles, axle load {:.1} N",
        axles.len(),
        vehicle.wheelsets[0].p0.z
    );
    let solver = model.static_solver()?;
    for &xp in &[1012.5, 1138.0, 1174.0, 1498.5] {
        let mut best = (0.0f64, 0.0, 0.0);
        let mut front = xp - 20.0;
        while front <= xp + 200.0 {
            let loads: Vec<DeckLoad> = axles
                .iter()
                .map(|&(offset, load)| DeckLoad {
                    x: front - offset,
                    lateral: 0.0,
                    vertical: load,
                    torque: params.track_eccentricity * load,
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
        deck.write(std::path::Path::new(path))?;
        println!("wrote {path}");
    }
    Ok(())
}
