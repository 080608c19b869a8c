//! A small general 3-D finite-element frame/cable model: nodes, beams, tensioned bars,
//! point masses, supports and tied DOFs; assembly of K and M; eigen-solution; static solve.
//!
//! [`Structure`] is what [`crate::FeModel`] builds for a suspension bridge; it is public so
//! that simple structures (a single beam, a taut cable) can be analysed with the very same
//! elements and solvers.

use crate::elements::{
    add, arm_force_stiffness, bar_block, beam_geometric_local, beam_mass_local,
    beam_stiffness_local, local_axes, norm, rotate12, scale, skew, sub, M3, V3,
};
use crate::error::FeError;
use crate::sparse::SparseMatrix;
use faer::linalg::solvers::Solve;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Side};
use serde::{Deserialize, Serialize};

/// Handle of a node in a [`Structure`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct NodeId(pub usize);

/// A nodal degree of freedom (global axes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Dof {
    /// Translation along x (longitudinal).
    Ux = 0,
    /// Translation along y (lateral, to the right).
    Uy = 1,
    /// Translation along z (vertical, downward).
    Uz = 2,
    /// Rotation about x (torsion/roll, right side down).
    Rx = 3,
    /// Rotation about y.
    Ry = 4,
    /// Rotation about z.
    Rz = 5,
}

impl Dof {
    /// All six DOFs.
    pub const ALL: [Dof; 6] = [Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz];
    /// The three translations.
    pub const TRANSLATIONS: [Dof; 3] = [Dof::Ux, Dof::Uy, Dof::Uz];
}

/// Cross-section and material of a 3-D Euler–Bernoulli beam.
///
/// Local axes: x′ along the member, y′ and z′ principal axes (see each use for how they are
/// oriented). Defaults are those of a unit steel section and mean nothing physically.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BeamSection {
    /// Young's modulus E, Pa. Default 2.0e11.
    pub e: f64,
    /// Shear modulus G, Pa. Default 8.0e10.
    pub g: f64,
    /// Cross-section area A, m². Default 1.
    pub area: f64,
    /// Second moment of area about local y′ (bending that displaces along z′), m⁴. Default 1.
    pub iy: f64,
    /// Second moment of area about local z′ (bending that displaces along y′), m⁴. Default 1.
    pub iz: f64,
    /// St Venant torsion constant J, m⁴. Default 1.
    pub j: f64,
    /// Mass per unit length, kg/m. Default 7850.
    pub mass_per_length: f64,
    /// Mass moment of inertia about the member axis per unit length, kg·m²/m. Default 15 700.
    pub mass_moment_per_length: f64,
}

impl Default for BeamSection {
    fn default() -> Self {
        Self {
            e: 2.0e11,
            g: 8.0e10,
            area: 1.0,
            iy: 1.0,
            iz: 1.0,
            j: 1.0,
            mass_per_length: 7850.0,
            mass_moment_per_length: 15_700.0,
        }
    }
}

impl BeamSection {
    pub(crate) fn validate(&self, name: &'static str) -> Result<(), FeError> {
        let checks = [
            ("e", self.e),
            ("g", self.g),
            ("area", self.area),
            ("iy", self.iy),
            ("iz", self.iz),
            ("j", self.j),
            ("mass_per_length", self.mass_per_length),
            ("mass_moment_per_length", self.mass_moment_per_length),
        ];
        for (field, v) in checks {
            if !(v.is_finite() && v > 0.0) {
                return Err(FeError::parameter(
                    name,
                    format!("{field} = {v}"),
                    "section properties must be positive and finite",
                ));
            }
        }
        Ok(())
    }
}

/// Properties of a bar (cable segment, hanger): axial stiffness, lumped mass, initial tension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BarProps {
    /// Axial stiffness E·A, N.
    pub ea: f64,
    /// Mass per unit length, kg/m (lumped half to each end).
    pub mass_per_length: f64,
    /// Initial (dead-load) tension, N; gives the geometric stiffness `T/L (I − n nᵀ)`.
    pub tension: f64,
}

