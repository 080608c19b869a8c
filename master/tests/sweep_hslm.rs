//! `tbi sweep --trains`: the EN 1991-2 HSLM-A trains over a speed range on a 25 m simply
//! supported span (f₁ ≈ 5 Hz, 1 % damping), as a bridge engineer runs the dynamic check.
//!
//! * The peak deck acceleration over 200–420 km/h occurs at the first resonance speed of the
//!   closed form v = f₁ D (D the coach length; f₁ = π/(2L²) √(EI/m) from the section), and
//!   over 140–190 km/h at the second, f₁ D / 2.
//! * A whole HSLM-A1 train equals the exact modal series summed over its axles.
//! * A row of `envelope.csv` equals `tbi run` of the same span with the train typed in as
//!   `moving_force` axles, built here from the standard's spacings (3, 11, 3, 3.525, d,
//!   D − 1.5d − 1.7625, then d, D − d per coach, and the mirror) independently of the
//!   tool's positions.
//! * `--trains hslm-a` runs all ten; bad trains and speed ranges are refused by name.

use std::path::{Path, PathBuf};
use tbi_tests::{read_summary, run, run_checked, scratch, tbi_command, text};

const SPAN: &str = r#"name = "span-25m"
[run]
speed_kmh = 300.0
dt_s = 0.001
solver = "monolithic"
free_vibration_s = 0.5
output_every = 10
[bridge]
kind = "simply_supported"
span_m = 25.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 1.696
mass_per_length_kg_m = 15000.0
modes = 3
damping_ratio = 0.01
[train]
kind = "hslm_a"
name = "A1"
[track]
irregularity = "none"
[[probe]]
name = "mid"
x_m = 12.5
"#;

fn scenario(dir: &Path, text: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("span.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// (train, speed km/h, acceleration m/s², displacement m, static displacement m, φ'dyn,
/// car-body acceleration m/s² with vehicles) rows of envelope.csv that are on the speed grid
/// asked for (not the resonance speeds and refinements the check adds).
type Row = (String, f64, f64, f64, f64, f64, Option<f64>);

const ENVELOPE_HEADER: &str = "train,speed_kmh,point,deck_acceleration_max_m_s2,deck_displacement_max_mm,deck_static_displacement_max_mm,phi_dyn,car_body_acceleration_max_m_s2,governing";

/// Every row of envelope.csv with its point kind (`grid`, `resonance`, `refined`);
/// displacements back in m.
fn envelope_all(path: &Path) -> Vec<(Row, String)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), ENVELOPE_HEADER);
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 9, "{l}");
            let n = |i: usize| f[i].parse::<f64>().unwrap();
            let body = (!f[7].is_empty()).then(|| n(7));
            (
                (
                    f[0].to_owned(),
                    n(1),
                    n(3),
                    n(4) / 1e3,
                    n(5) / 1e3,
                    n(6),
                    body,
                ),
                f[2].to_owned(),
            )
        })
        .collect()
}

fn envelope(path: &Path) -> Vec<Row> {
    envelope_all(path)
        .into_iter()
        .filter(|(_, point)| point == "grid")
        .map(|(r, _)| r)
        .collect()
}

