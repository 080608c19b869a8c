//! Spectra and generated samples against independent references: the PSD formulas of
//! domain.md §4 typed out again in their published units, integrated by adaptive Simpson in
//! log Ω, and an FFT periodogram (Welch, Hann window) of long samples.

use std::f64::consts::{PI, TAU};

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use tbi_track::{Component, GeneratedSample, GeneratedSpec, Spectrum};

// ---------------------------------------------------------------------------------------------
// Independent reference formulas, in the units they are published in.

/// German spectra in m²/(rad/m), cross-level already an angle with b = 0.75 m.
fn german(a_v: f64, a_a: f64, c: Component, w: f64) -> f64 {
    let (wc, wr, ws, b) = (0.8246, 0.0206, 0.4380, 0.75);
    let den = (w * w + wr * wr) * (w * w + wc * wc);
    match c {
        Component::Vertical => a_v * wc * wc / den,
        Component::Lateral => a_a * wc * wc / den,
        Component::CrossLevel => (a_v / (b * b)) * wc * wc * w * w / (den * (w * w + ws * ws)),
    }
}

/// FRA spectra in cm²/(rad/m); cross-level as a height difference.
fn fra_cm2(class: usize, c: Component, w: f64) -> f64 {
    let a_v = [1.2107, 1.0181, 0.6816, 0.5376, 0.2095, 0.0339][class - 1];
    let a_a = [3.3634, 1.2107, 0.4128, 0.3027, 0.0762, 0.0339][class - 1];
    let ws = [0.6046, 0.9308, 0.8520, 1.1312, 0.8209, 0.4380][class - 1];
    let (k, wc) = (0.25, 0.8245);
    match c {
        Component::Vertical => k * a_v * wc * wc / (w * w * (w * w + wc * wc)),
        Component::Lateral => k * a_a * wc * wc / (w * w * (w * w + wc * wc)),
        Component::CrossLevel => 4.0 * k * a_v * wc * wc / ((w * w + wc * wc) * (w * w + ws * ws)),
    }
}

