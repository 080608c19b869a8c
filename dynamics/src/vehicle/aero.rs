//! Steady crosswind on the car bodies (quasi-steady aerodynamics).
//!
//! A train at speed `v` (+x) in a mean wind `U` normal to the track (towards +y) sees the
//! relative wind `V = √(v² + U²)` at the yaw angle `β = atan(U / v)` (90° at standstill). On
//! each car body it exerts, with the air density ρ, the reference area `A` and height `h`,
//!
//! ```text
//! side force     F_S = ½ρV² A C_S(β)        (+y, leeward)
//! lift           F_L = ½ρV² A C_L(β)        (upward)
//! rolling moment M_R = ½ρV² A h C_MR(β)     (about +x, leeward side down, about the line of
//!                                            the wheelset reference points under the body)
//! yawing moment  M_Y = ½ρV² A L C_MY(β)     (about +z, nose leeward, about the body's centre)
//! pitching mom.  M_P = ½ρV² A L C_MP(β)     (about +y, nose up, about the body's centre)
//! ```
//!
//! the coefficients interpolated linearly in β from a table. On a body whose centre of
//! gravity is `H` above that line they are the generalised forces `F_S` on its lateral DOF,
//! `−F_L` on its vertical DOF (z down), `M_R − H F_S` on its roll DOF (the moment about the
//! centre of gravity), `M_Y` on its yaw and `M_P` on its pitch DOF (bodies that model them).
//! In static equilibrium the wheelsets at distances `a_i` ahead of the body's centre then
//! carry `Σ a_i F_y,i = M_Y` and `Σ a_i F_z,i = −M_P` (the nose-up moment unloads the front).
//!
//! Constant loads `f` on the vehicle DOFs only shift its static equilibrium, `v_s = K_vv⁻¹ f`,
//! as gravity does ([`super::assembly`]): with the DOFs measured from that equilibrium the
//! equations of motion are unchanged and the static rail forces become
//! `P0 − K_wv v_s` ([`LinearVehicle::with_body_loads`]). Their sums are the moment balance of
//! the body loads: `Σ F_y = F_S`, `Σ M_x = M_R`, `Σ F_z = W − F_L`; the still-air load of each
//! wheelset stays the reference `Q₀` of the wheel unloading `ΔQ/Q₀`.
//!
//! The default coefficients are assumptions of the magnitude reported for passenger coaches
//! (not measurements of the paper's coach): see [`VehicleAero::default`].

use super::LinearVehicle;
use nalgebra::DVector;
use serde::{Deserialize, Serialize};

/// Aerodynamic coefficients of a car body against the yaw angle of the relative wind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleAero {
    /// Reference area A, m². Default 10.
    pub area_m2: f64,
    /// Reference height h of the rolling moment, m. Default 3.
    pub height_m: f64,
    /// Yaw angles β of the table, degrees, ascending in [0, 90].
    pub yaw_deg: Vec<f64>,
    /// Side-force coefficient C_S(β), –.
    pub side: Vec<f64>,
    /// Lift coefficient C_L(β), –.
    pub lift: Vec<f64>,
    /// Rolling-moment coefficient C_MR(β), –.
    pub roll: Vec<f64>,
    /// Reference length L of the yawing and pitching moments, m. Default 26 (a coach body).
    pub length_m: f64,
    /// Yawing-moment coefficient C_MY(β), –; empty (the default): none.
    pub yaw: Vec<f64>,
    /// Pitching-moment coefficient C_MP(β), –; empty (the default): none.
    pub pitch: Vec<f64>,
}

