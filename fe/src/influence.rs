//! Static load effects on a line beam ([`ContinuousBeam`]) for the EN 1991-2 design
//! comparison: exact influence lines by the adjoint method, and the most unfavourable
//! placement of LM71 (§6.3.2) or of a train of point loads (HSLM, real trains).
//!
//! Conventions: x along the beam from 0 at the first support; loads and deflections w
//! positive **downward**; sagging moment positive; support reactions positive upward. SI.
//!
//! # Mathematics
//!
//! **Beam.** Euler–Bernoulli elements, cubic Hermite shapes on `(w₁, θ₁, w₂, θ₂)`, θ = w′,
//! ξ = s/l: `N₁ = 1 − 3ξ² + 2ξ³`, `N₂ = l (ξ − 2ξ² + ξ³)`, `N₃ = 3ξ² − 2ξ³`,
//! `N₄ = l (ξ³ − ξ²)`, `K_e = EI/l³ [12 6l −12 6l; 6l 4l² −6l 2l²; −12 −6l 12 −6l;
//! 6l 2l² −6l 4l²]`. w = 0 at every support; a continuous beam shares the rotation at the
//! interior supports, a chain has two nodes there (a hinge). A unit load at x has the
//! consistent nodal load `f(x) = N(ξ)` on its element, and the nodal solution of
//! `K u = f(x)` is exact (the homogeneous solutions of `EI w⁗ = 0` are cubics).
//!
//! **Adjoint influence line** (Müller–Breslau). An effect linear in the nodal values plus a
//! local term for a load in an element next to the section, `R = gᵀu + r(x)`, is for a unit
//! load at x
//!
//! ```text
//! η(x) = gᵀ K⁻¹ f(x) + r(x) = zᵀ f(x) + r(x),     K z = g      (K = Kᵀ: Maxwell–Betti)
//! ```
//!
//! one solve per effect, η a cubic on every element. *Deflection* at node n: `g = e(w_n)`
//! (z is the deflection line of a unit load at n). *Sagging moment* `M = −EI w″` at node n
//! as the right end of element e: `g = −EI/l² (6, 2l, −6, 4l)` on e's DOFs and the
//! clamped-end moment of a load in e, `r = −a²b/l² = N₄(ξ)` (a = ξl, b = l − a); as the left
//! end: `g = EI/l² (6, 4l, −6, 2l)`, `r = −ab²/l² = −N₂(ξ)` (the same internal moment, by
//! equilibrium). *Reaction* of support s: `R = Σₙ (f(w_n) − K(w_n,·) u)` over its node(s),
//! `g = −K(w_n,·)`, r = the shape of w_n (N₁ or N₃). A section is made a node of the mesh.
//!
//! **Integrals.** `∫ₐᵇ max(σ η, 0) dx` exactly: the cubic's roots in each element (bisection
//! between its stationary points) split it into pieces of one sign, integrated in closed
//! form; cumulative sums over the elements.
//!
//! **LM71** (α × characteristic values): axles Q = 250 kN at x₀ + 1.6 k (k = 0..3), and
//! q = 80 kN/m wherever σ η > 0 outside the axles' zone [x₀ − 0.8, x₀ + 5.6]:
//!
//! ```text
//! E(x₀) = α [ Q Σₖ η(x₀ + 1.6 k) + σ q ∫_{x ∉ [x₀−0.8, x₀+5.6]} max(σ η, 0) dx ]
//! ```
//!
//! σ E is maximised over x₀ ∈ [−5.6, L + 0.8] (axles may stand off the beam, η = 0 there):
//! a 0.01 m grid, the positions putting an axle on a kink of η (support, section), golden
//! sections about the best grid maxima. A train of loads Pᵢ at dᵢ behind the leading axle x₀,
//! `E(x₀) = Σ Pᵢ η(x₀ − dᵢ)`, is maximised the same way over x₀ ∈ [0, L + max dᵢ]. (On a
//! simple span LM71's largest midspan moment has an axle at midspan, q·0.32 m² above the
//! symmetric arrangement: Σ η of the axles is the same for shifts ≤ 0.8 m, and the unloaded
//! zone then cuts less off the peak of the line.)

use crate::beam::ContinuousBeam;
use crate::error::FeError;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// LM71 characteristic axle load Q_vk, N.
pub const LM71_AXLE_LOAD_N: f64 = 250e3;
/// LM71 axle spacing, m.
pub const LM71_AXLE_SPACING_M: f64 = 1.6;
/// LM71 characteristic distributed load q_vk, N/m.
pub const LM71_UDL_N_PER_M: f64 = 80e3;
/// LM71 length without distributed load before the first and after the last axle, m.
pub const LM71_CLEARANCE_M: f64 = 0.8;
/// Grid step of the load-position search, m.
const GRID_STEP_M: f64 = 0.01;
/// Grid maxima refined by golden section.
const REFINED_PEAKS: usize = 8;

