//! Beams over several spans (vertical bending), by the frame elements of
//! [`crate::structure`]: a straight member along x with `elements_per_span` Euler–Bernoulli
//! elements per span, a vertical support at every span end (pinned, rotation free),
//! continuous over the interior supports or, for a chain of simply supported spans, hinged
//! there (two nodes at the support, their rotations not tied), the
//! axial, lateral and torsional DOFs restrained so that only vertical bending modes remain.
//! The modes are mass-normalised (φᵀ M φ = 1 with the consistent mass of the elements) and
//! returned as a [`ModeSet`] (vertical component + downward).

use crate::error::FeError;
use crate::structure::{BeamSection, Dof, Structure};
use tbi_modes::{Mode, ModeSet};

/// The section of one span (uniform along it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpanSection {
    /// Young's modulus E, Pa.
    pub youngs_modulus_pa: f64,
    /// Second moment of area for vertical bending, m⁴.
    pub inertia_m4: f64,
    /// Mass per length, kg/m.
    pub mass_per_length_kg_m: f64,
}

/// A beam continuous over `spans_m` (or a chain of them), each span with its own section.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuousBeam {
    /// Span lengths, m, from the first support.
    pub spans_m: Vec<f64>,
    /// The section of each span, as many as `spans_m`.
    pub sections: Vec<SpanSection>,
    /// Elements per span (accuracy of the modes). Default 40.
    pub elements_per_span: usize,
    /// Continuous over the interior supports (`true`), or a chain of simply supported spans.
    pub continuous: bool,
}

impl ContinuousBeam {
    /// Every span with the same section.
    pub fn prismatic(spans_m: Vec<f64>, section: SpanSection, continuous: bool) -> Self {
        ContinuousBeam {
            sections: vec![section; spans_m.len()],
            spans_m,
            elements_per_span: 40,
            continuous,
        }
    }

