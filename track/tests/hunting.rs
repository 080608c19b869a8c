//! Wheel hunting, eq. (7).

use std::f64::consts::TAU;

use tbi_track::hunting::{klingel_wavelength_m, phases, DEFAULT_HUNTING_WAVELENGTH_M};
use tbi_track::{Component, GeneratedSpec, HuntingParams, Spectrum, WheelHunting};

fn hunting(amplitude_m: f64, wavelength_m: f64, seed: u64, n: usize) -> WheelHunting {
    WheelHunting::new(
        &HuntingParams {
            amplitude_m,
            wavelength_m,
            seed,
        },
        n,
    )
    .unwrap()
}

#[test]
fn derivatives_match_finite_differences() {
    let (a, l) = (3e-3, 15.77);
    let hu = hunting(a, l, 5, 8);
    let k = TAU / l;
    let d = 1e-4 * l;
    // Central differences are accurate to d²/6 · max|third derivative| plus round-off.
    let tol1 = d * d / 6.0 * a * k.powi(3) + 1e-15 / d;
    let tol2 = d * d / 6.0 * a * k.powi(4) + 1e-15 / d;
    for w in 0..8 {
        for i in 0..200 {
            let s = -30.0 + 0.731 * i as f64;
            let (m, z, p) = (hu.lateral(w, s - d), hu.lateral(w, s), hu.lateral(w, s + d));
            assert!(
                ((p[0] - m[0]) / (2.0 * d) - z[1]).abs() <= tol1,
                "wheelset {w} s={s}"
            );
            assert!(
                ((p[1] - m[1]) / (2.0 * d) - z[2]).abs() <= tol2,
                "wheelset {w} s={s}"
            );
        }
    }
}

#[test]
fn sinusoid_has_the_amplitude_wavelength_and_phase() {
    let (a, l) = (2e-3, 12.0);
    let hu = hunting(a, l, 9, 4);
    for (w, &phi) in hu.phases().iter().enumerate() {
        let y0 = hu.lateral(w, 0.0)[0];
        assert!((y0 - a * phi.sin()).abs() < 1e-18);
        // A quarter wavelength later the sine has become the cosine of the phase.
        assert!((hu.lateral(w, l / 4.0)[0] - a * phi.cos()).abs() < 1e-15);
        // Periodic in the wavelength.
        for s in [0.3, 7.1, 100.0] {
            let (p, q) = (hu.lateral(w, s), hu.lateral(w, s + l));
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() < 1e-12 * a * (TAU / l).powi(k as i32));
            }
        }
        // Peak value is the amplitude.
        let peak = (0..10_000)
            .map(|i| hu.lateral(w, i as f64 * l / 10_000.0)[0].abs())
            .fold(0.0, f64::max);
        assert!((peak - a).abs() < 1e-9);
    }
}

#[test]
fn phases_are_reproducible_uniform_and_independent_of_the_irregularity_streams() {
    let p = phases(17, 200);
    assert_eq!(p, phases(17, 200));
    assert_eq!(&phases(17, 50)[..], &p[..50]);
    assert_ne!(phases(18, 200), p);
    assert!(p.iter().all(|&x| (0.0..TAU).contains(&x)));
    // Uniform: each quarter of [0, 2π) holds 50 ± 5 standard deviations.
    let mut counts = [0usize; 4];
    for &x in &p {
        counts[(x / TAU * 4.0) as usize] += 1;
    }
    let sd = (200.0f64 * 0.25 * 0.75).sqrt();
    assert!(
        counts.iter().all(|&c| (c as f64 - 50.0).abs() < 5.0 * sd),
        "{counts:?}"
    );
    // A distinct random stream from the irregularity components with the same seed.
    let g = GeneratedSpec::new(Spectrum::GermanLow, 17)
        .generate(0.0, 100.0)
        .unwrap();
    for c in Component::ALL {
        let t = g.terms(c);
        assert!(
            t.iter().zip(&p).all(|(t, &phi)| t.phase_rad != phi),
            "{c:?}"
        );
    }
}

#[test]
fn defaults_and_validation() {
    let d = HuntingParams::default();
    assert_eq!(d.amplitude_m, 0.0);
    assert_eq!(d.wavelength_m, DEFAULT_HUNTING_WAVELENGTH_M);
    assert!((klingel_wavelength_m(0.42, 0.75, 0.05) - DEFAULT_HUNTING_WAVELENGTH_M).abs() < 0.005);
    let off = WheelHunting::new(&d, 3).unwrap();
    assert!(!off.is_active());
    assert_eq!(off.lateral(2, 123.0), [0.0; 3]);
    for (p, field) in [
        (
            HuntingParams {
                amplitude_m: -1e-3,
                ..d.clone()
            },
            "amplitude_m = -0.001",
        ),
        (
            HuntingParams {
                wavelength_m: 0.0,
                ..d.clone()
            },
            "wavelength_m = 0",
        ),
        (
            HuntingParams {
                wavelength_m: f64::NAN,
                ..d.clone()
            },
            "wavelength_m = NaN",
        ),
    ] {
        let e = WheelHunting::new(&p, 2).unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}