impl Default for VehicleAero {
    /// Assumed coefficients (A = 10 m², h = 3 m): side force rising with the yaw angle to 7.5
    /// at 90°, lift to 2.0 and rolling moment to 3.6, the shape of the curves reported for
    /// passenger coaches in crosswind studies; replace them with measured ones.
    fn default() -> Self {
        VehicleAero {
            area_m2: 10.0,
            height_m: 3.0,
            yaw_deg: vec![0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0],
            side: vec![0.0, 1.2, 2.6, 3.9, 5.0, 5.9, 6.6, 7.1, 7.4, 7.5],
            lift: vec![0.0, 0.3, 0.7, 1.1, 1.4, 1.7, 1.85, 1.95, 2.0, 2.0],
            roll: vec![0.0, 0.6, 1.3, 1.9, 2.4, 2.9, 3.2, 3.4, 3.55, 3.6],
            length_m: 26.0,
            yaw: Vec::new(),
            pitch: Vec::new(),
        }
    }
}

/// The steady loads on one car body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyLoads {
    /// Side force F_S, N (+y).
    pub side_n: f64,
    /// Lift F_L, N (upward).
    pub lift_n: f64,
    /// Rolling moment M_R about the wheelset reference line, N·m (leeward side down).
    pub roll_nm: f64,
    /// Yawing moment M_Y about the body's centre, N·m (nose leeward).
    #[serde(default)]
    pub yaw_nm: f64,
    /// Pitching moment M_P about the body's centre, N·m (nose up).
    #[serde(default)]
    pub pitch_nm: f64,
    /// Yaw angle β of the relative wind, degrees.
    pub yaw_deg: f64,
}

impl VehicleAero {
    /// Check the table (as many coefficients as angles, angles ascending in [0, 90], every
    /// number finite, A and h positive); the name of the first bad field and why.
    pub fn validate(&self) -> Result<(), (String, String)> {
        if !(self.area_m2.is_finite() && self.area_m2 > 0.0) {
            return Err((
                "area_m2".into(),
                format!("{} must be positive", self.area_m2),
            ));
        }
        if !(self.height_m.is_finite() && self.height_m > 0.0) {
            return Err((
                "height_m".into(),
                format!("{} must be positive", self.height_m),
            ));
        }
        let n = self.yaw_deg.len();
        if n < 2 {
            return Err(("yaw_deg".into(), "give at least two yaw angles".into()));
        }
        for (i, w) in self.yaw_deg.windows(2).enumerate() {
            if w[1].is_nan() || w[1] <= w[0] {
                return Err((
                    "yaw_deg".into(),
                    format!(
                        "yaw_deg[{}] = {} does not ascend from {}",
                        i + 1,
                        w[1],
                        w[0]
                    ),
                ));
            }
        }
        if !(self.yaw_deg[0] >= 0.0 && self.yaw_deg[n - 1] <= 90.0) {
            return Err((
                "yaw_deg".into(),
                "angles must lie in [0, 90] degrees".into(),
            ));
        }
        if !(self.length_m.is_finite() && self.length_m > 0.0) {
            return Err((
                "length_m".into(),
                format!("{} must be positive", self.length_m),
            ));
        }
        for (name, v) in [
            ("side", &self.side),
            ("lift", &self.lift),
            ("roll", &self.roll),
            ("yaw", &self.yaw),
            ("pitch", &self.pitch),
        ] {
            let optional = name == "yaw" || name == "pitch";
            if optional && v.is_empty() {
                continue;
            }
            if v.len() != n {
                return Err((
                    name.into(),
                    format!("{} values for {n} yaw angles", v.len()),
                ));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err((format!("{name}[{i}]"), format!("{} is not finite", v[i])));
            }
        }
        Ok(())
    }

    fn at(&self, table: &[f64], beta_deg: f64) -> f64 {
        if table.is_empty() {
            return 0.0;
        }
        let b = beta_deg.clamp(self.yaw_deg[0], *self.yaw_deg.last().expect("validated"));
        let k = self
            .yaw_deg
            .partition_point(|&a| a <= b)
            .clamp(1, self.yaw_deg.len() - 1);
        let (a0, a1) = (self.yaw_deg[k - 1], self.yaw_deg[k]);
        table[k - 1] + (b - a0) / (a1 - a0) * (table[k] - table[k - 1])
    }

