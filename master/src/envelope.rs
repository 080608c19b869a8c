//! `tbi sweep --trains …`: every train at every speed on the scenario's bridge, in parallel
//! on every core, and the envelope of the deck response.
//!
//! Each case is the scenario with its train replaced by the named train ([`tbi_dynamics::hslm`])
//! as moving forces, or as sprung masses when the scenario's train has a `vehicle`, and its
//! speed set; the bridge keeps the modes up to max(30 Hz, 1.5 f₁, f₃) (EN 1990 A2.4.4.2.1;
//! `--all-modes` keeps all); the runs go to `OUT/<train>/v<speed>`. The
//! envelope (`envelope.csv`, one row per train and speed) has the largest deck vertical
//! acceleration and displacement over the probes, the largest static displacement of the
//! train crossing (the modal static response Σₙ φₙ(x_p) Σⱼ Pⱼ ψₙ(xⱼ)/ωₙ² maximised over the
//! train's positions, with the modes kept) and the dynamic enhancement
//! φ'dyn = max y_dyn / max y_stat − 1 at the probe where it is largest, and, with vehicles,
//! the largest car-body vertical acceleration.
//!
//! Checks printed at the end: the deck acceleration against EN 1990 A2.4.4.2.1 (3.5 m/s²
//! ballasted track, 5 m/s² direct fastening: `--track`), with the governing train and speed,
//! and whether the modes kept reach max(30 Hz, 1.5 f₁, f₃); with vehicles, the car-body
//! vertical acceleration against a comfort level of EN 1990 Table A2.9 (`--comfort`); the
//! first resonance speeds v = f₁ D / i (D the coach length of the governing train, i = 1, 2, 3).

use crate::run::run_scenario;
use crate::scenario::Scenario;
use crate::sweep::SweepArgs;
use rayon::prelude::*;
use std::fmt::Write as _;

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

