//! Layout of the bridge model: the cable spans between the fixed points of a main cable
//! and the deck mesh with the points that carry the deck's dead load.

use crate::error::FeError;
use crate::params::SuspensionBridgeParams;

/// Split [a, b] into `n` equal parts, returning the interior points.
pub(super) fn interior(a: f64, b: f64, n: usize) -> Vec<f64> {
    (1..n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

/// Number of equal parts of about `target` length in `len` (at least one).
pub(super) fn parts(len: f64, target: f64) -> usize {
    ((len / target).round() as usize).max(1)
}

/// A cable span between fixed points a and b (z downward), its interior stations, whether
/// those carry hangers, and whether this is the main span.
pub(super) struct CableSpan {
    pub(super) xa: f64,
    pub(super) za: f64,
    pub(super) xb: f64,
    pub(super) zb: f64,
    pub(super) x: Vec<f64>,
    pub(super) hangers: bool,
    pub(super) main: bool,
}

/// The four spans of one main cable, left to right: back-stay (anchorage to cable pier),
/// left side span, main span, right side span (to the right anchorage).
pub(super) fn cable_spans(p: &SuspensionBridgeParams) -> [CableSpan; 4] {
    let saddle_elev = p.saddle_elevation();
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
    [
        CableSpan {
            xa: p.left_anchorage_x,
            za: -p.left_anchorage_elevation,
            xb: p.left_pier_x,
            zb: -p.left_pier_saddle_elevation,
            x: interior(p.left_anchorage_x, p.left_pier_x, n_back),
            hangers: false,
            main: false,
        },
        CableSpan {
            xa: p.left_pier_x,
            za: -p.left_pier_saddle_elevation,
            xb: p.left_tower_x,
            zb: -saddle_elev,
            x: interior(p.left_pier_x, p.left_tower_x, n_left),
            hangers: p.left_side_span_suspended,
            main: false,
        },
        CableSpan {
            xa: p.left_tower_x,
            za: -saddle_elev,
            xb: p.right_tower_x,
            zb: -saddle_elev,
            x: interior(p.left_tower_x, p.right_tower_x, n_main),
            hangers: true,
            main: true,
        },
        CableSpan {
            xa: p.right_tower_x,
            za: -saddle_elev,
            xb: p.right_anchorage_x,
            zb: -p.right_anchorage_elevation,
            x: interior(p.right_tower_x, p.right_anchorage_x, n_right),
            hangers: p.right_side_span_suspended,
            main: false,
        },
    ]
}

/// The deck mesh: node positions and the points that carry the deck's dead load.
pub(super) struct DeckMesh {
    /// Deck node positions x, m (ascending).
    pub(super) x: Vec<f64>,
    /// Points that carry the deck's dead load (supports and hangers), ascending x, m.
    carriers: Vec<f64>,
    /// Deck dead load per length, N/m.
    pub(super) deck_weight: f64,
}

impl DeckMesh {
    /// Mesh the deck between its supports and the hanger stations of `spans`, with elements
    /// no longer than `element_length`.
    pub(super) fn new(p: &SuspensionBridgeParams, spans: &[CableSpan]) -> Result<Self, FeError> {
        let mut hanger_x: Vec<f64> = spans
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
        Ok(DeckMesh {
            x: deck_x,
            carriers,
            deck_weight: p.deck.mass_per_length * p.gravity,
        })
    }

    /// Tributary deck length of the carrier at `x` (half the distance to each neighbour), m.
    pub(super) fn tributary(&self, x: f64) -> f64 {
        let carriers = &self.carriers;
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
    }

    /// Hanger force at the deck end (one cable side) of the hanger at `x`, N.
    pub(super) fn hanger_deck_force(&self, x: f64) -> f64 {
        0.5 * self.deck_weight * self.tributary(x)
    }
}
