//! `tbi sweep --trains …`: every train at every speed on the scenario's bridge, in parallel
//! on every core, and the envelope of the deck response.
//!
//! Each case is the scenario with its train replaced by the named train as moving forces
//! ([`tbi_dynamics::hslm`]) and its speed set; the runs go to `OUT/<train>/v<speed>`. The
//! envelope is the largest deck vertical acceleration and displacement over the probes, per
//! train and speed (`envelope.csv`), and the governing train and speed of each.

use crate::run::run_scenario;
use crate::scenario::Scenario;
use crate::sweep::SweepArgs;
use rayon::prelude::*;
use std::fmt::Write as _;
use tbi_dynamics::interface::TrainSpec;

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

/// One case's result: (train, speed km/h, deck vertical acceleration max m/s², deck vertical
/// displacement max m).
type Row = (String, f64, f64, f64);

pub fn main(
    args: &SweepArgs,
    base: &Scenario,
    speeds: &[f64],
) -> Result<(), Box<dyn std::error::Error>> {
    let trains = train_names(&args.trains)?;
    for (i, v) in speeds.iter().enumerate() {
        if speeds[..i].contains(v) {
            return Err(format!("--speeds: {} km/h is given twice", crate::model::num(*v)).into());
        }
    }
    let mut cases = Vec::with_capacity(trains.len() * speeds.len());
    for t in &trains {
        let axles = tbi_dynamics::hslm::hslm_a(t)?;
        for &v in speeds {
            let mut s = base.clone();
            s.train.spec = TrainSpec::MovingForce(axles.clone());
            s.set_speed_kmh(v).map_err(|e| format!("--speeds: {e}"))?;
            cases.push((t.clone(), v, s));
        }
    }
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let limits = if args.allow_large {
        crate::model::Limits::none()
    } else {
        crate::model::Limits::default()
    };
    crate::model::build_bridge(base)?;
    let pb = crate::progress::counted(cases.len(), "cases", true);
    let results: Vec<Result<Row, String>> = cases
        .par_iter()
        .map(|(t, v, s)| {
            let dir = args.out.join(t).join(format!("v{}", crate::model::num(*v)));
            let r = run_scenario(s, &dir, false, &limits)
                .map(|summary| {
                    let max = |f: fn(&tbi_dynamics::response::ProbeMax) -> f64| {
                        summary.probes.values().map(f).fold(0.0, f64::max)
                    };
                    (
                        t.clone(),
                        *v,
                        max(|p| p.vertical_acceleration_max_m_s2),
                        max(|p| p.vertical_displacement_max_m),
                    )
                })
                .map_err(|e| format!("{t} at {} km/h: {e}", crate::model::num(*v)));
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    let rows: Vec<Row> = results.into_iter().collect::<Result<_, _>>()?;
    let mut csv =
        String::from("train,speed_kmh,deck_acceleration_max_m_s2,deck_displacement_max_m\n");
    for (t, v, a, d) in &rows {
        let _ = writeln!(csv, "{t},{v:e},{a:e},{d:e}");
    }
    crate::outdir::write_atomically(&args.out.join("envelope.csv"), csv.as_bytes())?;
    let governing = |key: fn(&Row) -> f64| {
        rows.iter()
            .max_by(|a, b| key(a).total_cmp(&key(b)))
            .expect("at least one case")
    };
    let a = governing(|r| r.2);
    let d = governing(|r| r.3);
    println!(
        "deck vertical acceleration: largest {:.4} m/s² ({} at {} km/h)",
        a.2,
        a.0,
        crate::model::num(a.1)
    );
    println!(
        "deck vertical displacement: largest {:.6} m ({} at {} km/h)",
        d.3,
        d.0,
        crate::model::num(d.1)
    );
    eprintln!(
        "tbi: {} cases; envelope.csv and the runs in {}",
        rows.len(),
        args.out.display()
    );
    Ok(())
}