    /// The lowest `n` vertical modes, labelled `V-1`, `V-2`, …, at the nodes (x from 0 at the
    /// first support).
    pub fn modes(&self, n: usize) -> Result<ModeSet, FeError> {
        if self.spans_m.is_empty() || self.spans_m.iter().any(|&l| !(l > 0.0 && l.is_finite())) {
            return Err(FeError::Definition(format!(
                "spans {:?}: every span must be a positive length",
                self.spans_m
            )));
        }
        if self.sections.len() != self.spans_m.len() {
            return Err(FeError::Definition(format!(
                "{} sections for {} spans: give one section per span",
                self.sections.len(),
                self.spans_m.len()
            )));
        }
        let ne = self.elements_per_span.max(2);
        let mut s = Structure::new();
        let mut x = vec![0.0];
        let mut nodes = vec![s.add_node([0.0, 0.0, 0.0])];
        let mut supports = vec![nodes[0]];
        let mut at = 0.0;
        let mut all = nodes.clone();
        for (i, (&l, sec)) in self.spans_m.iter().zip(&self.sections).enumerate() {
            let section = BeamSection {
                e: sec.youngs_modulus_pa,
                iy: sec.inertia_m4,
                mass_per_length: sec.mass_per_length_kg_m,
                ..BeamSection::default()
            };
            // a chain starts each span after the first on a node of its own at the support
            let mut last = *nodes.last().expect("a node");
            if i > 0 && !self.continuous {
                let start = s.add_node([at, 0.0, 0.0]);
                s.tie(last, start, &[Dof::Ux, Dof::Uz])?;
                all.push(start);
                supports.push(start);
                last = start;
            }
            for k in 1..=ne {
                let xi = at + l * k as f64 / ne as f64;
                let node = s.add_node([xi, 0.0, 0.0]);
                s.add_beam(last, node, &section, [0.0, 1.0, 0.0], 0.0)?;
                last = node;
                nodes.push(node);
                all.push(node);
                x.push(xi);
            }
            at += l;
            supports.push(*nodes.last().expect("a node"));
        }
        for &node in &all {
            s.fix(node, &[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Rz])?;
        }
        for &node in &supports {
            s.fix(node, &[Dof::Uz])?;
        }
        let system = s.assemble()?;
        let pairs = system.eigen(n)?;
        let modes = (0..n)
            .map(|m| {
                let vertical: Vec<f64> = nodes
                    .iter()
                    .map(|&node| {
                        system
                            .dof(node, Dof::Uz)
                            .map_or(0.0, |d| -pairs.vectors[(d, m)])
                    })
                    .collect();
                Mode {
                    label: format!("V-{}", m + 1),
                    frequency_hz: pairs.omega2[m].sqrt() / (2.0 * std::f64::consts::PI),
                    damping_ratio: None,
                    lateral: vec![0.0; nodes.len()],
                    vertical,
                    torsion: vec![0.0; nodes.len()],
                }
            })
            .collect();
        Ok(ModeSet {
            format: tbi_modes::FORMAT_TAG.to_string(),
            x_m: x,
            modes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two equal spans: the antisymmetric mode is the simply supported span's,
    /// ω₁ = (π/L)² √(EI/m); the symmetric one has each span clamped at the middle support,
    /// ω₂ = (λ/L)² √(EI/m) with tan λ = tanh λ, λ = 3.926602; to 0.1 %.
    #[test]
    fn two_equal_spans_match_the_closed_forms() {
        let (l, e, i, m) = (20.0, 3.5e10, 1.2, 12_000.0);
        let section = SpanSection {
            youngs_modulus_pa: e,
            inertia_m4: i,
            mass_per_length_kg_m: m,
        };
        let beam = ContinuousBeam::prismatic(vec![l, l], section, true);
        let set = beam.modes(3).unwrap();
        let c = (e * i / m).sqrt() / (2.0 * std::f64::consts::PI);
        let f1 = (std::f64::consts::PI / l).powi(2) * c;
        let f2 = (3.926_602_312 / l).powi(2) * c;
        let got: Vec<f64> = set.modes.iter().map(|m| m.frequency_hz).collect();
        assert!((got[0] / f1 - 1.0).abs() < 1e-3, "{got:?} vs {f1}");
        assert!((got[1] / f2 - 1.0).abs() < 1e-3, "{got:?} vs {f2}");
        // mass-normalised: Σ m φ² Δx ≈ 1 (trapezoid over the nodes)
        let v = &set.modes[0].vertical;
        let dx = l / 40.0;
        let norm: f64 = v.iter().map(|p| m * p * p * dx).sum();
        assert!((norm - 1.0).abs() < 2e-2, "Σ m φ² Δx = {norm}");
        // no support moves
        for k in [0, 40, 80] {
            assert_eq!(set.modes[0].vertical[k], 0.0);
        }
        assert!(ContinuousBeam {
            spans_m: vec![l, 0.0],
            ..beam.clone()
        }
        .modes(1)
        .is_err());
        assert!(ContinuousBeam {
            sections: vec![section],
            ..beam.clone()
        }
        .modes(1)
        .unwrap_err()
        .to_string()
        .contains("1 sections for 2 spans"));

        // hinged at the middle support: two simply supported spans, both first modes at
        // (π/L)² √(EI/m), the next pair at (2π/L)²
        let chain = ContinuousBeam {
            continuous: false,
            ..beam
        };
        let set = chain.modes(3).unwrap();
        let got: Vec<f64> = set.modes.iter().map(|m| m.frequency_hz).collect();
        assert!((got[0] / f1 - 1.0).abs() < 1e-3, "{got:?} vs {f1}");
        assert!((got[1] / f1 - 1.0).abs() < 1e-3, "{got:?} vs {f1}");
        let f_second = (2.0 * std::f64::consts::PI / l).powi(2) * c;
        assert!(
            (got[2] / f_second - 1.0).abs() < 1e-3,
            "{got:?} vs {f_second}"
        );
        assert_eq!(
            set.x_m.len(),
            81,
            "one node of the middle support in the mode set"
        );
    }

    /// A chain of two simply supported spans of different lengths and sections: each span
    /// vibrates alone, so the modes are the union of the two spans' closed forms
    /// fₙ = (nπ/L)² √(EI/m) / 2π, to 0.1 %.
    #[test]
    fn a_chain_of_different_spans_is_the_union_of_their_modes() {
        let a = SpanSection {
            youngs_modulus_pa: 3.5e10,
            inertia_m4: 1.2,
            mass_per_length_kg_m: 12_000.0,
        };
        let b = SpanSection {
            youngs_modulus_pa: 3.0e10,
            inertia_m4: 0.5,
            mass_per_length_kg_m: 9_000.0,
        };
        let (la, lb) = (20.0, 15.0);
        let chain = ContinuousBeam {
            spans_m: vec![la, lb],
            sections: vec![a, b],
            elements_per_span: 40,
            continuous: false,
        };
        let f = |n: f64, l: f64, s: &SpanSection| {
            (n * std::f64::consts::PI / l).powi(2)
                * (s.youngs_modulus_pa * s.inertia_m4 / s.mass_per_length_kg_m).sqrt()
                / (2.0 * std::f64::consts::PI)
        };
        let mut expected: Vec<f64> = (1..=3)
            .flat_map(|n| [f(n as f64, la, &a), f(n as f64, lb, &b)])
            .collect();
        expected.sort_by(f64::total_cmp);
        let got: Vec<f64> = chain
            .modes(4)
            .unwrap()
            .modes
            .iter()
            .map(|m| m.frequency_hz)
            .collect();
        for (g, e) in got.iter().zip(&expected) {
            assert!((g / e - 1.0).abs() < 1e-3, "{got:?} vs {expected:?}");
        }
        // swapping the sections changes the modes: each section belongs to its span
        let swapped = ContinuousBeam {
            sections: vec![b, a],
            ..chain
        };
        let f1 = swapped.modes(1).unwrap().modes[0].frequency_hz;
        assert!((f1 / f(1.0, la, &b) - 1.0).abs() < 1e-3, "{f1}");
    }
}