#[derive(Debug, Clone)]
struct Node {
    pos: V3,
    rotations: bool,
}

#[derive(Debug, Clone)]
struct Beam {
    i: usize,
    j: usize,
    lam: M3,
    len: f64,
    section: BeamSection,
    axial_force: f64,
}

#[derive(Debug, Clone)]
struct Bar {
    i: usize,
    j: usize,
    ri: V3,
    rj: V3,
    props: BarProps,
}

#[derive(Debug, Clone)]
struct PointMass {
    node: usize,
    mass: f64,
    offset: V3,
}

/// A 3-D structure under construction. See the [module docs](self).
#[derive(Debug, Clone, Default)]
pub struct Structure {
    nodes: Vec<Node>,
    beams: Vec<Beam>,
    bars: Vec<Bar>,
    masses: Vec<PointMass>,
    parent: Vec<usize>,
    fixed: Vec<bool>,
}

impl Structure {
    /// An empty structure.
    pub fn new() -> Self {
        Self::default()
    }

    fn push_node(&mut self, pos: [f64; 3], rotations: bool) -> NodeId {
        let id = self.nodes.len();
        self.nodes.push(Node { pos, rotations });
        for d in 0..6 {
            self.parent.push(6 * id + d);
            self.fixed.push(false);
        }
        NodeId(id)
    }

    /// Add a frame node with six DOFs at `pos` (m).
    pub fn add_node(&mut self, pos: [f64; 3]) -> NodeId {
        self.push_node(pos, true)
    }