/// A run folder a check kept under a train's folder (its case of largest deck
/// acceleration, and the governing cases of the checks).
fn kept_run(train_dir: &Path) -> PathBuf {
    let mut kept: Vec<PathBuf> = std::fs::read_dir(train_dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    kept.sort();
    assert!((1..=3).contains(&kept.len()), "{kept:?}");
    kept[0].clone()
}

/// HSLM-A1's axle offsets from the standard's spacings (3, 11, 3, 3.525, d, D − 1.5d − 1.7625,
/// then d, D − d per coach, and the mirror), written independently of the tool's positions.
fn a1_offsets() -> Vec<f64> {
    let (n, d_coach, d) = (18, 18.0, 2.0);
    let mut spacings = vec![3.0, 11.0, 3.0, 3.525, d, d_coach - 1.5 * d - 1.7625];
    for _ in 0..n {
        spacings.extend([d, d_coach - d]);
    }
    spacings.extend([d, d_coach - 1.5 * d - 1.7625, d, 3.525, 3.0, 11.0, 3.0]);
    let mut offsets = vec![0.0];
    for sp in spacings {
        offsets.push(offsets.last().unwrap() + sp);
    }
    assert_eq!(offsets.len(), 2 * n + 14);
    offsets
}

/// `tbi run` of `text` in `dir`; the peak deck vertical acceleration at probe `mid`.
fn run_peak(dir: &Path, text: &str, extra: &[&str]) -> f64 {
    let s = scenario(dir, text);
    run_checked(
        tbi_command()
            .arg("run")
            .arg(&s)
            .args(extra)
            .args(["--quiet", "--out"])
            .arg(dir.join("out")),
    );
    read_summary(&dir.join("out"))["probes"]["mid"]["vertical_acceleration_max_m_s2"]
        .as_f64()
        .unwrap()
}

#[test]
fn hslm_a1_peaks_at_the_resonance_speed_and_equals_its_axles_typed_in() {
    let dir = scratch("sweep-hslm");
    let s = scenario(&dir, SPAN);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "200:420:5", "--trains", "A1", "--out"])
            .arg(dir.join("sweep")),
    );
    let rows = envelope(&dir.join("sweep/envelope.csv"));
    assert_eq!(rows.len(), 45, "200, 205, …, 420 km/h");
    let peak = rows.iter().max_by(|a, b| a.2.total_cmp(&b.2)).unwrap();
    // closed forms: f₁ of the span, resonance v = f₁ D
    let (l, ei, m): (f64, f64, f64) = (25.0, 3.5e10 * 1.696, 15000.0);
    let f1 = std::f64::consts::PI / (2.0 * l * l) * (ei / m).sqrt();
    let resonance_kmh = f1 * 18.0 * 3.6;
    println!(
        "peak deck acceleration {:.3} m/s² at {} km/h; resonance v = f₁ D = {resonance_kmh:.1} km/h",
        peak.2, peak.1
    );
    assert!(
        (peak.1 - resonance_kmh).abs() <= 0.02 * resonance_kmh,
        "peak at {} km/h, resonance {resonance_kmh} km/h",
        peak.1
    );
    // well above the response away from resonance
    let off = rows.iter().find(|r| r.1 == 250.0).unwrap();
    assert!(peak.2 > 3.0 * off.2, "{} vs {} at 250 km/h", peak.2, off.2);
    // and the second resonance at f₁ D / 2
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "140:190:2", "--trains", "A1", "--out"])
            .arg(dir.join("second")),
    );
    let rows2 = envelope(&dir.join("second/envelope.csv"));
    let peak2 = rows2.iter().max_by(|a, b| a.2.total_cmp(&b.2)).unwrap();
    println!(
        "second peak at {} km/h; f₁ D / 2 = {:.1} km/h",
        peak2.1,
        resonance_kmh / 2.0
    );
    assert!(
        (peak2.1 - resonance_kmh / 2.0).abs() <= 0.03 * resonance_kmh / 2.0,
        "second peak at {} km/h, f₁ D / 2 = {} km/h",
        peak2.1,
        resonance_kmh / 2.0
    );

    // the same case with the axles typed in from the standard's spacings
    let axles: Vec<String> = a1_offsets()
        .iter()
        .map(|x| format!("{{ offset_m = {x:?}, load_n = 170000.0 }}"))
        .collect();
    let typed = SPAN.replace(
        "kind = \"hslm_a\"\nname = \"A1\"",
        &format!("kind = \"moving_force\"\naxles = [{}]", axles.join(", ")),
    );
    // a stale lateral figure in the folder, which this vertical beam must not leave behind
    std::fs::create_dir_all(dir.join("typed/out")).unwrap();
    std::fs::write(dir.join("typed/out/deck_lateral.svg"), "<svg/>").unwrap();
    let a = run_peak(&dir.join("typed"), &typed, &["--speed-kmh", "300"]);
    assert!(dir.join("typed/out/deck_vertical.svg").is_file());
    assert!(
        !dir.join("typed/out/deck_lateral.svg").exists(),
        "no lateral figure for a deck without lateral motion"
    );
    // the run kept for A1 (its case of largest deck acceleration)
    let kept = kept_run(&dir.join("sweep/A1"));
    assert!(!kept.join("deck_lateral.svg").exists());
    assert!(kept.join("deck_vertical.svg").is_file());
    let row = rows.iter().find(|r| r.1 == 300.0).unwrap();
    assert!(
        (a - row.2).abs() <= 1e-9 * a,
        "typed-in axles {a} m/s², envelope {} m/s²",
        row.2
    );
}

#[test]
fn all_ten_trains_and_refusals() {
    let dir = scratch("sweep-hslm-all");
    let s = scenario(&dir, SPAN);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "300", "--trains", "hslm-a", "--out"])
            .arg(dir.join("all")),
    );
    let rows = envelope(&dir.join("all/envelope.csv"));
    let names: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
    assert_eq!(
        names,
        ["A1", "A2", "A3", "A4", "A5", "A6", "A7", "A8", "A9", "A10"]
    );
    assert!(rows.iter().all(|r| r.2 > 0.0 && r.3 > 0.0));
    for (args, needle) in [
        (["--speeds", "300", "--trains", "A11"], "--trains A11"),
        (
            ["--speeds", "300:200:5", "--trains", "A1"],
            "--speeds 300:200:5",
        ),
        (
            ["--speeds", "300,300", "--trains", "A1"],
            "300 km/h is given twice",
        ),
    ] {
        let r = run(tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(args)
            .arg("--out")
            .arg(dir.join("bad")));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!dir.join("bad/envelope.csv").exists());
    }
}

