//! The generated field against its targets, estimated here independently of the generator
//! (Welch's method with a Hann window, written in this file):
//!
//! * σ of u and w at every point within 3 % of the spectrum's integral σ = I U (the closed form
//!   of every family integrates to 1), for the three spectra;
//! * the Welch spectrum of a point within 10 % of S(f) in bands from 0.01 to 5 Hz;
//! * the coherence Re S_jl / √(S_jj S_ll) at separations of 5, 10 and 20 m within 0.05 of
//!   Davenport's exp(−C f Δx / U), in bands from 0.05 Hz where it is between 0.15 and 0.85
//!   (Welch spectra summed over four seeds of 25 600 s each: an ensemble average);
//! * the same seed gives the same field; another seed another.

use rustfft::{num_complex::Complex, FftPlanner};
use tbi_wind::{Component, Spectrum, Turbulence, WindField};

const U: f64 = 20.0;

/// One-sided Welch estimates (Hann window, 50 % overlap) of the auto-spectra of `a`, `b` and
/// their cross-spectrum, at the frequencies k / (m dt).
fn welch(
    a: &[f64],
    b: &[f64],
    dt: f64,
    m: usize,
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<Complex<f64>>) {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(m);
    let win: Vec<f64> = (0..m)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / m as f64).cos())
        .collect();
    let norm: f64 = win.iter().map(|w| w * w).sum::<f64>();
    let (mut saa, mut sbb) = (vec![0.0; m / 2], vec![0.0; m / 2]);
    let mut sab = vec![Complex::new(0.0, 0.0); m / 2];
    let mut count = 0;
    let mut start = 0;
    while start + m <= a.len() {
        let mut fa: Vec<Complex<f64>> = (0..m)
            .map(|i| Complex::new(a[start + i] * win[i], 0.0))
            .collect();
        let mut fb: Vec<Complex<f64>> = (0..m)
            .map(|i| Complex::new(b[start + i] * win[i], 0.0))
            .collect();
        fft.process(&mut fa);
        fft.process(&mut fb);
        for k in 1..m / 2 {
            saa[k] += fa[k].norm_sqr();
            sbb[k] += fb[k].norm_sqr();
            sab[k] += fa[k] * fb[k].conj();
        }
        count += 1;
        start += m / 2;
    }
    let scale = 2.0 * dt / (norm * count as f64);
    let f: Vec<f64> = (0..m / 2).map(|k| k as f64 / (m as f64 * dt)).collect();
    (
        f,
        saa.iter().map(|v| v * scale).collect(),
        sbb.iter().map(|v| v * scale).collect(),
        sab.iter().map(|v| v * scale).collect(),
    )
}

