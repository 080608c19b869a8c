//! Linear static response of the deck about the dead-load state: `K u = f`.

use crate::bridge::FeModel;
use crate::error::FeError;
use crate::structure::{Dof, StiffnessFactor};
use serde::{Deserialize, Serialize};

/// A point load on the deck, resolved at the shear centre.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DeckLoad {
    /// Position along the deck, m.
    pub x: f64,
    /// Lateral force (+y, to the right), N.
    pub lateral: f64,
    /// Vertical force (+z, downward), N.
    pub vertical: f64,
    /// Torque about +x (right side down), N·m. A vertical force `F` on a track at lateral
    /// offset `e` gives `e·F`.
    pub torque: f64,
}

/// Deck displacement at the shear centre.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DeckDisplacement {
    /// Position along the deck, m.
    pub x: f64,
    /// Lateral displacement (+y), m.
    pub lateral: f64,
    /// Vertical displacement (+ downward), m.
    pub vertical: f64,
    /// Torsional rotation (right side down), rad.
    pub torsion: f64,
}

/// Hermite shape functions on an element of length `l` at `t ∈ [0, 1]`.
fn hermite(t: f64, l: f64) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        1.0 - 3.0 * t2 + 2.0 * t3,
        l * (t - 2.0 * t2 + t3),
        3.0 * t2 - 2.0 * t3,
        l * (t3 - t2),
    ]
}

/// A factorised stiffness matrix of a bridge model for repeated deck load cases.
#[derive(Debug)]
pub struct StaticSolver<'a> {
    model: &'a FeModel,
    factor: StiffnessFactor,
}

impl FeModel {
    /// Factorise K once for repeated static solves.
    pub fn static_solver(&self) -> Result<StaticSolver<'_>, FeError> {
        Ok(StaticSolver {
            model: self,
            factor: self.system.factor_stiffness()?,
        })
    }

    /// Deck displacements at `at` (m) under `loads`: one direct solve `K u = f` with the
    /// tangent stiffness of the dead-load state.
    pub fn static_deck_deflection(
        &self,
        loads: &[DeckLoad],
        at: &[f64],
    ) -> Result<Vec<DeckDisplacement>, FeError> {
        self.static_solver()?.deck_deflection(loads, at)
    }

    /// Element index and local coordinate of deck position `x`.
    fn locate(&self, x: f64) -> Result<(usize, f64, f64), FeError> {
        let (start, end) = (self.deck[0].0, self.deck[self.deck.len() - 1].0);
        if !(x >= start && x <= end) {
            return Err(FeError::OutsideDeck { x, start, end });
        }
        let i = self
            .deck
            .partition_point(|d| d.0 <= x)
            .clamp(1, self.deck.len() - 1)
            - 1;
        let l = self.deck[i + 1].0 - self.deck[i].0;
        Ok((i, (x - self.deck[i].0) / l, l))
    }
}

impl StaticSolver<'_> {
    /// Deck displacements at `at` under `loads` (consistent nodal loads from the beam
    /// shape functions; cubic Hermite for bending, linear for torsion).
    pub fn deck_deflection(
        &self,
        loads: &[DeckLoad],
        at: &[f64],
    ) -> Result<Vec<DeckDisplacement>, FeError> {
        let u = self.solve(loads)?;
        at.iter().map(|&x| self.sample(&u, x)).collect()
    }

    /// Full displacement vector (free DOFs) under deck loads.
    pub fn solve(&self, loads: &[DeckLoad]) -> Result<Vec<f64>, FeError> {
        let m = self.model;
        let sys = &m.system;
        let mut f = vec![0.0; sys.dof_count()];
        let mut add = |node, d, v: f64| {
            if let Some(i) = sys.dof(node, d) {
                f[i] += v;
            }
        };
        for ld in loads {
            let (i, t, l) = m.locate(ld.x)?;
            let n = hermite(t, l);
            let (a, b) = (m.deck[i].1, m.deck[i + 1].1);
            // vertical: w' = −θy; lateral: v' = θz
            add(a, Dof::Uz, n[0] * ld.vertical);
            add(a, Dof::Ry, -n[1] * ld.vertical);
            add(b, Dof::Uz, n[2] * ld.vertical);
            add(b, Dof::Ry, -n[3] * ld.vertical);
            add(a, Dof::Uy, n[0] * ld.lateral);
            add(a, Dof::Rz, n[1] * ld.lateral);
            add(b, Dof::Uy, n[2] * ld.lateral);
            add(b, Dof::Rz, n[3] * ld.lateral);
            add(a, Dof::Rx, (1.0 - t) * ld.torque);
            add(b, Dof::Rx, t * ld.torque);
        }
        Ok(self.factor.solve(&f))
    }

    /// Deck displacement at `x` from a full displacement vector.
    pub fn sample(&self, u: &[f64], x: f64) -> Result<DeckDisplacement, FeError> {
        let m = self.model;
        let sys = &m.system;
        let (i, t, l) = m.locate(x)?;
        let n = hermite(t, l);
        let (a, b) = (m.deck[i].1, m.deck[i + 1].1);
        let g = |node, d| sys.dof(node, d).map_or(0.0, |k| u[k]);
        Ok(DeckDisplacement {
            x,
            vertical: n[0] * g(a, Dof::Uz) - n[1] * g(a, Dof::Ry) + n[2] * g(b, Dof::Uz)
                - n[3] * g(b, Dof::Ry),
            lateral: n[0] * g(a, Dof::Uy)
                + n[1] * g(a, Dof::Rz)
                + n[2] * g(b, Dof::Uy)
                + n[3] * g(b, Dof::Rz),
            torsion: (1.0 - t) * g(a, Dof::Rx) + t * g(b, Dof::Rx),
        })
    }
}
