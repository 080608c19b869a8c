//! The EN 1991-2 high-speed load model HSLM-A (EN 1991-2:2003 §6.4.6.1.1, Figure 6.12 and
//! Table 6.3; Annex E; Figure 8.12 and Table 8.4 in the 2024 edition): ten articulated trains
//! A1–A10 of point forces, every axle carrying the same force P.
//!
//! A train of N intermediate coaches of length D with bogie axle spacing d is, in order: a
//! power car (axles at 0, 3, 14, 17 m), an end coach, N intermediate coaches on N + 1 shared
//! (articulated) bogies, the other end coach and the mirrored power car. With the coupling
//! point c₀ = 17 + 3.525/2 = 18.7625 m, the positions from the first axle are
//!
//! ```text
//! power car            0, 3, 14, 17
//! leading end coach    c₀ + 1.7625 = 20.525,  20.525 + d
//! shared bogie i       c₀ + i·D ∓ d/2,        i = 1 … N + 1
//! trailing end coach   L − 20.525 − d,  L − 20.525
//! rear power car       L − 17, L − 14, L − 3, L,       L = 2 c₀ + (N + 2) D
//! ```
//!
//! so 2N + 14 axles and a length L = 37.525 + (N + 2) D from the first to the last axle (as
//! the spacings of the standard's figure: 3, 11, 3, 3.525, d, D − 1.5d − 1.7625, then d,
//! D − d per coach, and the mirror). Checked in the tests against the axle files of an
//! independent implementation (caldintav, UPM Madrid: `trains/a01.def` …).

use crate::vehicle::simple::MovingForceAxle;

/// One HSLM-A train of EN 1991-2 Table 6.3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HslmA {
    pub name: &'static str,
    /// Number of intermediate coaches N.
    pub coaches: usize,
    /// Coach length D, m.
    pub coach_length_m: f64,
    /// Bogie axle spacing d, m.
    pub bogie_axle_spacing_m: f64,
    /// Point force per axle P, N.
    pub axle_load_n: f64,
}

const fn a(name: &'static str, n: usize, d_coach: f64, d_axle: f64, p_kn: f64) -> HslmA {
    HslmA {
        name,
        coaches: n,
        coach_length_m: d_coach,
        bogie_axle_spacing_m: d_axle,
        axle_load_n: p_kn * 1e3,
    }
}

/// EN 1991-2 Table 6.3: HSLM-A1 … A10.
pub const HSLM_A: [HslmA; 10] = [
    a("A1", 18, 18.0, 2.0, 170.0),
    a("A2", 17, 19.0, 3.5, 200.0),
    a("A3", 16, 20.0, 2.0, 180.0),
    a("A4", 15, 21.0, 3.0, 190.0),
    a("A5", 14, 22.0, 2.0, 170.0),
    a("A6", 13, 23.0, 2.0, 180.0),
    a("A7", 13, 24.0, 2.0, 190.0),
    a("A8", 12, 25.0, 2.5, 190.0),
    a("A9", 11, 26.0, 2.0, 210.0),
    a("A10", 11, 27.0, 2.0, 210.0),
];

impl HslmA {
    /// Axle positions from the first axle, m (see the module documentation).
    pub fn positions(&self) -> Vec<f64> {
        let (n, dc, d) = (self.coaches, self.coach_length_m, self.bogie_axle_spacing_m);
        let c0 = 17.0 + 3.525 / 2.0;
        let length = 2.0 * c0 + (n as f64 + 2.0) * dc;
        let mut x = vec![0.0, 3.0, 14.0, 17.0, c0 + 1.7625, c0 + 1.7625 + d];
        for i in 1..=n + 1 {
            let centre = c0 + i as f64 * dc;
            x.extend([centre - d / 2.0, centre + d / 2.0]);
        }
        x.extend([
            length - 20.525 - d,
            length - 20.525,
            length - 17.0,
            length - 14.0,
            length - 3.0,
            length,
        ]);
        x
    }

    /// The train as moving forces.
    pub fn axles(&self) -> Vec<MovingForceAxle> {
        self.positions()
            .into_iter()
            .map(|offset_m| MovingForceAxle {
                offset_m,
                load_n: self.axle_load_n,
            })
            .collect()
    }

