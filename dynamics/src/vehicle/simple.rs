//! The two classical vehicle idealisations.
//!
//! * **Moving force**: a constant vertical force per axle; no DOFs, no inertia.
//! * **Sprung mass** (Biggs; Yang & Yau 1997): per axle a mass `m_s` on a spring `k` and a
//!   damper `c` above a wheel of mass `m_w` (default 0) that follows the rail vertically.
//!   DOF: the mass's vertical displacement `z` (+ down, from static equilibrium). The force
//!   on the rail is `F_z = (m_s + m_w) g − m_w ü_z − k (u_z − z) − c (u̇_z − ż)`.

use super::assembly::{Builder, Direction, Point};
use super::{BodyDofs, LinearVehicle, WheelsetCoupling};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// One moving axle load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MovingForceAxle {
    /// Distance behind the train's first axle, m. Default 0.
    #[serde(default)]
    pub offset_m: f64,
    /// Vertical load, N (+ downward).
    pub load_n: f64,
}

/// One sprung-mass axle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SprungMassAxle {
    /// Distance behind the train's first axle, m. Default 0.
    #[serde(default)]
    pub offset_m: f64,
    /// Sprung mass, kg.
    pub sprung_mass_kg: f64,
    /// Suspension stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Suspension damping, N·s/m. Default 0.
    #[serde(default)]
    pub damping_ns_m: f64,
    /// Unsprung (wheel) mass following the rail, kg. Default 0 (massless wheel).
    #[serde(default)]
    pub wheel_mass_kg: f64,
}

/// The vehicle under each axle of an axle-load train (HSLM, an axles file) when the user
/// supplies one: a sprung mass whose total mass carries the axle's load,
/// `m_s + m_w = P / g`, with the suspension tuned to a bounce frequency and a damping ratio:
/// `k = m_s (2π f)²`, `c = 2 ζ m_s (2π f)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxleVehicle {
    /// `"sprung_mass"`, the only model for axle-load trains (their axles are not grouped into
    /// bogies and car bodies).
    pub model: String,
    /// Bounce frequency of the sprung mass on its suspension, sqrt(k / m_s) / 2π, Hz.
    pub frequency_hz: f64,
    /// Damping ratio of the suspension, c / (2 m_s 2π f), –. Default 0.
    #[serde(default)]
    pub damping_ratio: f64,
    /// Unsprung (wheel) mass per axle, kg, less than P / g. Default 0.
    #[serde(default)]
    pub wheel_mass_kg: f64,
}

impl AxleVehicle {
    /// The sprung-mass axle carrying `axle`'s load.
    pub fn sprung(&self, axle: &MovingForceAxle) -> Result<SprungMassAxle, String> {
        let total = axle.load_n / super::GRAVITY;
        let sprung_mass_kg = total - self.wheel_mass_kg;
        if sprung_mass_kg.is_nan() || sprung_mass_kg <= 0.0 {
            return Err(format!(
                "wheel_mass_kg = {} leaves no sprung mass under an axle load of {} N (P / g = {total} kg)",
                self.wheel_mass_kg, axle.load_n
            ));
        }
        let omega = 2.0 * std::f64::consts::PI * self.frequency_hz;
        Ok(SprungMassAxle {
            offset_m: axle.offset_m,
            sprung_mass_kg,
            stiffness_n_m: sprung_mass_kg * omega * omega,
            damping_ns_m: 2.0 * self.damping_ratio * sprung_mass_kg * omega,
            wheel_mass_kg: self.wheel_mass_kg,
        })
    }
}

/// A moving constant force as a vehicle with no DOFs.
pub fn moving_force(load_n: f64) -> LinearVehicle {
    LinearVehicle {
        kind: "moving_force".into(),
        dof_names: vec![],
        m: DMatrix::zeros(0, 0),
        c: DMatrix::zeros(0, 0),
        k: DMatrix::zeros(0, 0),
        wheelsets: vec![WheelsetCoupling {
            offset_m: 0.0,
            k_vw: DMatrix::zeros(0, 3),
            c_vw: DMatrix::zeros(0, 3),
            k_ww: Matrix3::zeros(),
            c_ww: Matrix3::zeros(),
            m_w: Matrix3::zeros(),
            p0: Vector3::new(0.0, 0.0, load_n),
            still_air_load_n: None,
        }],
        body: BodyDofs {
            lateral: None,
            vertical: None,
            roll: None,
            yaw: None,
            pitch: None,
            cg_height_m: 0.0,
        },
        contact_distance_m: 1.5,
        inertia: Vec::new(),
    }
}

/// A single sprung-mass axle as a 1-DOF vehicle.
pub fn sprung_mass(a: &SprungMassAxle) -> Result<LinearVehicle, String> {
    let mut b = Builder::new();
    let mass = b.body(
        "mass",
        a.sprung_mass_kg,
        [0.0; 3],
        [false, false, false, true, false],
    );
    let w = b.wheelset(0.0, 0.0, 0.0);
    b.element(
        Point::Wheelset(w, [0.0; 3]),
        Point::Body(mass, [0.0; 3]),
        Direction::Vertical,
        a.stiffness_n_m,
        a.damping_ns_m,
    );
    let mut v = b.build(
        "sprung_mass",
        BodyDofs {
            lateral: None,
            vertical: Some(0),
            roll: None,
            yaw: None,
            pitch: None,
            cg_height_m: 0.0,
        },
        1.5,
    )?;
    // The wheel follows the rail vertically only.
    let ws = &mut v.wheelsets[0];
    ws.m_w = Matrix3::from_diagonal(&Vector3::new(0.0, 0.0, a.wheel_mass_kg));
    ws.p0.z += a.wheel_mass_kg * super::GRAVITY;
    Ok(v)
}
