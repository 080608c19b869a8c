//! Generation of the suspension-bridge model: mesh, dead-load state, members, supports.

use crate::error::FeError;
use crate::params::{LongitudinalRestraint, SuspensionBridgeParams};
use crate::structure::{BarProps, Dof, NodeId, Structure, System};
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

/// A suspension-bridge finite-element model: the structure, its assembled K and M, and
/// the bookkeeping needed to read deck results.
#[derive(Debug, Clone)]
pub struct FeModel {
    pub(crate) params: SuspensionBridgeParams,
    pub(crate) structure: Structure,
    pub(crate) system: System,
    /// Deck spine nodes, ascending x.
    pub(crate) deck: Vec<(f64, NodeId)>,
    /// Cable point nodes (both cables) that carry lumped mass.
    pub(crate) cable_nodes: Vec<NodeId>,
    pub(crate) dead_load: DeadLoadState,
}

/// Split [a, b] into `n` equal parts, returning the interior points.
fn interior(a: f64, b: f64, n: usize) -> Vec<f64> {
    (1..n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

fn parts(len: f64, target: f64) -> usize {
    ((len / target).round() as usize).max(1)
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

impl FeModel {
    /// Generate and assemble the model. See the crate docs for the modelling assumptions.
    pub fn build(params: &SuspensionBridgeParams) -> Result<FeModel, FeError> {
        params.validate()?;
        let p = params;
        let g = p.gravity;
        let half = 0.5 * p.cable_spacing;
        let saddle_elev = p.saddle_elevation();

        // ------------------------------------------------------------------ stations
        let main_len = p.main_span();
        let n_main = 2 * ((main_len / (2.0 * p.hanger_spacing)).round() as usize).max(1);
        let n_left = parts(
            p.left_tower_x - p.left_pier_x,
            if p.left_side_span_suspended {
                p.hanger_spacing
            } else {
                p.element_length
            },
        );
        let n_right = parts(
            p.right_anchorage_x - p.right_tower_x,
            if p.right_side_span_suspended {
                p.hanger_spacing
            } else {
                p.element_length
            },
        );
        let n_back = parts(p.left_pier_x - p.left_anchorage_x, p.element_length);

        // Cable spans between fixed points a and b (z downward), their interior stations,
        // whether those carry hangers, and whether this is the main span.
        struct Seg {
            xa: f64,
            za: f64,
            xb: f64,
            zb: f64,
            x: Vec<f64>,
            hangers: bool,
            main: bool,
        }
        let segs = [
            Seg {
                xa: p.left_anchorage_x,
                za: -p.left_anchorage_elevation,
                xb: p.left_pier_x,
                zb: -p.left_pier_saddle_elevation,
                x: interior(p.left_anchorage_x, p.left_pier_x, n_back),
                hangers: false,
                main: false,
            },
            Seg {
                xa: p.left_pier_x,
                za: -p.left_pier_saddle_elevation,
                xb: p.left_tower_x,
                zb: -saddle_elev,
                x: interior(p.left_pier_x, p.left_tower_x, n_left),
                hangers: p.left_side_span_suspended,
                main: false,
            },
            Seg {
                xa: p.left_tower_x,
                za: -saddle_elev,
                xb: p.right_tower_x,
                zb: -saddle_elev,
                x: interior(p.left_tower_x, p.right_tower_x, n_main),
                hangers: true,
                main: true,
            },
            Seg {
                xa: p.right_tower_x,
                za: -saddle_elev,
                xb: p.right_anchorage_x,
                zb: -p.right_anchorage_elevation,
                x: interior(p.right_tower_x, p.right_anchorage_x, n_right),
                hangers: p.right_side_span_suspended,
                main: false,
            },
        ];

        // ------------------------------------------------------------------ deck mesh
        let mut hanger_x: Vec<f64> = segs
            .iter()
            .filter(|s| s.hangers)
            .flat_map(|s| s.x.iter().copied())
            .collect();
        hanger_x.sort_by(f64::total_cmp);
        let mut supports_x = vec![
            p.deck_start_x,
            p.deck_end_x,
            p.left_pier_x,
            p.left_tower_x,
            p.right_tower_x,
        ];
        supports_x.extend(p.deck_piers_x.iter().copied());
        supports_x.sort_by(f64::total_cmp);
        supports_x.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        for &h in &hanger_x {
            if h <= p.deck_start_x || h >= p.deck_end_x {
                return Err(FeError::Geometry(format!(
                    "hanger at x = {h} m lies outside the deck"
                )));
            }
        }
        // Points that carry the deck's dead load: supports and hangers.
        let mut carriers: Vec<f64> = supports_x.iter().chain(hanger_x.iter()).copied().collect();
        carriers.sort_by(f64::total_cmp);
        carriers.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        let mut deck_x = Vec::new();
        for w in carriers.windows(2) {
            deck_x.push(w[0]);
            let n = (((w[1] - w[0]) / p.element_length) - 1e-9).ceil().max(1.0) as usize;
            deck_x.extend(interior(w[0], w[1], n));
        }
        deck_x.push(*carriers.last().expect("at least two supports"));
        let tributary = |x: f64| -> f64 {
            let i = carriers
                .iter()
                .position(|&c| (c - x).abs() < 1e-6)
                .expect("carrier");
            let left = if i > 0 { x - carriers[i - 1] } else { 0.0 };
            let right = if i + 1 < carriers.len() {
                carriers[i + 1] - x
            } else {
                0.0
            };
            0.5 * (left + right)
        };
        let deck_weight = p.deck.mass_per_length * g;
        // Hanger force at the deck end (one cable side), N.
        let hanger_deck_force = |x: f64| 0.5 * deck_weight * tributary(x);

        // ---------------------------------------------------- funicular dead-load state
        let sag = p.main_sag();
        let mut zs: Vec<Vec<f64>> = segs
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
            loads = segs
                .iter()
                .zip(&zs)
                .map(|(s, z)| {
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
                                load += hanger_deck_force(x1) + p.hanger.mass_per_length * g * len;
                            }
                            load
                        })
                        .collect()
                })
                .collect();
            let main = &segs[2];
            let mid = 0.5 * (main.xa + main.xb);
            let h_new = span_moment(main.xa, main.xb, &main.x, &loads[2], mid) / sag;
            zs = segs
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
        if !(h > 0.0 && h.is_finite()) {
            return Err(FeError::Geometry(format!(
                "no positive horizontal cable tension (H = {h})"
            )));
        }
        for (s, z) in segs.iter().zip(&zs) {
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

        // Station list of one cable.
        let mut stations = Vec::new();
        let fixed_kind = [
            CableStationKind::Anchorage,
            CableStationKind::PierSaddle,
            CableStationKind::TowerSaddle,
            CableStationKind::TowerSaddle,
            CableStationKind::Anchorage,
        ];
        for (si, s) in segs.iter().enumerate() {
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
        let last = segs.last().expect("four segments");
        stations.push(CableStation {
            x: last.xb,
            z: last.zb,
            kind: CableStationKind::Anchorage,
            load: 0.0,
        });
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
            .map(|s| (s.x, hanger_deck_force(s.x), p.hanger_length(s.z)))
            .collect();
        let saddle_reaction = {
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
        };
        let dead_load = DeadLoadState {
            horizontal_tension: h,
            stations,
            segment_tension,
            hangers,
            saddle_reaction,
        };

        // ------------------------------------------------------------------ structure
        let mut st = Structure::new();
        // Deck spine.
        let deck: Vec<(f64, NodeId)> = deck_x
            .iter()
            .map(|&x| (x, st.add_node([x, 0.0, 0.0])))
            .collect();
        for w in deck.windows(2) {
            st.add_beam(w[0].1, w[1].1, &p.deck, [0.0, 1.0, 0.0], 0.0)?;
        }
        let deck_node_at = |x: f64| -> NodeId {
            deck.iter()
                .find(|(dx, _)| (dx - x).abs() < 1e-6)
                .expect("deck node at a carrier")
                .1
        };

        // Towers: two legs each, portal beams, saddles at the leg tops.
        let top_elev = saddle_elev;
        let mut leg_elev: Vec<f64> = vec![-p.deck_level_above_tower_base, top_elev];
        leg_elev.extend(p.crossbeam_elevations.iter().copied());
        leg_elev.sort_by(f64::total_cmp);
        leg_elev.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        let mut levels = Vec::new();
        for w in leg_elev.windows(2) {
            levels.push(w[0]);
            levels.extend(interior(w[0], w[1], parts(w[1] - w[0], p.element_length)));
        }
        levels.push(top_elev);
        let leg_w = p.tower_leg.mass_per_length * g;
        let cb_weight_per_leg = p.tower_crossbeam.mass_per_length * g * half;
        // tower_top[t][c]: top node of leg c (0: y = −half, 1: y = +half) of tower t.
        let mut tower_top = [[NodeId(0); 2]; 2];
        for (t, &xt) in [p.left_tower_x, p.right_tower_x].iter().enumerate() {
            let deck_reaction = deck_weight * tributary(xt);
            let mut legs = [Vec::new(), Vec::new()];
            for (c, &y) in [-half, half].iter().enumerate() {
                let nodes: Vec<NodeId> = levels.iter().map(|&e| st.add_node([xt, y, -e])).collect();
                st.fix(nodes[0], &Dof::ALL)?;
                for (k, w) in nodes.windows(2).enumerate() {
                    let e_mid = 0.5 * (levels[k] + levels[k + 1]);
                    let above_cb = p
                        .crossbeam_elevations
                        .iter()
                        .filter(|&&e| e > e_mid)
                        .count() as f64;
                    let mut compression = dead_load.saddle_reaction[t]
                        + leg_w * (top_elev - e_mid)
                        + above_cb * cb_weight_per_leg;
                    if e_mid < 0.0 {
                        compression += 0.5 * deck_reaction;
                    }
                    st.add_beam(w[0], w[1], &p.tower_leg, [0.0, 1.0, 0.0], -compression)?;
                }
                tower_top[t][c] = *nodes.last().expect("leg nodes");
                legs[c] = nodes;
            }
            for &e in &p.crossbeam_elevations {
                let k = levels
                    .iter()
                    .position(|&l| (l - e).abs() < 1e-6)
                    .expect("crossbeam level");
                let centre = st.add_node([xt, 0.0, -e]);
                st.add_beam(
                    legs[0][k],
                    centre,
                    &p.tower_crossbeam,
                    [0.0, 0.0, -1.0],
                    0.0,
                )?;
                st.add_beam(
                    centre,
                    legs[1][k],
                    &p.tower_crossbeam,
                    [0.0, 0.0, -1.0],
                    0.0,
                )?;
                if e == 0.0 {
                    st.tie(centre, deck_node_at(xt), &[Dof::Uy, Dof::Uz, Dof::Rx])?;
                }
            }
        }

        // Cables and hangers.
        let mut cable_nodes = Vec::new();
        let ds = &dead_load;
        for (c, &y) in [-half, half].iter().enumerate() {
            let mut tower_count = 0;
            let mut nodes = Vec::with_capacity(ds.stations.len());
            for s in &ds.stations {
                let node = match s.kind {
                    CableStationKind::TowerSaddle => {
                        let n = tower_top[tower_count][c];
                        tower_count += 1;
                        n
                    }
                    CableStationKind::Anchorage | CableStationKind::PierSaddle => {
                        let n = st.add_point([s.x, y, s.z]);
                        st.fix(n, &Dof::TRANSLATIONS)?;
                        n
                    }
                    CableStationKind::Hanger | CableStationKind::Free => {
                        let n = st.add_point([s.x, y, s.z]);
                        cable_nodes.push(n);
                        n
                    }
                };
                nodes.push(node);
            }
            for (k, w) in nodes.windows(2).enumerate() {
                let xm = 0.5 * (ds.stations[k].x + ds.stations[k + 1].x);
                let main = xm > p.left_tower_x && xm < p.right_tower_x;
                let (area, mc) = if main {
                    (p.cable.area_main, p.cable.mass_per_length_main)
                } else {
                    (p.cable.area_side, p.cable.mass_per_length_side)
                };
                st.add_bar(
                    w[0],
                    w[1],
                    BarProps {
                        ea: p.cable.e * area,
                        mass_per_length: mc,
                        tension: ds.segment_tension[k],
                    },
                )?;
            }
            for (k, s) in ds.stations.iter().enumerate() {
                if s.kind != CableStationKind::Hanger {
                    continue;
                }
                let len = p.hanger_length(s.z);
                let t_deck = hanger_deck_force(s.x);
                st.add_bar_with_arms(
                    nodes[k],
                    [0.0; 3],
                    deck_node_at(s.x),
                    [0.0, y, -p.hanger_anchor_elevation],
                    BarProps {
                        ea: p.hanger.e * p.hanger.area,
                        mass_per_length: p.hanger.mass_per_length,
                        tension: t_deck + 0.5 * p.hanger.mass_per_length * g * len,
                    },
                )?;
            }
        }

        // Deck bearings.
        let bearing = [Dof::Uy, Dof::Uz, Dof::Rx];
        st.fix(deck[0].1, &bearing)?;
        st.fix(deck[deck.len() - 1].1, &bearing)?;
        st.fix(deck_node_at(p.left_pier_x), &bearing)?;
        for &x in &p.deck_piers_x {
            st.fix(deck_node_at(x), &bearing)?;
        }
        let restrained = match p.longitudinal_restraint {
            LongitudinalRestraint::LeftAbutment => deck[0].1,
            LongitudinalRestraint::RightAbutment => deck[deck.len() - 1].1,
        };
        st.fix(restrained, &[Dof::Ux])?;

        let system = st.assemble()?;
        Ok(FeModel {
            params: p.clone(),
            structure: st,
            system,
            deck,
            cable_nodes,
            dead_load,
        })
    }

    /// The parameters the model was built from.
    pub fn params(&self) -> &SuspensionBridgeParams {
        &self.params
    }

    /// The generated structure (nodes, members, supports).
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// Assembled K (elastic + geometric) and M over the free DOFs.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Deck node positions x, m (ascending).
    pub fn deck_x(&self) -> Vec<f64> {
        self.deck.iter().map(|d| d.0).collect()
    }

    /// Deck spine nodes (x, node), ascending x.
    pub fn deck_nodes(&self) -> &[(f64, NodeId)] {
        &self.deck
    }

    /// Dead-load state of the cables.
    pub fn dead_load(&self) -> &DeadLoadState {
        &self.dead_load
    }

    /// Free cable nodes (both cables), each carrying lumped cable and hanger mass.
    pub fn cable_nodes(&self) -> &[NodeId] {
        &self.cable_nodes
    }

    /// Tributary deck length of each deck node (half the adjacent elements), m.
    pub(crate) fn deck_tributary_lengths(&self) -> Vec<f64> {
        let n = self.deck.len();
        (0..n)
            .map(|i| {
                let l = if i > 0 {
                    self.deck[i].0 - self.deck[i - 1].0
                } else {
                    0.0
                };
                let r = if i + 1 < n {
                    self.deck[i + 1].0 - self.deck[i].0
                } else {
                    0.0
                };
                0.5 * (l + r)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
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