/// `damping = { rule = "en1991-2", … }`: the ratio of Table 6.6 plus eq. (6.13) for the 25 m
/// span, printed in the summary and used exactly as a `damping_ratio` of that value.
#[test]
fn the_en1991_damping_rule_is_applied_and_reported() {
    let dir = scratch("damping-rule");
    // Table 6.6, prestressed concrete, L ≥ 20 m: 1.0 %; eq. (6.13) at L = 25 m
    let l: f64 = 25.0;
    let extra =
        (0.0187 * l - 0.00064 * l * l) / (1.0 - 0.0441 * l - 0.0044 * l * l + 0.000255 * l * l * l);
    let ratio = (1.0 + extra) / 100.0;
    let ruled = SPAN.replace(
        "damping_ratio = 0.01",
        "damping = { rule = \"en1991-2\", structure = \"prestressed_concrete\" }",
    );
    let plain = SPAN.replace(
        "damping_ratio = 0.01",
        &format!("damping_ratio = {ratio:?}"),
    );
    let mut peaks = Vec::new();
    for (label, text) in [("ruled", &ruled), ("plain", &plain)] {
        let s = scenario(&dir.join(label), text);
        run_checked(
            tbi_command()
                .arg("run")
                .arg(&s)
                .args(["--quiet", "--out"])
                .arg(dir.join(label).join("out")),
        );
        let summary = read_summary(&dir.join(label).join("out"));
        peaks.push(
            summary["probes"]["mid"]["vertical_acceleration_max_m_s2"]
                .as_f64()
                .unwrap(),
        );
        if label == "ruled" {
            let d = &summary["bridge"]["damping"];
            assert_eq!(d["structure"], "prestressed_concrete");
            assert_eq!(d["minimum_percent"].as_f64(), Some(1.0));
            assert!((d["additional_percent"].as_f64().unwrap() - extra).abs() < 1e-12);
            assert!((d["ratio"].as_f64().unwrap() - ratio).abs() < 1e-15);
        } else {
            assert!(summary["bridge"].get("damping").is_none());
        }
    }
    assert_eq!(peaks[0], peaks[1], "the rule's ratio is the damping used");
    // refused: both ways at once, an unknown structure
    for (edit, needle) in [
        ("damping_ratio = 0.01\ndamping = { rule = \"en1991-2\", structure = \"prestressed_concrete\" }", "bridge.damping_ratio"),
        ("damping = { rule = \"en1991-2\", structure = \"timber\" }", "bridge.damping.structure"),
    ] {
        let s = scenario(&dir.join("bad"), &SPAN.replace("damping_ratio = 0.01", edit));
        let r = run(tbi_command().arg("run").arg(&s).args(["--quiet", "--out"]).arg(dir.join("bad/out")));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "{err}");
    }
}

/// The static displacement of the envelope equals the closed-form influence line of the
/// simply supported beam (δ(x, a) = b x (L² − b² − x²)/(6 E I L) for x ≤ a, b = L − a, and
/// its mirror) summed over the axles and maximised over the train's positions, to 0.5 %
/// (the three modes kept miss 0.1 % of it); at a crawl the dynamic enhancement φ'dyn is
/// small, and the report's checks and resonance speeds are printed.
#[test]
fn static_displacement_and_dynamic_enhancement() {
    let dir = scratch("sweep-hslm-static");
    let s = scenario(&dir, SPAN);
    let out = run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "30,325", "--trains", "A1", "--out"])
            .arg(dir.join("sweep")),
    );
    let stdout = text(&out.stdout);
    let rows = envelope(&dir.join("sweep/envelope.csv"));
    let (l, ei, x): (f64, f64, f64) = (25.0, 3.5e10 * 1.696, 12.5);
    let influence = |a: f64| {
        let (x, a) = if x <= a { (x, a) } else { (l - x, l - a) };
        let b = l - a;
        b * x * (l * l - b * b - x * x) / (6.0 * ei * l)
    };
    let offsets = a1_offsets();
    let mut best = 0.0_f64;
    let mut head = 0.0;
    while head <= l + offsets.last().unwrap() {
        let y: f64 = offsets
            .iter()
            .map(|o| head - o)
            .filter(|a| (0.0..=l).contains(a))
            .map(|a| 170e3 * influence(a))
            .sum();
        best = best.max(y);
        head += 0.05;
    }
    for r in &rows {
        assert!(
            (r.4 - best).abs() <= 5e-3 * best,
            "static {} m vs closed form {best} m",
            r.4
        );
    }
    let crawl = rows.iter().find(|r| r.1 == 30.0).unwrap();
    let resonance = rows.iter().find(|r| r.1 == 325.0).unwrap();
    assert!(crawl.5.abs() < 0.05, "φ'dyn at 30 km/h = {}", crawl.5);
    assert!((crawl.5 - (crawl.3 / crawl.4 - 1.0)).abs() < 1e-12);
    assert!(resonance.5 > 1.0, "φ'dyn at resonance = {}", resonance.5);
    assert!(
        stdout.contains("FAIL: deck vertical acceleration (ballasted track): "),
        "{stdout}"
    );
    let html = std::fs::read_to_string(dir.join("sweep/report.html")).unwrap();
    assert!(
        html.contains("Resonance speeds f₁ D / i in the range"),
        "report"
    );
}