/// Chinese main-line spectra in mm²/(1/m), f in 1/m; (left, right) for vertical and
/// alignment, the single cross-level height-difference spectrum twice.
fn chinese_mm2(c: Component, f: f64) -> (f64, f64) {
    let s = |p: [f64; 7]| {
        p[0] * (f.powi(2) + p[1] * f + p[2])
            / (f.powi(4) + p[3] * f.powi(3) + p[4] * f.powi(2) + p[5] * f + p[6])
    };
    match c {
        Component::Vertical => (
            s([1.1029, -1.4709, 0.5941, 0.8480, 3.8016, -0.2500, 0.0112]),
            s([0.8581, -1.4607, 0.5848, 0.0407, 2.8428, -0.1989, 0.0094]),
        ),
        Component::Lateral => (
            s([0.2244, -1.5746, 0.6683, -2.1466, 1.7665, -0.1506, 0.0052]),
            s([0.3743, -1.5894, 0.7265, 0.4353, 0.9101, -0.0270, 0.0031]),
        ),
        Component::CrossLevel => {
            let v = s([0.1214, -2.1603, 2.0214, 4.5089, 2.2227, -0.0396, 0.0073]);
            (v, v)
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Quadrature.

fn simpson_rec(
    f: &dyn Fn(f64) -> f64,
    (a, fa): (f64, f64),
    (m, fm): (f64, f64),
    (b, fb): (f64, f64),
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        left + right + delta / 15.0
    } else {
        simpson_rec(f, (a, fa), (lm, flm), (m, fm), left, 0.5 * tol, depth - 1)
            + simpson_rec(f, (m, fm), (rm, frm), (b, fb), right, 0.5 * tol, depth - 1)
    }
}

/// ∫_lo^hi g(w) dw, adaptive Simpson in u = ln w, relative tolerance 1e-10.
fn integrate_log(g: &dyn Fn(f64) -> f64, lo: f64, hi: f64) -> f64 {
    let f = |u: f64| {
        let w = u.exp();
        g(w) * w
    };
    let (a, b) = (lo.ln(), hi.ln());
    let m = 0.5 * (a + b);
    let (fa, fm, fb) = (f(a), f(m), f(b));
    let coarse = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_rec(
        &f,
        (a, fa),
        (m, fm),
        (b, fb),
        coarse,
        1e-10 * coarse.abs(),
        40,
    )
}

/// Reference σ of `component` over wavelengths [lambda_min, lambda_max], in m or rad
/// (contact distance 1.5 m).
fn reference_sigma(spectrum: Spectrum, c: Component, lambda_min: f64, lambda_max: f64) -> f64 {
    let (wlo, whi) = (TAU / lambda_max, TAU / lambda_min);
    match spectrum {
        Spectrum::GermanLow => {
            integrate_log(&|w| german(4.032e-7, 2.119e-7, c, w), wlo, whi).sqrt()
        }
        Spectrum::GermanHigh => {
            integrate_log(&|w| german(1.080e-6, 6.125e-7, c, w), wlo, whi).sqrt()
        }
        Spectrum::Fra(class) => {
            let var_cm2 = integrate_log(&|w| fra_cm2(class as usize, c, w), wlo, whi);
            let sigma_m = (var_cm2 * 1e-4).sqrt();
            if c == Component::CrossLevel {
                sigma_m / 1.5
            } else {
                sigma_m
            }
        }
        Spectrum::ChineseMainLine => {
            // Variance in mm² = ∫ S df over f ∈ [1/λ_max, 1/λ_min].
            let (flo, fhi) = (1.0 / lambda_max, 1.0 / lambda_min);
            let var_mm2 = integrate_log(
                &|f| {
                    let (l, r) = chinese_mm2(c, f);
                    0.5 * (l + r)
                },
                flo,
                fhi,
            );
            let sigma_m = var_mm2.sqrt() * 1e-3;
            if c == Component::CrossLevel {
                sigma_m / 1.5
            } else {
                sigma_m
            }
        }
    }
}

fn sample_sigma_over_period(g: &GeneratedSample, c: Component) -> f64 {
    let v = g.profile().values(c);
    let period = &v[..v.len() - 1]; // the last node closes the period
    let mean = period.iter().sum::<f64>() / period.len() as f64;
    (period.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / period.len() as f64).sqrt()
}

#[test]
fn quadrature_is_exact_on_a_known_integral() {
    // ∫_0.1^10 1/(w²+1) dw = atan(10) − atan(0.1).
    let got = integrate_log(&|w| 1.0 / (w * w + 1.0), 0.1, 10.0);
    let want = 10f64.atan() - 0.1f64.atan();
    assert!((got / want - 1.0).abs() < 1e-9, "{got} vs {want}");
}

#[test]
fn psd_matches_the_published_formulas_pointwise() {
    for &w in &[0.05, 0.0785, 0.2, 0.8, 1.0, 3.0, 6.0, 12.0] {
        for c in Component::ALL {
            let pairs = [
                (Spectrum::GermanLow, german(4.032e-7, 2.119e-7, c, w)),
                (Spectrum::GermanHigh, german(1.080e-6, 6.125e-7, c, w)),
                (Spectrum::ChineseMainLine, {
                    let (l, r) = chinese_mm2(c, w / TAU);
                    let g = 0.5 * (l + r) * 1e-6 / TAU;
                    if c == Component::CrossLevel {
                        g / 2.25
                    } else {
                        g
                    }
                }),
            ];
            let fra = (1..=6u8).map(|k| {
                let g = fra_cm2(k as usize, c, w) * 1e-4;
                (
                    Spectrum::Fra(k),
                    if c == Component::CrossLevel {
                        g / 2.25
                    } else {
                        g
                    },
                )
            });
            for (s, want) in pairs.into_iter().chain(fra) {
                let got = s.psd(c, w);
                assert!(
                    (got / want - 1.0).abs() < 1e-12,
                    "{s} {c:?} Ω={w}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn cross_level_scales_with_the_contact_distance() {
    for s in Spectrum::ALL {
        let g15 = s.psd(Component::CrossLevel, 0.7);
        let g20 = s.psd_with_contact_distance(Component::CrossLevel, 0.7, 2.0);
        assert!((g20 / g15 - (1.5f64 / 2.0).powi(2)).abs() < 1e-14);
        assert_eq!(
            s.psd(Component::Vertical, 0.7),
            s.psd_with_contact_distance(Component::Vertical, 0.7, 2.0)
        );
    }
}

#[test]
fn psd_is_positive_over_a_wide_band() {
    for s in Spectrum::ALL {
        for c in Component::ALL {
            for i in 0..=400 {
                let lambda = 0.5 * 400f64.powf(i as f64 / 400.0); // 0.5 … 200 m
                let g = s.psd(c, TAU / lambda);
                assert!(g.is_finite() && g > 0.0, "{s} {c:?} λ={lambda}: {g}");
            }
        }
    }
}

#[test]
fn sample_sigma_matches_the_integral_of_the_psd() {
    let (lambda_min, lambda_max) = (1.0, 80.0);
    let spectra = [
        Spectrum::GermanLow,
        Spectrum::GermanHigh,
        Spectrum::Fra(1),
        Spectrum::Fra(5),
        Spectrum::ChineseMainLine,
    ];
    for s in spectra {
        let mut spec = GeneratedSpec::new(s, 11);
        spec.lambda_min_m = lambda_min;
        spec.lambda_max_m = lambda_max;
        let g = spec.generate(0.0, 2500.0).unwrap();
        assert!(g.period_m() >= 2500.0);
        for c in Component::ALL {
            let want = reference_sigma(s, c, lambda_min, lambda_max);
            let got = sample_sigma_over_period(&g, c);
            let err = got / want - 1.0;
            eprintln!(
                "sigma {s:>18} {c:>10?}: sample {got:.6e} reference {want:.6e} error {:+.4} %",
                100.0 * err
            );
            // Measured: |error| ≤ 0.0049 % (fra-1/fra-5 lateral and vertical); bound ≈ 2×.
            assert!(err.abs() < 1e-4, "{s} {c:?}: σ {got} vs {want}");
        }
    }
}

#[test]
fn sample_sigma_matches_for_a_narrow_band() {
    // The paper's significant band, 5–40 m, on the Chinese spectrum.
    let mut spec = GeneratedSpec::new(Spectrum::ChineseMainLine, 3);
    spec.lambda_min_m = 5.0;
    spec.lambda_max_m = 40.0;
    spec.grid_spacing_m = 0.25;
    let g = spec.generate(-300.0, 2200.0).unwrap();
    for c in Component::ALL {
        let want = reference_sigma(Spectrum::ChineseMainLine, c, 5.0, 40.0);
        let got = sample_sigma_over_period(&g, c);
        eprintln!(
            "sigma chinese 5–40 m {c:?}: error {:+.4} %",
            100.0 * (got / want - 1.0)
        );
        // Measured: |error| ≤ 0.0096 % (cross-level); bound ≈ 2×.
        assert!((got / want - 1.0).abs() < 2e-4, "{c:?}: σ {got} vs {want}");
    }
}

// ---------------------------------------------------------------------------------------------
// Periodogram.

/// Welch estimate of the one-sided PSD in Ω (rad/m) from samples `r` with spacing `h`:
/// Hann-windowed segments of `len` samples with 50 % overlap,
/// `G(Ω_b) = h |X_b|² / (π Σ w²)` at `Ω_b = 2π b / (len h)`.
fn welch(r: &[f64], h: f64, len: usize) -> Vec<(f64, f64)> {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(len);
    let w: Vec<f64> = (0..len)
        .map(|j| 0.5 - 0.5 * (TAU * j as f64 / len as f64).cos())
        .collect();
    let w2: f64 = w.iter().map(|x| x * x).sum();
    let mut acc = vec![0.0; len / 2];
    let mut segments = 0;
    let mut start = 0;
    while start + len <= r.len() {
        let mut buf: Vec<Complex<f64>> = (0..len)
            .map(|j| Complex::new(r[start + j] * w[j], 0.0))
            .collect();
        fft.process(&mut buf);
        for (a, z) in acc.iter_mut().zip(&buf) {
            *a += z.norm_sqr();
        }
        segments += 1;
        start += len / 2;
    }
    assert!(segments >= 20, "too few segments: {segments}");
    acc.iter()
        .enumerate()
        .map(|(b, a)| {
            (
                TAU * b as f64 / (len as f64 * h),
                h * a / (PI * w2 * segments as f64),
            )
        })
        .collect()
}

fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x.ln() - mx) * (y.ln() - my), b + (x.ln() - mx).powi(2))
    });
    num / den
}

#[test]
fn periodogram_follows_the_psd() {
    let cases = [
        (Spectrum::GermanHigh, Component::Vertical, 21),
        (Spectrum::Fra(5), Component::Lateral, 22),
        (Spectrum::Fra(5), Component::CrossLevel, 23),
        (Spectrum::ChineseMainLine, Component::Vertical, 24),
        (Spectrum::ChineseMainLine, Component::Lateral, 25),
    ];
    // Octaves from λ = 32 m to 2 m, well inside the band 1–80 m.
    let octaves = [
        (PI / 16.0, PI / 8.0),
        (PI / 8.0, PI / 4.0),
        (PI / 4.0, PI / 2.0),
        (PI / 2.0, PI),
    ];
    for (s, c, seed) in cases {
        let g = GeneratedSpec::new(s, seed).generate(0.0, 16000.0).unwrap();
        let v = g.profile().values(c);
        let est = welch(&v[..v.len() - 1], g.grid_spacing_m(), 4096);
        let mut est_bands = Vec::new();
        let mut psd_bands = Vec::new();
        for &(lo, hi) in &octaves {
            let in_band: Vec<&(f64, f64)> =
                est.iter().filter(|(w, _)| *w >= lo && *w < hi).collect();
            assert!(in_band.len() >= 6);
            let n = in_band.len() as f64;
            let e = in_band.iter().map(|(_, p)| p).sum::<f64>() / n;
            let p = in_band.iter().map(|(w, _)| s.psd(c, *w)).sum::<f64>() / n;
            let centre = (lo * hi).sqrt();
            eprintln!(
                "periodogram {s} {c:?} Ω {lo:.3}–{hi:.3}: ratio {:.3}",
                e / p
            );
            assert!(
                (e / p - 1.0).abs() < 0.25,
                "{s} {c:?} band {lo}–{hi}: {e} vs {p}"
            );
            est_bands.push((centre, e));
            psd_bands.push((centre, p));
        }
        let (se, sp) = (slope(&est_bands), slope(&psd_bands));
        eprintln!("periodogram {s} {c:?}: log–log slope {se:.3} vs PSD {sp:.3}");
        assert!((se - sp).abs() < 0.2, "{s} {c:?}: slope {se} vs {sp}");
    }
}
