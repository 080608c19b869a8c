//! The paper's 4-axle coach: car body and two bogies with 5 DOF each (15 free DOFs), four
//! wheelsets with 3 prescribed rail DOFs each — the "27-DOF" vehicle of Xia, Xu & Chan (2000).
//!
//! Free DOFs, in this order (Appendix A, eqs. A7–A9):
//! `car.(Y, θ, ψ, Z, φ)`, `bogie1.(…)` (front), `bogie2.(…)` (rear).
//!
//! Geometry (Figure 1 and Table 1; x forward, y right, z down, distances positive):
//!
//! * bogie centres at `x = ±s` from the car-body centre of gravity (front +s);
//! * wheelsets at `x = ±d` from their bogie centre;
//! * secondary suspension: per bogie a vertical stiffness `k2v` (total, split equally between
//!   two springs at `y = ±b`) and a lateral stiffness `k2h` acting between the car-body point
//!   `h1` below the car CG and the bogie point `h2` above the bogie CG;
//! * primary suspension: per wheelset a vertical stiffness `k1v` (total, two springs at
//!   `y = ±a`) and a lateral stiffness `k1h` between the bogie point `h3` below the bogie CG
//!   and the wheelset reference point (axle centre).
//!
//! The appendix of the paper prints these matrices with index and factor typos (e.g. a
//! missing `h1` in K_cc(Y,θ), `2d` for `d`, `h4` for `h3` in eq. 3); here they are derived
//! from the element list by [`super::assembly`] and checked against hand-derived entries,
//! symmetry, static loads and eigenfrequencies in the tests.

use super::assembly::{Builder, Direction, Point};
use super::{BodyDofs, LinearVehicle};
use serde::{Deserialize, Serialize};

/// Coach properties. Defaults are the paper's Table 1 (crush load), preset `xia2000`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CoachParams {
    /// Full length of a coach (coupler to coupler), m. Default 22.5.
    pub length_m: f64,
    /// Half distance between bogie centres `s`, m. Default 7.8 (2s = 15.6).
    pub s_m: f64,
    /// Half distance between the wheelsets of a bogie `d`, m. Default 1.25 (2d = 2.5).
    pub d_m: f64,
    /// Car-body mass `M_c`, kg. Default 50 990.
    pub car_mass_kg: f64,
    /// Car-body roll moment of inertia `J_cθ`, kg·m². Default 154 830.
    pub car_roll_inertia_kg_m2: f64,
    /// Car-body pitch moment of inertia `J_cφ`, kg·m². Default 1 958 700.
    pub car_pitch_inertia_kg_m2: f64,
    /// Car-body yaw moment of inertia `J_cψ`, kg·m². Default 1 875 300.
    pub car_yaw_inertia_kg_m2: f64,
    /// Bogie mass `M_t`, kg. Default 4 360.
    pub bogie_mass_kg: f64,
    /// Bogie roll moment of inertia `J_tθ`, kg·m². Default 1 470.
    pub bogie_roll_inertia_kg_m2: f64,
    /// Bogie pitch moment of inertia `J_tφ`, kg·m². Default 3 430.
    pub bogie_pitch_inertia_kg_m2: f64,
    /// Bogie yaw moment of inertia `J_tψ`, kg·m². Default 5 070.
    pub bogie_yaw_inertia_kg_m2: f64,
    /// Wheelset mass `m_w`, kg. Default 1 770.
    pub wheelset_mass_kg: f64,
    /// Wheelset roll moment of inertia `J_w`, kg·m². Default 920.
    pub wheelset_roll_inertia_kg_m2: f64,
    /// Primary vertical stiffness per wheelset `k1v`, N/m. Default 2.976e6.
    pub k1v_n_m: f64,
    /// Primary lateral stiffness per wheelset `k1h`, N/m. Default 2.0e7.
    pub k1h_n_m: f64,
    /// Secondary vertical stiffness per bogie `k2v`, N/m. Default 1.06e6.
    pub k2v_n_m: f64,
    /// Secondary lateral stiffness per bogie `k2h`, N/m. Default 4.6e5.
    pub k2h_n_m: f64,
    /// Primary vertical damping per wheelset `c1v`, N·s/m. Default 1.5e4.
    pub c1v_ns_m: f64,
    /// Primary lateral damping per wheelset `c1h`, N·s/m. Default 1.5e4.
    pub c1h_ns_m: f64,
    /// Secondary vertical damping per bogie `c2v`, N·s/m. Default 3.0e4.
    pub c2v_ns_m: f64,
    /// Secondary lateral damping per bogie `c2h`, N·s/m. Default 3.0e4.
    pub c2h_ns_m: f64,
    /// Car-body CG to secondary lateral spring (below), `h1`, m. Default 0.98.
    pub h1_m: f64,
    /// Secondary lateral spring to bogie CG (spring above the CG), `h2`, m. Default 0.36.
    pub h2_m: f64,
    /// Bogie CG to primary lateral spring / axle centre (below), `h3`, m. Default 0.07.
    pub h3_m: f64,
    /// Half lateral spacing of the primary vertical springs `a`, m. Default 0.98.
    pub a_m: f64,
    /// Half lateral spacing of the secondary vertical springs `b`, m. Default 1.12.
    pub b_m: f64,
    /// Lateral distance between the wheel–rail contact points `B`, m. Default 1.435.
    pub contact_distance_m: f64,
}