    /// Add a node with the three translations only (cable node).
    pub fn add_point(&mut self, pos: [f64; 3]) -> NodeId {
        self.push_node(pos, false)
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Position of a node, m.
    pub fn position(&self, n: NodeId) -> [f64; 3] {
        self.nodes[n.0].pos
    }

    fn check_node(&self, n: NodeId) -> Result<(), FeError> {
        if n.0 < self.nodes.len() {
            Ok(())
        } else {
            Err(FeError::Definition(format!("node {} does not exist", n.0)))
        }
    }

    fn has_dof(&self, n: NodeId, d: Dof) -> bool {
        self.nodes[n.0].rotations || (d as usize) < 3
    }

    /// Add a beam from `i` to `j`. Local y′ is the part of `reference` normal to the member;
    /// `axial_force` (N, tension positive) enters the geometric stiffness.
    pub fn add_beam(
        &mut self,
        i: NodeId,
        j: NodeId,
        section: &BeamSection,
        reference: [f64; 3],
        axial_force: f64,
    ) -> Result<(), FeError> {
        self.check_node(i)?;
        self.check_node(j)?;
        if !self.nodes[i.0].rotations || !self.nodes[j.0].rotations {
            return Err(FeError::Definition(format!(
                "beam {}–{} needs frame nodes (with rotations)",
                i.0, j.0
            )));
        }
        section.validate("beam section")?;
        let (a, b) = (self.nodes[i.0].pos, self.nodes[j.0].pos);
        let lam = local_axes(a, b, reference).ok_or_else(|| {
            FeError::Definition(format!(
                "beam {}–{}: zero length or reference vector parallel to the member",
                i.0, j.0
            ))
        })?;
        self.beams.push(Beam {
            i: i.0,
            j: j.0,
            lam,
            len: norm(sub(b, a)),
            section: *section,
            axial_force,
        });
        Ok(())
    }

    /// Add a bar between two nodes.
    pub fn add_bar(&mut self, i: NodeId, j: NodeId, props: BarProps) -> Result<(), FeError> {
        self.add_bar_with_arms(i, [0.0; 3], j, [0.0; 3], props)
    }

    /// Add a bar between the points `pos(i) + ri` and `pos(j) + rj`, each attached to its
    /// node by a rigid arm (a non-zero arm needs a frame node).
    pub fn add_bar_with_arms(
        &mut self,
        i: NodeId,
        ri: [f64; 3],
        j: NodeId,
        rj: [f64; 3],
        props: BarProps,
    ) -> Result<(), FeError> {
        self.check_node(i)?;
        self.check_node(j)?;
        for (n, r) in [(i, ri), (j, rj)] {
            if norm(r) > 0.0 && !self.nodes[n.0].rotations {
                return Err(FeError::Definition(format!(
                    "bar arm at node {} needs a frame node",
                    n.0
                )));
            }
        }
        let a = add(self.nodes[i.0].pos, ri);
        let b = add(self.nodes[j.0].pos, rj);
        if norm(sub(b, a)) <= 0.0 {
            return Err(FeError::Definition(format!(
                "bar {}–{} has zero length",
                i.0, j.0
            )));
        }
        if !(props.ea > 0.0 && props.mass_per_length >= 0.0 && props.tension.is_finite()) {
            return Err(FeError::Definition(format!(
                "bar {}–{}: needs EA > 0, mass ≥ 0 and a finite tension",
                i.0, j.0
            )));
        }
        self.bars.push(Bar {
            i: i.0,
            j: j.0,
            ri,
            rj,
            props,
        });
        Ok(())
    }

    /// Add a lumped mass (kg) at `offset` (m) from a node (non-zero offset needs a frame node).
    pub fn add_point_mass(
        &mut self,
        node: NodeId,
        mass: f64,
        offset: [f64; 3],
    ) -> Result<(), FeError> {
        self.check_node(node)?;
        if norm(offset) > 0.0 && !self.nodes[node.0].rotations {
            return Err(FeError::Definition(format!(
                "offset mass at node {} needs a frame node",
                node.0
            )));
        }
        self.masses.push(PointMass {
            node: node.0,
            mass,
            offset,
        });
        Ok(())
    }

    fn root(&self, mut r: usize) -> usize {
        while self.parent[r] != r {
            r = self.parent[r];
        }
        r
    }

    /// Restrain DOFs of a node (also restrains every DOF tied to them).
    pub fn fix(&mut self, n: NodeId, dofs: &[Dof]) -> Result<(), FeError> {
        self.check_node(n)?;
        for &d in dofs {
            if !self.has_dof(n, d) {
                return Err(FeError::Definition(format!(
                    "node {} has no DOF {d:?}",
                    n.0
                )));
            }
            let r = self.root(6 * n.0 + d as usize);
            self.fixed[r] = true;
        }
        Ok(())
    }

    /// Make DOFs of two nodes one and the same (a rigid bearing or saddle in those directions).
    pub fn tie(&mut self, a: NodeId, b: NodeId, dofs: &[Dof]) -> Result<(), FeError> {
        self.check_node(a)?;
        self.check_node(b)?;
        for &d in dofs {
            if !self.has_dof(a, d) || !self.has_dof(b, d) {
                return Err(FeError::Definition(format!(
                    "tie {}–{}: DOF {d:?} missing",
                    a.0, b.0
                )));
            }
            let ra = self.root(6 * a.0 + d as usize);
            let rb = self.root(6 * b.0 + d as usize);
            if ra != rb {
                self.parent[rb] = ra;
                self.fixed[ra] = self.fixed[ra] || self.fixed[rb];
            }
        }
        Ok(())
    }

    /// Number the free DOFs and assemble K (elastic + geometric) and M.
    pub fn assemble(&self) -> Result<System, FeError> {
        let mut map = vec![None; 6 * self.nodes.len()];
        let mut root_index = vec![None; 6 * self.nodes.len()];
        let mut n = 0usize;
        for (node, nd) in self.nodes.iter().enumerate() {
            for d in 0..6 {
                if d >= 3 && !nd.rotations {
                    continue;
                }
                let r = self.root(6 * node + d);
                if self.fixed[r] {
                    continue;
                }
                let idx = *root_index[r].get_or_insert_with(|| {
                    n += 1;
                    n - 1
                });
                map[6 * node + d] = Some(idx);
            }
        }
        // Triplets in the order a dense `+=` assembly would add them (see `crate::sparse`).
        let mut k: Vec<(usize, usize, f64)> = Vec::new();
        let mut m: Vec<(usize, usize, f64)> = Vec::new();
        let scatter = |target: &mut Vec<(usize, usize, f64)>,
                       dofs: &[Option<usize>],
                       e: &dyn Fn(usize, usize) -> f64| {
            for (a, da) in dofs.iter().enumerate() {
                let Some(ga) = *da else { continue };
                for (b, db) in dofs.iter().enumerate() {
                    let Some(gb) = *db else { continue };
                    target.push((ga, gb, e(a, b)));
                }
            }
        };
        for bm in &self.beams {
            let s = &bm.section;
            let mut kl =
                beam_stiffness_local(s.e * s.area, s.g * s.j, s.e * s.iy, s.e * s.iz, bm.len);
            let kgl = beam_geometric_local(bm.axial_force, bm.len);
            for (row, grow) in kl.iter_mut().zip(kgl.iter()) {
                for (v, g) in row.iter_mut().zip(grow.iter()) {
                    *v += g;
                }
            }
            let ke = rotate12(&kl, &bm.lam);
            let me = rotate12(
                &beam_mass_local(s.mass_per_length, s.mass_moment_per_length, bm.len),
                &bm.lam,
            );
            let dofs: Vec<Option<usize>> = (0..12)
                .map(|q| {
                    let node = if q < 6 { bm.i } else { bm.j };
                    map[6 * node + q % 6]
                })
                .collect();
            scatter(&mut k, &dofs, &|a, b| ke[a][b]);
            scatter(&mut m, &dofs, &|a, b| me[a][b]);
        }
        for br in &self.bars {
            let pa = add(self.nodes[br.i].pos, br.ri);
            let pb = add(self.nodes[br.j].pos, br.rj);
            let kb = bar_block(br.props.ea, br.props.tension, pa, pb);
            let len = norm(sub(pb, pa));
            let half_mass = 0.5 * br.props.mass_per_length * len;
            // Transformation from node DOFs to end-point translations: [I | −[r]×].
            let (ti, di) = self.arm_transform(br.i, br.ri, &map);
            let (tj, dj) = self.arm_transform(br.j, br.rj, &map);
            let t_all = [&ti, &tj];
            let dofs: Vec<Option<usize>> = di.iter().chain(dj.iter()).copied().collect();
            let ncol = [ti[0].len(), tj[0].len()];
            // Element stiffness on end translations: [[kb, −kb], [−kb, kb]].
            let mut ke = vec![vec![0.0; ncol[0] + ncol[1]]; ncol[0] + ncol[1]];
            let mut mel = vec![vec![0.0; ncol[0] + ncol[1]]; ncol[0] + ncol[1]];
            for ea in 0..2 {
                for eb in 0..2 {
                    let sgn = if ea == eb { 1.0 } else { -1.0 };
                    let (ta, tb) = (t_all[ea], t_all[eb]);
                    let oa = if ea == 0 { 0 } else { ncol[0] };
                    let ob = if eb == 0 { 0 } else { ncol[0] };
                    for p in 0..ncol[ea] {
                        for q in 0..ncol[eb] {
                            let mut s = 0.0;
                            let mut sm = 0.0;
                            for r in 0..3 {
                                for c in 0..3 {
                                    s += ta[r][p] * kb[r][c] * tb[c][q];
                                }
                                if ea == eb {
                                    sm += ta[r][p] * tb[r][q];
                                }
                            }
                            ke[oa + p][ob + q] += sgn * s;
                            mel[oa + p][ob + q] += half_mass * sm;
                        }
                    }
                }
            }
            // Second-order work of the bar force on rigid arms.
            let n = scale(sub(pb, pa), 1.0 / len);
            for (end, r, f) in [
                (0usize, br.ri, scale(n, br.props.tension)),
                (1usize, br.rj, scale(n, -br.props.tension)),
            ] {
                if norm(r) > 0.0 {
                    let ka = arm_force_stiffness(f, r);
                    let o = if end == 0 { 0 } else { ncol[0] };
                    for a in 0..3 {
                        for b in 0..3 {
                            ke[o + 3 + a][o + 3 + b] += ka[a][b];
                        }
                    }
                }
            }
            scatter(&mut k, &dofs, &|a, b| ke[a][b]);
            scatter(&mut m, &dofs, &|a, b| mel[a][b]);
        }
        for pm in &self.masses {
            let (t, d) = self.arm_transform(pm.node, pm.offset, &map);
            let nc = t[0].len();
            let mut me = vec![vec![0.0; nc]; nc];
            for (p, row) in me.iter_mut().enumerate() {
                for (q, v) in row.iter_mut().enumerate() {
                    *v = pm.mass * (0..3).map(|r| t[r][p] * t[r][q]).sum::<f64>();
                }
            }
            scatter(&mut m, &d, &|a, b| me[a][b]);
        }
        Ok(System {
            k: SparseMatrix::from_triplets(n, &k),
            m: SparseMatrix::from_triplets(n, &m),
            map,
        })
    }

    /// `[I | −[r]×]` (3×6) for frame nodes, `I` (3×3) for point nodes, with the DOF indices.
    fn arm_transform(
        &self,
        node: usize,
        r: V3,
        map: &[Option<usize>],
    ) -> (Vec<Vec<f64>>, Vec<Option<usize>>) {
        if self.nodes[node].rotations {
            let sk = skew(r);
            let t: Vec<Vec<f64>> = (0..3)
                .map(|a| {
                    let mut row = vec![0.0; 6];
                    row[a] = 1.0;
                    for b in 0..3 {
                        row[3 + b] = -sk[a][b];
                    }
                    row
                })
                .collect();
            (t, (0..6).map(|d| map[6 * node + d]).collect())
        } else {
            let t: Vec<Vec<f64>> = (0..3)
                .map(|a| {
                    let mut row = vec![0.0; 3];
                    row[a] = 1.0;
                    row
                })
                .collect();
            (t, (0..3).map(|d| map[6 * node + d]).collect())
        }
    }
}

/// Assembled stiffness and mass matrices over the free DOFs.
#[derive(Debug, Clone)]
pub struct System {
    /// Tangent stiffness K = K_E + K_G at the reference state, N/m, N, N·m (sparse).
    pub k: SparseMatrix,
    /// Mass matrix M, kg, kg·m, kg·m² (sparse).
    pub m: SparseMatrix,
    map: Vec<Option<usize>>,
}

/// The lowest eigenpairs of `K φ = ω² M φ`, mass-normalised.
#[derive(Debug, Clone)]
pub struct EigenPairs {
    /// ω², (rad/s)², ascending.
    pub omega2: Vec<f64>,
    /// Eigenvectors as columns, `φᵀ M φ = 1`.
    pub vectors: Mat<f64>,
}

impl System {
    /// Number of free DOFs.
    pub fn dof_count(&self) -> usize {
        self.k.nrows()
    }