    /// Length from the first to the last axle, m.
    pub fn length_m(&self) -> f64 {
        37.525 + (self.coaches as f64 + 2.0) * self.coach_length_m
    }
}

/// The moving forces of the HSLM-A train named `name` (`A1` … `A10`, case-insensitive).
pub fn hslm_a(name: &str) -> Result<Vec<MovingForceAxle>, String> {
    HSLM_A
        .iter()
        .find(|t| t.name.eq_ignore_ascii_case(name.trim()))
        .map(HslmA::axles)
        .ok_or_else(|| format!("\"{name}\" is not an HSLM-A train (A1 … A10)"))
}

/// HSLM-B's point force, N (EN 1991-2 §6.4.6.1.1: N point forces of 170 kN at a uniform
/// spacing d).
pub const HSLM_B_FORCE_N: f64 = 170e3;

/// HSLM-B, the load model of simply supported spans under 7 m: `forces` point forces of
/// 170 kN at a uniform `spacing_m`. The standard gives N and d as functions of the span in a
/// figure of §6.4.6.1.1, which the user reads for the span; they are not derived here.
pub fn hslm_b(forces: usize, spacing_m: f64) -> Result<Vec<MovingForceAxle>, String> {
    if forces == 0 {
        return Err("forces = 0: HSLM-B needs at least one point force".into());
    }
    if !(spacing_m.is_finite() && spacing_m > 0.0) {
        return Err(format!(
            "spacing_m = {spacing_m}: must be a positive finite number"
        ));
    }
    Ok((0..forces)
        .map(|i| MovingForceAxle {
            offset_m: i as f64 * spacing_m,
            load_n: HSLM_B_FORCE_N,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hslm_b_is_n_forces_of_170_kn_at_d() {
        let b = hslm_b(12, 3.25).unwrap();
        assert_eq!(b.len(), 12);
        assert!(b.iter().all(|a| a.load_n == 170e3));
        for (i, a) in b.iter().enumerate() {
            assert!((a.offset_m - 3.25 * i as f64).abs() < 1e-12);
        }
        assert!(hslm_b(0, 3.0).unwrap_err().contains("forces = 0"));
        assert!(hslm_b(10, 0.0).unwrap_err().contains("spacing_m = 0"));
        assert!(hslm_b(10, f64::NAN).is_err());
    }

    /// HSLM-A1 from caldintav's `trains/a01.def` (UPM Madrid), first and last 12 axles.
    #[test]
    fn a1_equals_an_independent_axle_file() {
        let x = HSLM_A[0].positions();
        let first = [
            0.0, 3.0, 14.0, 17.0, 20.525, 22.525, 35.7625, 37.7625, 53.7625, 55.7625, 71.7625,
            73.7625,
        ];
        let last = [
            323.7625, 325.7625, 341.7625, 343.7625, 359.7625, 361.7625, 375.0, 377.0, 380.525,
            383.525, 394.525, 397.525,
        ];
        assert_eq!(x.len(), 50);
        for (a, b) in x
            .iter()
            .zip(&first)
            .chain(x[x.len() - 12..].iter().zip(&last))
        {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    /// Every train: 2N + 14 axles, increasing, the stated length, mirror symmetric, every
    /// axle carrying P.
    #[test]
    fn every_train_has_the_standard_shape() {
        for t in &HSLM_A {
            let x = t.positions();
            assert_eq!(x.len(), 2 * t.coaches + 14, "{}", t.name);
            assert!(x.windows(2).all(|w| w[1] > w[0]), "{}: {x:?}", t.name);
            let l = t.length_m();
            assert!((x[x.len() - 1] - l).abs() < 1e-9, "{}", t.name);
            for (a, b) in x.iter().zip(x.iter().rev()) {
                assert!((a + b - l).abs() < 1e-9, "{}: not symmetric", t.name);
            }
            assert!(t.axles().iter().all(|a| a.load_n == t.axle_load_n));
        }
        // the lengths of the independent axle files (last axle), A1 … A10
        let lengths = [
            397.525, 398.525, 397.525, 394.525, 389.525, 382.525, 397.525, 387.525, 375.525,
            388.525,
        ];
        for (t, l) in HSLM_A.iter().zip(lengths) {
            assert!((t.length_m() - l).abs() < 1e-9, "{}", t.name);
        }
        assert!(hslm_a("a7").is_ok() && hslm_a("A11").is_err());
    }
}
