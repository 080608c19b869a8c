//! The mean wind on the deck (`[wind]`, `tbi run --wind-speed`).
//!
//! * On the Tsing Ma model, the static lateral displacement of the deck under the uniform drag
//!   by modal superposition (Σ φₙ(x) Sₙ / ωₙ² with the modes kept, the bridge's state at
//!   t = 0) agrees with a direct static solution `K u = f` of the FE model under the same load,
//!   to within the truncation of the modes: the difference falls as modes are added (10, 20,
//!   50), and is under 0.5 % with 50 modes.
//! * Co-simulation of a case with wind equals the monolithic solver to 1e-8 per history
//!   column; the first history row is the static response.
//! * Bad wind input is refused by field and value.

use tbi::scenario::Scenario;

/// Lateral deck displacement at `x` by modal superposition of the steady response with the
/// default scenario's bridge (the Tsing Ma preset) reduced to `modes` modes.
fn modal_static(modes: usize, u: f64, x: f64) -> (f64, [f64; 3]) {
    let mut s = Scenario::default_case();
    s.bridge.set_modes(modes);
    s.set_wind_speed(u).unwrap();
    let model = tbi::model::build(&s).unwrap();
    let b = &model.bridge;
    let q = b.steady_response();
    let mut phi = vec![[0.0; 3]; b.n_modes()];
    b.deck_shapes(x, &mut phi);
    let y: f64 = phi.iter().zip(&q).map(|(p, q)| p[0] * q).sum();
    (y, s.wind.unwrap().deck_load())
}

/// The scenario of `text` (named `label`) run into a scratch folder: it and its history.
fn run_text(text: &str, label: &str) -> (Scenario, tbi_tests::Table) {
    let s = Scenario::from_toml(text, &format!("{label}.toml"), std::path::Path::new(".")).unwrap();
    let out = tbi_tests::scratch(label).join("run");
    tbi::solve::run_scenario(&s, &out, false, &tbi::model::Limits::none()).unwrap();
    (s, tbi_tests::Table::read(&out.join("history.csv")))
}

#[test]
fn mean_wind_on_the_tsing_ma_deck_modal_against_direct_static() {
    let (u, x) = (25.0, 1141.0);
    let fe = tbi_fe::FeModel::build(&tbi::model::suspension::preset_params(
        tbi::scenario::SuspensionPreset::TsingMa,
    ))
    .unwrap();
    let (_, load) = modal_static(20, u, x);
    let (start, end) = (fe.deck_x()[0], *fe.deck_x().last().unwrap());
    // the uniform drag as point loads every 0.5 m (midpoint rule; consistent nodal loads)
    let n = ((end - start) / 0.5).round() as usize;
    let dx = (end - start) / n as f64;
    let loads: Vec<tbi_fe::statics::DeckLoad> = (0..n)
        .map(|i| tbi_fe::statics::DeckLoad {
            x: start + (i as f64 + 0.5) * dx,
            lateral: load[0] * dx,
            vertical: 0.0,
            torque: 0.0,
        })
        .collect();
    let direct = fe.static_deck_deflection(&loads, &[x]).unwrap()[0].lateral;
    assert!(direct > 0.05, "lateral static displacement {direct} m");
    let mut errors = Vec::new();
    for modes in [10, 20, 50] {
        let (y, _) = modal_static(modes, u, x);
        errors.push(((y - direct) / direct).abs());
    }
    eprintln!("direct {direct} m; relative differences with 10, 20, 50 modes: {errors:?}");
    // measured: 1.7 %, 0.35 %, 0.22 %
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 0.005, "{errors:?}");
}