/// A static load effect whose influence line is sought.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Effect {
    /// Vertical deflection (+ downward) at `x_m` (m from the first support), m per N.
    Displacement {
        /// Section, m.
        x_m: f64,
    },
    /// Internal bending moment (sagging +) at `x_m` (m from the first support), N·m per N.
    Moment {
        /// Section, m.
        x_m: f64,
    },
    /// Reaction (upward +) of support `support` (0 at x = 0 … `spans_m.len()`), N per N.
    Reaction {
        /// Support index.
        support: usize,
    },
}

/// A line beam for static analysis: Euler–Bernoulli Hermite elements, pinned at every
/// support, continuous or hinged at the interior supports as the [`ContinuousBeam`].
#[derive(Debug, Clone, PartialEq)]
pub struct StaticBeam {
    spans_m: Vec<f64>,
    /// EI of each span, N·m².
    rigidity: Vec<f64>,
    continuous: bool,
    elements_per_span: usize,
}

/// The influence line η(x) of an effect: its value for a unit downward load (1 N) at x, a
/// cubic on every element (exact for Euler–Bernoulli beams).
#[derive(Debug, Clone, PartialEq)]
pub struct InfluenceLine {
    effect: Effect,
    length_m: f64,
    /// Element ends, m.
    ends: Vec<[f64; 2]>,
    /// η on each element in powers of ξ = (x − x₁)/(x₂ − x₁).
    poly: Vec<[f64; 4]>,
    /// Positions where η may have a kink or jump (supports, section), m.
    kinks: Vec<f64>,
    /// `cum[s][e]`: ∫ max(σ η, 0) over the elements before e (s = 0: σ = +1, 1: σ = −1).
    cum: [Vec<f64>; 2],
}

/// The most unfavourable position of a load model for an effect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The effect, signed, N × (unit of η): m (deflection), N·m (moment), N (reaction).
    pub value: f64,
    /// Position of the first axle, m (LM71: the leftmost axle; a train: the leading axle).
    pub first_axle_x_m: f64,
}

/// Element from node `first` to `first + 1` (nodes in order of x, two at a hinge).
struct Element {
    first: usize,
    x: [f64; 2],
    ei: f64,
}

impl StaticBeam {
    /// The beam's spans, sections (EI = `youngs_modulus_pa` × `inertia_m4`) and continuity,
    /// with `elements_per_span` (≥ 1) elements per span (the beam's own `elements_per_span`
    /// is not used; influence lines are exact for any mesh).
    pub fn new(beam: &ContinuousBeam, elements_per_span: usize) -> Result<StaticBeam, FeError> {
        let spans = &beam.spans_m;
        if spans.is_empty() || spans.iter().any(|&l| !(l > 0.0 && l.is_finite())) {
            let msg = format!("spans {spans:?}: every span must be a positive length");
            return Err(FeError::Definition(msg));
        }
        if beam.sections.len() != spans.len() {
            let (ns, nl) = (beam.sections.len(), spans.len());
            let msg = format!("{ns} sections for {nl} spans: give one section per span");
            return Err(FeError::Definition(msg));
        }
        if elements_per_span == 0 {
            return Err(FeError::parameter("elements_per_span", 0, "at least 1"));
        }
        let mut rigidity = Vec::new();
        for section in &beam.sections {
            let ei = section.youngs_modulus_pa * section.inertia_m4;
            if !(ei > 0.0 && ei.is_finite()) {
                return Err(FeError::parameter("EI", ei, "must be positive"));
            }
            rigidity.push(ei);
        }
        let (spans_m, continuous) = (spans.clone(), beam.continuous);
        Ok(StaticBeam {
            spans_m,
            rigidity,
            continuous,
            elements_per_span,
        })
    }

    /// Total length L (sum of the spans), m.
    pub fn length_m(&self) -> f64 {
        self.spans_m.iter().sum()
    }

    /// The influence line of `effect` (deflection m/N, moment N·m/N, reaction N/N), exact
    /// for a unit point load anywhere on the beam.
    pub fn influence(&self, effect: Effect) -> Result<InfluenceLine, FeError> {
        self.line(effect, false)
    }

    /// Node positions, elements and the node(s) of each support, with a node at `extra` (m).
    fn mesh(&self, extra: Option<f64>) -> (Vec<f64>, Vec<Element>, Vec<Vec<usize>>) {
        let (tol, n) = (1e-9 * self.length_m(), self.elements_per_span);
        let (mut x, mut elements, mut supports) = (vec![0.0], Vec::new(), vec![vec![0]]);
        let mut start = 0.0;
        for (i, (&l, &ei)) in self.spans_m.iter().zip(&self.rigidity).enumerate() {
            let mut local: Vec<f64> = (1..n).map(|k| l * k as f64 / n as f64).collect();
            local.push(l);
            if let Some(s) = extra.map(|x| x - start) {
                if s > tol && s < l - tol && local.iter().all(|&p| (p - s).abs() > tol) {
                    local.push(s);
                    local.sort_by(f64::total_cmp);
                }
            }
            if i > 0 && !self.continuous {
                x.push(start);
                supports[i].push(x.len() - 1);
            }
            for s in local {
                let first = x.len() - 1;
                x.push(start + s);
                elements.push(Element {
                    first,
                    x: [x[first], start + s],
                    ei,
                });
            }
            supports.push(vec![x.len() - 1]);
            start += l;
        }
        (x, elements, supports)
    }