impl Default for CoachParams {
    fn default() -> Self {
        Self::xia2000()
    }
}

impl CoachParams {
    /// Table 1 of Xia, Xu & Chan (2000), crush mass.
    pub fn xia2000() -> Self {
        CoachParams {
            length_m: 22.5,
            s_m: 7.8,
            d_m: 1.25,
            car_mass_kg: 50_990.0,
            car_roll_inertia_kg_m2: 154_830.0,
            car_pitch_inertia_kg_m2: 1_958_700.0,
            car_yaw_inertia_kg_m2: 1_875_300.0,
            bogie_mass_kg: 4_360.0,
            bogie_roll_inertia_kg_m2: 1_470.0,
            bogie_pitch_inertia_kg_m2: 3_430.0,
            bogie_yaw_inertia_kg_m2: 5_070.0,
            wheelset_mass_kg: 1_770.0,
            wheelset_roll_inertia_kg_m2: 920.0,
            k1v_n_m: 2.976e6,
            k1h_n_m: 2.0e7,
            k2v_n_m: 1.06e6,
            k2h_n_m: 4.6e5,
            c1v_ns_m: 1.5e4,
            c1h_ns_m: 1.5e4,
            c2v_ns_m: 3.0e4,
            c2h_ns_m: 3.0e4,
            h1_m: 0.98,
            h2_m: 0.36,
            h3_m: 0.07,
            a_m: 0.98,
            b_m: 1.12,
            contact_distance_m: 1.435,
        }
    }