fn std(v: &[f64]) -> f64 {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

fn turbulence(spectrum: Spectrum) -> Turbulence {
    Turbulence {
        spectrum,
        ..Turbulence::default()
    }
}

#[test]
fn sigma_of_every_component_is_the_spectrum_integral() {
    let points = [0.0, 10.0, 30.0, 60.0, 500.0];
    for spectrum in [
        Spectrum::Kaimal,
        Spectrum::VonKarman,
        Spectrum::SimiuScanlan,
    ] {
        let t = turbulence(spectrum);
        let field = WindField::generate(&t, U, &points, 3200.0).unwrap();
        assert_eq!(field.n_times(), 65536);
        for (c, series) in [(Component::U, &field.u), (Component::W, &field.w)] {
            let target = t.sigma(c, U);
            for (j, s) in series.iter().enumerate() {
                let got = std(s);
                assert!(
                    (got / target - 1.0).abs() < 0.03,
                    "{spectrum:?} {c:?} point {j}: σ = {got} m/s, target {target} m/s"
                );
            }
        }
    }
}

#[test]
fn the_welch_spectrum_follows_the_target() {
    let t = turbulence(Spectrum::VonKarman);
    let field = WindField::generate(&t, U, &[0.0], 6400.0).unwrap();
    for (c, s) in [(Component::U, &field.u[0]), (Component::W, &field.w[0])] {
        let (f, saa, _, _) = welch(s, s, t.dt_s, 4096);
        let mut lo = 0.01;
        while lo < 5.0 {
            let hi = lo * 2.0;
            let bins: Vec<usize> = (1..f.len()).filter(|&k| f[k] >= lo && f[k] < hi).collect();
            let est: f64 = bins.iter().map(|&k| saa[k]).sum();
            let target: f64 = bins.iter().map(|&k| t.psd(c, f[k], U)).sum();
            assert!(
                (est / target - 1.0).abs() < 0.10,
                "{c:?} {lo}–{hi} Hz: Welch {est} vs target {target}"
            );
            lo = hi;
        }
    }
}

#[test]
fn the_coherence_is_davenports() {
    let points = [0.0, 5.0, 10.0, 20.0];
    let seeds = 1..=4_u64;
    // per component and separation: the Welch spectra summed over four seeds (an ensemble
    // average of four 25 600 s records)
    type Sums = (Component, f64, f64, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);
    let mut sums: Vec<Sums> = Vec::new();
    for seed in seeds {
        let t = Turbulence {
            seed,
            ..turbulence(Spectrum::Kaimal)
        };
        let field = WindField::generate(&t, U, &points, 25600.0).unwrap();
        let mut i = 0;
        for (c, series, decay) in [
            (Component::U, &field.u, t.coherence_u),
            (Component::W, &field.w, t.coherence_w),
        ] {
            for j in 1..points.len() {
                let (f, saa, sbb, sab) = welch(&series[0], &series[j], t.dt_s, 32768);
                let re: Vec<f64> = sab.iter().map(|z| z.re).collect();
                if sums.len() <= i {
                    sums.push((c, points[j] - points[0], decay, f, saa, sbb, re));
                } else {
                    let e = &mut sums[i];
                    for k in 0..f.len() {
                        e.4[k] += saa[k];
                        e.5[k] += sbb[k];
                        e.6[k] += re[k];
                    }
                }
                i += 1;
            }
        }
    }
    let mut checked = 0;
    for (c, dx, decay, f, saa, sbb, re) in &sums {
        let mut lo = 0.05;
        while lo < 2.0 {
            let hi = lo * 1.5;
            let bins: Vec<usize> = (1..f.len()).filter(|&k| f[k] >= lo && f[k] < hi).collect();
            let weight = |k: usize| (saa[k] * sbb[k]).sqrt();
            let w: f64 = bins.iter().map(|&k| weight(k)).sum();
            let target: f64 = bins
                .iter()
                .map(|&k| weight(k) * (-decay * f[k] * dx / U).exp())
                .sum::<f64>()
                / w;
            if (0.15..=0.85).contains(&target) {
                let est: f64 = bins.iter().map(|&k| re[k]).sum::<f64>() / w;
                assert!(
                    (est - target).abs() < 0.05,
                    "{c:?} Δx = {dx} m, {lo:.3}–{hi:.3} Hz: coherence {est:.3} vs {target:.3}"
                );
                checked += 1;
            }
            lo = hi;
        }
    }
    assert!(checked >= 20, "only {checked} bands checked");
}

#[test]
fn seeds_and_bad_input() {
    let t = Turbulence::default();
    let a = WindField::generate(&t, U, &[0.0, 50.0], 100.0).unwrap();
    let b = WindField::generate(&t, U, &[0.0, 50.0], 100.0).unwrap();
    assert_eq!(a, b);
    let c = WindField::generate(
        &Turbulence {
            seed: 2,
            ..t.clone()
        },
        U,
        &[0.0, 50.0],
        100.0,
    )
    .unwrap();
    assert_ne!(a.u, c.u);
    let bad = |t: Turbulence, u: f64, x: &[f64], needle: &str| {
        let e = WindField::generate(&t, u, x, 100.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{needle:?} not in {e:?}");
    };
    bad(t.clone(), -5.0, &[0.0], "mean_speed_m_s = -5");
    bad(
        Turbulence {
            intensity_u: -0.1,
            ..t.clone()
        },
        U,
        &[0.0],
        "intensity_u = -0.1",
    );
    bad(
        Turbulence {
            intensity_w: f64::NAN,
            ..t.clone()
        },
        U,
        &[0.0],
        "intensity_w = NaN",
    );
    bad(
        Turbulence {
            length_scale_u_m: 0.0,
            ..t.clone()
        },
        U,
        &[0.0],
        "length_scale_u_m = 0",
    );
    bad(
        Turbulence {
            dt_s: 0.0,
            ..t.clone()
        },
        U,
        &[0.0],
        "dt_s = 0",
    );
    bad(t.clone(), U, &[0.0, 10.0, 5.0], "strictly increasing");
    bad(t.clone(), U, &[], "between 1 and 100000");
    // interpolation between points and periodicity in time
    let x = a.at(25.0, 3.0);
    let (u0, u1) = (a.at(0.0, 3.0)[0], a.at(50.0, 3.0)[0]);
    assert!((x[0] - 0.5 * (u0 + u1)).abs() < 1e-12);
    let period = a.n_times() as f64 * a.dt_s;
    assert!((a.at(10.0, 3.3)[1] - a.at(10.0, 3.3 + period)[1]).abs() < 1e-9);
}
