//! Assembly of vehicle matrices from rigid bodies and spring–damper elements.
//!
//! A rigid body has up to five DOFs `(Y, θ, ψ, Z, φ)`: lateral and vertical displacement of
//! its centre of gravity and rotations about x (roll), z (yaw) and y (pitch). For small
//! rotations the displacement of a point at `r = (r_x, r_y, r_z)` from the centre of gravity
//! is `d = (Y, ·, Z) + ω × r` with `ω = (θ, φ, ψ)`, so (axes: x forward, y right, z down)
//!
//! ```text
//! d_y = Y − θ r_z + ψ r_x
//! d_z = Z + θ r_y − φ r_x
//! ```
//!
//! A wheelset has the prescribed rail DOFs `(Y_w, θ_w, Z_w)`; its points move by
//! `d_y = Y_w − θ_w r_z`, `d_z = Z_w + θ_w r_y`.
//!
//! An element of stiffness `k` and damping `c` acting along y or z between points `a` and
//! `b` has elongation `δ = d(b) − d(a) = bᵀ x` (x = all DOFs, free then prescribed), energy
//! `½ k δ²` and dissipation `½ c δ̇²`, hence contributions `k b bᵀ` and `c b bᵀ`. Gravity acts
//! on the Z DOF of each body (+z is down). The static state `v_s` solves `K_vv v_s = G` with
//! the wheelsets fixed, and the static rail force of wheelset w is
//! `P0_w = m_w g e_z − K_wv,w v_s` (the wheelset's weight plus the spring forces it carries).

use super::{BodyDofs, LinearVehicle, WheelsetCoupling, GRAVITY};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Direction of an element's line of action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Lateral,
    Vertical,
}

/// Handle of a rigid body added to a [`Builder`].
#[derive(Debug, Clone, Copy)]
pub struct Body {
    /// Global DOF index of Y, θ, ψ, Z, φ (None where the body lacks that DOF).
    dofs: [Option<usize>; 5],
}

/// A point where an element attaches.
#[derive(Debug, Clone, Copy)]
pub enum Point {
    /// A point of a free rigid body at `r` (m) from its centre of gravity.
    Body(Body, [f64; 3]),
    /// A point of wheelset `w` at `r` (m) from its reference point (axle centre).
    Wheelset(usize, [f64; 3]),
}

struct Element {
    a: Point,
    b: Point,
    dir: Direction,
    k: f64,
    c: f64,
}

/// Collects bodies, wheelsets and elements, then produces a [`LinearVehicle`].
#[derive(Default)]
pub struct Builder {
    names: Vec<String>,
    mass: Vec<f64>,
    gravity: Vec<f64>,
    wheelsets: Vec<(f64, f64, f64)>,
    elements: Vec<Element>,
}

const DOF_NAMES: [&str; 5] = ["Y", "theta", "psi", "Z", "phi"];