    /// Global index of a node DOF, `None` if restrained or absent.
    pub fn dof(&self, n: NodeId, d: Dof) -> Option<usize> {
        self.map.get(6 * n.0 + d as usize).copied().flatten()
    }

    /// Lowest `n` eigenpairs of `K φ = ω² M φ`, each eigenvector's sign fixed (see
    /// `normalise_signs`).
    ///
    /// Models much larger than `n` (the bridges: thousands of DOFs, tens of modes) by a block
    /// Krylov subspace of `K⁻¹ M` with a sparse Cholesky factor of `K` (see `krylov.rs`); small
    /// ones, and any the subspace method declines, by [`System::eigen_dense`].
    pub fn eigen(&self, n: usize) -> Result<EigenPairs, FeError> {
        self.check_count(n)?;
        match crate::krylov::lowest(&self.k, &self.m, n) {
            Some((omega2, mut vectors)) => {
                normalise_signs(&mut vectors);
                Ok(EigenPairs { omega2, vectors })
            }
            None => self.eigen_dense(n),
        }
    }

    fn check_count(&self, n: usize) -> Result<(), FeError> {
        let ndof = self.dof_count();
        if n > ndof {
            return Err(FeError::TooManyModes {
                requested: n,
                available: ndof,
            });
        }
        Ok(())
    }

