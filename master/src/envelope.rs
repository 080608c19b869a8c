//! `tbi sweep --trains …`: every train at every speed on the scenario's bridge, in parallel
//! on every core, and the envelope of the deck response.
//!
//! Each case is the scenario with its train replaced by the named train as moving forces
//! ([`tbi_dynamics::hslm`]) and its speed set; the runs go to `OUT/<train>/v<speed>`. The
//! envelope (`envelope.csv`, one row per train and speed) has the largest deck vertical
//! acceleration and displacement over the probes, the largest static displacement of the
//! train crossing (the modal static response Σₙ φₙ(x_p) Σⱼ Pⱼ ψₙ(xⱼ)/ωₙ² maximised over the
//! train's positions, with the modes kept) and the dynamic enhancement
//! φ'dyn = max y_dyn / max y_stat − 1 at the probe where it is largest.
//!
//! Checks printed at the end: the deck acceleration against EN 1990 A2.4.4.2.1 (3.5 m/s²
//! ballasted track, 5 m/s² direct fastening: `--track`), with the governing train and speed,
//! and whether the modes kept reach max(30 Hz, 1.5 f₁, f₃); the first resonance speeds
//! v = f₁ D / i (D the coach length of the governing train, i = 1, 2, 3).

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
/// displacement max m, φ'dyn).
type Row = (String, f64, f64, f64, f64);

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

pub fn main(
    args: &SweepArgs,
    base: &Scenario,
    speeds: &[f64],
) -> Result<(), Box<dyn std::error::Error>> {
    let trains = train_names(&args.trains)?;
    let (limit, track) = match args.track.as_str() {
        "ballasted" => (3.5, "ballasted track"),
        "direct" => (5.0, "direct fastening"),
        other => return Err(format!("--track {other}: expected ballasted or direct").into()),
    };
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
    let bridge = crate::model::build_bridge(base)?;
    // per train and probe: the largest static displacement
    let mut statics: std::collections::HashMap<(String, String), f64> = Default::default();
    for t in &trains {
        let axles = tbi_dynamics::hslm::hslm_a(t)?;
        for p in &base.probes {
            statics.insert(
                (t.clone(), p.name.clone()),
                static_displacement_max(&bridge, &axles, p.x_m, 0.05),
            );
        }
    }
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
                    let phi = summary
                        .probes
                        .iter()
                        .filter_map(|(name, p)| {
                            let st = statics[&(t.clone(), name.clone())];
                            (st > 0.0).then(|| p.vertical_displacement_max_m / st - 1.0)
                        })
                        .fold(f64::NEG_INFINITY, f64::max);
                    (
                        t.clone(),
                        *v,
                        max(|p| p.vertical_acceleration_max_m_s2),
                        max(|p| p.vertical_displacement_max_m),
                        phi,
                    )
                })
                .map_err(|e| format!("{t} at {} km/h: {e}", crate::model::num(*v)));
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    let rows: Vec<Row> = results.into_iter().collect::<Result<_, _>>()?;
    let mut csv = String::from(
        "train,speed_kmh,deck_acceleration_max_m_s2,deck_displacement_max_m,deck_static_displacement_max_m,phi_dyn\n",
    );
    for (t, v, a, d, phi) in &rows {
        let st = base
            .probes
            .iter()
            .map(|p| statics[&(t.clone(), p.name.clone())])
            .fold(0.0, f64::max);
        let _ = writeln!(csv, "{t},{v:e},{a:e},{d:e},{st:e},{phi:e}");
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
    let phi = governing(|r| r.4);
    println!(
        "dynamic enhancement φ'dyn: largest {:.3} ({} at {} km/h)",
        phi.4,
        phi.0,
        crate::model::num(phi.1)
    );
    println!(
        "check deck acceleration ≤ {limit} m/s² ({track}, EN 1990 A2.4.4.2.1): {} ({:.3} m/s², {} at {} km/h)",
        if a.2 <= limit { "PASS" } else { "FAIL" },
        a.2,
        a.0,
        crate::model::num(a.1)
    );
    let f = &bridge.frequencies_hz;
    let needed = 30.0_f64
        .max(1.5 * f[0])
        .max(f.get(2).copied().unwrap_or(0.0));
    let kept = f.iter().copied().fold(0.0, f64::max);
    if kept < needed {
        println!(
            "note: the modes kept reach {kept:.1} Hz; EN 1990 A2.4.4.2.1 asks for max(30 Hz, 1.5 f₁, f₃) = {needed:.1} Hz (raise bridge.modes)"
        );
    }
    if let Some(t) = tbi_dynamics::hslm::HSLM_A.iter().find(|t| t.name == a.0) {
        let v: Vec<String> = (1..=3)
            .map(|i| format!("{:.1}", f[0] * t.coach_length_m / i as f64 * 3.6))
            .collect();
        println!(
            "resonance speeds v = f₁ D / i of {} (D = {} m, f₁ = {:.3} Hz): {} km/h",
            t.name,
            t.coach_length_m,
            f[0],
            v.join(", ")
        );
    }
    let report = report(
        args,
        base,
        &bridge,
        &trains,
        &rows,
        (limit, track),
        (kept, needed),
    )?;
    crate::outdir::write_atomically(&args.out.join("report.html"), report.as_bytes())?;
    eprintln!(
        "tbi: {} cases; envelope.csv, report.html and the runs in {}",
        rows.len(),
        args.out.display()
    );
    Ok(())
}

