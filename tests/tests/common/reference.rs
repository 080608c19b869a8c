//! Independent references for the bridge's static response: the analytic modes of the
//! scenarios' simply supported span (from the section constants of [`super::scenarios`]),
//! truncated modal series and the untruncated closed forms.

use super::scenarios::*;
use std::f64::consts::PI;

/// One mode of the analytic simply supported model: family ('V', 'L', 'T'), half-wave
/// number n, ω (rad/s).
pub fn analytic_modes() -> Vec<(char, u32, f64)> {
    let l = SPAN_M;
    let mut all = Vec::new();
    for n in 1..=FORCE_MODES as u32 {
        let k = n as f64 * PI / l;
        all.push(('V', n, k * k * (E_PA * IV_M4 / MU_KG_M).sqrt()));
        all.push(('L', n, k * k * (E_PA * IH_M4 / MU_KG_M).sqrt()));
        all.push(('T', n, k * (G_PA * J_M4 / IM_KG_M).sqrt()));
    }
    all.sort_by(|a, b| a.2.total_cmp(&b.2));
    all.truncate(FORCE_MODES);
    all
}

/// Static response of the span to a vertical force `f` at `a` on the track (eccentricity e):
/// (vertical deflection, torsion) at `x` from the modes kept.
///
/// Truncated series of the closed forms (mass-normalised sine modes, ωₙ² from the section):
/// `z(x) = 2 F L³/(E I π⁴) Σ_{V modes kept} sin(nπx/L) sin(nπa/L)/n⁴` and
/// `θ(x) = 2 (e F) L/(G J π²) Σ_{T modes kept} sin(nπx/L) sin(nπa/L)/n²`, where the kept modes
/// are the lowest FORCE_MODES frequencies of all three families (as the bridge keeps them).
pub fn truncated_series(x: f64, a: f64, f: f64) -> (f64, f64) {
    let l = SPAN_M;
    let (mut z, mut th) = (0.0, 0.0);
    for (fam, n, _) in analytic_modes() {
        let n_f = n as f64;
        let s = (n_f * PI * x / l).sin() * (n_f * PI * a / l).sin();
        match fam {
            'V' => z += 2.0 * f * l.powi(3) / (E_PA * IV_M4 * PI.powi(4)) * s / n_f.powi(4),
            'T' => th += 2.0 * E_TRACK_M * f * l / (G_PA * J_M4 * PI * PI) * s / (n_f * n_f),
            _ => {}
        }
    }
    (z, th)
}

/// Closed forms of the untruncated static response: simply supported Euler–Bernoulli beam under
/// a point load, and a fork-supported St-Venant bar under a point torque e·F.
pub fn closed_form(x: f64, a: f64, f: f64) -> (f64, f64) {
    let l = SPAN_M;
    let (xl, al) = if x <= a { (x, a) } else { (l - x, l - a) };
    let b = l - al;
    let z = f * b * xl * (l * l - b * b - xl * xl) / (6.0 * E_PA * IV_M4 * l);
    let th = E_TRACK_M * f * xl * b / (G_PA * J_M4 * l);
    (z, th)
}

/// Bounds of the truncation error of [`truncated_series`] against [`closed_form`]: the
/// dropped terms are bounded by the tails Σ_{n not kept} 1/n⁴ and 1/n² (summed to N, plus
/// the integral bound 1/((p−1) N^(p−1)) of the rest).
pub fn truncation_bounds(f: f64) -> (f64, f64) {
    let kept = analytic_modes();
    const N: u32 = 100_000;
    let tail = |fam: char, p: i32| -> f64 {
        let head: f64 = (1..=N)
            .filter(|n| !kept.iter().any(|m| m.0 == fam && m.1 == *n))
            .map(|n| 1.0 / (n as f64).powi(p))
            .sum();
        head + 1.0 / ((p - 1) as f64 * (N as f64).powi(p - 1))
    };
    let l = SPAN_M;
    (
        2.0 * f * l.powi(3) / (E_PA * IV_M4 * PI.powi(4)) * tail('V', 4),
        2.0 * E_TRACK_M * f * l / (G_PA * J_M4 * PI * PI) * tail('T', 2),
    )
}