    /// Lowest `n` eigenpairs by the dense reduction to standard form: `M = L Lᵀ` (Cholesky),
    /// `A = L⁻¹ K L⁻ᵀ`, symmetric eigen-decomposition `A y = λ y` (eigenvalues ascending),
    /// `φ = L⁻ᵀ y`; since `yᵀ y = 1`, `φᵀ M φ = 1`. `O(N³)` for `N` DOFs; signs as
    /// [`System::eigen`].
    pub fn eigen_dense(&self, n: usize) -> Result<EigenPairs, FeError> {
        self.check_count(n)?;
        let par = faer::get_global_parallelism();
        let llt = self
            .m
            .to_dense()
            .llt(Side::Lower)
            .map_err(|e| FeError::NotPositiveDefinite {
                matrix: "mass matrix",
                hint: format!("{e:?}: a free DOF without mass"),
            })?;
        let l = llt.L();
        let mut a = self.k.to_dense();
        solve_lower_triangular_in_place(l, a.as_mut(), par);
        let mut b = a.transpose().to_owned();
        drop(a);
        solve_lower_triangular_in_place(l, b.as_mut(), par);
        // The symmetric solver reads the lower triangle only.
        let evd = b
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| FeError::Eigen(format!("{e:?}")))?;
        let s = evd.S().column_vector();
        let omega2: Vec<f64> = (0..n).map(|i| s[i]).collect();
        if let Some(&w) = omega2.first() {
            if w <= 0.0 {
                return Err(FeError::Eigen(format!(
                    "non-positive eigenvalue ω² = {w:e}: the structure is a mechanism or unstable"
                )));
            }
        }
        let mut vectors = evd.U().subcols(0, n).to_owned();
        solve_upper_triangular_in_place(l.transpose(), vectors.as_mut(), par);
        normalise_signs(&mut vectors);
        Ok(EigenPairs { omega2, vectors })
    }

