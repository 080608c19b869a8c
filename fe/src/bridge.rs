//! Generation of the suspension-bridge model: mesh, dead-load state, members, supports.
//!
//! [`FeModel::build`] lays out the cable spans and meshes the deck (submodule `layout`),
//! finds the cables' funicular dead-load state (submodule `dead_load`), then adds the deck
//! spine, the towers, the cables with their hangers and the deck bearings to a
//! [`Structure`] and assembles it.

mod dead_load;
mod layout;

pub use dead_load::{CableStation, CableStationKind, DeadLoadState};

use crate::error::FeError;
use crate::params::{LongitudinalRestraint, SuspensionBridgeParams};
use crate::structure::{BarProps, Dof, NodeId, Structure, System};
use layout::{cable_spans, interior, parts, DeckMesh};

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

impl FeModel {
    /// Generate and assemble the model. See the crate docs for the modelling assumptions.
    pub fn build(params: &SuspensionBridgeParams) -> Result<FeModel, FeError> {
        params.validate()?;
        let p = params;
        let spans = cable_spans(p);
        let mesh = DeckMesh::new(p, &spans)?;
        let dead_load = DeadLoadState::solve(p, &spans, &mesh)?;

        let mut st = Structure::new();
        let deck = add_deck(&mut st, p, &mesh.x)?;
        let tower_top = add_towers(&mut st, p, &mesh, &deck, &dead_load)?;
        let cable_nodes = add_cables(&mut st, p, &mesh, &deck, &dead_load, &tower_top)?;
        add_deck_bearings(&mut st, p, &deck)?;

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

/// The deck node at `x` (a support or hanger station of the mesh).
fn deck_node_at(deck: &[(f64, NodeId)], x: f64) -> NodeId {
    deck.iter()
        .find(|(dx, _)| (dx - x).abs() < 1e-6)
        .expect("deck node at a carrier")
        .1
}

/// Adds the deck spine: a node at each mesh point and beams between them; returns the
/// (x, node) pairs, ascending x.
fn add_deck(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    deck_x: &[f64],
) -> Result<Vec<(f64, NodeId)>, FeError> {
    let deck: Vec<(f64, NodeId)> = deck_x
        .iter()
        .map(|&x| (x, st.add_node([x, 0.0, 0.0])))
        .collect();
    for w in deck.windows(2) {
        st.add_beam(w[0].1, w[1].1, &p.deck, [0.0, 1.0, 0.0], 0.0)?;
    }
    Ok(deck)
}

/// Node elevations of a tower leg from its base to the saddle: the portal-beam levels and
/// equal parts of about `element_length` between them, m.
fn tower_levels(p: &SuspensionBridgeParams) -> Vec<f64> {
    let top_elev = p.saddle_elevation();
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
    levels
}

/// Adds both towers (two legs each, portal beams, saddles at the leg tops); returns the top
/// node of each leg, `[tower][leg]` (leg 0 at y = −half, leg 1 at y = +half).
fn add_towers(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    mesh: &DeckMesh,
    deck: &[(f64, NodeId)],
    dead_load: &DeadLoadState,
) -> Result<[[NodeId; 2]; 2], FeError> {
    let half = 0.5 * p.cable_spacing;
    let levels = tower_levels(p);
    let mut tower_top = [[NodeId(0); 2]; 2];
    for (t, &xt) in [p.left_tower_x, p.right_tower_x].iter().enumerate() {
        let deck_reaction = mesh.deck_weight * mesh.tributary(xt);
        let mut legs = [Vec::new(), Vec::new()];
        for (c, &y) in [-half, half].iter().enumerate() {
            let nodes = add_tower_leg(
                st,
                p,
                &levels,
                [xt, y],
                dead_load.saddle_reaction[t],
                deck_reaction,
            )?;
            tower_top[t][c] = *nodes.last().expect("leg nodes");
            legs[c] = nodes;
        }
        add_portal_beams(st, p, &levels, xt, &legs, deck)?;
    }
    Ok(tower_top)
}

/// Adds one tower leg at `(x, y)`: nodes at `levels`, fixed at the base, and beams
/// pre-compressed by the saddle reaction, the leg and portal-beam weight above them and,
/// below the deck, half the deck reaction at the tower; returns the nodes, base first.
fn add_tower_leg(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    levels: &[f64],
    [xt, y]: [f64; 2],
    saddle_reaction: f64,
    deck_reaction: f64,
) -> Result<Vec<NodeId>, FeError> {
    let g = p.gravity;
    let half = 0.5 * p.cable_spacing;
    let top_elev = p.saddle_elevation();
    let leg_w = p.tower_leg.mass_per_length * g;
    let cb_weight_per_leg = p.tower_crossbeam.mass_per_length * g * half;
    let nodes: Vec<NodeId> = levels.iter().map(|&e| st.add_node([xt, y, -e])).collect();
    st.fix(nodes[0], &Dof::ALL)?;
    for (k, w) in nodes.windows(2).enumerate() {
        let e_mid = 0.5 * (levels[k] + levels[k + 1]);
        let above_cb = p
            .crossbeam_elevations
            .iter()
            .filter(|&&e| e > e_mid)
            .count() as f64;
        let mut compression =
            saddle_reaction + leg_w * (top_elev - e_mid) + above_cb * cb_weight_per_leg;
        if e_mid < 0.0 {
            compression += 0.5 * deck_reaction;
        }
        st.add_beam(w[0], w[1], &p.tower_leg, [0.0, 1.0, 0.0], -compression)?;
    }
    Ok(nodes)
}

/// Adds the portal beams of the tower at `xt` between its two `legs` (each split at a
/// centre node); the one at deck level carries the deck (tied in Uy, Uz and Rx).
fn add_portal_beams(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    levels: &[f64],
    xt: f64,
    legs: &[Vec<NodeId>; 2],
    deck: &[(f64, NodeId)],
) -> Result<(), FeError> {
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
            st.tie(centre, deck_node_at(deck, xt), &[Dof::Uy, Dof::Uz, Dof::Rx])?;
        }
    }
    Ok(())
}