impl Builder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a rigid body of mass `mass` (kg) and moments of inertia `(J_roll, J_yaw,
    /// J_pitch)` (kg·m²) with the DOFs flagged in `active` (order Y, θ, ψ, Z, φ).
    pub fn body(&mut self, name: &str, mass: f64, inertia: [f64; 3], active: [bool; 5]) -> Body {
        let inert = [mass, inertia[0], inertia[1], mass, inertia[2]];
        let mut dofs = [None; 5];
        for i in 0..5 {
            if active[i] {
                dofs[i] = Some(self.names.len());
                self.names.push(format!("{name}.{}", DOF_NAMES[i]));
                self.mass.push(inert[i]);
                self.gravity.push(if i == 3 { mass * GRAVITY } else { 0.0 });
            }
        }
        Body { dofs }
    }

    /// Add a wheelset at `offset_m` behind the vehicle's first wheelset, with mass `m_w`
    /// (kg, lateral and vertical) and roll inertia `j_w` (kg·m²). Returns its index.
    pub fn wheelset(&mut self, offset_m: f64, m_w: f64, j_w: f64) -> usize {
        self.wheelsets.push((offset_m, m_w, j_w));
        self.wheelsets.len() - 1
    }

    /// A spring–damper along `dir` from point `a` to point `b`.
    pub fn element(&mut self, a: Point, b: Point, dir: Direction, k: f64, c: f64) {
        self.elements.push(Element { a, b, dir, k, c });
    }

    fn add_point(&self, row: &mut DVector<f64>, p: &Point, dir: Direction, sign: f64) {
        let n = self.names.len();
        match *p {
            Point::Body(body, r) => {
                let terms: [(usize, f64); 3] = match dir {
                    // d_y = Y − θ r_z + ψ r_x
                    Direction::Lateral => [(0, 1.0), (1, -r[2]), (2, r[0])],
                    // d_z = Z + θ r_y − φ r_x
                    Direction::Vertical => [(3, 1.0), (1, r[1]), (4, -r[0])],
                };
                for (slot, coeff) in terms {
                    if let Some(i) = body.dofs[slot] {
                        row[i] += sign * coeff;
                    }
                }
            }
            Point::Wheelset(w, r) => {
                let base = n + 3 * w;
                match dir {
                    Direction::Lateral => {
                        row[base] += sign;
                        row[base + 1] -= sign * r[2];
                    }
                    Direction::Vertical => {
                        row[base + 2] += sign;
                        row[base + 1] += sign * r[1];
                    }
                }
            }
        }
    }

    /// Full stiffness and damping over (free DOFs, then 3 rail DOFs per wheelset).
    pub fn full_matrices(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let dim = self.names.len() + 3 * self.wheelsets.len();
        let mut k = DMatrix::zeros(dim, dim);
        let mut c = DMatrix::zeros(dim, dim);
        for e in &self.elements {
            let mut b = DVector::zeros(dim);
            self.add_point(&mut b, &e.b, e.dir, 1.0);
            self.add_point(&mut b, &e.a, e.dir, -1.0);
            let bbt = &b * b.transpose();
            k += e.k * &bbt;
            c += e.c * &bbt;
        }
        (k, c)
    }

    /// Produce the vehicle. Fails if the free DOFs are not restrained (singular `K_vv`).
    pub fn build(
        self,
        kind: &str,
        body: BodyDofs,
        contact_distance_m: f64,
    ) -> Result<LinearVehicle, String> {
        let n = self.names.len();
        let (kf, cf) = self.full_matrices();
        let k = kf.view((0, 0), (n, n)).into_owned();
        let c = cf.view((0, 0), (n, n)).into_owned();
        let m = DMatrix::from_diagonal(&DVector::from_vec(self.mass.clone()));
        let v_static = if n > 0 {
            let chol = k.clone().cholesky().ok_or_else(|| {
                format!("{kind}: stiffness matrix is not positive definite (unrestrained DOF)")
            })?;
            chol.solve(&DVector::from_vec(self.gravity.clone()))
        } else {
            DVector::zeros(0)
        };
        let wheelsets = self
            .wheelsets
            .iter()
            .enumerate()
            .map(|(w, &(offset_m, m_w, j_w))| {
                let base = n + 3 * w;
                let k_vw = kf.view((0, base), (n, 3)).into_owned();
                let c_vw = cf.view((0, base), (n, 3)).into_owned();
                let k_ww = Matrix3::from_fn(|i, j| kf[(base + i, base + j)]);
                let c_ww = Matrix3::from_fn(|i, j| cf[(base + i, base + j)]);
                let spring = if n > 0 {
                    -(k_vw.tr_mul(&v_static))
                } else {
                    DVector::zeros(3)
                };
                let p0 = Vector3::new(spring[0], spring[1], spring[2] + m_w * GRAVITY);
                WheelsetCoupling {
                    offset_m,
                    k_vw,
                    c_vw,
                    k_ww,
                    c_ww,
                    m_w: Matrix3::from_diagonal(&Vector3::new(m_w, j_w, m_w)),
                    p0,
                    still_air_load_n: None,
                }
            })
            .collect();
        Ok(LinearVehicle {
            kind: kind.to_string(),
            dof_names: self.names,
            m,
            c,
            k,
            wheelsets,
            body,
            contact_distance_m,
            inertia: Vec::new(),
        })
    }
}
