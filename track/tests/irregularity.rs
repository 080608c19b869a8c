//! Generated samples and their evaluation against the direct spectral sum, reproducibility,
//! interpolation error bounds and the record round trip.

use std::f64::consts::TAU;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tbi_track::{
    Component, GeneratedSample, GeneratedSpec, Irregularity, RailIrregularity, Record,
    SpectralTerm, Spectrum,
};

/// The sum Σ a cos(Ω x + φ) and its exact first and second derivative.
fn direct(terms: &[SpectralTerm], x: f64) -> [f64; 3] {
    terms.iter().fold([0.0; 3], |[r, d1, d2], t| {
        let (s, c) = (t.omega_rad_m * x + t.phase_rad).sin_cos();
        let w = t.omega_rad_m;
        [
            r + t.amplitude * c,
            d1 - t.amplitude * w * s,
            d2 - t.amplitude * w * w * c,
        ]
    })
}

/// Σ a_k Ω_k^p: bounds max|r^(p)|.
fn moment(terms: &[SpectralTerm], p: i32) -> f64 {
    terms
        .iter()
        .map(|t| t.amplitude * t.omega_rad_m.powi(p))
        .sum()
}

/// Cubic Hermite error bounds (value, slope, curvature) for spacing h and max|f⁗| = m4.
fn hermite_bounds(h: f64, m4: f64) -> [f64; 3] {
    [
        h.powi(4) / 384.0 * m4,
        3f64.sqrt() / 216.0 * h.powi(3) * m4,
        h * h / 12.0 * m4,
    ]
}

fn sample(spectrum: Spectrum, seed: u64, x0: f64, x1: f64) -> GeneratedSample {
    GeneratedSpec::new(spectrum, seed).generate(x0, x1).unwrap()
}

fn random_points(seed: u64, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| lo + (hi - lo) * rng.random::<f64>())
        .collect()
}

fn assert_bit_identical(a: RailIrregularity, b: RailIrregularity, x: f64) {
    for c in Component::ALL {
        let (p, q) = (a.component(c), b.component(c));
        for k in 0..3 {
            assert_eq!(
                p[k].to_bits(),
                q[k].to_bits(),
                "x = {x}, {c:?}[{k}]: {} vs {}",
                p[k],
                q[k]
            );
        }
    }
}

#[test]
fn grid_layout_follows_the_documented_choices() {
    let mut spec = GeneratedSpec::new(Spectrum::GermanLow, 5);
    spec.lambda_min_m = 1.0;
    spec.lambda_max_m = 80.0;
    let g = spec.generate(-150.0, 2350.0).unwrap();
    let (lo, hi) = g.band_rad_m();
    let dw = g.delta_omega_rad_m();
    assert!((lo - TAU / 80.0).abs() < 1e-14, "lower band edge {lo}");
    assert!(
        (hi - TAU / 1.0).abs() <= 0.5 * dw + 1e-12,
        "upper band edge {hi}"
    );
    assert!(g.period_m() >= 2500.0 && g.period_m() < 2500.0 + 80.0);
    assert!((g.period_m() - TAU / dw).abs() < 1e-9);
    let nodes = g.profile().nodes();
    assert_eq!(nodes[0], -150.0);
    assert!(g.grid_spacing_m() <= 0.1 + 1e-15);
    assert!((nodes[nodes.len() - 1] - nodes[0] - g.period_m()).abs() < 1e-9);
    assert!(g.profile().is_periodic());
    // Terms at the bin mid-points, whole multiples of ΔΩ.
    for c in Component::ALL {
        let t = g.terms(c);
        assert_eq!(t.len(), g.n_terms());
        for (k, term) in t.iter().enumerate() {
            let mid = lo + (k as f64 + 0.5) * dw;
            assert!((term.omega_rad_m - mid).abs() < 1e-12);
            let multiple = term.omega_rad_m / dw;
            assert!((multiple - multiple.round()).abs() < 1e-9);
            assert!((0.0..TAU).contains(&term.phase_rad));
        }
    }
    // A caller-chosen minimum number of terms lengthens the period.
    spec.min_terms = 6000;
    let g2 = spec.generate(-150.0, 2350.0).unwrap();
    assert!(g2.n_terms() >= 6000 && g2.n_terms() < 6000 + 80);
    assert!(g2.period_m() > g.period_m());
}

