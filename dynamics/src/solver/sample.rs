//! The monolithic solver's state as a response [`Sample`] (what the recorder of both
//! solvers takes): deck response at the probes, car-body accelerations, wheelset forces.
//!
//! The deck at a probe x is `u(x) = Σ_n φ_n(x) q_n` (lateral, vertical, torsion at the shear
//! centre), its acceleration `Σ_n φ_n(x) q̈_n`; the shapes `φ_n(x)` are evaluated once.

use super::partitioned::ProbeValues;
use super::Monolithic;
use crate::bridge::ModalBridge;
use crate::response::Sample;

/// Deck shapes `φ_n(x)` at the probes, evaluated once.
#[derive(Debug, Clone)]
pub struct ProbeShapes(Vec<Vec<[f64; 3]>>);

impl ProbeShapes {
    /// The shapes of `bridge` at the probe positions `x` (m).
    pub fn new(bridge: &ModalBridge, x: &[f64]) -> Self {
        ProbeShapes(
            x.iter()
                .map(|&x| {
                    let mut sh = vec![[0.0; 3]; bridge.n_modes()];
                    bridge.deck_shapes(x, &mut sh);
                    sh
                })
                .collect(),
        )
    }
}

impl Monolithic {
    /// The response at the current time.
    pub fn sample(&self, probes: &ProbeShapes) -> Sample {
        let mut out = Sample::default();
        self.sample_into(probes, &mut out);
        out
    }

    /// [`Monolithic::sample`] into `out`, reusing its vectors (no allocation once they have
    /// their lengths).
    pub fn sample_into(&self, probes: &ProbeShapes, out: &mut Sample) {
        let (q, qdd) = (self.q.as_slice(), self.qdd.as_slice());
        out.t = self.t;
        out.probes.clear();
        out.probes.extend(
            probes
                .0
                .iter()
                .map(|sh| ProbeValues::from_shapes(sh, q, qdd)),
        );
        out.vehicles.clear();
        out.vehicles.extend(
            self.train
                .vehicles
                .iter()
                .zip(&self.vehicles)
                .map(|(tv, s)| {
                    [
                        tv.model.body.lateral.map(|i| s.vdd[i]),
                        tv.model.body.vertical.map(|i| s.vdd[i]),
                    ]
                }),
        );
        out.forces.clone_from(&self.forces);
        self.forces_varying_into(&mut out.forces_varying);
    }
}