#[test]
fn bad_wind_input_is_refused_by_name() {
    let base = tbi::scenario::DEFAULT_SCENARIO;
    let with = |table: &str| format!("{base}\n[wind]\n{table}\n");
    let refused = |text: String, needles: &[&str]| {
        let e = Scenario::from_toml(&text, "w.toml", std::path::Path::new("."))
            .unwrap_err()
            .to_string();
        for n in needles {
            assert!(e.contains(n), "{n:?} not in {e}");
        }
    };
    refused(
        with("mean_speed_m_s = -3.0"),
        &["w.toml", "wind.mean_speed_m_s", "-3"],
    );
    refused(
        with("mean_speed_m_s = 300.0"),
        &["wind.mean_speed_m_s", "300"],
    );
    refused(
        with("mean_speed_m_s = 20.0\nair_density_kg_m3 = 0.0"),
        &["wind.air_density_kg_m3", "0"],
    );
    refused(with("mean_speed_m_s = 20.0\ngust = 3.0"), &["gust"]);
    refused(
        with("mean_speed_m_s = 20.0\ndeck = { width_m = -41.0, drag = 0.1 }"),
        &["wind.deck.width_m", "-41"],
    );
    refused(
        with("mean_speed_m_s = 20.0\ndeck = { width_m = 41.0, drag = nan }"),
        &["wind.deck.drag", "NaN"],
    );
    refused(
        with("mean_speed_m_s = 20.0\nturbulence = { intensity_u = -0.1 }"),
        &["wind.turbulence.intensity_u", "-0.1"],
    );
    refused(
        with("mean_speed_m_s = 20.0\nturbulence = { spectrum = \"davenport\" }"),
        &["w.toml", "davenport"],
    );
    refused(
        with("mean_speed_m_s = 20.0\ndeck_points = 1"),
        &["wind.deck_points", "1"],
    );
    refused(
        with("mean_speed_m_s = 20.0\ndeck = { width_m = 41.0, drag = 0.1, admittance = -7.0 }"),
        &["wind.deck.admittance", "-7"],
    );
    refused(
        with("mean_speed_m_s = 20.0\nrecord = \"w.csv\"\ndeck = { width_m = 41.0, drag = 0.1, admittance = 7.0 }"),
        &["wind.deck.admittance", "w.csv"],
    );
    refused(
        with("mean_speed_m_s = 20.0\nvehicle_on_deck = { area_m2 = 0.0 }"),
        &["wind.vehicle_on_deck.area_m2", "0"],
    );
    refused(
        with("mean_speed_m_s = 0.0\nrecord = \"wind.csv\""),
        &["wind.record", "wind.csv", "mean_speed_m_s > 0"],
    );
    // a simply supported span has no preset deck: its coefficients are required
    let span =
        std::fs::read_to_string(tbi_tests::repo_path("master/tests/data/yang-yau.toml")).unwrap();
    refused(
        format!("{span}\n[wind]\nmean_speed_m_s = 20.0\n"),
        &["wind.deck", "(missing)", "simply_supported"],
    );
    // the Tsing Ma preset's deck is the default; the summary reports the load
    let s = Scenario::from_toml(
        &with("mean_speed_m_s = 20.0"),
        "w.toml",
        std::path::Path::new("."),
    )
    .unwrap();
    let load = s.wind.as_ref().unwrap().deck_load();
    let expected = 0.5 * 1.225 * 400.0 * 41.0 * 0.14;
    assert!((load[0] - expected).abs() < 1e-9 * expected, "{load:?}");
    let mut d = Scenario::default_case();
    assert!(d
        .set_wind_speed(-1.0)
        .unwrap_err()
        .to_string()
        .contains("wind.mean_speed_m_s"));
}

/// Buffeting of a single mode: a 100 m simply supported span with one vertical mode (f₁ ≈
/// 1.1 Hz, ζ = 10 %) under the lift of the vertical turbulence, L_b = ½ρU²B (C_L′ + C_D) w/U
/// (C_L′ = 3, all else 0), at 50 deck points over 3600 s. The time-domain σ of the midspan
/// displacement (after 100 s) is within 5 % of the random-vibration integral written here,
/// σ² = φ(L/2)² ∫ |H(f)|² S_F(f) df with H = 1/(ω₁² − ω² + 2iζω₁ω) and the generalised-force
/// spectrum S_F = (½ρUB C_L′)² S_w(f) Σ_j Σ_k Δx_j Δx_k φ_j φ_k exp(−C f |x_j − x_k| / U);
/// with Davenport's admittance (`admittance = 16`, a strong one so that the cases differ well
/// beyond the 5 %) the same with S_F times |χ(f)|² = (2/λ²)(λ − 1 + e^(−λ)), λ = 16 f B / U,
/// written here too.
#[test]
fn buffeting_of_a_single_mode_against_the_frequency_domain() {
    let plain = single_mode_buffeting(None);
    let admitted = single_mode_buffeting(Some(16.0));
    assert!(
        admitted < 0.9 * plain,
        "σ {admitted} with, {plain} without admittance"
    );
}