/// `report.html` is one self-contained file that a headless Chromium renders without a
/// console message, with its four charts, the checks and the table of maxima.
#[test]
fn the_report_renders_in_a_headless_browser() {
    let dir = scratch("sweep-report");
    let s = scenario(&dir, SPAN);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "300:340:10", "--trains", "A1,A6", "--out"])
            .arg(dir.join("sweep")),
    );
    let report = dir.join("sweep/report.html");
    let html = std::fs::read_to_string(&report).unwrap();
    tbi_tests::browser::assert_self_contained(&html);
    let out = tbi_tests::browser::open(
        &report,
        &dir.join("chromium-profile"),
        &["--dump-dom".to_string()],
    );
    let (dom, log) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "chromium failed:\n{log}");
    assert!(!log.contains("CONSOLE"), "console messages:\n{log}");
    assert_eq!(dom.matches("<svg").count(), 4, "four charts");
    assert!(
        dom.contains("Deck vertical acceleration") && dom.contains("Governing deck acceleration")
    );
    assert_eq!(
        dom.matches("class=\"check\"").count(),
        3,
        "deck acceleration, modes, LM71 deflection"
    );
    assert!(
        dom.contains("<td>A1</td>") && dom.contains("<td>A6</td>"),
        "the table of maxima"
    );
    assert!(
        dom.contains(
            "<td>deck vertical acceleration (ballasted track)</td><td class=\"fail\">FAIL</td>"
        ),
        "A1 at 325 km/h is over 3.5 m/s²"
    );
}

/// Exact response of q'' + 2ζω q' + ω² q = f₀ sin(Ω τ) for 0 ≤ τ ≤ T from rest, then free
/// vibration: (q, q') at τ (q = 0 for τ < 0).
fn sdof(omega: f64, zeta: f64, f0: f64, big: f64, t_force: f64, tau: f64) -> (f64, f64) {
    if tau <= 0.0 {
        return (0.0, 0.0);
    }
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let forced = |t: f64| -> (f64, f64) {
        let d = (omega * omega - big * big).powi(2) + (2.0 * zeta * omega * big).powi(2);
        let a = f0 * (omega * omega - big * big) / d;
        let b = -f0 * 2.0 * zeta * omega * big / d;
        let c1 = -b;
        let c2 = (zeta * omega * c1 - a * big) / wd;
        let e = (-zeta * omega * t).exp();
        let (s, c) = (wd * t).sin_cos();
        let x = a * (big * t).sin() + b * (big * t).cos() + e * (c1 * c + c2 * s);
        let xd = a * big * (big * t).cos() - b * big * (big * t).sin()
            + e * (-zeta * omega * (c1 * c + c2 * s) + wd * (-c1 * s + c2 * c));
        (x, xd)
    };
    if tau <= t_force {
        return forced(tau);
    }
    let (x0, v0) = forced(t_force);
    let t = tau - t_force;
    let e = (-zeta * omega * t).exp();
    let (s, c) = (wd * t).sin_cos();
    let b = (v0 + zeta * omega * x0) / wd;
    let x = e * (x0 * c + b * s);
    let xd = e * (-zeta * omega * (x0 * c + b * s) + wd * (-x0 * s + b * c));
    (x, xd)
}