#[test]
fn nodes_hold_the_exact_sum_and_evaluate_to_the_stored_values() {
    let g = sample(Spectrum::GermanHigh, 9, -200.0, 2300.0);
    let p = g.profile();
    let nodes = p.nodes();
    for c in Component::ALL {
        let terms = g.terms(c);
        let (values, slopes) = (p.values(c), p.slopes(c));
        let (scale0, scale1) = (moment(terms, 0), moment(terms, 1));
        for j in (0..nodes.len()).step_by(37) {
            let got = g.at(nodes[j]).component(c);
            assert_eq!(got[0].to_bits(), values[j].to_bits());
            assert_eq!(got[1].to_bits(), slopes[j].to_bits());
            let want = direct(terms, nodes[j]);
            assert!(
                (values[j] - want[0]).abs() < 1e-10 * scale0,
                "{c:?} node {j}"
            );
            assert!(
                (slopes[j] - want[1]).abs() < 1e-10 * scale1,
                "{c:?} node {j}"
            );
        }
    }
}

#[test]
fn interpolation_is_within_the_hermite_error_bounds_everywhere() {
    let g = sample(Spectrum::ChineseMainLine, 4, 0.0, 1200.0);
    let h = g.grid_spacing_m();
    let period = g.period_m();
    // Inside the line, and beyond it (the sample is periodic, the sum too).
    let mut xs = random_points(1, 3000, 0.0, 1200.0);
    xs.extend([
        -123.4,
        -period,
        1200.0 + 777.7,
        3.5 * period,
        41.0 * period + 0.03,
    ]);
    for c in Component::ALL {
        let terms = g.terms(c);
        let bounds = hermite_bounds(h, moment(terms, 4));
        let eps = [moment(terms, 0), moment(terms, 1), moment(terms, 2)].map(|m| 1e-10 * m);
        let mut worst = [0.0f64; 3];
        for &x in &xs {
            let got = g.at(x).component(c);
            let want = direct(terms, x);
            for k in 0..3 {
                let err = (got[k] - want[k]).abs();
                worst[k] = worst[k].max(err / bounds[k]);
                assert!(
                    err <= bounds[k] + eps[k],
                    "{c:?} x={x} derivative {k}: error {err:e} > bound {:e}",
                    bounds[k]
                );
            }
        }
        eprintln!("{c:?}: worst error / Hermite bound (r, r', r'') = {worst:.3?}");
    }
}

#[test]
fn derivatives_are_consistent_with_finite_differences() {
    let g = sample(Spectrum::Fra(5), 2, 0.0, 500.0);
    let nodes = g.profile().nodes().to_vec();
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    for c in Component::ALL {
        let terms = g.terms(c);
        let (s1, s2) = (moment(terms, 1), moment(terms, 2));
        for _ in 0..500 {
            let i = (rng.random::<f64>() * (nodes.len() - 1) as f64) as usize;
            let h = nodes[i + 1] - nodes[i];
            let x = nodes[i] + (0.2 + 0.6 * rng.random::<f64>()) * h;
            let d = 1e-3 * h;
            let (m, p, z) = (g.at(x - d), g.at(x + d), g.at(x));
            let (m, p, z) = (m.component(c), p.component(c), z.component(c));
            let fd1 = (p[0] - m[0]) / (2.0 * d);
            let fd2 = (p[1] - m[1]) / (2.0 * d);
            let fd2b = (p[0] - 2.0 * z[0] + m[0]) / (d * d);
            assert!(
                (fd1 - z[1]).abs() < 1e-6 * s1,
                "{c:?} x={x}: r' {} vs fd {fd1}",
                z[1]
            );
            assert!(
                (fd2 - z[2]).abs() < 1e-6 * s2,
                "{c:?} x={x}: r'' {} vs fd {fd2}",
                z[2]
            );
            assert!(
                (fd2b - z[2]).abs() < 1e-4 * s2,
                "{c:?} x={x}: r'' {} vs fd {fd2b}",
                z[2]
            );
        }
    }
}