/// The time-domain σ of the midspan displacement, checked against the frequency domain.
fn single_mode_buffeting(admittance: Option<f64>) -> f64 {
    let (l, ei, m, zeta): (f64, f64, f64, f64) = (100.0, 3.0e11, 2.0e4, 0.10);
    let (u, b, slope, rho) = (20.0_f64, 10.0, 3.0, 1.225);
    let text = format!(
        r#"name = "buffeting"
[run]
speed_kmh = 360.0
dt_s = 0.02
solver = "monolithic"
free_vibration_s = 3600.0
output_every = 5
[bridge]
kind = "simply_supported"
span_m = {l}
youngs_modulus_pa = {ei}
inertia_vertical_m4 = 1.0
mass_per_length_kg_m = {m}
modes = 1
damping_ratio = {zeta}
[train]
kind = "moving_force"
axles = [{{ offset_m = 0.0, load_n = 0.0 }}]
[[probe]]
name = "mid"
x_m = {mid}
[wind]
mean_speed_m_s = {u}
air_density_kg_m3 = {rho}
deck = {{ width_m = {b}, drag = 0.0, lift_slope = {slope}{extra} }}
deck_points = 50
turbulence = {{ spectrum = "von-karman", intensity_u = 0.0, intensity_w = 0.1, length_scale_w_m = 30.0, coherence_w = 8.0, dt_s = 0.05, seed = 3 }}
"#,
        mid = l / 2.0,
        extra = admittance.map_or(String::new(), |c| format!(", admittance = {c}"))
    );
    let (s, h) = run_text(
        &text,
        if admittance.is_some() {
            "buffeting-admittance"
        } else {
            "buffeting"
        },
    );
    let t = h.column("time_s");
    let y: Vec<f64> = h
        .column("mid.vertical_displacement_m")
        .into_iter()
        .zip(&t)
        .filter(|(_, &t)| t > 100.0)
        .map(|(y, _)| y)
        .collect();
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let sigma = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / y.len() as f64).sqrt();
    // the frequency-domain reference
    let w1 = (std::f64::consts::PI / l).powi(2) * (ei / m).sqrt();
    let phi = |x: f64| (2.0 / (m * l)).sqrt() * (std::f64::consts::PI * x / l).sin();
    let p = 50;
    let dx = l / (p - 1) as f64;
    let pts: Vec<(f64, f64)> = (0..p)
        .map(|j| {
            let w = if j == 0 || j == p - 1 { 0.5 * dx } else { dx };
            let x = j as f64 * dx;
            (x, w * phi(x))
        })
        .collect();
    let turb = s.wind.as_ref().unwrap().turbulence.clone().unwrap();
    let gain = 0.5 * rho * u * b * slope; // ½ρU²B C_L′ / U
    let (f_lo, f_hi, nf) = (1e-4, 10.0, 200_000);
    let df = (f_hi - f_lo) / nf as f64;
    let mut var = 0.0;
    for i in 0..=nf {
        let f = f_lo + i as f64 * df;
        let om = 2.0 * std::f64::consts::PI * f;
        let h2 = 1.0 / ((w1 * w1 - om * om).powi(2) + (2.0 * zeta * w1 * om).powi(2));
        if h2 * gain * gain < 1e-30 {
            continue;
        }
        let mut sum = 0.0;
        for &(xj, aj) in &pts {
            for &(xk, ak) in &pts {
                sum += aj * ak * (-8.0 * f * (xj - xk).abs() / u).exp();
            }
        }
        let sw = turb.psd(tbi_wind::Component::W, f, u);
        let chi2 = admittance.map_or(1.0, |c| {
            let lambda = c * f * b / u;
            2.0 / (lambda * lambda) * (lambda - 1.0 + (-lambda).exp())
        });
        let wgt = if i == 0 || i == nf { 0.5 } else { 1.0 };
        var += wgt * df * h2 * gain * gain * chi2 * sw * sum;
    }
    let reference = phi(l / 2.0).abs() * var.sqrt();
    eprintln!(
        "buffeting (admittance {admittance:?}): time-domain σ {sigma} m, frequency domain {reference} m"
    );
    assert!(
        (sigma / reference - 1.0).abs() < 0.05,
        "admittance {admittance:?}: time-domain σ {sigma} m vs frequency domain {reference} m"
    );
    sigma
}