    /// The influence line; a moment from the element right of the section if `right`
    /// (and there is one), else from the one on its left.
    fn line(&self, effect: Effect, right: bool) -> Result<InfluenceLine, FeError> {
        let (length, tol) = (self.length_m(), 1e-9 * self.length_m());
        let section = match effect {
            Effect::Displacement { x_m } | Effect::Moment { x_m } => {
                if !(x_m >= -tol && x_m <= length + tol) {
                    let (start, end) = (0.0, length);
                    return Err(FeError::OutsideDeck { x: x_m, start, end });
                }
                Some(x_m.clamp(0.0, length))
            }
            Effect::Reaction { support } if support > self.spans_m.len() => {
                let reason = format!("the beam has supports 0..={}", self.spans_m.len());
                return Err(FeError::parameter("support", support, reason));
            }
            Effect::Reaction { .. } => None,
        };
        let (x, elements, supports) = self.mesh(section);
        let node = section.and_then(|s| x.iter().position(|&p| (p - s).abs() <= tol));
        let mut g = vec![0.0; 2 * x.len()];
        // (element, Hermite index, coefficient) of the local term r(x)
        let mut local: Vec<(usize, usize, f64)> = Vec::new();
        match effect {
            Effect::Displacement { .. } => g[2 * node.expect("section node")] = 1.0,
            Effect::Moment { .. } => {
                let n = node.expect("section node");
                let left = elements.iter().position(|e| e.first + 1 == n);
                let on_right = elements.iter().position(|e| e.first == n);
                let use_right = on_right.is_some() && (right || left.is_none());
                let e = if use_right { on_right } else { left }.expect("an element");
                let l = elements[e].x[1] - elements[e].x[0];
                let c = elements[e].ei / (l * l);
                let (row, r) = if use_right {
                    ([6.0 * c, 4.0 * l * c, -6.0 * c, 2.0 * l * c], (1, -1.0))
                } else {
                    ([-6.0 * c, -2.0 * l * c, 6.0 * c, -4.0 * l * c], (3, 1.0))
                };
                for (d, v) in dofs(&elements[e]).into_iter().zip(row) {
                    g[d] += v;
                }
                local.push((e, r.0, r.1));
            }
            Effect::Reaction { support } => {
                for (e, el) in elements.iter().enumerate() {
                    for end in (0..2).filter(|i| supports[support].contains(&(el.first + i))) {
                        for (d, v) in dofs(el).into_iter().zip(stiffness(el)[2 * end]) {
                            g[d] -= v;
                        }
                        local.push((e, 2 * end, 1.0));
                    }
                }
            }
        }
        let z = solve_free(&elements, supports.iter().flatten(), &g)?;
        let mut poly: Vec<[f64; 4]> = elements.iter().map(|el| dofs(el).map(|d| z[d])).collect();
        for (e, i, v) in local {
            poly[e][i] += v;
        }
        let ends: Vec<[f64; 2]> = elements.iter().map(|el| el.x).collect();
        for (p, x) in poly.iter_mut().zip(&ends) {
            *p = to_power(p, x[1] - x[0]);
        }
        let mut cum = [vec![0.0], vec![0.0]];
        for ((x, p), s) in ends.iter().zip(&poly).flat_map(|e| [(e, 0), (e, 1)]) {
            let part = (x[1] - x[0]) * positive_part(&p.map(|c| [1.0, -1.0][s] * c), 0.0, 1.0);
            cum[s].push(cum[s].last().expect("a value") + part);
        }
        let mut kinks: Vec<f64> = supports.iter().map(|s| x[s[0]]).collect();
        kinks.extend(section);
        Ok(InfluenceLine {
            effect,
            length_m: length,
            ends,
            poly,
            kinks,
            cum,
        })
    }
}

/// Global DOFs (w₁, θ₁, w₂, θ₂) of an element.
fn dofs(el: &Element) -> [usize; 4] {
    [0, 1, 2, 3].map(|i| 2 * el.first + i)
}

/// Hermite coefficients (w₁, θ₁, w₂, θ₂) → powers of ξ.
fn to_power(c: &[f64; 4], l: f64) -> [f64; 4] {
    let p2 = 3.0 * (c[2] - c[0]) - l * (2.0 * c[1] + c[3]);
    let p3 = 2.0 * (c[0] - c[2]) + l * (c[1] + c[3]);
    [c[0], l * c[1], p2, p3]
}

/// Element stiffness on (w₁, θ₁, w₂, θ₂).
fn stiffness(el: &Element) -> [[f64; 4]; 4] {
    let l = el.x[1] - el.x[0];
    let c = el.ei / (l * l * l);
    let (k, a, b, d) = (12.0 * c, 6.0 * l * c, 4.0 * l * l * c, 2.0 * l * l * c);
    [[k, a, -k, a], [a, b, -a, d], [-k, -a, k, -a], [a, d, -a, b]]
}