#[test]
fn a_single_cosine_is_reproduced_within_tight_bounds() {
    // r = A cos(Ω x + φ) tabulated with exact slopes on a fine grid.
    let (a, w, phi, h) = (2.0e-3, TAU / 5.0, 0.7, 0.01);
    let x: Vec<f64> = (0..=2000).map(|i| i as f64 * h).collect();
    let f = |x: f64| {
        [
            a * (w * x + phi).cos(),
            -a * w * (w * x + phi).sin(),
            -a * w * w * (w * x + phi).cos(),
        ]
    };
    let values: Vec<f64> = x.iter().map(|&x| f(x)[0]).collect();
    let slopes: Vec<f64> = x.iter().map(|&x| f(x)[1]).collect();
    let zeros = vec![0.0; x.len()];
    let rec = Record::from_columns(
        "cosine",
        x,
        [values.clone(), zeros.clone(), zeros.clone()],
        Some([slopes, zeros.clone(), zeros]),
        false,
    )
    .unwrap();
    let bounds = hermite_bounds(h, a * w.powi(4));
    let tiny = [1e-15, 1e-14, 1e-12];
    for xq in random_points(3, 5000, 0.0, 20.0) {
        let got = rec.at(xq).lateral;
        let want = f(xq);
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() <= bounds[k] + tiny[k],
                "x={xq} derivative {k}: {} vs {}",
                got[k],
                want[k]
            );
        }
        assert_eq!(rec.at(xq).vertical, [0.0; 3]);
    }
    // Relative accuracy this bound guarantees for r'' on this grid: (Ωh)²/12.
    assert!(bounds[2] / (a * w * w) < 2e-5);
}

#[test]
fn a_cubic_with_given_slopes_is_exact_at_and_between_all_nodes() {
    // Cubic Hermite interpolation reproduces cubics, including r'' at the last node.
    let f = |x: f64| {
        [
            1e-3 - 2e-4 * x + 3e-5 * x * x - 4e-7 * x.powi(3),
            -2e-4 + 6e-5 * x - 12e-7 * x * x,
            6e-5 - 24e-7 * x,
        ]
    };
    let x: Vec<f64> = (0..30)
        .map(|i| -5.0 + 0.5 * i as f64 + 0.01 * (i * i) as f64)
        .collect();
    let values: Vec<f64> = x.iter().map(|&x| f(x)[0]).collect();
    let slopes: Vec<f64> = x.iter().map(|&x| f(x)[1]).collect();
    let rec = Record::from_columns(
        "cubic",
        x.clone(),
        [values.clone(), values.clone(), values],
        Some([slopes.clone(), slopes.clone(), slopes]),
        false,
    )
    .unwrap();
    let mut xs = random_points(4, 500, x[0], x[x.len() - 1]);
    xs.extend_from_slice(&x);
    for xq in xs {
        let (got, want) = (rec.at(xq).cross_level, f(xq));
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-14,
                "x={xq} [{k}]: {} vs {}",
                got[k],
                want[k]
            );
        }
    }
}

#[test]
fn same_seed_reproduces_and_another_seed_differs() {
    let a = sample(Spectrum::GermanLow, 42, 0.0, 1000.0);
    let b = sample(Spectrum::GermanLow, 42, 0.0, 1000.0);
    let c = sample(Spectrum::GermanLow, 43, 0.0, 1000.0);
    assert_eq!(a.profile().nodes(), b.profile().nodes());
    for comp in Component::ALL {
        assert_eq!(a.terms(comp), b.terms(comp));
        let (va, vb, vc) = (
            a.profile().values(comp),
            b.profile().values(comp),
            c.profile().values(comp),
        );
        assert!(va.iter().zip(&vb).all(|(x, y)| x.to_bits() == y.to_bits()));
        let sigma = (va.iter().map(|v| v * v).sum::<f64>() / va.len() as f64).sqrt();
        let max_diff = va
            .iter()
            .zip(&vc)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(
            max_diff > 0.5 * sigma,
            "{comp:?}: seeds 42 and 43 too similar"
        );
    }
    for x in random_points(5, 200, -50.0, 1100.0) {
        assert_bit_identical(a.at(x), b.at(x), x);
    }
}