/// One case's result.
struct Row {
    train: String,
    speed_kmh: f64,
    /// Deck vertical acceleration, largest over the probes, m/s².
    acceleration: f64,
    /// Deck vertical displacement, largest over the probes, m.
    displacement: f64,
    /// φ'dyn at the probe where it is largest, –.
    phi: f64,
    /// Car-body vertical acceleration, largest over the vehicles, m/s² (vehicles only).
    body: Option<f64>,
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

/// The number of the lowest modes up to max(30 Hz, 1.5 f₁, f₃) (EN 1990 A2.4.4.2.1), and
/// that frequency, for frequencies in ascending order.
pub fn modes_considered(frequencies_hz: &[f64]) -> (usize, f64) {
    let f = frequencies_hz;
    let needed = 30.0_f64
        .max(1.5 * f.first().copied().unwrap_or(0.0))
        .max(f.get(2).copied().unwrap_or(0.0));
    (
        f.iter().take_while(|&&x| x <= needed).count().max(1),
        needed,
    )
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
    let comfort = comfort_limit(&args.comfort)?;
    let vehicles = base.train.axle_vehicle.is_some();
    // the modes EN 1990 A2.4.4.2.1 considers
    let mut base = base.clone();
    let all = crate::model::build_bridge(&base)?;
    let ascending = all.frequencies_hz.windows(2).all(|w| w[0] <= w[1]);
    let (considered, needed) = modes_considered(&all.frequencies_hz);
    if !args.all_modes && ascending && considered < all.n_modes() {
        base.bridge.set_modes(considered);
        println!(
            "modes: the lowest {considered} of {}, up to max(30 Hz, 1.5 f₁, f₃) = {needed:.1} Hz (EN 1990 A2.4.4.2.1; --all-modes keeps all)",
            all.n_modes()
        );
    }
    let base = &base;
    let bridge = crate::model::build_bridge(base)?;
    let mut cases = Vec::with_capacity(trains.len() * speeds.len());
    for t in &trains {
        let spec = base
            .train
            .axle_train(tbi_dynamics::hslm::hslm_a(t)?)
            .map_err(|e| format!("{t} with train.vehicle: {e}"))?;
        for &v in speeds {
            let mut s = base.clone();
            s.train.spec = spec.clone();
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
                    Row {
                        train: t.clone(),
                        speed_kmh: *v,
                        acceleration: max(|p| p.vertical_acceleration_max_m_s2),
                        displacement: max(|p| p.vertical_displacement_max_m),
                        phi,
                        body: vehicles.then_some(summary.vehicles.vertical_acceleration_max_m_s2),
                    }
                })
                .map_err(|e| format!("{t} at {} km/h: {e}", crate::model::num(*v)));
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    let rows: Vec<Row> = results.into_iter().collect::<Result<_, _>>()?;
    let mut csv = String::from(
        "train,speed_kmh,deck_acceleration_max_m_s2,deck_displacement_max_m,deck_static_displacement_max_m,phi_dyn,car_body_acceleration_max_m_s2\n",
    );
    for r in &rows {
        let st = base
            .probes
            .iter()
            .map(|p| statics[&(r.train.clone(), p.name.clone())])
            .fold(0.0, f64::max);
        let body = r.body.map(|b| format!("{b:e}")).unwrap_or_default();
        let _ = writeln!(
            csv,
            "{},{:e},{:e},{:e},{st:e},{:e},{body}",
            r.train, r.speed_kmh, r.acceleration, r.displacement, r.phi
        );
    }
    crate::outdir::write_atomically(&args.out.join("envelope.csv"), csv.as_bytes())?;
    let governing = |key: fn(&Row) -> f64| {
        rows.iter()
            .max_by(|a, b| key(a).total_cmp(&key(b)))
            .expect("at least one case")
    };
    let num = crate::model::num;
    let a = governing(|r| r.acceleration);
    let d = governing(|r| r.displacement);
    println!(
        "deck vertical acceleration: largest {:.4} m/s² ({} at {} km/h)",
        a.acceleration,
        a.train,
        num(a.speed_kmh)
    );
    println!(
        "deck vertical displacement: largest {:.6} m ({} at {} km/h)",
        d.displacement,
        d.train,
        num(d.speed_kmh)
    );
    let phi = governing(|r| r.phi);
    println!(
        "dynamic enhancement φ'dyn: largest {:.3} ({} at {} km/h)",
        phi.phi,
        phi.train,
        num(phi.speed_kmh)
    );
    println!(
        "check deck acceleration ≤ {limit} m/s² ({track}, EN 1990 A2.4.4.2.1): {} ({:.3} m/s², {} at {} km/h)",
        pass(a.acceleration <= limit),
        a.acceleration,
        a.train,
        num(a.speed_kmh)
    );
    if vehicles {
        let b = governing(|r| r.body.unwrap_or(0.0));
        println!(
            "check car-body vertical acceleration ≤ {comfort} m/s² ({} comfort, EN 1990 Table A2.9): {} ({:.3} m/s², {} at {} km/h)",
            args.comfort,
            pass(b.body.unwrap_or(0.0) <= comfort),
            b.body.unwrap_or(0.0),
            b.train,
            num(b.speed_kmh)
        );
    }
    let f = &bridge.frequencies_hz;
    let needed = modes_considered(f).1;
    let kept = f.iter().copied().fold(0.0, f64::max);
    if kept < needed {
        println!(
            "note: the modes kept reach {kept:.1} Hz; EN 1990 A2.4.4.2.1 asks for max(30 Hz, 1.5 f₁, f₃) = {needed:.1} Hz (raise bridge.modes)"
        );
    }
    if let Some(t) = tbi_dynamics::hslm::HSLM_A
        .iter()
        .find(|t| t.name == a.train)
    {
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
        vehicles.then_some(comfort),
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
fn pass(ok: bool) -> &'static str {
    if ok {
        "PASS"
    } else {
        "FAIL"
    }
}

#[allow(clippy::too_many_arguments)]
fn report(
    args: &SweepArgs,
    base: &Scenario,
    bridge: &tbi_dynamics::bridge::ModalBridge,
    trains: &[String],
    rows: &[Row],
    (limit, track): (f64, &str),
    comfort: Option<f64>,
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
                    .filter(|r| &r.train == t)
                    .map(|r| (r.speed_kmh, key(r)))
                    .collect(),
            })
            .collect()
    };
    let worst = |key: fn(&Row) -> f64| {
        rows.iter()
            .max_by(|a, b| key(a).total_cmp(&key(b)))
            .expect("at least one case")
    };
    let a = worst(|r| r.acceleration);
    let f1 = bridge.frequencies_hz[0];
    let d_coach = tbi_dynamics::hslm::HSLM_A
        .iter()
        .find(|t| t.name == a.train)
        .map(|t| t.coach_length_m);
    let resonances: Vec<f64> = d_coach
        .map(|d| (1..=3).map(|i| f1 * d / i as f64 * 3.6).collect())
        .unwrap_or_default();
    let mut charts = vec![(
        format!(
            "Deck vertical acceleration against speed; red: the limit {limit} m/s² ({track}); grey: resonance speeds f₁ D / i of {} ({})",
            a.train,
            resonances.iter().map(|v| format!("{v:.1}")).collect::<Vec<_>>().join(", ")
        ),
        chart(
            "Deck vertical acceleration",
            "speed (km/h)",
            "acceleration (m/s²)",
            &by(|r| r.acceleration),
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
            &by(|r| r.displacement),
            &Marks::default(),
        )?,
    ));
    charts.push((
        "Dynamic enhancement φ'dyn = max y_dyn / max y_stat − 1 against speed".into(),
        chart(
            "Dynamic enhancement φ'dyn",
            "speed (km/h)",
            "φ'dyn (–)",
            &by(|r| r.phi),
            &Marks::default(),
        )?,
    ));
    if let Some(comfort) = comfort {
        charts.push((
            format!(
                "Car-body vertical acceleration against speed; red: {comfort} m/s² ({} comfort, EN 1990 Table A2.9)",
                args.comfort
            ),
            chart(
                "Car-body vertical acceleration",
                "speed (km/h)",
                "acceleration (m/s²)",
                &by(|r| r.body.unwrap_or(0.0)),
                &Marks {
                    limit: Some((comfort, format!("{} {comfort} m/s²", args.comfort))),
                    verticals: Vec::new(),
                },
            )?,
        ));
    }
    // the governing case's time history, at the probe with the largest acceleration
    let history = args
        .out
        .join(&a.train)
        .join(format!("v{}", num(a.speed_kmh)))
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
                a.train,
                num(a.speed_kmh)
            ),
            chart(
                "Governing deck acceleration",
                "time (s)",
                "acceleration (m/s²)",
                &[Series {
                    label: format!("{} at {} km/h", a.train, num(a.speed_kmh)),
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
            "{} trains × {} speeds ({} to {} km/h), {}; probes: {}",
            trains.len(),
            rows.len() / trains.len().max(1),
            num(rows
                .iter()
                .map(|r| r.speed_kmh)
                .fold(f64::INFINITY, f64::min)),
            num(rows
                .iter()
                .map(|r| r.speed_kmh)
                .fold(f64::NEG_INFINITY, f64::max)),
            match &base.train.axle_vehicle {
                None => "moving forces".to_string(),
                Some(v) => format!(
                    "a sprung mass under every axle ({} Hz, damping {} %, wheel {} kg)",
                    num(v.frequency_hz),
                    num(100.0 * v.damping_ratio),
                    num(v.wheel_mass_kg)
                ),
            },
            base.probes
                .iter()
                .map(|p| format!("{} (x = {} m)", p.name, num(p.x_m)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    ];
    let mut checks = vec![
        (
            format!("deck acceleration ≤ {limit} m/s² ({track}, EN 1990 A2.4.4.2.1)"),
            a.acceleration <= limit,
            format!(
                "largest {:.3} m/s², {} at {} km/h",
                a.acceleration,
                a.train,
                num(a.speed_kmh)
            ),
        ),
        (
            "modes up to max(30 Hz, 1.5 f₁, f₃) (EN 1990 A2.4.4.2.1)".into(),
            kept >= needed,
            format!("kept up to {kept:.1} Hz, needed {needed:.1} Hz"),
        ),
    ];
    if let Some(comfort) = comfort {
        let b = worst(|r| r.body.unwrap_or(0.0));
        checks.push((
            format!(
                "car-body vertical acceleration ≤ {comfort} m/s² ({} comfort, EN 1990 Table A2.9)",
                args.comfort
            ),
            b.body.unwrap_or(0.0) <= comfort,
            format!(
                "largest {:.3} m/s², {} at {} km/h",
                b.body.unwrap_or(0.0),
                b.train,
                num(b.speed_kmh)
            ),
        ));
    }
    let mut header = [
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
    if comfort.is_some() {
        header.extend([
            "car-body acceleration max (m/s²)".into(),
            "at (km/h)".into(),
        ]);
    }
    let table_rows = trains
        .iter()
        .map(|t| {
            let mine: Vec<&Row> = rows.iter().filter(|r| &r.train == t).collect();
            let best = |key: fn(&Row) -> f64| {
                mine.iter()
                    .max_by(|a, b| key(a).total_cmp(&key(b)))
                    .map(|r| (key(r), r.speed_kmh))
                    .unwrap_or((f64::NAN, f64::NAN))
            };
            let (a, va) = best(|r| r.acceleration);
            let (d, vd) = best(|r| r.displacement);
            let (p, vp) = best(|r| r.phi);
            let mut row = vec![
                t.clone(),
                format!("{a:.4}"),
                num(va),
                format!("{d:.6}"),
                num(vd),
                format!("{p:.3}"),
                num(vp),
            ];
            if comfort.is_some() {
                let (b, vb) = best(|r| r.body.unwrap_or(0.0));
                row.extend([format!("{b:.4}"), num(vb)]);
            }
            row
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