/// z = K⁻¹ g on the free DOFs (w = 0 at the `fixed` nodes), zero on the others (Cholesky).
fn solve_free<'a>(
    elements: &[Element],
    fixed: impl Iterator<Item = &'a usize>,
    g: &[f64],
) -> Result<Vec<f64>, FeError> {
    let mut index = vec![Some(0); g.len()];
    for &n in fixed {
        index[2 * n] = None;
    }
    let mut free = Vec::new();
    for (d, i) in index.iter_mut().enumerate().filter(|(_, i)| i.is_some()) {
        *i = Some(free.len());
        free.push(d);
    }
    let mut k = Mat::<f64>::zeros(free.len(), free.len());
    for el in elements {
        let (ke, dofs) = (stiffness(el), dofs(el).map(|d| index[d]));
        for (r, &di) in dofs.iter().enumerate() {
            for (c, &dj) in dofs.iter().enumerate() {
                if let (Some(i), Some(j)) = (di, dj) {
                    k[(i, j)] += ke[r][c];
                }
            }
        }
    }
    let hint = |e| format!("{e:?}: a mechanism?");
    let llt = k
        .llt(Side::Lower)
        .map_err(|e| FeError::NotPositiveDefinite {
            matrix: "static stiffness",
            hint: hint(e),
        })?;
    let z = llt.solve(Mat::from_fn(free.len(), 1, |i, _| g[free[i]]));
    Ok(index.iter().map(|i| i.map_or(0.0, |i| z[(i, 0)])).collect())
}

fn horner(p: &[f64; 4], t: f64) -> f64 {
    ((p[3] * t + p[2]) * t + p[1]) * t + p[0]
}

/// ∫ p dξ from 0 to t.
fn primitive(p: &[f64; 4], t: f64) -> f64 {
    (((p[3] / 4.0 * t + p[2] / 3.0) * t + p[1] / 2.0) * t + p[0]) * t
}

/// Real roots of a t² + b t + c = 0 (stable form; a or b may vanish).
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    let disc = b * b - 4.0 * a * c;
    let q = -0.5 * (b + b.signum() * disc.max(0.0).sqrt());
    match (a == 0.0, disc < 0.0, q == 0.0) {
        (true, _, _) if b == 0.0 => vec![],
        (true, _, _) => vec![-c / b],
        (_, true, _) => vec![],
        (_, _, true) => vec![0.0],
        _ => vec![q / a, c / q],
    }
}

/// ∫ max(p(ξ), 0) dξ over [t0, t1] ⊂ [0, 1], exact up to rounding.
fn positive_part(p: &[f64; 4], t0: f64, t1: f64) -> f64 {
    if t1 <= t0 {
        return 0.0;
    }
    let mut cuts = vec![t0, t1];
    let stationary = quadratic_roots(3.0 * p[3], 2.0 * p[2], p[1]);
    cuts.extend(stationary.into_iter().filter(|&t| t > t0 && t < t1));
    cuts.sort_by(f64::total_cmp);
    let mut points = vec![t0];
    for w in cuts.windows(2) {
        let (mut a, mut b) = (w[0], w[1]);
        let fa = horner(p, a);
        if fa * horner(p, b) < 0.0 {
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                let same = horner(p, m) * fa > 0.0;
                (a, b) = (if same { m } else { a }, if same { b } else { m });
            }
            points.push(0.5 * (a + b));
        }
        points.push(w[1]);
    }
    let positive = |w: &&[f64]| horner(p, 0.5 * (w[0] + w[1])) > 0.0;
    let pieces = points.windows(2).filter(positive);
    pieces
        .map(|w| primitive(p, w[1]) - primitive(p, w[0]))
        .sum()
}

impl InfluenceLine {
    /// The effect this line belongs to.
    pub fn effect(&self) -> Effect {
        self.effect
    }

    /// Length L of the beam, m.
    pub fn length_m(&self) -> f64 {
        self.length_m
    }

    /// Element index and ξ of x (clamped to the beam).
    fn locate(&self, x: f64) -> (usize, f64) {
        let x = x.clamp(0.0, self.length_m);
        let last = self.ends.len() - 1;
        let e = self.ends.partition_point(|end| end[1] < x).min(last);
        let [a, b] = self.ends[e];
        (e, ((x - a) / (b - a)).clamp(0.0, 1.0))
    }

    /// η(x): the effect of a unit downward load (1 N) at `x_m` (m), in the effect's unit per
    /// N. Zero off the beam (x < 0 or x > L, beyond a rounding tolerance of 10⁻¹² L).
    pub fn at(&self, x_m: f64) -> f64 {
        let tol = 1e-12 * self.length_m;
        if !(x_m >= -tol && x_m <= self.length_m + tol) {
            return 0.0;
        }
        let (e, t) = self.locate(x_m);
        horner(&self.poly[e], t)
    }