/// HSLM-A1 as moving forces on the 25 m span against the exact modal series summed over its
/// 50 axles (three sine modes, 1 % damping, every axle entering at its own time): peak
/// midspan displacement and acceleration within 0.5 % at resonance (v = f₁ D = 324 km/h)
/// and off it (250 km/h).
#[test]
fn hslm_a1_equals_the_exact_modal_series_over_its_axles() {
    let dir = scratch("hslm-exact");
    let fine = SPAN
        .replace("dt_s = 0.001", "dt_s = 0.0002")
        .replace("output_every = 10", "output_every = 1");
    let s = scenario(&dir, &fine);
    let (l, ei, m, zeta): (f64, f64, f64, f64) = (25.0, 3.5e10 * 1.696, 15000.0, 0.01);
    let offsets = a1_offsets();
    for v_kmh in [324.0, 250.0] {
        let out = dir.join(format!("v{v_kmh}"));
        run_checked(
            tbi_command()
                .arg("run")
                .arg(&s)
                .args(["--speed-kmh", &v_kmh.to_string(), "--quiet", "--out"])
                .arg(&out),
        );
        let summary = read_summary(&out);
        let probe = &summary["probes"]["mid"];
        let ours_y = probe["vertical_displacement_max_m"].as_f64().unwrap();
        let ours_a = probe["vertical_acceleration_max_m_s2"].as_f64().unwrap();
        let t_end = summary["simulated_time_s"].as_f64().unwrap();
        let v = v_kmh / 3.6;
        let (mut y_max, mut a_max) = (0.0_f64, 0.0_f64);
        let steps = (t_end / 1e-4).round() as usize;
        for k in 0..=steps {
            let t = k as f64 * 1e-4;
            let (mut y, mut a) = (0.0, 0.0);
            for n in 1..=3 {
                let nf = n as f64;
                let omega = (nf * std::f64::consts::PI / l).powi(2) * (ei / m).sqrt();
                let big = nf * std::f64::consts::PI * v / l;
                let f0 = 2.0 * 170e3 / (m * l);
                let (mut q, mut qd, mut force) = (0.0, 0.0, 0.0);
                for o in &offsets {
                    let tau = t - o / v;
                    let (x, xd) = sdof(omega, zeta, f0, big, l / v, tau);
                    q += x;
                    qd += xd;
                    if tau > 0.0 && tau <= l / v {
                        force += f0 * (big * tau).sin();
                    }
                }
                let qdd = force - 2.0 * zeta * omega * qd - omega * omega * q;
                let shape = (nf * std::f64::consts::PI / 2.0).sin();
                y += shape * q;
                a += shape * qdd;
            }
            y_max = y_max.max(y.abs());
            a_max = a_max.max(a.abs());
        }
        println!(
            "{v_kmh} km/h: displacement {ours_y:.6e} vs exact {y_max:.6e}, acceleration {ours_a:.5} vs exact {a_max:.5}"
        );
        assert!(
            (ours_y - y_max).abs() <= 5e-3 * y_max,
            "{v_kmh} km/h displacement"
        );
        assert!(
            (ours_a - a_max).abs() <= 5e-3 * a_max,
            "{v_kmh} km/h acceleration"
        );
    }
}