    /// Sparse Cholesky factor of K (fill-reducing ordering) for repeated static solves.
    pub fn factor_stiffness(&self) -> Result<StiffnessFactor, FeError> {
        let not_pd = |hint: String| FeError::NotPositiveDefinite {
            matrix: "stiffness matrix",
            hint,
        };
        let lower = self
            .k
            .lower()
            .ok_or_else(|| not_pd("its lower triangle could not be compressed".into()))?;
        let llt = lower
            .sp_cholesky(Side::Lower)
            .map_err(|e| not_pd(format!("{e:?}: the structure is a mechanism or unstable")))?;
        Ok(StiffnessFactor { llt })
    }
}

/// Each eigenvector's sign chosen so that its product with a fixed generic vector
/// (`cᵢ = frac((i + 1) g) − ½`, g the golden ratio) is positive: the same modes whichever
/// solver found them. (The largest component would not do: a symmetric structure has modes
/// whose largest components are equal and opposite, on its two cables.)
fn normalise_signs(vectors: &mut Mat<f64>) {
    const G: f64 = 0.618_033_988_749_894_8;
    for j in 0..vectors.ncols() {
        let s: f64 = (0..vectors.nrows())
            .map(|i| vectors[(i, j)] * (((i + 1) as f64 * G).fract() - 0.5))
            .sum();
        if s < 0.0 {
            for i in 0..vectors.nrows() {
                vectors[(i, j)] = -vectors[(i, j)];
            }
        }
    }
}

/// A factorised stiffness matrix.
#[derive(Debug)]
pub struct StiffnessFactor {
    llt: faer::sparse::linalg::solvers::Llt<usize, f64>,
}

impl StiffnessFactor {
    /// Solve `K u = f`.
    pub fn solve(&self, f: &[f64]) -> Vec<f64> {
        let rhs = Mat::<f64>::from_fn(f.len(), 1, |i, _| f[i]);
        let u = self.llt.solve(&rhs);
        (0..f.len()).map(|i| u[(i, 0)]).collect()
    }
}
