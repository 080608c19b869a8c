//! `report.html` of a design check: one self-contained page an engineer can file.
//!
//! In order: the inputs (scenario file and its SHA-256, bridge, section, damping, modes
//! kept with their frequencies, time step, trains, speed grid and refinement, tool version
//! and commit, date), the checks (PASS/FAIL, value, limit, clause, governing train and
//! speed, the command that reproduces it), the EN 1991-2 §6.4.6.5 comparison with LM71,
//! the envelopes against speed (deck acceleration with the limit and each train's resonance
//! speeds as labelled markers, deck displacement in mm, φ'dyn; car-body acceleration with
//! vehicles), the governing time history, the table of resonance speeds and of each train's
//! maxima.

use super::{checks, governing_row, Options, Outcome, Quantity, Row};
use crate::output::html::{chart, escape, page, table, Marks, Series};
use crate::text::num;
use std::fmt::Write as _;
use std::path::Path;

/// The page.
pub fn html(
    source: &super::cases::Source,
    outcome: &Outcome,
    o: &Options,
    out: &Path,
    started: std::time::Instant,
) -> Result<String, String> {
    let mut b = String::new();
    b.push_str("<h2>Inputs</h2>\n");
    b.push_str(&table(
        &["input".into(), "value".into()],
        &inputs(source, outcome, started),
    ));
    b.push_str("<h2>Checks</h2>\n<table>\n<tr><th>check</th><th>result</th><th>value</th><th>limit</th><th>clause</th><th>governing</th><th>reproduce</th></tr>\n");
    for c in checks(outcome, o) {
        let (class, word) = if c.passed {
            ("pass", "PASS")
        } else {
            ("fail", "FAIL")
        };
        let _ = writeln!(
            b,
            "<tr class=\"check\"><td>{}</td><td class=\"{class}\">{word}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&c.name),
            escape(&c.value),
            escape(&c.limit),
            c.clause,
            escape(&c.governing),
            c.command
                .map(|cmd| format!("<code>{}</code>", escape(&cmd)))
                .unwrap_or_default()
        );
    }
    b.push_str("</table>\n");
    comparison(&mut b, outcome);
    charts(&mut b, outcome, o, out)?;
    resonance_table(&mut b, outcome);
    maxima_table(&mut b, outcome, o);
    Ok(page(&format!("Dynamic check of {}", source.name), &b))
}

