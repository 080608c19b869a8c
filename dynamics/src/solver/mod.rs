//! Time integration: the monolithic solver of eq. (14) and the two partitions (bridge with
//! track, train) that the FMUs wrap.

pub mod monolithic;
pub mod partitioned;
pub mod sample;

use crate::newmark::Newmark;
use crate::track::{rail_motion, RailProfile};
use crate::train::Train;
use crate::vehicle::LinearVehicle;
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};

pub use monolithic::Monolithic;

/// Displacement, velocity and acceleration of a vehicle's free DOFs.
#[derive(Debug, PartialEq, Serialize, Deserialize)]
pub struct VehicleState {
    pub v: DVector<f64>,
    pub vd: DVector<f64>,
    pub vdd: DVector<f64>,
}

impl Clone for VehicleState {
    fn clone(&self) -> Self {
        VehicleState {
            v: self.v.clone(),
            vd: self.vd.clone(),
            vdd: self.vdd.clone(),
        }
    }

    /// Copies into the existing vectors when the sizes agree.
    fn clone_from(&mut self, source: &Self) {
        for (to, from) in [
            (&mut self.v, &source.v),
            (&mut self.vd, &source.vd),
            (&mut self.vdd, &source.vdd),
        ] {
            if to.len() == from.len() {
                to.copy_from(from);
            } else {
                *to = from.clone();
            }
        }
    }
}

impl VehicleState {
    /// Static equilibrium on the rail under the wheelsets (`rails[l] = (u, u̇, ü)`):
    /// `K v = −Σ K_vw u`, quasi-static velocity `K v̇ = −Σ K_vw u̇`, and the acceleration from
    /// the equations of motion.
    pub fn initial(model: &LinearVehicle, rails: &[[Vector3<f64>; 3]]) -> Self {
        Self::initial_loaded(model, rails, None)
    }

    /// As [`Self::initial`], with the external forces `f` (one per DOF, beyond the static
    /// loads: the wind's) in the initial acceleration.
    pub fn initial_loaded(
        model: &LinearVehicle,
        rails: &[[Vector3<f64>; 3]],
        f: Option<&DVector<f64>>,
    ) -> Self {
        let n = model.ndof();
        if n == 0 {
            return VehicleState {
                v: DVector::zeros(0),
                vd: DVector::zeros(0),
                vdd: DVector::zeros(0),
            };
        }
        let chol = model
            .k
            .clone()
            .cholesky()
            .expect("vehicle stiffness is positive definite");
        let mut fu = DVector::zeros(n);
        let mut fud = DVector::zeros(n);
        for (c, r) in model.wheelsets.iter().zip(rails) {
            fu -= &c.k_vw * r[0];
            fud -= &c.k_vw * r[1];
        }
        let v = chol.solve(&fu);
        let vd = chol.solve(&fud);
        let mut rhs = -(&model.c * &vd) - &model.k * &v;
        for (c, r) in model.wheelsets.iter().zip(rails) {
            rhs -= &c.k_vw * r[0] + &c.c_vw * r[1];
        }
        if let Some(f) = f {
            rhs += f;
        }
        let vdd = model
            .m
            .clone()
            .cholesky()
            .expect("vehicle mass matrix is positive definite")
            .solve(&rhs);
        VehicleState { v, vd, vdd }
    }

    /// Newmark update to the new displacement `v1`.
    pub fn newmark_update(&mut self, nm: &Newmark, v1: &DVector<f64>) {
        for i in 0..v1.len() {
            let (d, a) = nm.update(v1[i], self.v[i], self.vd[i], self.vdd[i]);
            self.vd[i] = d;
            self.vdd[i] = a;
        }
        self.v.copy_from(v1);
    }
}

/// Prescribed (non-deck) rail motion of train wheelset `w` at position `x` and time `t`:
/// track irregularity plus hunting, as `(r, ṙ, r̈)` in rail-DOF order.
pub fn rail_prescribed(
    track: &dyn RailProfile,
    train: &Train,
    w: usize,
    x: f64,
    t: f64,
) -> [Vector3<f64>; 3] {
    let mut r = rail_motion(&track.at(x), train.speed_m_s);
    let h = crate::track::hunting_motion(&train.hunting, w, train.speed_m_s * t, train.speed_m_s);
    r[0].x += h[0];
    r[1].x += h[1];
    r[2].x += h[2];
    r
}