    /// ∫ max(σ η, 0) dx from 0 to x, σ = +1 (`s` = 0) or −1 (`s` = 1).
    fn cumulative(&self, x: f64, s: usize) -> f64 {
        let (e, t) = self.locate(x);
        let sigma = [1.0, -1.0][s];
        let [a, b] = self.ends[e];
        self.cum[s][e] + (b - a) * positive_part(&self.poly[e].map(|c| sigma * c), 0.0, t)
    }

    /// `∫ₐᵇ max(sign·η(x), 0) dx` (effect's unit per N × m): the part of the line with the
    /// sign sought over [a, b] (m) clipped to the beam (negative if b < a), exact up to
    /// rounding. A load q (N/m) where sign·η > 0 on [a, b] gives `sign · q ·` this.
    pub fn integral(&self, a: f64, b: f64, sign: f64) -> f64 {
        let s = usize::from(sign < 0.0);
        sign.abs() * (self.cumulative(b, s) - self.cumulative(a, s))
    }
}

/// σ = ±1 from a sign argument (+1 for 0 or positive).
fn unit_sign(sign: f64) -> f64 {
    [1.0, -1.0][usize::from(sign < 0.0)]
}

/// The LM71 effect (N × unit of η) with the leftmost axle at `first_axle_x_m` (m): axles
/// 250 kN · α at 1.6 m and 80 kN/m · α wherever `sign`·η > 0 outside the axles' zone
/// [x₀ − 0.8, x₀ + 5.6] m.
pub fn lm71_at(line: &InfluenceLine, alpha: f64, sign: f64, first_axle_x_m: f64) -> f64 {
    let (sigma, x0, l) = (unit_sign(sign), first_axle_x_m, line.length_m);
    let (s, c) = (LM71_AXLE_SPACING_M, LM71_CLEARANCE_M);
    let axles = [0.0, s, 2.0 * s, 3.0 * s].map(|o| line.at(x0 + o));
    let axles: f64 = axles.iter().sum();
    let [a, b] = [-c, 3.0 * s + c].map(|o| (x0 + o).clamp(0.0, l));
    let udl = line.integral(0.0, l, sigma) - line.integral(a, b, sigma);
    alpha * (LM71_AXLE_LOAD_N * axles + sigma * LM71_UDL_N_PER_M * udl)
}

/// The most unfavourable LM71 (× `alpha`) for the effect of `line`: the largest value for
/// `sign` ≥ 0, the most negative for `sign` < 0; `value` in N × (unit of η),
/// `first_axle_x_m` the leftmost axle (m).
pub fn lm71_max(line: &InfluenceLine, alpha: f64, sign: f64) -> Placement {
    let (s, c) = (LM71_AXLE_SPACING_M, LM71_CLEARANCE_M);
    let mut candidates = Vec::new();
    for k in &line.kinks {
        candidates.extend([0.0, s, 2.0 * s, 3.0 * s].map(|o| k - o));
    }
    let range = [-(3.0 * s + c), line.length_m + c];
    place(|x| lm71_at(line, alpha, sign, x), sign, range, &candidates)
}

/// The effect (N × unit of η) of point loads `(offset behind the leading axle, m; load, N)`
/// with the leading axle at `first_axle_x_m` (m): Σ Pᵢ η(x₀ − dᵢ).
pub fn axles_at(line: &InfluenceLine, loads: &[(f64, f64)], first_axle_x_m: f64) -> f64 {
    let x0 = first_axle_x_m;
    loads.iter().map(|&(d, p)| p * line.at(x0 - d)).sum()
}

/// The most unfavourable position of a train of point loads `(offset behind the leading
/// axle, m, ≥ 0; load, N)` crossing the beam (leading axle from 0 to L + the largest
/// offset): the largest value for `sign` ≥ 0, the most negative for `sign` < 0; `value` in
/// N × (unit of η), `first_axle_x_m` the leading axle (m).
pub fn axles_max(line: &InfluenceLine, loads: &[(f64, f64)], sign: f64) -> Placement {
    let hi = line.length_m + loads.iter().map(|l| l.0).fold(0.0, f64::max);
    let mut candidates = Vec::new();
    for k in &line.kinks {
        candidates.extend(loads.iter().map(|l| k + l.0));
    }
    place(|x| axles_at(line, loads, x), sign, [0.0, hi], &candidates)
}