/// Self-excited forces: the free decay of the one vertical mode of a light 30 m span after a
/// load has crossed it, in a 30 m/s wind with flutter derivatives H₁*, H₄*. The damping
/// measured from the logarithmic decrement of the midspan displacement, and the frequency from
/// its zero crossings, equal structural plus aerodynamic damping and the aerodynamic stiffness
/// worked by hand: ζ_ae = −¼ρB² H₁* ∫φ² dx, ω² − ½ρB²ω² H₄* ∫φ² dx (∫φ² dx = 1/m for the
/// mass-normalised sine; the crossings give the damped frequency), to 2 % and 0.1 % (measured
/// 2e-5 and 3e-5); without wind the decay is the structural 1 %.
#[test]
fn self_excited_damping_in_a_free_decay() {
    let (l, ei, m, b, zeta_s): (f64, f64, f64, f64, f64) = (30.0, 5.0e8, 500.0, 10.0, 0.01);
    let case = |wind: &str| {
        let text = format!(
            r#"name = "decay"
[run]
speed_kmh = 100.0
dt_s = 0.001
solver = "monolithic"
free_vibration_s = 12.0
[bridge]
kind = "simply_supported"
span_m = {l}
youngs_modulus_pa = {ei}
inertia_vertical_m4 = 1.0
mass_per_length_kg_m = {m}
modes = 1
damping_ratio = {zeta_s}
[train]
kind = "moving_force"
axles = [{{ offset_m = 0.0, load_n = 20000.0 }}]
[[probe]]
name = "mid"
x_m = 15.0
{wind}
"#
        );
        let (_, h) = run_text(&text, "decay");
        let t = h.column("time_s");
        let y = h.column("mid.vertical_displacement_m");
        // after the load has left (30 m at 100 km/h: 1.08 s) and a settling second
        let free: Vec<(f64, f64)> = t.into_iter().zip(y).filter(|(t, _)| *t > 2.5).collect();
        // positive peaks and upward zero crossings
        let mut peaks = Vec::new();
        let mut ups = Vec::new();
        for k in 1..free.len() - 1 {
            let (a, b, c) = (free[k - 1].1, free[k].1, free[k + 1].1);
            if b > a && b >= c && b > 0.0 {
                peaks.push(b);
            }
            if a < 0.0 && b >= 0.0 {
                ups.push(free[k - 1].0 + (0.0 - a) / (b - a) * (free[k].0 - free[k - 1].0));
            }
        }
        let n = peaks.len().min(8) - 1;
        let delta = (peaks[0] / peaks[n]).ln() / n as f64;
        let zeta = delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt();
        let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
        (zeta, 1.0 / period)
    };
    let w = (std::f64::consts::PI / l).powi(2) * (ei / m).sqrt();
    let f = w / (2.0 * std::f64::consts::PI);
    let (zeta_still, f_still) = case("");
    assert!(
        (zeta_still / zeta_s - 1.0).abs() < 0.02,
        "still air: ζ {zeta_still}"
    );
    assert!(
        (f_still / f - 1.0).abs() < 0.005,
        "still air: f {f_still} vs {f}"
    );
    let (u, rho) = (30.0_f64, 1.225_f64);
    let wind = format!(
        "[wind]\nmean_speed_m_s = {u}\ndeck = {{ width_m = {b}, drag = 0.0, flutter = {{ reduced_velocity = [1.0, 2.0, 4.0], h1 = [-0.5, -1.0, -2.0], h4 = [1.0, 1.0, 1.0] }} }}"
    );
    let (zeta_wind, f_wind) = case(&wind);
    // by hand: U_r = U/(f B), H₁* interpolated between 1 and 2
    let ur = u / (f * b);
    assert!((1.0..2.0).contains(&ur), "U_r = {ur}");
    let h1 = -0.5 + (ur - 1.0) * (-0.5);
    let integral = 1.0 / m;
    let zeta_ae = -0.25 * rho * b * b * h1 * integral;
    let w_wind = (w * w - 0.5 * rho * b * b * w * w * 1.0 * integral).sqrt();
    let expected_zeta = (zeta_s + zeta_ae) * w / w_wind;
    assert!(zeta_ae > 0.03, "ζ_ae = {zeta_ae}");
    assert!(
        (zeta_wind / expected_zeta - 1.0).abs() < 0.02,
        "in wind: ζ {zeta_wind} vs {expected_zeta} (ζ_ae {zeta_ae})"
    );
    // zero crossings give the damped frequency ω √(1 − ζ²)
    let expected_f =
        w_wind * (1.0 - expected_zeta * expected_zeta).sqrt() / (2.0 * std::f64::consts::PI);
    assert!(
        (f_wind / expected_f - 1.0).abs() < 1e-3,
        "in wind: f {f_wind} vs {expected_f}"
    );
    // a table out of order is refused by name
    let bad = wind.replace("[1.0, 2.0, 4.0]", "[1.0, 4.0, 2.0]");
    let text = format!("{}\n{bad}\n", tbi::scenario::DEFAULT_SCENARIO);
    let e = Scenario::from_toml(&text, "w.toml", std::path::Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("wind.deck.flutter.reduced_velocity[2]") && e.contains("out of order"),
        "{e}"
    );
}