    /// The loads on a car body at train speed `v` (m/s, ≥ 0) in a mean wind `u` (m/s, ≥ 0)
    /// normal to the track, air density `rho` (kg/m³).
    /// A wind towards −y (`u < 0`, a gust reversing the mean) gives the mirror loads: side
    /// force and rolling moment change sign, the lift does not.
    pub fn loads(&self, v: f64, u: f64, rho: f64) -> BodyLoads {
        let v2 = v * v + u * u;
        let beta = if v2 > 0.0 {
            u.abs().atan2(v).to_degrees()
        } else {
            0.0
        };
        let q = 0.5 * rho * v2 * self.area_m2;
        let sign = if u < 0.0 { -1.0 } else { 1.0 };
        BodyLoads {
            side_n: sign * q * self.at(&self.side, beta),
            lift_n: q * self.at(&self.lift, beta),
            roll_nm: sign * q * self.height_m * self.at(&self.roll, beta),
            yaw_nm: sign * q * self.length_m * self.at(&self.yaw, beta),
            pitch_nm: q * self.length_m * self.at(&self.pitch, beta),
            yaw_deg: sign * beta,
        }
    }
}

impl LinearVehicle {
    /// The vehicle with constant loads `f` (one per DOF) added to its static equilibrium
    /// (module docs); the still-air loads stay the wheelsets' reference.
    pub fn with_body_loads(&self, f: &DVector<f64>) -> Result<LinearVehicle, String> {
        let n = self.ndof();
        if f.len() != n {
            return Err(format!("{} loads for {n} DOFs", f.len()));
        }
        let mut out = self.clone();
        if n == 0 {
            return Ok(out);
        }
        let v_s = self
            .k
            .clone()
            .cholesky()
            .ok_or("the stiffness matrix is not positive definite")?
            .solve(f);
        for ws in &mut out.wheelsets {
            ws.still_air_load_n.get_or_insert(ws.p0.z);
            let shift = ws.k_vw.tr_mul(&v_s);
            for k in 0..3 {
                ws.p0[k] -= shift[k];
            }
        }
        Ok(out)
    }

    /// The vehicle in a steady crosswind: `loads` on its car body (lateral, vertical and roll
    /// DOFs of [`super::BodyDofs`]). Vehicles without a car body that rolls (moving forces,
    /// sprung masses) are returned unchanged.
    pub fn in_crosswind(&self, loads: &BodyLoads) -> Result<LinearVehicle, String> {
        let Some(body) = WindBody::of(self) else {
            return Ok(self.clone());
        };
        let mut f = DVector::zeros(self.ndof());
        body.add(loads, 1.0, &mut f);
        self.with_body_loads(&f)
    }
}

/// The car body of a vehicle as the wind loads it: its lateral, vertical and roll DOFs (and
/// yaw and pitch where modelled) and the height of its centre of gravity above the wheelset
/// reference line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindBody {
    /// DOF indices (lateral, vertical, roll).
    pub dofs: [usize; 3],
    /// DOF indices of yaw and pitch, if modelled.
    pub yaw_pitch: [Option<usize>; 2],
    /// Height H of the centre of gravity above the wheelset reference line, m.
    pub cg_height_m: f64,
}

impl WindBody {
    /// `(d, K̂⁻¹ e_d)` for each DOF `d` the wind loads on the body of `v` (lateral, vertical,
    /// roll, and yaw and pitch where modelled; none without a body): `solve` replaces a
    /// vector of `v`'s DOFs by `K̂⁻¹` times it. With these, the wind's share of a solve is
    /// `K̂⁻¹ F = Σ_d F_d K̂⁻¹ e_d` ([`Self::add`] writes only these DOFs).
    pub fn unit_responses(
        v: &LinearVehicle,
        mut solve: impl FnMut(&mut [f64]),
    ) -> Vec<(usize, Vec<f64>)> {
        let Some(b) = WindBody::of(v) else {
            return Vec::new();
        };
        let dofs = b.dofs.into_iter().chain(b.yaw_pitch.into_iter().flatten());
        dofs.map(|d| {
            let mut e = vec![0.0; v.ndof()];
            e[d] = 1.0;
            solve(&mut e);
            (d, e)
        })
        .collect()
    }