/// Adds both main cables (at y = ∓half) with their hangers; returns the free cable nodes
/// (hanger clamps and free points) of both cables.
fn add_cables(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    mesh: &DeckMesh,
    deck: &[(f64, NodeId)],
    ds: &DeadLoadState,
    tower_top: &[[NodeId; 2]; 2],
) -> Result<Vec<NodeId>, FeError> {
    let half = 0.5 * p.cable_spacing;
    let mut cable_nodes = Vec::new();
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
        add_cable_bars(st, p, ds, &nodes)?;
        add_hangers(st, p, mesh, deck, ds, y, &nodes)?;
    }
    Ok(cable_nodes)
}

/// Adds the bars of one cable between consecutive station `nodes`, with the main-span or
/// side-span section and the dead-load segment tension.
fn add_cable_bars(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    ds: &DeadLoadState,
    nodes: &[NodeId],
) -> Result<(), FeError> {
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
    Ok(())
}

/// Adds the hangers of the cable at `y`: bars from the hanger-clamp `nodes` to rigid arms
/// on the deck spine, pre-tensioned by the deck force plus half their own weight.
fn add_hangers(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    mesh: &DeckMesh,
    deck: &[(f64, NodeId)],
    ds: &DeadLoadState,
    y: f64,
    nodes: &[NodeId],
) -> Result<(), FeError> {
    let g = p.gravity;
    for (k, s) in ds.stations.iter().enumerate() {
        if s.kind != CableStationKind::Hanger {
            continue;
        }
        let len = p.hanger_length(s.z);
        let t_deck = mesh.hanger_deck_force(s.x);
        st.add_bar_with_arms(
            nodes[k],
            [0.0; 3],
            deck_node_at(deck, s.x),
            [0.0, y, -p.hanger_anchor_elevation],
            BarProps {
                ea: p.hanger.e * p.hanger.area,
                mass_per_length: p.hanger.mass_per_length,
                tension: t_deck + 0.5 * p.hanger.mass_per_length * g * len,
            },
        )?;
    }
    Ok(())
}

/// Adds the deck bearings (Uy, Uz, Rx fixed at both ends, the cable pier and the deck
/// piers) and the longitudinal restraint (Ux at one abutment).
fn add_deck_bearings(
    st: &mut Structure,
    p: &SuspensionBridgeParams,
    deck: &[(f64, NodeId)],
) -> Result<(), FeError> {
    let bearing = [Dof::Uy, Dof::Uz, Dof::Rx];
    st.fix(deck[0].1, &bearing)?;
    st.fix(deck[deck.len() - 1].1, &bearing)?;
    st.fix(deck_node_at(deck, p.left_pier_x), &bearing)?;
    for &x in &p.deck_piers_x {
        st.fix(deck_node_at(deck, x), &bearing)?;
    }
    let restrained = match p.longitudinal_restraint {
        LongitudinalRestraint::LeftAbutment => deck[0].1,
        LongitudinalRestraint::RightAbutment => deck[deck.len() - 1].1,
    };
    st.fix(restrained, &[Dof::Ux])
}