#[test]
fn components_draw_independent_phases() {
    // German lateral and vertical spectra have the same shape (A_a vs A_v): with shared random
    // streams the two samples would be exactly proportional.
    let g = sample(Spectrum::GermanLow, 7, 0.0, 2500.0);
    let lat = g.profile().values(Component::Lateral);
    let ver = g.profile().values(Component::Vertical);
    let (ka, kv) = (2.119e-7f64.sqrt(), 4.032e-7f64.sqrt());
    let sigma = (ver.iter().map(|v| (v / kv).powi(2)).sum::<f64>() / ver.len() as f64).sqrt();
    let max_diff = lat
        .iter()
        .zip(&ver)
        .map(|(l, v)| (l / ka - v / kv).abs())
        .fold(0.0, f64::max);
    assert!(max_diff > sigma, "lateral and vertical look proportional");
    // The phases are uniform: each eighth of [0, 2π) holds N/8 within 5 standard deviations.
    for c in Component::ALL {
        let t = g.terms(c);
        let n = t.len() as f64;
        let mut counts = [0usize; 8];
        for term in t {
            counts[(term.phase_rad / TAU * 8.0) as usize] += 1;
        }
        let sd = (n / 8.0 * 7.0 / 8.0).sqrt();
        for k in counts {
            assert!((k as f64 - n / 8.0).abs() < 5.0 * sd, "{c:?}: {counts:?}");
        }
    }
}