    /// `y ← y + K̂⁻¹ f` for a force `f` on `v`'s DOFs that loads only the body's
    /// ([`Self::add`]), from its [`Self::unit_responses`]: `Σ_d f_d K̂⁻¹ e_d`.
    pub fn add_responses(responses: &[(usize, Vec<f64>)], f: &[f64], y: &mut [f64]) {
        debug_assert!(
            (0..f.len()).all(|k| f[k] == 0.0 || responses.iter().any(|(d, _)| *d == k)),
            "the wind loads only the body's DOFs"
        );
        for (d, column) in responses {
            crate::simd::axpy(y, f[*d], column);
        }
    }

    /// The body of `v`, if it has one that rolls (coaches; not moving forces or sprung
    /// masses).
    pub fn of(v: &LinearVehicle) -> Option<WindBody> {
        let b = v.body;
        match (b.lateral, b.vertical, b.roll) {
            (Some(y), Some(z), Some(r)) => Some(WindBody {
                dofs: [y, z, r],
                yaw_pitch: [b.yaw, b.pitch],
                cg_height_m: b.cg_height_m,
            }),
            _ => None,
        }
    }

    /// Add `scale` times the generalised forces of `loads` to `f`: `F_S` on the lateral
    /// DOF, `−F_L` on the vertical one (z down), `M_R − H F_S` on the roll (the moment
    /// about the centre of gravity), `M_Y` and `M_P` on yaw and pitch.
    pub fn add(&self, loads: &BodyLoads, scale: f64, f: &mut DVector<f64>) {
        let [y, z, r] = self.dofs;
        f[y] += scale * loads.side_n;
        f[z] -= scale * loads.lift_n;
        f[r] += scale * (loads.roll_nm - self.cg_height_m * loads.side_n);
        if let Some(d) = self.yaw_pitch[0] {
            f[d] += scale * loads.yaw_nm;
        }
        if let Some(d) = self.yaw_pitch[1] {
            f[d] += scale * loads.pitch_nm;
        }
    }
}

/// The wind on a running train's car bodies, step by step.
///
/// Car body `i`, whose centre (the mean of its wheelsets' positions) is at `x_c(t)`, sees
/// the along-wind velocity `U + u(x_c, t)` (the turbulence `u` from the wind field, or 0 in
/// a steady wind; the vertical turbulence is not applied to the bodies) and carries the loads
/// of [`VehicleAero::loads`] with the coefficients of where it is: `deck` while
/// `x_c` lies on the deck, `ground` elsewhere (the shielding or exposure of the deck). Its
/// static equilibrium already holds the steady loads at its starting place
/// (`reference`, [`LinearVehicle::in_crosswind`]), so the equations of motion get the
/// difference `f(t) = F(loads(U + u, set(x_c))) − F(reference)` on the body's DOFs
/// ([`WindBody::add`]) — zero in a steady wind that stays on one kind of ground.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainWind {
    /// Mean wind speed U, m/s.
    pub mean_speed_m_s: f64,
    /// Air density ρ, kg/m³.
    pub air_density_kg_m3: f64,
    /// Train speed v, m/s.
    pub speed_m_s: f64,
    /// Coefficients off the deck.
    pub ground: VehicleAero,
    /// Coefficients on the deck.
    pub deck: VehicleAero,
    /// The deck's extent `[start, end]`, m (None: all ground).
    pub deck_m: Option<[f64; 2]>,
    /// Per vehicle: its body, the distance of the body's centre behind the first axle (m)
    /// and the loads in its static equilibrium; None for a vehicle without a rolling body.
    pub bodies: Vec<Option<(WindBody, f64, BodyLoads)>>,
}