/// The sweep's `report.html` ([`crate::report`]).
fn report(
    args: &SweepArgs,
    base: &Scenario,
    bridge: &tbi_dynamics::bridge::ModalBridge,
    trains: &[String],
    rows: &[Row],
    (limit, track): (f64, &str),
    (kept, needed): (f64, f64),
) -> Result<String, Box<dyn std::error::Error>> {
    use crate::report::{chart, Marks, Report, Series};
    let num = crate::model::num;
    let by = |key: fn(&Row) -> f64| -> Vec<Series> {
        trains
            .iter()
            .map(|t| Series {
                label: t.clone(),
                points: rows
                    .iter()
                    .filter(|r| &r.0 == t)
                    .map(|r| (r.1, key(r)))
                    .collect(),
            })
            .collect()
    };
    let worst = |key: fn(&Row) -> f64| {
        rows.iter()
            .max_by(|a, b| key(a).total_cmp(&key(b)))
            .expect("at least one case")
    };
    let a = worst(|r| r.2);
    let f1 = bridge.frequencies_hz[0];
    let d_coach = tbi_dynamics::hslm::HSLM_A
        .iter()
        .find(|t| t.name == a.0)
        .map(|t| t.coach_length_m);
    let resonances: Vec<f64> = d_coach
        .map(|d| (1..=3).map(|i| f1 * d / i as f64 * 3.6).collect())
        .unwrap_or_default();
    let mut charts = vec![(
        format!(
            "Deck vertical acceleration against speed; red: the limit {limit} m/s² ({track}); grey: resonance speeds f₁ D / i of {} ({})",
            a.0,
            resonances.iter().map(|v| format!("{v:.1}")).collect::<Vec<_>>().join(", ")
        ),
        chart(
            "Deck vertical acceleration",
            "speed (km/h)",
            "acceleration (m/s²)",
            &by(|r| r.2),
            &Marks {
                limit: Some((limit, format!("limit {limit} m/s²"))),
                verticals: resonances.clone(),
            },
        )?,
    )];
    charts.push((
        "Deck vertical displacement against speed".into(),
        chart(
            "Deck vertical displacement",
            "speed (km/h)",
            "displacement (m)",
            &by(|r| r.3),
            &Marks::default(),
        )?,
    ));
    charts.push((
        "Dynamic enhancement φ'dyn = max y_dyn / max y_stat − 1 against speed".into(),
        chart(
            "Dynamic enhancement φ'dyn",
            "speed (km/h)",
            "φ'dyn (–)",
            &by(|r| r.4),
            &Marks::default(),
        )?,
    ));
    // the governing case's time history, at the probe with the largest acceleration
    let history = args
        .out
        .join(&a.0)
        .join(format!("v{}", num(a.1)))
        .join("history.csv");
    let h = crate::plots::History::read(&history)?;
    let t = h
        .column("time_s")
        .ok_or("history.csv has no time_s")?
        .to_vec();
    let mut best: Option<(String, Vec<f64>)> = None;
    for p in &base.probes {
        let name = format!("{}.vertical_acceleration_m_s2", p.name);
        if let Some(c) = h.column(&name) {
            let m = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            if best
                .as_ref()
                .is_none_or(|(_, b)| m > b.iter().fold(0.0_f64, |x, v| x.max(v.abs())))
            {
                best = Some((p.name.clone(), c.to_vec()));
            }
        }
    }
    if let Some((probe, c)) = best {
        charts.push((
            format!(
                "Governing time history: deck vertical acceleration at probe {probe}, {} at {} km/h",
                a.0,
                num(a.1)
            ),
            chart(
                "Governing deck acceleration",
                "time (s)",
                "acceleration (m/s²)",
                &[Series {
                    label: format!("{} at {} km/h", a.0, num(a.1)),
                    points: t.iter().copied().zip(c).collect(),
                }],
                &Marks {
                    limit: Some((limit, format!("limit {limit} m/s²"))),
                    verticals: Vec::new(),
                },
            )?,
        ));
    }
    let damping = match &base.damping_rule {
        Some(r) => format!(
            "damping {:.3} % ({} for {}: Table 6.6 {:.3} % + eq. (6.13) {:.3} %)",
            100.0 * r.ratio,
            r.rule,
            r.structure,
            r.minimum_percent,
            r.additional_percent
        ),
        None => format!("damping {:.3} % (as given)", 100.0 * bridge.damping[0]),
    };
    let facts = vec![
        format!(
            "bridge: {} m, {} modes (f₁ = {f1:.3} Hz, up to {kept:.1} Hz), {damping}",
            num(bridge.length_m()),
            bridge.n_modes()
        ),
        format!(
            "{} trains × {} speeds ({} to {} km/h), moving forces; probes: {}",
            trains.len(),
            rows.len() / trains.len().max(1),
            num(rows.iter().map(|r| r.1).fold(f64::INFINITY, f64::min)),
            num(rows.iter().map(|r| r.1).fold(f64::NEG_INFINITY, f64::max)),
            base.probes
                .iter()
                .map(|p| format!("{} (x = {} m)", p.name, num(p.x_m)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    ];
    let checks = vec![
        (
            format!("deck acceleration ≤ {limit} m/s² ({track}, EN 1990 A2.4.4.2.1)"),
            a.2 <= limit,
            format!("largest {:.3} m/s², {} at {} km/h", a.2, a.0, num(a.1)),
        ),
        (
            "modes up to max(30 Hz, 1.5 f₁, f₃) (EN 1990 A2.4.4.2.1)".into(),
            kept >= needed,
            format!("kept up to {kept:.1} Hz, needed {needed:.1} Hz"),
        ),
    ];
    let header = [
        "train",
        "acceleration max (m/s²)",
        "at (km/h)",
        "displacement max (m)",
        "at (km/h)",
        "φ'dyn max",
        "at (km/h)",
    ]
    .map(String::from)
    .to_vec();
    let table_rows = trains
        .iter()
        .map(|t| {
            let mine: Vec<&Row> = rows.iter().filter(|r| &r.0 == t).collect();
            let best = |key: fn(&Row) -> f64| {
                mine.iter()
                    .max_by(|a, b| key(a).total_cmp(&key(b)))
                    .map(|r| (key(r), r.1))
                    .unwrap_or((f64::NAN, f64::NAN))
            };
            let (a, va) = best(|r| r.2);
            let (d, vd) = best(|r| r.3);
            let (p, vp) = best(|r| r.4);
            vec![
                t.clone(),
                format!("{a:.4}"),
                num(va),
                format!("{d:.6}"),
                num(vd),
                format!("{p:.3}"),
                num(vp),
            ]
        })
        .collect();
    Ok(Report {
        title: format!("Dynamic check of {}", base.name),
        facts,
        checks,
        charts,
        table: (header, table_rows),
    }
    .html())
}
