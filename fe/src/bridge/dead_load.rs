//! Dead-load (reference) state of the main cables: the funicular polygon through the fixed
//! points under the cable, hanger and deck weight, its tensions and the saddle reactions.

use super::layout::{CableSpan, DeckMesh};
use crate::error::FeError;
use crate::params::SuspensionBridgeParams;
use serde::{Deserialize, Serialize};

/// What sits at a station of the cable polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CableStationKind {
    /// Fixed anchorage (left or right).
    Anchorage,
    /// Saddle on the cable pier (fixed).
    PierSaddle,
    /// Saddle on a tower top (moves with the tower).
    TowerSaddle,
    /// Hanger clamp.
    Hanger,
    /// Free cable node (no hanger).
    Free,
}

/// One node of a main cable in the dead-load state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CableStation {
    /// x, m.
    pub x: f64,
    /// z (downward), m.
    pub z: f64,
    pub kind: CableStationKind,
    /// Vertical dead load applied to this node of one cable (hanger + cable weight), N.
    /// Zero at fixed points and saddles (carried directly by the support).
    pub load: f64,
}

/// Dead-load (reference) state of one main cable; both cables are identical, at
/// y = ∓ cable_spacing / 2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeadLoadState {
    /// Horizontal cable tension H of one cable, N (the same in every span).
    pub horizontal_tension: f64,
    /// Cable stations from the left to the right anchorage.
    pub stations: Vec<CableStation>,
    /// Tension of each cable segment between consecutive stations, N.
    pub segment_tension: Vec<f64>,
    /// Hanger stations: (x, tension at the deck end, hanger length), N and m.
    pub hangers: Vec<(f64, f64, f64)>,
    /// Vertical reaction of one tower leg at its saddle from the cable, N (left, right tower).
    pub saddle_reaction: [f64; 2],
}

/// Funicular polygon of one span: given fixed ends `(xa, za)`, `(xb, zb)`, interior stations
/// `x` with downward loads `p`, and horizontal tension `h`, return z at the stations
/// (chord + M(x)/H, M the simply-supported moment).
fn funicular(xa: f64, za: f64, xb: f64, zb: f64, x: &[f64], p: &[f64], h: f64) -> Vec<f64> {
    x.iter()
        .map(|&xi| za + (zb - za) * (xi - xa) / (xb - xa) + span_moment(xa, xb, x, p, xi) / h)
        .collect()
}

/// Bending moment at `xi` of a simply supported beam on [xa, xb] under point loads `p` at `x`.
fn span_moment(xa: f64, xb: f64, x: &[f64], p: &[f64], xi: f64) -> f64 {
    let l = xb - xa;
    x.iter()
        .zip(p)
        .map(|(&xk, &pk)| {
            if xk <= xi {
                pk * (xk - xa) * (xb - xi) / l
            } else {
                pk * (xi - xa) * (xb - xk) / l
            }
        })
        .sum()
}

impl DeadLoadState {
    /// Find the dead-load state of one cable over `spans`, the deck hanging from the hangers
    /// as meshed in `mesh`: funicular shape, stations, segment tensions, hanger forces and
    /// saddle reactions.
    pub(super) fn solve(
        p: &SuspensionBridgeParams,
        spans: &[CableSpan],
        mesh: &DeckMesh,
    ) -> Result<Self, FeError> {
        let (h, zs, loads) = funicular_shape(p, spans, mesh);
        if !(h > 0.0 && h.is_finite()) {
            return Err(FeError::Geometry(format!(
                "no positive horizontal cable tension (H = {h})"
            )));
        }
        check_hanger_clearance(p, spans, &zs)?;
        let stations = cable_stations(spans, &zs, &loads);
        let segment_tension: Vec<f64> = stations
            .windows(2)
            .map(|w| {
                let dx = w[1].x - w[0].x;
                let dz = w[1].z - w[0].z;
                h * (dx * dx + dz * dz).sqrt() / dx
            })
            .collect();
        let hangers: Vec<(f64, f64, f64)> = stations
            .iter()
            .filter(|s| s.kind == CableStationKind::Hanger)
            .map(|s| (s.x, mesh.hanger_deck_force(s.x), p.hanger_length(s.z)))
            .collect();
        let saddle_reaction = saddle_reactions(&stations, &segment_tension);
        Ok(DeadLoadState {
            horizontal_tension: h,
            stations,
            segment_tension,
            hangers,
            saddle_reaction,
        })
    }
}

/// Iterate the funicular shape of the cable from the parabolic main-span guess until the
/// horizontal tension H (fixed by the main-span sag) settles; returns H, the station z and
/// the station loads of each span.
fn funicular_shape(
    p: &SuspensionBridgeParams,
    spans: &[CableSpan],
    mesh: &DeckMesh,
) -> (f64, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let sag = p.main_sag();
    let mut zs: Vec<Vec<f64>> = spans
        .iter()
        .map(|s| {
            s.x.iter()
                .map(|&x| {
                    let chord = s.za + (s.zb - s.za) * (x - s.xa) / (s.xb - s.xa);
                    let t = (x - s.xa) / (s.xb - s.xa);
                    chord
                        + if s.main {
                            4.0 * sag * t * (1.0 - t)
                        } else {
                            0.0
                        }
                })
                .collect()
        })
        .collect();
    let mut h = 0.0;
    let mut loads: Vec<Vec<f64>> = Vec::new();
    for _iter in 0..200 {
        loads = spans
            .iter()
            .zip(&zs)
            .map(|(s, z)| station_loads(p, s, z, mesh))
            .collect();
        let main = &spans[2];
        let mid = 0.5 * (main.xa + main.xb);
        let h_new = span_moment(main.xa, main.xb, &main.x, &loads[2], mid) / sag;
        zs = spans
            .iter()
            .zip(&loads)
            .map(|(s, pl)| funicular(s.xa, s.za, s.xb, s.zb, &s.x, pl, h_new))
            .collect();
        let done = (h_new - h).abs() <= 1e-13 * h_new.abs();
        h = h_new;
        if done {
            break;
        }
    }
    (h, zs, loads)
}