#[test]
fn generated_record_round_trip_is_bit_exact_everywhere() {
    let g = Irregularity::Generated(Box::new(sample(
        Spectrum::ChineseMainLine,
        12,
        -100.0,
        900.0,
    )));
    let csv = g.to_record_csv().unwrap();
    assert!(csv.lines().any(|l| l.trim() == "# periodic"));
    let back = Record::parse(&csv, "exported.csv").unwrap();
    assert!(back.slopes_given());
    assert!(back.profile().is_periodic());
    let p = g.profile().unwrap();
    assert_eq!(back.profile().nodes(), p.nodes());
    // The reader computes the writer's identity bytes (the bridge FMU's GUID rests on this);
    // one ulp in one value or slope, or periodicity, changes them.
    assert_eq!(
        back.profile().identity_bytes(),
        g.record_identity().unwrap()
    );
    let ulp = |text: &str, col: usize, row: usize| -> String {
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        let data: Vec<usize> = (0..lines.len())
            .filter(|&i| !lines[i].starts_with('#') && !lines[i].starts_with('x'))
            .collect();
        let i = data[row];
        let mut cells: Vec<String> = lines[i].split(',').map(str::to_owned).collect();
        let v: f64 = cells[col].parse().unwrap();
        cells[col] = format!("{:e}", f64::from_bits(v.to_bits() + 1));
        lines[i] = cells.join(",");
        lines.join("\n")
    };
    for (col, row) in [(5, 17), (1, 5000), (6, 1), (0, 300)] {
        let edited = Record::parse(&ulp(&csv, col, row), "edited.csv").unwrap();
        assert_ne!(
            edited.profile().identity_bytes(),
            back.profile().identity_bytes(),
            "column {col}, row {row}"
        );
    }
    let open = Record::parse(&csv.replace("# periodic\n", ""), "open.csv").unwrap();
    assert_ne!(
        open.profile().identity_bytes(),
        back.profile().identity_bytes()
    );
    let mut xs = random_points(6, 4000, -100.0, 1100.0);
    xs.extend_from_slice(&p.nodes()[..50]);
    xs.extend([-5000.0, -100.0 - 1e-9, 7777.7, 1e6 + 0.123]);
    for x in xs {
        assert_bit_identical(g.at(x), back.at(x), x);
    }
    // Through a file as well.
    let path = std::env::temp_dir().join(format!("tbi-track-roundtrip-{}.csv", std::process::id()));
    g.write_record_file(&path).unwrap();
    let from_file = Irregularity::read_record(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    for x in random_points(7, 500, -2000.0, 3000.0) {
        assert_bit_identical(g.at(x), from_file.at(x), x);
    }
}

#[test]
fn measured_record_uses_exact_parabolic_slopes_and_is_held_beyond_its_ends() {
    // Strongly non-uniform nodes; quadratics are reproduced exactly by parabolic slopes and
    // cubic Hermite interpolation.
    let x: Vec<f64> = (0..60)
        .map(|i| 0.05 * (i * i) as f64 + 0.3 * i as f64 - 10.0)
        .collect();
    let q = [
        (1e-3, 2e-4, -3e-6),
        (-2e-3, 5e-5, 4e-6),
        (5e-4, -1e-5, 1e-6),
    ];
    let f = |c: usize, x: f64| {
        let (a, b, cc) = q[c];
        [a + b * x + cc * x * x, b + 2.0 * cc * x, 2.0 * cc]
    };
    let mut text = String::from("# measured\n\nx_m, lateral_m, vertical_m, cross_level_rad\n");
    for &xi in &x {
        text += &format!("{xi},{},{},{}\n", f(0, xi)[0], f(1, xi)[0], f(2, xi)[0]);
    }
    let rec = Record::parse(&text, "measured.csv").unwrap();
    assert!(!rec.slopes_given() && !rec.profile().is_periodic());
    let (x0, x1) = (x[0], x[x.len() - 1]);
    let mut xs = random_points(9, 2000, x0, x1);
    xs.extend_from_slice(&x);
    for xq in xs {
        let got = rec.at(xq);
        for c in Component::ALL {
            let (g, w) = (got.component(c), f(c.index(), xq));
            for k in 0..3 {
                assert!(
                    (g[k] - w[k]).abs() < 1e-12,
                    "{c:?} x={xq} [{k}]: {} vs {}",
                    g[k],
                    w[k]
                );
            }
        }
    }
    // Held beyond the ends.
    for (xq, end) in [(x0 - 3.0, x0), (x1 + 100.0, x1)] {
        let got = rec.at(xq);
        for c in Component::ALL {
            assert_eq!(got.component(c), [f(c.index(), end)[0], 0.0, 0.0]);
        }
    }
    // Export and re-read: identical everywhere, held beyond the ends.
    let back = Record::parse(
        &Irregularity::Record(rec.clone()).to_record_csv().unwrap(),
        "re",
    )
    .unwrap();
    assert!(!back.profile().is_periodic());
    for xq in random_points(10, 1000, x0 - 50.0, x1 + 50.0) {
        assert_bit_identical(rec.at(xq), back.at(xq), xq);
    }
}

#[test]
fn periodic_record_without_slopes_wraps_smoothly() {
    // One period of a cosine, declared periodic: wrap-around slopes make the join C¹.
    let n = 400;
    let period = 20.0;
    let w = TAU / period;
    let mut text = String::from("x_m,lateral_m,vertical_m,cross_level_rad\n# periodic\n");
    for i in 0..=n {
        let x = i as f64 * period / n as f64;
        let v = if i == n { 1e-3 } else { 1e-3 * (w * x).cos() };
        text += &format!("{x},{v},0,0\n");
    }
    let rec = Record::parse(&text, "cos.csv").unwrap();
    assert!(rec.profile().is_periodic());
    let h = period / n as f64;
    let bound = hermite_bounds(h, 1e-3 * w.powi(4));
    // Parabolic slopes are second-order: r' error ≤ h² r‴/6 at the nodes.
    let slope_err = h * h / 6.0 * 1e-3 * w.powi(3);
    for x in [
        -0.01,
        0.0,
        1e-9,
        period - 1e-9,
        period + 0.013,
        3.0 * period + 7.3,
        -41.2,
    ] {
        let got = rec.at(x).lateral;
        let want = [1e-3 * (w * x).cos(), -1e-3 * w * (w * x).sin()];
        assert!(
            (got[0] - want[0]).abs() <= bound[0] + h * slope_err,
            "x={x}"
        );
        assert!(
            (got[1] - want[1]).abs() <= bound[1] + slope_err + 1e-15,
            "x={x}"
        );
    }
}

fn parse_err(text: &str) -> String {
    Record::parse(text, "track.csv").unwrap_err().to_string()
}

#[test]
fn malformed_records_name_the_file_line_and_problem() {
    let head = "# comment\nx_m,lateral_m,vertical_m,cross_level_rad\n";
    let e = parse_err(&format!("{head}0,0,0,0\n0.5,0.001,abc,0\n"));
    assert!(
        e.starts_with("track.csv:4:") && e.contains("vertical_m") && e.contains("abc"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n\n# note\n0.5,0.001,0\n"));
    assert!(
        e.starts_with("track.csv:6:") && e.contains("expected 4, found 3"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n0.5,0,0,0\n0.5,0,0,0\n"));
    assert!(
        e.starts_with("track.csv:5:") && e.contains("increase"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n-1,0,0,0\n"));
    assert!(
        e.starts_with("track.csv:4:") && e.contains("increase"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n1,0,NaN,0\n"));
    assert!(
        e.starts_with("track.csv:4:") && e.contains("NaN") && e.contains("vertical_m"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n1,0,0,inf\n"));
    assert!(
        e.starts_with("track.csv:4:") && e.contains("cross_level_rad"),
        "{e}"
    );

    let e = parse_err("\n# only comments\nx,y,z,w\n0,0,0,0\n");
    assert!(e.starts_with("track.csv:3:") && e.contains("header"), "{e}");

    let e = parse_err("# nothing\n\n");
    assert!(
        e.starts_with("track.csv:") && e.contains("no header"),
        "{e}"
    );

    let e = parse_err(&format!("{head}0,0,0,0\n"));
    assert!(
        e.contains("at least 2 data rows") && e.contains("found 1"),
        "{e}"
    );

    let slopes =
        "x_m,lateral_m,vertical_m,cross_level_rad,lateral_slope,vertical_slope,cross_level_slope\n";
    let e = parse_err(&format!("{slopes}0,0,0,0,0,0,0\n1,0,0,0,0,0\n"));
    assert!(
        e.starts_with("track.csv:3:") && e.contains("expected 7, found 6"),
        "{e}"
    );
    let e = parse_err(&format!("{slopes}0,0,0,0,0,0,0\n1,0,0,0,0,x1,0\n"));
    assert!(
        e.starts_with("track.csv:3:") && e.contains("vertical_slope"),
        "{e}"
    );

    let e = parse_err(&format!(
        "# periodic\n{slopes}0,1,0,0,0,0,0\n1,0,0,0,0,0,0\n2,1,0,0,0,0.5,0\n"
    ));
    assert!(
        e.starts_with("track.csv:5:") && e.contains("periodic"),
        "{e}"
    );

    let e = Record::read("/nonexistent/dir/track.csv")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/nonexistent/dir/track.csv:"), "{e}");
}

/// Rows in any spelling `str::parse` accepts read the same bits as bare rows (the reader's
/// one-pass path for rows as written by the exporter, and the general one for the rest), and
/// fields the general path refuses are refused whatever their spelling.
#[test]
fn record_rows_read_the_same_in_every_spelling() {
    let g = Irregularity::Generated(Box::new(sample(Spectrum::Fra(6), 3, 0.0, 60.0)));
    let csv = g.to_record_csv().unwrap();
    let bare = Record::parse(&csv, "bare.csv").unwrap();
    let respell = |f: &dyn Fn(usize, &str) -> String, eol: &str| -> String {
        let mut out = String::new();
        for line in csv.lines() {
            if line.starts_with('#') || line.starts_with('x') {
                out += line;
            } else {
                let cells: Vec<String> = (line.split(',').enumerate())
                    .map(|(k, c)| f(k, c))
                    .collect();
                out += &cells.join(",");
            }
            out += eol;
        }
        out
    };
    let exp = |c: &str| format!("{:E}", c.parse::<f64>().unwrap());
    let plus = |c: &str| {
        if c.starts_with('-') {
            c.to_owned()
        } else {
            format!("+{c}")
        }
    };
    let spellings: [(&str, String); 5] = [
        ("blanks", respell(&|_, c| format!(" {c}\t"), "\n")),
        ("crlf", respell(&|_, c| c.to_owned(), "\r\n")),
        ("exponents", respell(&|_, c| exp(c), "\n")),
        ("plus signs", respell(&|_, c| plus(c), "\n")),
        (
            "mixed",
            respell(
                &|k, c| match k % 3 {
                    0 => exp(c),
                    1 => format!("{c} "),
                    _ => plus(c),
                },
                "\n",
            ),
        ),
    ];
    for (name, text) in &spellings {
        let r = Record::parse(text, name).unwrap();
        assert_eq!(r.profile().nodes(), bare.profile().nodes(), "{name}");
        assert_eq!(
            r.profile().identity_bytes(),
            bare.profile().identity_bytes(),
            "{name}"
        );
    }
    let head = "x_m,lateral_m,vertical_m,cross_level_rad\n0,0,0,0\n";
    for (row, column) in [
        ("1,0,1e,0", "vertical_m"),
        ("1,0,1..5,0", "vertical_m"),
        ("1,--2,0,0", "lateral_m"),
        ("1,0,0,0x1", "cross_level_rad"),
        ("1,0,,0", "vertical_m"),
        ("1,0,0,infinity", "cross_level_rad"),
        ("1,0,0,1e999", "cross_level_rad"),
        ("2_0,0,0,0", "x_m"),
    ] {
        let e = parse_err(&format!("{head}{row}\n"));
        assert!(
            e.starts_with("track.csv:3:") && e.contains(column),
            "{row}: {e}"
        );
    }
    let e = parse_err(&format!("{head}1,0,0,0,\n"));
    assert!(e.contains("expected 4, found 5"), "{e}");
}

#[test]
fn ideal_track_and_nan_positions() {
    assert_eq!(Irregularity::None.at(12.3), RailIrregularity::default());
    assert!(Irregularity::None.to_record_csv().is_none());
    let g = sample(Spectrum::Fra(6), 1, 0.0, 100.0);
    let r = g.at(f64::NAN);
    assert!(r
        .lateral
        .iter()
        .chain(&r.vertical)
        .chain(&r.cross_level)
        .all(|v| v.is_nan()));
}

#[test]
fn irregularity_is_send_sync_and_clone() {
    fn check<T: Send + Sync + Clone + 'static>() {}
    check::<Irregularity>();
    check::<tbi_track::IrregularitySpec>();
    check::<tbi_track::WheelHunting>();
}

#[test]
fn record_columns_are_validated() {
    let z = || vec![0.0; 3];
    let err = |x: Vec<f64>, v: [Vec<f64>; 3], s: Option<[Vec<f64>; 3]>, periodic| {
        Record::from_columns("cols", x, v, s, periodic)
            .unwrap_err()
            .to_string()
    };
    let e = err(vec![0.0, 1.0, 1.0], [z(), z(), z()], None, false);
    assert!(e.contains("x_m = 1 at index 2"), "{e}");
    let e = err(vec![0.0, 1.0, 2.0], [z(), vec![0.0; 2], z()], None, false);
    assert!(e.contains("vertical_m = 2 entries"), "{e}");
    let e = err(
        vec![0.0, 1.0, 2.0],
        [z(), z(), vec![0.0, f64::NAN, 0.0]],
        None,
        false,
    );
    assert!(e.contains("cross_level_rad = NaN at index 1"), "{e}");
    let e = err(
        vec![0.0, 1.0, 2.0],
        [vec![1.0, 0.0, 2.0], z(), z()],
        None,
        true,
    );
    assert!(
        e.contains("lateral_m = 1 / 2") && e.contains("periodic"),
        "{e}"
    );
    let e = err(
        vec![0.0, 1.0, 2.0],
        [z(), z(), z()],
        Some([z(), z(), vec![0.0, 1.0]]),
        false,
    );
    assert!(e.contains("cross_level_slope = 2 entries"), "{e}");
    let e = err(vec![0.0], [vec![0.0], vec![0.0], vec![0.0]], None, false);
    assert!(e.contains("at least 2"), "{e}");
}

/// The prefetch hint reads and changes nothing: anywhere, including outside the table and
/// at non-finite positions, the values afterwards are bit for bit those before.
#[test]
fn a_prefetch_changes_no_value() {
    let s = sample(Spectrum::GermanLow, 7, 0.0, 500.0);
    let irr = Irregularity::Generated(Box::new(s));
    let (x0, x1) = irr.profile().unwrap().domain();
    let mut xs = random_points(3, 200, x0 - 50.0, x1 + 50.0);
    xs.extend([x0, x1, x0 - 1e-9, x1 + 1e-9, 0.5 * (x0 + x1)]);
    let before: Vec<RailIrregularity> = xs.iter().map(|&x| irr.at(x)).collect();
    for x in xs
        .iter()
        .copied()
        .chain([f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1e300, 1e300])
    {
        irr.prefetch(x);
        Irregularity::None.prefetch(x);
    }
    for (&x, b) in xs.iter().zip(before) {
        assert_bit_identical(irr.at(x), b, x);
    }
}