/// The placement maximising σ·value(x₀) over x₀ ∈ [lo, hi]: the candidates, a grid, golden
/// section about the best grid maxima; a point off the candidates must beat them by 10⁻¹²
/// relative (so that an optimum on a kink or jump is reported where it is).
fn place(value: impl Fn(f64) -> f64, sign: f64, range: [f64; 2], cand: &[f64]) -> Placement {
    let [lo, hi] = range;
    let f = |x| unit_sign(sign) * value(x);
    let n = ((hi - lo) / GRID_STEP_M).ceil().max(1.0) as usize;
    let step = (hi - lo) / n as f64;
    let xs: Vec<f64> = (0..=n).map(|i| lo + step * i as f64).collect();
    let mut vs = vec![f64::NEG_INFINITY];
    vs.extend(xs.iter().map(|&x| f(x)));
    vs.push(f64::NEG_INFINITY);
    let mut best = (xs[0], vs[1]);
    for &c in cand.iter().filter(|&&c| c >= lo && c <= hi) {
        let v = f(c);
        if v > best.1 {
            best = (c, v);
        }
    }
    // grid maxima (vs[i + 1] is f(xs[i])), plateaus counted at their ends
    let is_peak = |w: &[f64]| w[1] >= w[0] && w[1] >= w[2] && (w[1] > w[0] || w[1] > w[2]);
    let mut peaks: Vec<usize> = (0..=n).filter(|&i| is_peak(&vs[i..i + 3])).collect();
    peaks.sort_by(|&a, &b| vs[b + 1].total_cmp(&vs[a + 1]));
    for &i in peaks.iter().take(REFINED_PEAKS) {
        let refined = golden(&f, xs[i.saturating_sub(1)], xs[(i + 1).min(n)]);
        for (x, v) in [(xs[i], vs[i + 1]), refined] {
            if v > best.1 + 1e-12 * best.1.abs() {
                best = (x, v);
            }
        }
    }
    Placement {
        value: value(best.0),
        first_axle_x_m: best.0,
    }
}