fn inputs(
    source: &super::cases::Source,
    outcome: &Outcome,
    started: std::time::Instant,
) -> Vec<Vec<String>> {
    let f = &outcome.bridge.frequencies_hz;
    let mut rows = vec![
        vec!["scenario file".into(), source.origin.clone()],
        vec!["SHA-256 of its bytes".into(), source.sha256.clone()],
    ];
    {
        let s = &outcome.scenario;
        rows.push(vec!["bridge".into(), bridge_text(s, &outcome.bridge)]);
        rows.push(vec!["damping".into(), damping_text(s, &outcome.bridge)]);
        rows.push(vec![
            "time step".into(),
            format!(
                "{} s; free vibration after the train {} s",
                num(s.run.dt_s),
                num(s.run.free_vibration_s)
            ),
        ]);
        rows.push(vec![
            "probes".into(),
            s.probes
                .iter()
                .map(|p| format!("{} (x = {} m)", p.name, num(p.x_m)))
                .collect::<Vec<_>>()
                .join(", "),
        ]);
        rows.push(vec![
            "trains".into(),
            format!(
                "{} ({})",
                outcome
                    .resonances
                    .iter()
                    .map(|r| r.0.clone())
                    .collect::<Vec<_>>()
                    .join(", "),
                match &s.train.axle_vehicle {
                    None => "moving forces".to_string(),
                    Some(v) => format!(
                        "a sprung mass under every axle: {} Hz, damping {} %, wheel {} kg",
                        num(v.frequency_hz),
                        num(100.0 * v.damping_ratio),
                        num(v.wheel_mass_kg)
                    ),
                }
            ),
        ]);
        rows.push(vec![
            "modes kept".into(),
            format!(
                "{} (bridge.modes_rule = \"{}\"): {}",
                f.len(),
                s.modes_rule.as_str(),
                f.iter()
                    .zip(&outcome.bridge.labels)
                    .map(|(f, l)| format!("{l} {f:.3} Hz"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ]);
    }
    let (lo, hi) = outcome
        .speeds
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let step = if outcome.speeds.len() > 1 {
        format!(", {} speeds", outcome.speeds.len())
    } else {
        String::new()
    };
    rows.push(vec![
        "speeds".into(),
        format!(
            "{} to {} km/h{step}, with each train's resonance speeds f₁ D / i in the range: {} cases; {} more refining every peak of the deck acceleration to a bracket of 0.2 km/h or ends within 0.5 % of its value",
            num(lo),
            num(hi),
            outcome.grid_runs,
            outcome.refined_runs
        ),
    ]);
    rows.push(vec![
        "tool".into(),
        format!(
            "tbi {} (commit {})",
            env!("CARGO_PKG_VERSION"),
            option_env!("TBI_COMMIT").unwrap_or("unknown")
        ),
    ]);
    rows.push(vec![
        "date".into(),
        format!(
            "{} UTC (the check took {:.1} s)",
            utc_now(),
            started.elapsed().as_secs_f64()
        ),
    ]);
    rows
}

fn bridge_text(
    s: &crate::scenario::Scenario,
    bridge: &tbi_dynamics::bridge::ModalBridge,
) -> String {
    use crate::scenario::Bridge;
    match &s.bridge {
        Bridge::SimplySupported(b) => format!(
            "simply supported span L = {} m; section E = {} Pa, I = {} m⁴, m = {} kg/m",
            num(b.span_m),
            num(b.youngs_modulus_pa),
            num(b.inertia_vertical_m4),
            num(b.mass_per_length_kg_m)
        ),
        Bridge::Beam { beam, .. } => format!(
            "beam over spans {:?} m ({}); sections {}",
            beam.spans_m,
            if beam.continuous {
                "continuous"
            } else {
                "a chain of simply supported spans"
            },
            beam.sections
                .iter()
                .map(|c| format!(
                    "E = {} Pa, I = {} m⁴, m = {} kg/m",
                    num(c.youngs_modulus_pa),
                    num(c.inertia_m4),
                    num(c.mass_per_length_kg_m)
                ))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        other => format!("{} ({} m)", other.kind(), num(bridge.length_m())),
    }
}

fn damping_text(
    s: &crate::scenario::Scenario,
    bridge: &tbi_dynamics::bridge::ModalBridge,
) -> String {
    match &s.damping_rule {
        Some(r) => format!(
            "ζ = {:.3} % ({} for {}: Table 6.6 {:.3} % + eq. (6.13) {:.3} %)",
            100.0 * r.ratio,
            r.rule,
            r.structure,
            r.minimum_percent,
            r.additional_percent
        ),
        None => format!("ζ = {:.3} % (as given)", 100.0 * bridge.damping[0]),
    }
}

fn comparison(b: &mut String, outcome: &Outcome) {
    b.push_str("<h2>EN 1991-2 §6.4.6.5(3): LM71 against HSLM</h2>\n");
    let Some(c) = &outcome.en else {
        b.push_str("<p>Not computed: the static comparison needs a beam bridge (kind \"simply_supported\" or \"beam\").</p>\n");
        return;
    };
    let (phi, share) = c.phi_name();
    let _ = writeln!(
        b,
        "<p>Each load effect is designed for the more unfavourable of {phi}·(α·LM71) and (1 + φ'dyn + {share})·HSLM; α = {:.2}; {} track.</p>",
        c.options.alpha,
        if c.options.careful { "carefully maintained" } else { "standard maintenance" }
    );
    let header = [
        "effect",
        "L_Φ (m)",
        "Φ₂",
        "Φ₃",
        "LM71",
        &format!("LM71·{phi}"),
        "HSLM train",
        "HSLM static",
        "φ'dyn",
        "φ''",
        "HSLM dynamic",
        "governs",
    ]
    .map(String::from)
    .to_vec();
    let rows: Vec<Vec<String>> = c
        .effects
        .iter()
        .map(|e| {
            let v = |x: f64| format!("{:.3} {}", e.scale * x, e.unit);
            vec![
                e.name.clone(),
                format!("{:.3}", e.l_phi_m),
                format!("{:.3}", e.phi2),
                format!("{:.3}", e.phi3),
                v(e.lm71),
                v(e.lm71_phi),
                e.train.clone(),
                v(e.hslm_static),
                format!("{:.3}", e.phi_dyn),
                format!("{:.3}", e.phi_dd),
                v(e.hslm_dynamic),
                e.governs().into(),
            ]
        })
        .collect();
    b.push_str(&table(&header, &rows));
    for n in &c.notes {
        let _ = writeln!(b, "<p>{}</p>", escape(n));
    }
}

/// One series per train of `key` (scaled), in the trains' order.
fn by_train(outcome: &Outcome, key: impl Fn(&Row) -> f64) -> Vec<Series> {
    outcome
        .resonances
        .iter()
        .map(|(t, _)| Series {
            label: t.clone(),
            points: outcome
                .rows
                .iter()
                .filter(|r| &r.train == t)
                .map(|r| (r.speed_kmh, key(r)))
                .collect(),
        })
        .collect()
}

fn charts(b: &mut String, outcome: &Outcome, o: &Options, out: &Path) -> Result<(), String> {
    let markers: Vec<(f64, usize, String)> = outcome
        .resonances
        .iter()
        .enumerate()
        .flat_map(|(k, (t, vs))| {
            let n = vs.len();
            vs.iter()
                .enumerate()
                .map(move |(j, v)| (*v, k, format!("{t}/{}", n - j)))
        })
        .collect();
    let mut figures = vec![(
        format!(
            "Deck vertical acceleration against speed; dashed red: the limit {} m/s² ({}); triangles: each train's resonance speeds f₁ D / i, labelled train/i",
            o.limit_m_s2, o.track
        ),
        chart(
            "Deck vertical acceleration",
            "speed (km/h)",
            "acceleration (m/s²)",
            &by_train(outcome, |r| r.acceleration),
            &Marks {
                limit: Some((o.limit_m_s2, format!("limit {} m/s²", o.limit_m_s2))),
                verticals: Vec::new(),
                markers,
            },
        )?,
    )];
    figures.push((
        "Deck vertical displacement against speed".into(),
        chart(
            "Deck vertical displacement",
            "speed (km/h)",
            "displacement (mm)",
            &by_train(outcome, |r| 1000.0 * r.displacement),
            &Marks::default(),
        )?,
    ));
    figures.push((
        "Dynamic enhancement φ'dyn = max y_dyn / max y_stat − 1 against speed".into(),
        chart(
            "Dynamic enhancement φ'dyn",
            "speed (km/h)",
            "φ'dyn (–)",
            &by_train(outcome, |r| r.phi),
            &Marks::default(),
        )?,
    ));
    if let Some((limit, level)) = &o.comfort {
        figures.push((
            format!("Car-body vertical acceleration against speed; dashed red: {limit} m/s² ({level} comfort, EN 1990 Table A2.9)"),
            chart(
                "Car-body vertical acceleration",
                "speed (km/h)",
                "acceleration (m/s²)",
                &by_train(outcome, |r| r.body.unwrap_or(0.0)),
                &Marks {
                    limit: Some((*limit, format!("{level} {limit} m/s²"))),
                    ..Marks::default()
                },
            )?,
        ));
    }
    if let Some(f) = governing_history(outcome, o, out)? {
        figures.push(f);
    }
    for (caption, svg) in figures {
        let _ = writeln!(
            b,
            "<figure>{svg}<figcaption>{}</figcaption></figure>",
            escape(&caption)
        );
    }
    Ok(())
}

/// The governing case's deck acceleration history at the probe where it is largest.
fn governing_history(
    outcome: &Outcome,
    o: &Options,
    out: &Path,
) -> Result<Option<(String, String)>, String> {
    let a = &outcome.rows[governing_row(&outcome.rows, Quantity::DeckAcceleration)];
    let path = super::case_dir(out, &a.train, a.speed_kmh).join("history.csv");
    let h = crate::output::plots::History::read(&path)?;
    let t = h
        .column("time_s")
        .ok_or("history.csv has no time_s")?
        .to_vec();
    let mut best: Option<(String, Vec<f64>, f64)> = None;
    for name in h
        .names
        .iter()
        .filter(|n| n.ends_with(".vertical_acceleration_m_s2"))
    {
        let Some(c) = h.column(name) else { continue };
        let m = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if best.as_ref().is_none_or(|b| m > b.2) {
            let probe = name
                .trim_end_matches(".vertical_acceleration_m_s2")
                .to_string();
            best = Some((probe, c.to_vec(), m));
        }
    }
    let Some((probe, c, _)) = best else {
        return Ok(None);
    };
    let label = format!("{} at {} km/h", a.train, super::kmh(a.speed_kmh));
    Ok(Some((
        format!("Governing time history: deck vertical acceleration at probe {probe}, {label} (history.csv in {})", path.parent().unwrap_or(out).display()),
        chart(
            "Governing deck acceleration",
            "time (s)",
            "acceleration (m/s²)",
            &[Series {
                label,
                points: t.iter().copied().zip(c).collect(),
            }],
            &Marks {
                limit: Some((o.limit_m_s2, format!("limit {} m/s²", o.limit_m_s2))),
                ..Marks::default()
            },
        )?,
    )))
}

fn resonance_table(b: &mut String, outcome: &Outcome) {
    b.push_str("<h2>Resonance speeds f₁ D / i in the range</h2>\n");
    let f1 = outcome.bridge.frequencies_hz[0];
    let rows: Vec<Vec<String>> = outcome
        .resonances
        .iter()
        .map(|(t, vs)| {
            let d = tbi_dynamics::hslm::HSLM_A
                .iter()
                .find(|h| h.name == t)
                .map_or(0.0, |h| h.coach_length_m);
            let n = vs.len();
            vec![
                t.clone(),
                num(d),
                vs.iter()
                    .enumerate()
                    .map(|(j, v)| format!("i = {}: {v:.1}", n - j))
                    .collect::<Vec<_>>()
                    .join("; "),
            ]
        })
        .collect();
    let _ = writeln!(b, "<p>f₁ = {f1:.3} Hz.</p>");
    b.push_str(&table(
        &[
            "train".into(),
            "D (m)".into(),
            "resonance speeds (km/h)".into(),
        ],
        &rows,
    ));
}

fn maxima_table(b: &mut String, outcome: &Outcome, o: &Options) {
    b.push_str("<h2>Maxima per train</h2>\n");
    let mut header = [
        "train",
        "deck acceleration (m/s²)",
        "at (km/h)",
        "deck displacement (mm)",
        "at (km/h)",
        "φ'dyn",
        "at (km/h)",
    ]
    .map(String::from)
    .to_vec();
    if o.comfort.is_some() {
        header.extend(["car-body acceleration (m/s²)".into(), "at (km/h)".into()]);
    }
    let rows: Vec<Vec<String>> = outcome
        .resonances
        .iter()
        .map(|(t, _)| {
            let mine: Vec<&Row> = outcome.rows.iter().filter(|r| &r.train == t).collect();
            let best = |key: &dyn Fn(&Row) -> f64| {
                mine.iter()
                    .max_by(|a, b| key(a).total_cmp(&key(b)))
                    .map_or((f64::NAN, f64::NAN), |r| (key(r), r.speed_kmh))
            };
            let (a, va) = best(&|r| r.acceleration);
            let (d, vd) = best(&|r| 1000.0 * r.displacement);
            let (p, vp) = best(&|r| r.phi);
            let mut row = vec![
                t.clone(),
                format!("{a:.3}"),
                format!("{va:.1}"),
                format!("{d:.3}"),
                format!("{vd:.1}"),
                format!("{p:.3}"),
                format!("{vp:.1}"),
            ];
            if o.comfort.is_some() {
                let (c, vc) = best(&|r| r.body.unwrap_or(0.0));
                row.extend([format!("{c:.3}"), format!("{vc:.1}")]);
            }
            row
        })
        .collect();
    b.push_str(&table(&header, &rows));
}

/// The time now as `YYYY-MM-DD HH:MM:SS` (UTC), from the system clock.
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // civil from days (H. Hinnant's algorithm)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}
