//! Modal analysis of a [`FeModel`]: eigen-solution, deck components, classification.

use crate::bridge::FeModel;
use crate::error::FeError;
use crate::structure::{Dof, EigenPairs};
use serde::{Deserialize, Serialize};
use tbi_modes::{Mode, ModeSet, FORMAT_TAG};

/// Modes whose deck kinetic-energy share is below this fraction are labelled `C-k`
/// (cable/tower-dominated).
pub const DECK_SHARE_MIN: f64 = 0.2;

/// Dominant deck motion of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ModeKind {
    /// Deck vertical bending (`V`).
    Vertical,
    /// Deck lateral bending (`L`).
    Lateral,
    /// Deck torsion (`T`).
    Torsional,
    /// Dominated by cables or towers (`C`).
    CableOrTower,
}

/// Kinetic-energy shares of a mass-normalised mode (they add up to about 1).
///
/// Deck shares use the deck mass lumped at its nodes over their tributary lengths: lateral
/// `Σ m ℓᵢ φ_h,ᵢ²`, vertical `Σ m ℓᵢ φ_v,ᵢ²`, torsional `Σ I_m ℓᵢ φ_θ,ᵢ²`; the cable share is
/// exact (lumped cable masses); `other` is the rest (towers, longitudinal deck motion).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EnergyShares {
    pub deck_lateral: f64,
    pub deck_vertical: f64,
    pub deck_torsion: f64,
    pub cables: f64,
    pub other: f64,
}

impl EnergyShares {
    /// Deck share (lateral + vertical + torsional).
    pub fn deck(&self) -> f64 {
        self.deck_lateral + self.deck_vertical + self.deck_torsion
    }
}

/// One mode with its deck components at the deck nodes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeInfo {
    /// Natural frequency, Hz.
    pub frequency_hz: f64,
    /// Label such as `V-S-1`, `L-A-1`, `T-S-1` or `C-1`.
    pub label: String,
    pub kind: ModeKind,
    /// Symmetric about the main-span centre (judged on the main span, dominant component).
    pub symmetric: bool,
    pub energy: EnergyShares,
    /// Lateral deck displacement at the shear centre, kg^-1/2.
    pub lateral: Vec<f64>,
    /// Vertical deck displacement (+ down), kg^-1/2.
    pub vertical: Vec<f64>,
    /// Deck torsion (right side down), rad·kg^-1/2·m^-1.
    pub torsion: Vec<f64>,
}

/// The lowest modes of a bridge model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalResult {
    /// Deck node positions, m.
    pub deck_x: Vec<f64>,
    /// Modes in ascending frequency.
    pub modes: Vec<ModeInfo>,
}

impl ModalResult {
    /// Frequencies, Hz.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.modes.iter().map(|m| m.frequency_hz).collect()
    }

    /// Labels.
    pub fn labels(&self) -> Vec<&str> {
        self.modes.iter().map(|m| m.label.as_str()).collect()
    }

    /// The mode with a given label.
    pub fn by_label(&self, label: &str) -> Option<&ModeInfo> {
        self.modes.iter().find(|m| m.label == label)
    }

    /// All modes (cable/tower modes `C-k` included) with their deck components as a
    /// [`ModeSet`] (damping left to the scenario).
    pub fn to_mode_set(&self) -> ModeSet {
        self.mode_set(self.modes.iter())
    }

    /// The first `n` modes with deck participation, i.e. all modes except the cable/tower
    /// modes `C-k` ([`ModeKind::CableOrTower`]), in ascending frequency, as a [`ModeSet`]
    /// (labels and mass-normalised deck components as in [`ModalResult::modes`], damping
    /// left to the scenario).
    ///
    /// Fails with [`FeError::TooFewDeckModes`] if this result holds fewer than `n` of them;
    /// [`FeModel::deck_modes`] computes as many modes as needed.
    pub fn to_deck_mode_set(&self, n: usize) -> Result<ModeSet, FeError> {
        let deck = || self.modes.iter().filter(|m| m.is_deck_mode());
        let found = deck().count();
        if found < n {
            return Err(FeError::TooFewDeckModes {
                requested: n,
                found,
                computed: self.modes.len(),
            });
        }
        Ok(self.mode_set(deck().take(n)))
    }

    fn mode_set<'a>(&self, modes: impl Iterator<Item = &'a ModeInfo>) -> ModeSet {
        ModeSet {
            format: FORMAT_TAG.to_string(),
            x_m: self.deck_x.clone(),
            modes: modes
                .map(|m| Mode {
                    label: m.label.clone(),
                    frequency_hz: m.frequency_hz,
                    damping_ratio: None,
                    lateral: m.lateral.clone(),
                    vertical: m.vertical.clone(),
                    torsion: m.torsion.clone(),
                })
                .collect(),
        }
    }
}

impl ModeInfo {
    /// Whether the deck takes part in the mode: every kind except
    /// [`ModeKind::CableOrTower`] (deck kinetic-energy share ≥ [`DECK_SHARE_MIN`]).
    pub fn is_deck_mode(&self) -> bool {
        self.kind != ModeKind::CableOrTower
    }
}

/// Linear interpolation of `v` (given at ascending `x`) at `xq`.
fn interp(x: &[f64], v: &[f64], xq: f64) -> f64 {
    let i = x.partition_point(|&a| a < xq).clamp(1, x.len() - 1);
    let (x0, x1) = (x[i - 1], x[i]);
    let t = ((xq - x0) / (x1 - x0)).clamp(0.0, 1.0);
    v[i - 1] + t * (v[i] - v[i - 1])
}

