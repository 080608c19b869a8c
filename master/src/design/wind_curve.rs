//! `tbi sweep --speeds … --wind-speeds …`: the characteristic wind curve. Every train speed
//! runs in every mean wind (the scenario with `[wind] mean_speed_m_s` set, so deck and car
//! bodies carry the steady wind loads), in parallel on every core. Per case the largest wheel
//! unloading ΔQ/Q₀ over all wheels and times (the per-wheel offload factor against the
//! still-air static wheel load). Per train speed the characteristic wind speed is the wind
//! at which ΔQ/Q₀ reaches the limit (0.9 by default, EN 14067-6), by linear interpolation
//! between the last wind below and the first above it; empty when no wind of the sweep
//! reaches it.
//!
//! Files: `wind_cases.csv` (every case), `wind_curve.csv` (train speed, characteristic wind
//! speed), `wind_curve.svg` (the curve), and the runs in `OUT/v<speed>/u<wind>`.

use crate::design::SweepOptions;
use crate::scenario::Scenario;
use crate::solve::run_scenario;
use rayon::prelude::*;
use std::fmt::Write as _;

/// One case: (train speed km/h, wind m/s, ΔQ/Q₀ max, derail factor max).
type Case = (f64, f64, f64, f64);

/// The wind at which `unloading` (ascending winds) first reaches `limit`, interpolated
/// linearly; None when it never does. Winds at which it is already above the limit at the
/// lowest wind give that lowest wind.
pub fn characteristic_wind(points: &[(f64, f64)], limit: f64) -> Option<f64> {
    let k = points.iter().position(|p| p.1 > limit)?;
    if k == 0 {
        return Some(points[0].0);
    }
    let ((u0, a0), (u1, a1)) = (points[k - 1], points[k]);
    Some(u0 + (limit - a0) / (a1 - a0) * (u1 - u0))
}

pub fn main(
    args: &SweepOptions,
    base: &Scenario,
    speeds: &[f64],
) -> Result<(), Box<dyn std::error::Error>> {
    let winds = crate::design::speeds::parse_range(&args.wind_speeds, "--wind-speeds", "m/s")?;
    let limit = args.wheel_unloading_limit;
    if !(limit.is_finite() && limit > 0.0) {
        return Err(format!("--wheel-unloading-limit {limit}: must be positive").into());
    }
    let num = crate::text::num;
    let mut cases = Vec::new();
    for &v in speeds {
        for &u in &winds {
            let mut s = base.clone();
            s.set_speed_kmh(v).map_err(|e| format!("--speeds: {e}"))?;
            s.set_wind_speed(u)
                .map_err(|e| format!("--wind-speeds: {e}"))?;
            cases.push((v, u, s));
        }
    }
    // the sweep owns its folder: a second sweep into it is refused before any case runs
    let _claim = crate::output::outdir::OutputDir::claim(&args.out)?;
    let limits = if args.allow_large {
        crate::model::Limits::none()
    } else {
        crate::model::Limits::default()
    };
    crate::model::build_bridge(base)?;
    let pb = crate::output::progress::counted(cases.len(), "cases", true);
    let results: Vec<Result<Case, String>> = cases
        .par_iter()
        .map(|(v, u, s)| {
            let dir = args
                .out
                .join(format!("v{}", num(*v)))
                .join(format!("u{}", num(*u)));
            let r = run_scenario(s, &dir, false, &limits)
                .and_then(|sum| {
                    let f = sum.safety.ok_or(
                        "the wind curve needs wheel loads that vary: a train of coaches or sprung masses, not moving forces",
                    )?;
                    Ok((*v, *u, f.offload_factor_wheel_max, f.derail_factor_wheel_max))
                })
                .map_err(|e| format!("{} km/h in {} m/s: {e}", num(*v), num(*u)));
            pb.inc(1);
            r
        })
        .collect();
    pb.finish_and_clear();
    let rows: Vec<Case> = results.into_iter().collect::<Result<_, _>>()?;
    let mut csv =
        String::from("speed_kmh,wind_speed_m_s,wheel_unloading_max,derail_factor_wheel_max\n");
    for (v, u, a, d) in &rows {
        let _ = writeln!(csv, "{v:e},{u:e},{a:e},{d:e}");
    }
    crate::output::outdir::write_atomically(&args.out.join("wind_cases.csv"), csv.as_bytes())?;
    let mut curve = String::from("speed_kmh,characteristic_wind_speed_m_s\n");
    let mut points = Vec::new();
    crate::say!(
        "characteristic wind speed (ΔQ/Q₀ = {limit}, steady wind, {} winds from {} to {} m/s):",
        winds.len(),
        num(winds[0]),
        num(*winds.last().expect("a wind"))
    );
    for &v in speeds {
        let mut mine: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.0 == v)
            .map(|r| (r.1, r.2))
            .collect();
        mine.sort_by(|a, b| a.0.total_cmp(&b.0));
        let c = characteristic_wind(&mine, limit);
        let _ = writeln!(
            curve,
            "{v:e},{}",
            c.map(|x| format!("{x:e}")).unwrap_or_default()
        );
        crate::say!(
            "  {} km/h: {}",
            num(v),
            match c {
                Some(x) => format!("{x:.1} m/s"),
                None => format!("above {} m/s", num(*winds.last().expect("a wind"))),
            }
        );
        if let Some(x) = c {
            points.push((v, x));
        }
    }
    crate::output::outdir::write_atomically(&args.out.join("wind_curve.csv"), curve.as_bytes())?;
    let svg = crate::output::html::chart(
        &format!(
            "Characteristic wind curve of {} (ΔQ/Q₀ = {limit})",
            base.name
        ),
        "train speed (km/h)",
        "mean wind speed (m/s)",
        &[crate::output::html::Series {
            label: format!("ΔQ/Q₀ = {limit}"),
            points,
        }],
        &crate::output::html::Marks::default(),
    )?;
    crate::output::outdir::write_atomically(&args.out.join("wind_curve.svg"), svg.as_bytes())?;
    eprintln!(
        "tbi: {} cases; wind_curve.csv, wind_curve.svg, wind_cases.csv and the runs in {}",
        rows.len(),
        args.out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::characteristic_wind;

    #[test]
    fn the_crossing_is_interpolated() {
        let p = [(0.0, 0.1), (10.0, 0.5), (20.0, 1.3)];
        assert!((characteristic_wind(&p, 0.9).unwrap() - 15.0).abs() < 1e-12);
        assert_eq!(characteristic_wind(&p, 2.0), None);
        assert_eq!(characteristic_wind(&p, 0.05), Some(0.0));
    }
}