impl TrainWind {
    /// Whether a body centred at `x` is on the deck.
    pub fn on_deck(&self, x: f64) -> bool {
        self.deck_m.is_some_and(|[a, b]| (a..=b).contains(&x))
    }

    /// The loads on a body centred at `x` in the along-wind turbulence `u`.
    pub fn loads_at(&self, x: f64, u: f64) -> BodyLoads {
        let aero = if self.on_deck(x) {
            &self.deck
        } else {
            &self.ground
        };
        aero.loads(
            self.speed_m_s,
            self.mean_speed_m_s + u,
            self.air_density_kg_m3,
        )
    }

    /// Add `scale` times the wind force of vehicle `i` (centred at `x`, in the turbulence
    /// `u`) beyond its static loads to `f` (see the type's docs).
    pub fn add_force(&self, i: usize, x: f64, u: f64, scale: f64, f: &mut DVector<f64>) {
        if let Some((body, _, reference)) = &self.bodies[i] {
            body.add(&self.loads_at(x, u), scale, f);
            body.add(reference, -scale, f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::coach::CoachParams;
    use crate::vehicle::WheelLoads;

    /// The 27-DOF coach in a steady crosswind on rigid track: the static rail forces balance
    /// the body loads exactly (Σ F_y = F_S, Σ M_x = M_R, Σ F_z = W − F_L), every wheelset
    /// carries a quarter (the coach is symmetric), so the windward wheel unloading is the
    /// closed form ΔQ/Q₀ = (F_L + 2 M_R / b) / W, b the contact distance.
    #[test]
    fn a_coach_in_crosswind_balances_the_body_loads() {
        let p = CoachParams::xia2000();
        let coach = p.build().unwrap();
        let aero = VehicleAero::default();
        let loads = aero.loads(200.0 / 3.6, 25.0, 1.225);
        assert!((loads.yaw_deg - (25.0_f64).atan2(200.0 / 3.6).to_degrees()).abs() < 1e-12);
        let windy = coach.in_crosswind(&loads).unwrap();
        let w: f64 = coach.wheelsets.iter().map(|ws| ws.p0.z).sum();
        let sum = |k: usize| windy.wheelsets.iter().map(|ws| ws.p0[k]).sum::<f64>();
        let tol = 1e-9 * w;
        assert!(
            (sum(0) - loads.side_n).abs() < tol,
            "Σ F_y {} vs F_S {}",
            sum(0),
            loads.side_n
        );
        assert!(
            (sum(1) - loads.roll_nm).abs() < tol,
            "Σ M_x {} vs M_R {}",
            sum(1),
            loads.roll_nm
        );
        assert!(
            (sum(2) - (w - loads.lift_n)).abs() < tol,
            "Σ F_z {} vs W − F_L",
            sum(2)
        );
        let b = coach.contact_distance_m;
        let closed = (loads.lift_n + 2.0 * loads.roll_nm / b) / w;
        assert!(closed > 0.05, "{closed}");
        for ws in &windy.wheelsets {
            assert_eq!(ws.reference_load_n(), w / 4.0);
            let l = WheelLoads::from_force(&ws.p0, ws.reference_load_n(), b);
            assert!(
                (l.offload_wheel - closed).abs() < 1e-9,
                "ΔQ/Q₀ {} vs closed form {closed}",
                l.offload_wheel
            );
        }
        // the equations of motion are unchanged: only the static loads moved
        assert_eq!(windy.k, coach.k);
        assert_eq!(windy.m, coach.m);
        // no wind, no change
        let calm = coach.in_crosswind(&aero.loads(50.0, 0.0, 1.225)).unwrap();
        for (a, b) in calm.wheelsets.iter().zip(&coach.wheelsets) {
            assert!((a.p0 - b.p0).norm() < 1e-6 * w);
        }
    }

    /// Yawing and pitching moments: the coach's static rail forces carry them through the
    /// bogies (Σ a_i F_y,i = M_Y, Σ a_i F_z,i = −M_P with a_i the wheelset's distance ahead
    /// of the body's centre), while the side force, lift and rolling moment stay balanced.
    #[test]
    fn a_coach_carries_the_yawing_and_pitching_moments() {
        let coach = CoachParams::xia2000().build().unwrap();
        let aero = VehicleAero {
            yaw: vec![0.0, 0.3, 0.6, 0.9, 1.1, 1.2, 1.2, 1.1, 0.9, 0.7],
            pitch: vec![0.0, 0.1, 0.2, 0.3, 0.35, 0.4, 0.4, 0.35, 0.3, 0.25],
            ..VehicleAero::default()
        };
        assert!(aero.validate().is_ok());
        let loads = aero.loads(200.0 / 3.6, 25.0, 1.225);
        assert!(loads.yaw_nm > 1e4 && loads.pitch_nm > 1e3, "{loads:?}");
        let windy = coach.in_crosswind(&loads).unwrap();
        let centre = windy.wheelsets.iter().map(|w| w.offset_m).sum::<f64>() / 4.0;
        let moment = |k: usize| {
            windy
                .wheelsets
                .iter()
                .map(|w| (centre - w.offset_m) * w.p0[k])
                .sum::<f64>()
        };
        let w: f64 = coach.wheelsets.iter().map(|ws| ws.p0.z).sum();
        let tol = 1e-9 * w * 20.0;
        assert!(
            (moment(0) - loads.yaw_nm).abs() < tol,
            "Σ a F_y {} vs M_Y {}",
            moment(0),
            loads.yaw_nm
        );
        assert!(
            (moment(2) + loads.pitch_nm).abs() < tol,
            "Σ a F_z {} vs −M_P {}",
            moment(2),
            -loads.pitch_nm
        );
        let sum = |k: usize| windy.wheelsets.iter().map(|ws| ws.p0[k]).sum::<f64>();
        assert!((sum(0) - loads.side_n).abs() < 1e-9 * w);
        assert!((sum(1) - loads.roll_nm).abs() < 1e-9 * w);
        assert!((sum(2) - (w - loads.lift_n)).abs() < 1e-9 * w);
        // the front bogie carries less than the rear under the nose-up moment
        assert!(windy.wheelsets[0].p0.z < windy.wheelsets[3].p0.z);
        // a wind from the other side mirrors the yawing moment, not the pitching one
        let mirrored = aero.loads(200.0 / 3.6, -25.0, 1.225);
        assert_eq!(mirrored.yaw_nm, -loads.yaw_nm);
        assert_eq!(mirrored.pitch_nm, loads.pitch_nm);
        let mut bad = aero.clone();
        bad.yaw.pop();
        assert_eq!(bad.validate().unwrap_err().0, "yaw");
    }

    #[test]
    fn coefficients_interpolate_and_bad_tables_are_named() {
        let a = VehicleAero::default();
        assert!(a.validate().is_ok());
        // at standstill β = 90°, the table's last values
        let l = a.loads(0.0, 20.0, 1.2);
        let q = 0.5 * 1.2 * 400.0 * 10.0;
        assert!((l.side_n - q * 7.5).abs() < 1e-9 && (l.roll_nm - q * 3.0 * 3.6).abs() < 1e-9);
        // halfway between 10° and 20°
        assert!((a.at(&a.side, 15.0) - 1.9).abs() < 1e-12);
        let bad = |f: fn(&mut VehicleAero), field: &str| {
            let mut t = VehicleAero::default();
            f(&mut t);
            assert_eq!(t.validate().unwrap_err().0, field);
        };
        bad(|t| t.yaw_deg[3] = 5.0, "yaw_deg");
        bad(|t| t.yaw_deg[9] = 95.0, "yaw_deg");
        bad(|t| t.side.pop().map(drop).unwrap_or(()), "side");
        bad(|t| t.lift[2] = f64::NAN, "lift[2]");
        bad(|t| t.area_m2 = 0.0, "area_m2");
    }
}