/// Golden-section search for a maximum of f on [a, b]; the best point evaluated.
fn golden(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    let mut best = (c, f64::NEG_INFINITY);
    loop {
        for p in [(c, fc), (d, fd)] {
            if p.1 > best.1 {
                best = p;
            }
        }
        if b - a <= 1e-13 * (1.0 + a.abs().max(b.abs())) {
            return best;
        }
        if fc >= fd {
            (b, d, fd) = (d, c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::SpanSection;

    const EI: f64 = 3.15e10;
    const P: f64 = 250e3;
    const Q: f64 = 80e3;

    fn beam(spans: Vec<f64>, continuous: bool, n: usize) -> StaticBeam {
        let (youngs_modulus_pa, inertia_m4, mass_per_length_kg_m) = (EI, 1.0, 1e4);
        let s = SpanSection {
            youngs_modulus_pa,
            inertia_m4,
            mass_per_length_kg_m,
        };
        StaticBeam::new(&ContinuousBeam::prismatic(spans, s, continuous), n).unwrap()
    }

    fn line(b: &StaticBeam, effect: Effect) -> InfluenceLine {
        b.influence(effect).unwrap()
    }

    /// |got − want| ≤ 10⁻¹⁰ |want|.
    fn close(got: f64, want: f64) {
        let err = (got - want).abs() / want.abs();
        assert!(err <= 1e-10, "got {got:e}, want {want:e} (rel {err:e})");
    }

    /// ∫ₐᵇ η dx (both signs).
    fn udl(line: &InfluenceLine, a: f64, b: f64) -> f64 {
        line.integral(a, b, 1.0) - line.integral(a, b, -1.0)
    }

    /// Simply supported span, L = 20 m, EI = 3.15e10 N·m²: deflection, moment and reaction
    /// lines against the textbook forms, at sections that are not nodes of the uniform mesh.
    #[test]
    fn simply_supported_span_matches_closed_forms() {
        let l = 20.0;
        let b = beam(vec![l], true, 7); // L/2, 6.3 and 7.3 are not nodes of the uniform mesh
        let w = line(&b, Effect::Displacement { x_m: l / 2.0 });
        assert!(w.at(0.0).abs() < 1e-20 && w.at(l).abs() < 1e-20);
        assert_eq!((w.at(-0.1), w.at(l + 0.1)), (0.0, 0.0));
        for a in [1.3, 4.0, 7.7, 10.0, 12.5, 19.9] {
            let nb = f64::min(a, l - a); // P b (3L² − 4b²)/48EI
            close(
                P * w.at(a),
                P * nb * (3.0 * l * l - 4.0 * nb * nb) / (48.0 * EI),
            );
        }
        close(Q * udl(&w, 0.0, l), 5.0 * Q * l.powi(4) / (384.0 * EI));
        // deflection at x = 6.3 under a load b from the far support: b x (L² − b² − x²)/6LEI
        let (x, wx) = (6.3, line(&b, Effect::Displacement { x_m: 6.3 }));
        for bb in [l - 6.3, l - 9.0, l - 15.1] {
            close(
                wx.at(l - bb),
                bb * x * (l * l - bb * bb - x * x) / (6.0 * l * EI),
            );
        }
        let m = line(&b, Effect::Moment { x_m: l / 2.0 });
        close(P * m.at(l / 2.0), P * l / 4.0);
        close(Q * udl(&m, 0.0, l), Q * l * l / 8.0);
        // moment at x = 7.3: min(a, x) (L − max(a, x))/L
        let mx = line(&b, Effect::Moment { x_m: 7.3 });
        for a in [0.5, 3.0, 7.3, 11.0, 18.2] {
            close(mx.at(a), f64::min(a, 7.3) * (l - f64::max(a, 7.3)) / l);
        }
        let r0 = line(&b, Effect::Reaction { support: 0 });
        let r1 = line(&b, Effect::Reaction { support: 1 });
        assert!(r0.at(l).abs() < 1e-12);
        for a in [0.0, 2.2, 10.0, 17.0] {
            close(P * r0.at(a), P * (l - a) / l);
            close(P * r1.at(a) + P * r0.at(a), P);
        }
        assert!(b.influence(Effect::Reaction { support: 2 }).is_err());
        assert!(b.influence(Effect::Moment { x_m: 20.5 }).is_err());
    }

    /// LM71 on simply supported spans. Midspan moment (η = x/2 for x ≤ L/2): two axles on
    /// each side give Σ η = L − 3.2 wherever the group stands, and the unloaded 6.4 m zone
    /// cuts least off the triangle when shifted off-centre, so the maximum has an axle at
    /// midspan (x₀ = L/2 − 1.6 or its mirror L/2 − 3.2):
    /// M = Q (L − 3.2) + q [(L/2 − 2.4)² + (L/2 − 4)²]/4, which is q·0.32 above the
    /// symmetric arrangement's Q (L − 3.2) + q (L/2 − 3.2)²/2.
    /// Midspan deflection (η = x (3L² − 4x²)/48EI, smooth and concave): the symmetric
    /// arrangement, Σ Q η(L/2 ± 0.8, ± 2.4) + 2q [3L²c²/2 − c⁴]/48EI, c = L/2 − 3.2.
    /// End reaction: an axle on the support, R = Q (4L − 9.6)/L + q (L − 5.6)²/(2L).
    #[test]
    fn lm71_on_simple_spans_matches_closed_forms() {
        for l in [10.0, 20.0, 30.0] {
            let (b, h) = (beam(vec![l], true, 16), l / 2.0);
            let m = line(&b, Effect::Moment { x_m: h });
            let best = lm71_max(&m, 1.0, 1.0);
            let want = P * (l - 3.2) + Q * ((h - 2.4).powi(2) + (h - 4.0).powi(2)) / 4.0;
            close(best.value, want);
            let x0 = best.first_axle_x_m;
            let on_axle = (x0 - h + 1.6).abs() < 1e-6 || (x0 - h + 3.2).abs() < 1e-6;
            assert!(on_axle, "{best:?}");
            let symmetric = P * (l - 3.2) + Q * (h - 3.2).powi(2) / 2.0;
            close(lm71_at(&m, 1.0, 1.0, h - 2.4), symmetric);
            close(best.value, symmetric + Q * 0.32);

            let w = line(&b, Effect::Displacement { x_m: h });
            let eta = |x: f64| x * (3.0 * l * l - 4.0 * x * x) / (48.0 * EI);
            let c = h - 3.2;
            let want = 2.0 * P * (eta(h - 0.8) + eta(h - 2.4))
                + 2.0 * Q * (1.5 * l * l * c * c - c.powi(4)) / (48.0 * EI);
            let best = lm71_max(&w, 1.0, 1.0);
            close(best.value, want);
            assert!((best.first_axle_x_m - (h - 2.4)).abs() < 1e-4, "{best:?}");

            let best = lm71_max(&line(&b, Effect::Reaction { support: 0 }), 1.0, 1.0);
            close(
                best.value,
                P * (4.0 * l - 9.6) / l + Q * (l - 5.6).powi(2) / (2.0 * l),
            );
            assert!(best.first_axle_x_m.abs() < 1e-9, "{best:?}");
        }
    }

    /// Two equal continuous spans. Interior support moment for a unit load at a in span 1:
    /// −a (L² − a²)/(4L²) (three-moment equation); under q on both spans −qL²/8. Midspan
    /// deflection of span 1 with q on span 1 only: 5qL⁴/384EI − (qL²/16) L²/(16 EI)
    /// = 7qL⁴/768EI.
    #[test]
    fn two_continuous_spans_match_closed_forms() {
        let l = 20.0;
        let b = beam(vec![l, l], true, 9);
        let mb = line(&b, Effect::Moment { x_m: l });
        for a in [1.0, 6.6, 10.0, 17.5] {
            let want = -a * (l * l - a * a) / (4.0 * l * l);
            close(mb.at(a), want);
            close(mb.at(2.0 * l - a), want);
        }
        close(Q * udl(&mb, 0.0, 2.0 * l), -Q * l * l / 8.0);
        assert_eq!(mb.integral(0.0, 2.0 * l, 1.0), 0.0);
        let w = line(&b, Effect::Displacement { x_m: l / 2.0 });
        close(Q * udl(&w, 0.0, l), 7.0 * Q * l.powi(4) / (768.0 * EI));
        assert!(
            w.integral(l, 2.0 * l, -1.0) > 0.0,
            "span 2 lifts span 1's midspan"
        );
        // the moment from the element on either side of a section is the same
        for x in [l, 13.7, 31.0] {
            let left = b.line(Effect::Moment { x_m: x }, false).unwrap();
            let right = b.line(Effect::Moment { x_m: x }, true).unwrap();
            for a in (0..=400).map(|k| 0.1 * k as f64) {
                assert!((left.at(a) - right.at(a)).abs() < 1e-9 * l, "x {x}, a {a}");
            }
        }
        // LM71 hogging: negative for sign −1, nothing sagging at the interior support; α
        // scales linearly
        let hog = lm71_max(&mb, 1.0, -1.0);
        assert!(hog.value < -1e6, "{hog:?}");
        assert!(lm71_max(&mb, 1.0, 1.0).value.abs() < 1e-6);
        close(lm71_max(&mb, 1.21, -1.0).value, 1.21 * hog.value);
        let sag = line(&b, Effect::Moment { x_m: 8.0 });
        let one = lm71_max(&sag, 1.0, 1.0).value;
        close(lm71_max(&sag, 0.83, 1.0).value, 0.83 * one);
    }

    /// A chain of two simply supported spans (20 m and 15 m): each span alone. The midspan
    /// moment of span 2 is the simple span's triangle, zero on span 1, nothing at the hinge;
    /// the interior support (two bearings) carries a/L₁ and (L − a)/L₂; span 1's midspan
    /// deflection under q on both spans is 5qL₁⁴/384EI.
    #[test]
    fn chain_of_simple_spans_behaves_as_separate_spans() {
        let (l1, l2) = (20.0, 15.0);
        let b = beam(vec![l1, l2], false, 8);
        let m2 = line(&b, Effect::Moment { x_m: l1 + l2 / 2.0 });
        let hinge = line(&b, Effect::Moment { x_m: l1 });
        for a in [2.0, 11.0, 19.0, 21.0, 30.0] {
            assert!(hinge.at(a).abs() < 1e-9, "{}", hinge.at(a));
            if a < l1 {
                assert!(m2.at(a).abs() < 1e-9, "{}", m2.at(a));
            } else {
                close(m2.at(a), f64::min(a - l1, l1 + l2 - a) / 2.0);
            }
        }
        let r1 = line(&b, Effect::Reaction { support: 1 });
        assert!(r1.at(0.0).abs() < 1e-12 && r1.at(l1 + l2).abs() < 1e-12);
        for a in [5.0, 20.0, 23.0, 34.0] {
            close(r1.at(a), f64::min(a / l1, (l1 + l2 - a) / l2));
        }
        let w = line(&b, Effect::Displacement { x_m: l1 / 2.0 });
        close(
            Q * udl(&w, 0.0, l1 + l2),
            5.0 * Q * l1.powi(4) / (384.0 * EI),
        );
        assert!(w.at(27.0).abs() < 1e-20);
        let h = l2 / 2.0; // LM71 on span 2's midspan moment: the 15 m simple span's value
        let want = P * (l2 - 3.2) + Q * ((h - 2.4).powi(2) + (h - 4.0).powi(2)) / 4.0;
        close(lm71_max(&m2, 1.0, 1.0).value, want);
    }

    /// Point loads on a 20 m simple span: one axle gives PL/4 at midspan; two axles d apart
    /// give P (L − d)/2 (any position straddling midspan) and, on the end reaction,
    /// P + P (L − d)/L with the trailing axle on the support. Also the exact positive part
    /// of p = (ξ − 0.2)(ξ − 0.5)(ξ − 0.9) (positive on (0.2, 0.5) and (0.9, 1)).
    #[test]
    fn point_load_trains_and_positive_parts() {
        let l = 20.0;
        let b = beam(vec![l], true, 10);
        let m = line(&b, Effect::Moment { x_m: l / 2.0 });
        let one = axles_max(&m, &[(0.0, P)], 1.0);
        close(one.value, P * l / 4.0);
        assert!((one.first_axle_x_m - l / 2.0).abs() < 1e-6, "{one:?}");
        close(
            axles_max(&m, &[(0.0, P), (3.0, P)], 1.0).value,
            P * (l - 3.0) / 2.0,
        );
        let r = line(&b, Effect::Reaction { support: 0 });
        let best = axles_max(&r, &[(0.0, P), (3.0, P)], 1.0);
        close(best.value, P + P * (l - 3.0) / l);
        assert!((best.first_axle_x_m - 3.0).abs() < 1e-9, "{best:?}");
        assert_eq!(axles_max(&m, &[(0.0, P)], -1.0).value, 0.0);
        assert_eq!(axles_max(&m, &[], 1.0).value, 0.0);

        let p = [-0.09, 0.73, -1.6, 1.0];
        let f = |t: f64| t.powi(4) / 4.0 - 1.6 * t.powi(3) / 3.0 + 0.365 * t * t - 0.09 * t;
        close(
            positive_part(&p, 0.0, 1.0),
            f(0.5) - f(0.2) + f(1.0) - f(0.9),
        );
        let neg = p.map(|c| -c);
        close(
            positive_part(&neg, 0.0, 1.0),
            f(0.0) - f(0.2) + f(0.5) - f(0.9),
        );
    }
}