/// `train = { kind = "moving_force", file = "axles.csv" }`: a user train as a CSV of axles
/// gives the run of the same axles typed into the scenario (also when a spreadsheet put a
/// byte-order mark before the header); an empty or malformed file, or a negative load, is
/// refused with its line.
#[test]
fn a_train_from_an_axles_csv() {
    let dir = scratch("axles-csv");
    let axles = [(0.0, 170e3), (3.0, 170e3), (14.0, 150e3), (17.0, 150e3)];
    let mut csv = String::from("offset_m,load_n\n");
    for (o, p) in axles {
        csv.push_str(&format!("{o},{p}\n"));
    }
    std::fs::create_dir_all(dir.join("file")).unwrap();
    std::fs::write(dir.join("file/axles.csv"), format!("\u{feff}{csv}")).unwrap();
    let from_file = SPAN.replace(
        "kind = \"hslm_a\"\nname = \"A1\"",
        "kind = \"moving_force\"\nfile = \"axles.csv\"",
    );
    let typed = SPAN.replace(
        "kind = \"hslm_a\"\nname = \"A1\"",
        &format!(
            "kind = \"moving_force\"\naxles = [{}]",
            axles
                .iter()
                .map(|(o, p)| format!("{{ offset_m = {o:?}, load_n = {p:?} }}"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    assert_eq!(
        run_peak(&dir.join("file"), &from_file, &[]),
        run_peak(&dir.join("typed"), &typed, &[])
    );
    for (content, needle) in [
        ("", "axles.csv:1: the file is empty"),
        (
            "offset_m,load_n\n0,170000\n3,abc\n",
            "axles.csv:3: load_n `abc` is not a number",
        ),
        (
            "offset_m,load_n\n0,170000,1\n",
            "axles.csv:2: `0,170000,1` has 3 fields",
        ),
        (
            "position,force\n0,1\n",
            "axles.csv:1: the header is `position,force`",
        ),
        (
            "offset_m,load_n\n",
            "axles.csv:1: no axles after the header",
        ),
        (
            "offset_m,load_n\n0,170000\n3,-170000\n",
            "axles.csv:3: load_n = -170000 is negative",
        ),
    ] {
        std::fs::write(dir.join("file/axles.csv"), content).unwrap();
        let r = run(tbi_command()
            .arg("run")
            .arg(dir.join("file/span.toml"))
            .args(["--quiet", "--out"])
            .arg(dir.join("file/bad")));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "expected {needle:?} in {err}");
        assert!(!dir.join("file/bad/summary.json").exists());
    }
}

/// `kind = "beam"`: two equal continuous spans; the first two frequencies of the run's
/// bridge equal the closed forms (π/L)² √(EI/m) and (3.9266/L)² √(EI/m) over 2π, to 0.1 %;
/// as a chain of simply supported spans both first modes are the single span's; a zero span
/// is refused by name.
#[test]
fn a_two_span_continuous_beam() {
    let dir = scratch("two-span");
    let two = SPAN
        .replace(
            "kind = \"simply_supported\"\nspan_m = 25.0",
            "kind = \"beam\"\nspans_m = [20.0, 20.0]",
        )
        .replace("modes = 3", "modes = 4");
    let s = scenario(&dir, &two);
    run_checked(
        tbi_command()
            .arg("run")
            .arg(&s)
            .args(["--quiet", "--out"])
            .arg(dir.join("out")),
    );
    let summary = read_summary(&dir.join("out"));
    let f: Vec<f64> = summary["bridge"]["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let c = (3.5e10_f64 * 1.696 / 15000.0).sqrt() / (2.0 * std::f64::consts::PI);
    let f1 = (std::f64::consts::PI / 20.0).powi(2) * c;
    let f2 = (3.926_602_312_f64 / 20.0).powi(2) * c;
    assert!((f[0] / f1 - 1.0).abs() < 1e-3, "{f:?} vs {f1}");
    assert!((f[1] / f2 - 1.0).abs() < 1e-3, "{f:?} vs {f2}");
    assert_eq!(summary["bridge"]["length_m"].as_f64(), Some(40.0));
    // a chain of the same two spans: both first modes are the single span's
    let chain = scenario(
        &dir.join("chain"),
        &two.replace(
            "spans_m = [20.0, 20.0]",
            "spans_m = [20.0, 20.0]\nsupports = \"simply_supported\"",
        ),
    );
    run_checked(
        tbi_command()
            .arg("run")
            .arg(&chain)
            .args(["--quiet", "--out"])
            .arg(dir.join("chain/out")),
    );
    let g = read_summary(&dir.join("chain/out"))["bridge"]["frequencies_hz"].clone();
    for k in [0, 1] {
        let fk = g[k].as_f64().unwrap();
        assert!((fk / f1 - 1.0).abs() < 1e-3, "chain: {g} vs {f1}");
    }
    let bad = scenario(
        &dir.join("bad"),
        &two.replace("[20.0, 20.0]", "[20.0, 0.0]"),
    );
    let r = run(tbi_command()
        .arg("run")
        .arg(&bad)
        .args(["--quiet", "--out"])
        .arg(dir.join("bad/out")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("bridge.spans_m[1]"), "{err}");
}

/// Without `--speeds`, a trains sweep runs EN 1991-2's range: 144 km/h (40 m/s) to 1.2 × the
/// scenario's line speed (300 km/h here) in 2.5 km/h steps.
#[test]
fn the_default_speed_range_of_a_trains_sweep() {
    let dir = scratch("sweep-default-speeds");
    let s = scenario(&dir, SPAN);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--trains", "A1", "--out"])
            .arg(dir.join("sweep")),
    );
    let rows = envelope(&dir.join("sweep/envelope.csv"));
    let speeds: Vec<f64> = rows.iter().map(|r| r.1).collect();
    assert_eq!(speeds.len(), 87, "{speeds:?}");
    assert_eq!(speeds[0], 144.0);
    assert_eq!(*speeds.last().unwrap(), 359.0);
}

/// `run` a scenario expected to be refused; its stderr.
fn refused(dir: &Path, text: &str) -> String {
    let s = scenario(dir, text);
    let r = run(tbi_command()
        .arg("run")
        .arg(&s)
        .args(["--quiet", "--out"])
        .arg(dir.join("out")));
    let err = tbi_tests::text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(!dir.join("out/summary.json").exists());
    err
}

const VEHICLE: &str =
    "vehicle = { model = \"sprung_mass\", frequency_hz = 1.0, damping_ratio = 0.1, wheel_mass_kg = 2000.0 }";

/// HSLM-A1 with a sprung mass under every axle (`train.vehicle`), the sweep's comfort check.
/// At a crawl (5 km/h) the deck displacement equals the static displacement of the 170 kN
/// axles (the envelope's, equal to the closed-form influence line in
/// `static_displacement_and_dynamic_enhancement`) to 0.1 %: the sprung masses carry each
/// axle's load (m_s + m_w = P / g). The envelope's car-body column equals the
/// `tbi run` of the same case, the check is printed against EN 1990 Table A2.9 and appears in
/// the report.
#[test]
fn hslm_a_as_sprung_masses_and_the_comfort_check() {
    let dir = scratch("sweep-hslm-vehicle");
    let with = SPAN
        .replace("name = \"A1\"", &format!("name = \"A1\"\n{VEHICLE}"))
        .replace("dt_s = 0.001", "dt_s = 0.002");
    let s = scenario(&dir, &with);
    let out = run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args([
                "--speeds",
                "5,325",
                "--trains",
                "A1",
                "--comfort",
                "good",
                "--out",
            ])
            .arg(dir.join("sweep")),
    );
    let stdout = text(&out.stdout);
    let rows = envelope(&dir.join("sweep/envelope.csv"));
    let crawl = &rows[0];
    assert_eq!(crawl.1, 5.0);
    assert!(
        (crawl.3 / crawl.4 - 1.0).abs() < 1e-3,
        "sprung masses {} m vs static {} m",
        crawl.3,
        crawl.4
    );
    // moving forces have no car-body column
    let forces = scenario(&dir.join("forces"), SPAN);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&forces)
            .args(["--speeds", "325", "--trains", "A1", "--out"])
            .arg(dir.join("forces/sweep")),
    );
    let plain = envelope(&dir.join("forces/sweep/envelope.csv"));
    assert!(plain.iter().all(|r| r.6.is_none()), "{plain:?}");
    let body = rows[1].6.expect("a car-body column with vehicles");
    assert!(body > 0.0, "{rows:?}");
    // the same case as one run
    let case = with.replace("speed_kmh = 300.0", "speed_kmh = 325.0");
    run_peak(&dir.join("one"), &case, &[]);
    let summary = read_summary(&dir.join("one/out"));
    assert_eq!(summary["train"]["wheelsets"].as_u64(), Some(50));
    let run_body = summary["vehicles"]["vertical_acceleration_max_m_s2"]
        .as_f64()
        .unwrap();
    assert!(
        (run_body / body - 1.0).abs() < 1e-9,
        "run {run_body} vs envelope {body}"
    );
    assert!(
        stdout.contains("car-body vertical acceleration (good comfort): "),
        "{stdout}"
    );
    let html = std::fs::read_to_string(dir.join("sweep/report.html")).unwrap();
    assert!(html.contains("Car-body vertical acceleration"), "report");
    assert!(html.contains("a sprung mass under every axle"), "report");
    // refusals, by field and value
    let bad = |name: &str, from: &str, to: &str, needles: &[&str]| {
        let err = refused(&dir.join(name), &with.replace(from, to));
        for n in needles {
            assert!(err.contains(n), "{name}: expected {n:?} in {err}");
        }
    };
    bad(
        "model",
        "model = \"sprung_mass\"",
        "model = \"bogie\"",
        &["train.vehicle.model", "\"bogie\""],
    );
    bad(
        "frequency",
        "frequency_hz = 1.0",
        "frequency_hz = 0.0",
        &["train.vehicle.frequency_hz", "0"],
    );
    bad(
        "wheel",
        "wheel_mass_kg = 2000.0",
        "wheel_mass_kg = 20000.0",
        &["train.vehicle", "leaves no sprung mass", "170000"],
    );
    bad(
        "unknown",
        "damping_ratio = 0.1",
        "damping = 0.1",
        &["train.vehicle", "damping"],
    );
    let coach = refused(
        &dir.join("coach"),
        &SPAN.replace(
            "kind = \"hslm_a\"\nname = \"A1\"",
            &format!("kind = \"coach_27dof\"\n{VEHICLE}"),
        ),
    );
    assert!(
        coach.contains("train.vehicle") && coach.contains("does not apply to kind \"coach_27dof\""),
        "{coach}"
    );
    let err = text(
        &run(tbi_command()
            .arg("sweep")
            .arg(&s)
            .args([
                "--speeds",
                "300",
                "--trains",
                "A1",
                "--comfort",
                "fair",
                "--out",
            ])
            .arg(dir.join("fair")))
        .stderr,
    );
    assert!(err.contains("--comfort fair"), "{err}");
}

/// HSLM-B on a 5 m span: N = 10 forces of 170 kN at d = 3.5 m equal the same forces typed in
/// as `moving_force` axles; missing or bad N and d are refused by name.
#[test]
fn hslm_b_equals_its_forces_typed_in() {
    let dir = scratch("hslm-b");
    let short = SPAN
        .replace("span_m = 25.0", "span_m = 5.0")
        .replace("x_m = 12.5", "x_m = 2.5")
        .replace("dt_s = 0.001", "dt_s = 0.0005");
    let b = short.replace(
        "kind = \"hslm_a\"\nname = \"A1\"",
        "kind = \"hslm_b\"\nforces = 10\nspacing_m = 3.5",
    );
    let axles: Vec<String> = (0..10)
        .map(|i| format!("{{ offset_m = {}, load_n = 170000.0 }}", 3.5 * i as f64))
        .collect();
    let typed = short.replace(
        "kind = \"hslm_a\"\nname = \"A1\"",
        &format!("kind = \"moving_force\"\naxles = [{}]", axles.join(", ")),
    );
    let a = run_peak(&dir.join("b"), &b, &[]);
    let t = run_peak(&dir.join("typed"), &typed, &[]);
    assert!(
        a > 0.0 && (a / t - 1.0).abs() < 1e-12,
        "HSLM-B {a} vs typed {t}"
    );
    assert_eq!(
        read_summary(&dir.join("b/out"))["train"]["wheelsets"].as_u64(),
        Some(10)
    );
    for (name, from, to, needles) in [
        (
            "missing",
            "forces = 10\n",
            "",
            &["train.forces", "(missing)"][..],
        ),
        (
            "zero",
            "forces = 10",
            "forces = 0",
            &["train.forces", "at least 1"],
        ),
        (
            "spacing",
            "spacing_m = 3.5",
            "spacing_m = -3.5",
            &["train.spacing_m", "-3.5"],
        ),
        (
            "name",
            "forces = 10",
            "forces = 10\nname = \"A1\"",
            &["train.name", "does not apply to kind \"hslm_b\""],
        ),
    ] {
        let err = refused(&dir.join(name), &b.replace(from, to));
        for n in needles {
            assert!(err.contains(n), "{name}: expected {n:?} in {err}");
        }
    }
}

/// EN 1990 A2.4.4.2.1 considers the modes up to max(30 Hz, 1.5 f₁, f₃): of the 25 m span's
/// six modes (5, 20, 45, 80 … Hz) the sweep keeps three, equal to a sweep of the span given
/// three modes; `--all-modes` keeps all six.
#[test]
fn a_trains_sweep_keeps_the_modes_en1990_considers() {
    let dir = scratch("sweep-modes");
    let six = scenario(&dir.join("six"), &SPAN.replace("modes = 3", "modes = 6"));
    let three = scenario(&dir.join("three"), SPAN);
    let sweep = |s: &Path, out: &str, extra: &[&str]| {
        let o = run_checked(
            tbi_command()
                .arg("sweep")
                .arg(s)
                .args(["--speeds", "250,325", "--trains", "A1"])
                .args(extra)
                .arg("--out")
                .arg(dir.join(out)),
        );
        (
            text(&o.stdout),
            envelope(&dir.join(out).join("envelope.csv")),
        )
    };
    let (said, kept) = sweep(&six, "kept", &[]);
    assert!(said.contains("span-25m: 3 modes kept, up to 45."), "{said}");
    let (_, given) = sweep(&three, "given", &[]);
    assert_eq!(kept, given);
    let (said, all) = sweep(&six, "all", &["--all-modes"]);
    assert!(said.contains("span-25m: 6 modes kept"), "{said}");
    assert_ne!(all, given);
    let summary = read_summary(&kept_run(&dir.join("all/A1")));
    assert_eq!(summary["bridge"]["modes_rule"], "all");
    assert_eq!(summary["bridge"]["modes"].as_u64(), Some(6));
}

/// `bridge.sections`: a chain of a 20 m and a 15 m span with sections of their own has the
/// union of the two simply supported spans' closed forms fₙ = (nπ/L)² √(EI/m) / 2π as its
/// frequencies, to 0.1 %; a section list of the wrong length or with an unknown key is
/// refused by name.
#[test]
fn a_chain_of_spans_with_sections_of_their_own() {
    let dir = scratch("beam-sections");
    let chain = SPAN
        .replace(
            "kind = \"simply_supported\"\nspan_m = 25.0",
            "kind = \"beam\"\nspans_m = [20.0, 15.0]\nsupports = \"simply_supported\"\n\
             sections = [{ inertia_vertical_m4 = 1.2 }, { youngs_modulus_pa = 3.0e10, inertia_vertical_m4 = 0.5, mass_per_length_kg_m = 9000.0 }]",
        )
        .replace("modes = 3", "modes = 4\nmodes_rule = \"all\"");
    run_peak(&dir.join("ok"), &chain, &[]);
    let f: Vec<f64> = read_summary(&dir.join("ok/out"))["bridge"]["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let closed = |n: f64, l: f64, ei: f64, m: f64| {
        (n * std::f64::consts::PI / l).powi(2) * (ei / m).sqrt() / (2.0 * std::f64::consts::PI)
    };
    let mut expected: Vec<f64> = (1..=3)
        .flat_map(|n| {
            [
                closed(n as f64, 20.0, 3.5e10 * 1.2, 15000.0),
                closed(n as f64, 15.0, 3.0e10 * 0.5, 9000.0),
            ]
        })
        .collect();
    expected.sort_by(f64::total_cmp);
    assert_eq!(f.len(), 4);
    for (g, e) in f.iter().zip(&expected) {
        assert!((g / e - 1.0).abs() < 1e-3, "{f:?} vs {expected:?}");
    }
    let err = refused(
        &dir.join("count"),
        &chain.replace("[20.0, 15.0]", "[20.0, 15.0, 10.0]"),
    );
    assert!(
        err.contains("bridge.sections") && err.contains("3 spans"),
        "{err}"
    );
    let err = refused(
        &dir.join("key"),
        &chain.replace("{ inertia_vertical_m4 = 1.2 }", "{ inertia_m4 = 1.2 }"),
    );
    assert!(err.contains("inertia_m4"), "{err}");
    let err = refused(
        &dir.join("value"),
        &chain.replace(
            "{ inertia_vertical_m4 = 1.2 }",
            "{ inertia_vertical_m4 = -1.2 }",
        ),
    );
    assert!(
        err.contains("bridge.sections[0].inertia_vertical_m4") && err.contains("-1.2"),
        "{err}"
    );
}