impl FeModel {
    /// Eigenpairs of the full model (all DOFs), mass-normalised.
    pub fn eigen(&self, n: usize) -> Result<EigenPairs, FeError> {
        self.system.eigen(n)
    }

    /// The lowest `n` modes, mass-normalised (φᵀMφ = 1), with deck components and labels.
    pub fn modes(&self, n: usize) -> Result<ModalResult, FeError> {
        let pairs = self.system.eigen(n)?;
        Ok(self.modal_result(&pairs))
    }

    /// The lowest `n` modes with deck participation (the cable/tower modes `C-k` skipped),
    /// mass-normalised and labelled, as a [`ModeSet`] for the dynamics crate; see
    /// [`ModalResult::to_deck_mode_set`].
    ///
    /// Solves for the lowest `2n + 20` modes (at most all free DOFs) and, while these hold
    /// fewer than `n` deck modes, for twice as many (each attempt is a new eigen-solution).
    /// Fails with [`FeError::TooManyModes`] if `n` exceeds the free DOFs and with
    /// [`FeError::TooFewDeckModes`] if even all modes do not contain `n` deck modes.
    pub fn deck_modes(&self, n: usize) -> Result<ModeSet, FeError> {
        let available = self.system.dof_count();
        if n > available {
            return Err(FeError::TooManyModes {
                requested: n,
                available,
            });
        }
        let mut computed = (2 * n + 20).min(available);
        loop {
            match self.modes(computed)?.to_deck_mode_set(n) {
                Err(FeError::TooFewDeckModes { .. }) if computed < available => {
                    computed = (2 * computed).min(available);
                }
                result => return result,
            }
        }
    }

    /// Classify eigenpairs and extract their deck components.
    pub fn modal_result(&self, pairs: &EigenPairs) -> ModalResult {
        let sys = &self.system;
        let deck_x = self.deck_x();
        let trib = self.deck_tributary_lengths();
        let m = self.params.deck.mass_per_length;
        let jm = self.params.deck.mass_moment_per_length;
        let (xl, xr) = (self.params.left_tower_x, self.params.right_tower_x);
        let main: Vec<usize> = (0..deck_x.len())
            .filter(|&i| deck_x[i] >= xl - 1e-9 && deck_x[i] <= xr + 1e-9)
            .collect();
        let cable_dofs: Vec<usize> = self
            .cable_nodes
            .iter()
            .flat_map(|&n| Dof::TRANSLATIONS.iter().filter_map(move |&d| sys.dof(n, d)))
            .collect();
        let mut counters = std::collections::HashMap::<String, usize>::new();
        let mut modes = Vec::with_capacity(pairs.omega2.len());
        for (k, &w2) in pairs.omega2.iter().enumerate() {
            let phi = pairs.vectors.col(k);
            let comp = |d: Dof| -> Vec<f64> {
                self.deck
                    .iter()
                    .map(|&(_, node)| sys.dof(node, d).map_or(0.0, |i| phi[i]))
                    .collect()
            };
            let (lat, ver, tor) = (comp(Dof::Uy), comp(Dof::Uz), comp(Dof::Rx));
            let e_of = |v: &[f64], mass: f64| -> f64 {
                v.iter().zip(&trib).map(|(a, l)| mass * l * a * a).sum()
            };
            let (el, ev, et) = (e_of(&lat, m), e_of(&ver, m), e_of(&tor, jm));
            let ec: f64 = cable_dofs
                .iter()
                .map(|&i| sys.m.get(i, i) * phi[i] * phi[i])
                .sum();
            let energy = EnergyShares {
                deck_lateral: el,
                deck_vertical: ev,
                deck_torsion: et,
                cables: ec,
                other: 1.0 - el - ev - et - ec,
            };
            let (kind, dom) = if energy.deck() < DECK_SHARE_MIN {
                (ModeKind::CableOrTower, None)
            } else if ev >= el && ev >= et {
                (ModeKind::Vertical, Some(&ver))
            } else if el >= et {
                (ModeKind::Lateral, Some(&lat))
            } else {
                (ModeKind::Torsional, Some(&tor))
            };
            let symmetric = {
                let v = dom.unwrap_or(&ver);
                let (mut s, mut a) = (0.0, 0.0);
                for &i in &main {
                    let mirror = interp(&deck_x, v, xl + xr - deck_x[i]);
                    s += trib[i] * (v[i] + mirror).powi(2);
                    a += trib[i] * (v[i] - mirror).powi(2);
                }
                s >= a
            };
            let label = match kind {
                ModeKind::CableOrTower => {
                    let c = counters.entry("C".into()).or_insert(0);
                    *c += 1;
                    format!("C-{c}")
                }
                _ => {
                    let t = match kind {
                        ModeKind::Vertical => "V",
                        ModeKind::Lateral => "L",
                        _ => "T",
                    };
                    let s = if symmetric { "S" } else { "A" };
                    let key = format!("{t}-{s}");
                    let c = counters.entry(key.clone()).or_insert(0);
                    *c += 1;
                    format!("{key}-{c}")
                }
            };
            modes.push(ModeInfo {
                frequency_hz: w2.sqrt() / (2.0 * std::f64::consts::PI),
                label,
                kind,
                symmetric,
                energy,
                lateral: lat,
                vertical: ver,
                torsion: tor,
            });
        }
        ModalResult { deck_x, modes }
    }
}