    /// All fields by name (for validation and FMI parameters).
    pub fn fields(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("length_m", self.length_m),
            ("s_m", self.s_m),
            ("d_m", self.d_m),
            ("car_mass_kg", self.car_mass_kg),
            ("car_roll_inertia_kg_m2", self.car_roll_inertia_kg_m2),
            ("car_pitch_inertia_kg_m2", self.car_pitch_inertia_kg_m2),
            ("car_yaw_inertia_kg_m2", self.car_yaw_inertia_kg_m2),
            ("bogie_mass_kg", self.bogie_mass_kg),
            ("bogie_roll_inertia_kg_m2", self.bogie_roll_inertia_kg_m2),
            ("bogie_pitch_inertia_kg_m2", self.bogie_pitch_inertia_kg_m2),
            ("bogie_yaw_inertia_kg_m2", self.bogie_yaw_inertia_kg_m2),
            ("wheelset_mass_kg", self.wheelset_mass_kg),
            (
                "wheelset_roll_inertia_kg_m2",
                self.wheelset_roll_inertia_kg_m2,
            ),
            ("k1v_n_m", self.k1v_n_m),
            ("k1h_n_m", self.k1h_n_m),
            ("k2v_n_m", self.k2v_n_m),
            ("k2h_n_m", self.k2h_n_m),
            ("c1v_ns_m", self.c1v_ns_m),
            ("c1h_ns_m", self.c1h_ns_m),
            ("c2v_ns_m", self.c2v_ns_m),
            ("c2h_ns_m", self.c2h_ns_m),
            ("h1_m", self.h1_m),
            ("h2_m", self.h2_m),
            ("h3_m", self.h3_m),
            ("a_m", self.a_m),
            ("b_m", self.b_m),
            ("contact_distance_m", self.contact_distance_m),
        ]
    }

    /// Mutable access to a field by name.
    pub fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "length_m" => &mut self.length_m,
            "s_m" => &mut self.s_m,
            "d_m" => &mut self.d_m,
            "car_mass_kg" => &mut self.car_mass_kg,
            "car_roll_inertia_kg_m2" => &mut self.car_roll_inertia_kg_m2,
            "car_pitch_inertia_kg_m2" => &mut self.car_pitch_inertia_kg_m2,
            "car_yaw_inertia_kg_m2" => &mut self.car_yaw_inertia_kg_m2,
            "bogie_mass_kg" => &mut self.bogie_mass_kg,
            "bogie_roll_inertia_kg_m2" => &mut self.bogie_roll_inertia_kg_m2,
            "bogie_pitch_inertia_kg_m2" => &mut self.bogie_pitch_inertia_kg_m2,
            "bogie_yaw_inertia_kg_m2" => &mut self.bogie_yaw_inertia_kg_m2,
            "wheelset_mass_kg" => &mut self.wheelset_mass_kg,
            "wheelset_roll_inertia_kg_m2" => &mut self.wheelset_roll_inertia_kg_m2,
            "k1v_n_m" => &mut self.k1v_n_m,
            "k1h_n_m" => &mut self.k1h_n_m,
            "k2v_n_m" => &mut self.k2v_n_m,
            "k2h_n_m" => &mut self.k2h_n_m,
            "c1v_ns_m" => &mut self.c1v_ns_m,
            "c1h_ns_m" => &mut self.c1h_ns_m,
            "c2v_ns_m" => &mut self.c2v_ns_m,
            "c2h_ns_m" => &mut self.c2h_ns_m,
            "h1_m" => &mut self.h1_m,
            "h2_m" => &mut self.h2_m,
            "h3_m" => &mut self.h3_m,
            "a_m" => &mut self.a_m,
            "b_m" => &mut self.b_m,
            "contact_distance_m" => &mut self.contact_distance_m,
            _ => return None,
        })
    }

    /// Check every field: finite; masses, inertias, stiffnesses and lengths positive;
    /// dampings and heights non-negative; bogies inside the coach. Returns (field, value,
    /// reason) of the first violation.
    pub fn check(&self) -> Result<(), (String, f64, String)> {
        for (name, value) in self.fields() {
            if !value.is_finite() {
                return Err((name.into(), value, "must be a finite number".into()));
            }
            let may_be_zero =
                name.starts_with('c') && name.ends_with("_ns_m") || name.starts_with('h');
            if may_be_zero && value < 0.0 {
                return Err((name.into(), value, "must not be negative".into()));
            }
            if !may_be_zero && value <= 0.0 {
                return Err((name.into(), value, "must be positive".into()));
            }
        }
        if 2.0 * (self.s_m + self.d_m) > self.length_m {
            return Err((
                "length_m".into(),
                self.length_m,
                format!(
                    "is shorter than the wheelbase 2(s + d) = {} m",
                    2.0 * (self.s_m + self.d_m)
                ),
            ));
        }
        Ok(())
    }

    /// Distance from the coach's front coupler to its first wheelset, m.
    pub fn front_overhang_m(&self) -> f64 {
        0.5 * self.length_m - self.s_m - self.d_m
    }

    /// Assemble the linear vehicle. Wheelset offsets are measured from the first wheelset.
    pub fn build(&self) -> Result<LinearVehicle, String> {
        let p = self;
        let mut b = Builder::new();
        let all = [true; 5];
        let car = b.body(
            "car",
            p.car_mass_kg,
            [
                p.car_roll_inertia_kg_m2,
                p.car_yaw_inertia_kg_m2,
                p.car_pitch_inertia_kg_m2,
            ],
            all,
        );
        let bogie_inertia = [
            p.bogie_roll_inertia_kg_m2,
            p.bogie_yaw_inertia_kg_m2,
            p.bogie_pitch_inertia_kg_m2,
        ];
        let bogies = [
            b.body("bogie1", p.bogie_mass_kg, bogie_inertia, all),
            b.body("bogie2", p.bogie_mass_kg, bogie_inertia, all),
        ];
        for (j, &bogie) in bogies.iter().enumerate() {
            let eta_j = if j == 0 { 1.0 } else { -1.0 };
            let xs = eta_j * p.s_m;
            // Secondary vertical: two springs at y = ±b, half the bogie's stiffness each.
            for side in [-1.0, 1.0] {
                b.element(
                    Point::Body(car, [xs, side * p.b_m, 0.0]),
                    Point::Body(bogie, [0.0, side * p.b_m, 0.0]),
                    Direction::Vertical,
                    0.5 * p.k2v_n_m,
                    0.5 * p.c2v_ns_m,
                );
            }
            // Secondary lateral: car point h1 below the car CG, bogie point h2 above the bogie CG.
            b.element(
                Point::Body(car, [xs, 0.0, p.h1_m]),
                Point::Body(bogie, [0.0, 0.0, -p.h2_m]),
                Direction::Lateral,
                p.k2h_n_m,
                p.c2h_ns_m,
            );
            for l in 0..2 {
                let eta_l = if l == 0 { 1.0 } else { -1.0 };
                let xw = eta_l * p.d_m;
                // Offset behind the first wheelset: bogie 1 front wheelset is at x = s + d.
                let offset = (p.s_m + p.d_m) - (xs + xw);
                let w = b.wheelset(offset, p.wheelset_mass_kg, p.wheelset_roll_inertia_kg_m2);
                for side in [-1.0, 1.0] {
                    b.element(
                        Point::Wheelset(w, [0.0, side * p.a_m, 0.0]),
                        Point::Body(bogie, [xw, side * p.a_m, 0.0]),
                        Direction::Vertical,
                        0.5 * p.k1v_n_m,
                        0.5 * p.c1v_ns_m,
                    );
                }
                b.element(
                    Point::Wheelset(w, [0.0, 0.0, 0.0]),
                    Point::Body(bogie, [xw, 0.0, p.h3_m]),
                    Direction::Lateral,
                    p.k1h_n_m,
                    p.c1h_ns_m,
                );
            }
        }
        let mut v = b.build(
            "coach_27dof",
            // the car body's DOFs come first, in the builder's order Y, θ, ψ, Z, φ
            BodyDofs {
                lateral: Some(0),
                vertical: Some(3),
                roll: Some(1),
                yaw: Some(2),
                pitch: Some(4),
                cg_height_m: p.h1_m + p.h2_m + p.h3_m,
            },
            p.contact_distance_m,
        )?;
        v.inertia = p.inertia_moments();
        Ok(v)
    }

    /// The pitching moments of a longitudinal acceleration `a` (m/s², + speeding up), per
    /// m/s², on the car body's and the bogies' pitch φ (nose up; the DOFs 4, 9 and 14). The
    /// longitudinal forces pass from the car body to the bogies at the secondary suspension
    /// (`h1` below the car body's centre of gravity, `h2` above the bogie's) and from the
    /// bogies to the wheelsets at the axles (`h3` below the bogie's), each body's own
    /// inertia `−m a` at its centre of gravity. The moments about each centre of gravity
    /// (`M = z F_x`, z down) are then
    ///
    /// ```text
    /// car body:  M_c = m_c a h1
    /// bogie:     M_t = (m_c / 2) a h2 + (m_t + m_c / 2) a h3
    /// ```
    ///
    /// (braking, a < 0: the car body and bogies pitch nose down), and the moment of the whole
    /// coach's inertia about the axles, `a (m_c (h1 + h2 + h3) + 2 m_t h3)`, is carried by
    /// the wheel loads. The wheelsets' own inertia acts at the axles and reaches the rails
    /// below them through a wheel radius the model does not have: it is not included.
    pub fn inertia_moments(&self) -> Vec<(usize, f64)> {
        let (mc, mt) = (self.car_mass_kg, self.bogie_mass_kg);
        let bogie = 0.5 * mc * self.h2_m + (mt + 0.5 * mc) * self.h3_m;
        vec![(4, mc * self.h1_m), (9, bogie), (14, bogie)]
    }
}