/// Vertical load at each interior station of span `s` with station z `z`: the cable weight
/// over half of each adjacent segment, plus the hanger's deck force and weight if the span
/// carries hangers.
fn station_loads(
    p: &SuspensionBridgeParams,
    s: &CableSpan,
    z: &[f64],
    mesh: &DeckMesh,
) -> Vec<f64> {
    let g = p.gravity;
    let mc = if s.main {
        p.cable.mass_per_length_main
    } else {
        p.cable.mass_per_length_side
    };
    let n = s.x.len();
    let pt = |k: isize| -> (f64, f64) {
        if k < 0 {
            (s.xa, s.za)
        } else if k as usize >= n {
            (s.xb, s.zb)
        } else {
            (s.x[k as usize], z[k as usize])
        }
    };
    (0..n)
        .map(|k| {
            let (x0, z0) = pt(k as isize - 1);
            let (x1, z1) = pt(k as isize);
            let (x2, z2) = pt(k as isize + 1);
            let l1 = ((x1 - x0).powi(2) + (z1 - z0).powi(2)).sqrt();
            let l2 = ((x2 - x1).powi(2) + (z2 - z1).powi(2)).sqrt();
            let mut load = 0.5 * mc * g * (l1 + l2);
            if s.hangers {
                let len = p.hanger_length(z1);
                load += mesh.hanger_deck_force(x1) + p.hanger.mass_per_length * g * len;
            }
            load
        })
        .collect()
}

/// Fail if, in a span with hangers, the lowest cable point is less than 1 m above the
/// hanger anchors on the deck.
fn check_hanger_clearance(
    p: &SuspensionBridgeParams,
    spans: &[CableSpan],
    zs: &[Vec<f64>],
) -> Result<(), FeError> {
    for (s, z) in spans.iter().zip(zs) {
        if s.hangers {
            if let Some((k, &zk)) = z
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .filter(|(_, &zk)| p.hanger_length(zk) < 1.0)
            {
                return Err(FeError::Geometry(format!(
                    "the cable at x = {} m is only {} m above the hanger anchors on the deck",
                    s.x[k],
                    p.hanger_length(zk)
                )));
            }
        }
    }
    Ok(())
}

/// Station list of one cable, left to right: the fixed point at the start of each span, its
/// interior stations with their loads, and the right anchorage.
fn cable_stations(spans: &[CableSpan], zs: &[Vec<f64>], loads: &[Vec<f64>]) -> Vec<CableStation> {
    let mut stations = Vec::new();
    let fixed_kind = [
        CableStationKind::Anchorage,
        CableStationKind::PierSaddle,
        CableStationKind::TowerSaddle,
        CableStationKind::TowerSaddle,
        CableStationKind::Anchorage,
    ];
    for (si, s) in spans.iter().enumerate() {
        stations.push(CableStation {
            x: s.xa,
            z: s.za,
            kind: fixed_kind[si],
            load: 0.0,
        });
        for k in 0..s.x.len() {
            stations.push(CableStation {
                x: s.x[k],
                z: zs[si][k],
                kind: if s.hangers {
                    CableStationKind::Hanger
                } else {
                    CableStationKind::Free
                },
                load: loads[si][k],
            });
        }
    }
    let last = spans.last().expect("four segments");
    stations.push(CableStation {
        x: last.xb,
        z: last.zb,
        kind: CableStationKind::Anchorage,
        load: 0.0,
    });
    stations
}

/// Vertical reaction of one tower leg at each tower saddle (left, right): the vertical
/// components of the tensions of the two cable segments meeting there, N.
fn saddle_reactions(stations: &[CableStation], segment_tension: &[f64]) -> [f64; 2] {
    let mut r = [0.0; 2];
    let mut t = 0;
    for (i, s) in stations.iter().enumerate() {
        if s.kind == CableStationKind::TowerSaddle {
            let mut v = 0.0;
            for (nb, seg) in [(i - 1, i - 1), (i + 1, i)] {
                let o = stations[nb];
                let l = ((o.x - s.x).powi(2) + (o.z - s.z).powi(2)).sqrt();
                v += segment_tension[seg] * (o.z - s.z) / l;
            }
            r[t] = v;
            t += 1;
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::super::layout::interior;
    use super::*;

    /// Equal loads P at equal spacing h: the funicular polygon through the end points has
    /// its vertices on the parabola z = chord + 4 f t (1 − t) with H = w L²/(8f), w = P/h.
    #[test]
    fn funicular_of_uniform_loads_is_the_parabola() {
        let (xa, xb, za, zb, n) = (10.0, 410.0, -30.0, -50.0, 40);
        let h_sp = (xb - xa) / n as f64;
        let x = interior(xa, xb, n);
        let (pload, sag) = (2.0e5, 33.0);
        let p = vec![pload; x.len()];
        let w = pload / h_sp;
        let h = span_moment(xa, xb, &x, &p, 0.5 * (xa + xb)) / sag;
        let l = xb - xa;
        assert!((h / (w * l * l / (8.0 * sag)) - 1.0).abs() < 1e-12);
        let z = funicular(xa, za, xb, zb, &x, &p, h);
        for (xi, zi) in x.iter().zip(&z) {
            let t = (xi - xa) / l;
            let parabola = za + (zb - za) * t + 4.0 * sag * t * (1.0 - t);
            assert!((zi - parabola).abs() < 1e-9, "x = {xi}: {zi} vs {parabola}");
        }
    }
}
