//! Small scenarios for the FMU tests. The section constants are public so that the tests
//! can compute their references from them (and not from the exported data alone).

/// Span of the 30 m test bridge, m.
pub const SPAN_M: f64 = 30.0;
/// Young's modulus E, Pa.
pub const E_PA: f64 = 3.45e10;
/// Vertical bending inertia I_v, m⁴.
pub const IV_M4: f64 = 3.0;
/// Lateral bending inertia I_h, m⁴.
pub const IH_M4: f64 = 15.0;
/// Shear modulus G, Pa.
pub const G_PA: f64 = 1.5e10;
/// Torsion constant J, m⁴.
pub const J_M4: f64 = 5.0;
/// Polar mass moment per length I_m, kg·m²/m.
pub const IM_KG_M: f64 = 1.5e5;
/// Mass per length μ, kg/m.
pub const MU_KG_M: f64 = 2.0e4;
/// Track eccentricity e (+y from the shear centre), m.
pub const E_TRACK_M: f64 = 0.8;
/// Wheelset reference height h4 above the shear centre, m.
pub const H4_M: f64 = 1.2;
/// Modes kept by the moving-force scenario.
pub const FORCE_MODES: usize = 20;
/// Damping ratio of the moving-force scenario (large, so a step load settles quickly).
pub const FORCE_DAMPING: f64 = 0.2;
/// Probe positions of the moving-force scenario, m.
pub const FORCE_PROBES_M: [f64; 3] = [7.5, 15.0, 22.5];

fn section() -> String {
    format!(
        "kind = \"simply_supported\"\nspan_m = {SPAN_M:?}\nyoungs_modulus_pa = {E_PA:e}\n\
         inertia_vertical_m4 = {IV_M4:?}\ninertia_lateral_m4 = {IH_M4:?}\n\
         shear_modulus_pa = {G_PA:e}\ntorsion_constant_m4 = {J_M4:?}\n\
         polar_inertia_kg_m = {IM_KG_M:e}\nmass_per_length_kg_m = {MU_KG_M:e}\n\
         track_eccentricity_m = {E_TRACK_M:?}\ntrack_height_m = {H4_M:?}\n"
    )
}

/// Two `coach_27dof` (xia2000) coaches at 200 km/h on the 30 m span with lateral and
/// torsional modes, German low-disturbance irregularity and two probes.
pub fn coach2() -> String {
    format!(
        r#"name = "coach2"
[run]
speed_kmh = 200.0
dt_s = 0.002
free_vibration_s = 0.2
[bridge]
{}modes = 12
damping_ratio = 0.02
[train]
kind = "coach_27dof"
preset = "xia2000"
vehicles = 2
[track]
irregularity = {{ spectrum = "german-low", seed = 7, lambda_min_m = 1.0, lambda_max_m = 80.0 }}
[[probe]]
name = "quarter"
x_m = 7.5
[[probe]]
name = "mid"
x_m = 15.0
"#,
        section()
    )
}

/// [`coach2`] in a turbulent 20 m/s crosswind (a 12 m deck, the default turbulence at 12
/// deck points): exported as three FMUs, the wind's feeding the bridge and the train.
#[allow(dead_code)]
pub fn coach2_windy() -> String {
    coach2()
        + "[wind]\nmean_speed_m_s = 20.0\ndeck_points = 12\n\
           deck = { width_m = 12.0, drag = 1.5, lift = 0.3, moment = 0.1, lift_slope = 3.0, moment_slope = 0.8 }\n\
           turbulence = {}\n"
}

/// Two moving forces on the same span, smooth track, 20 modes with 20 % damping and three
/// probes ([`FORCE_PROBES_M`]).
pub fn moving_force() -> String {
    let [p1, p2, p3] = FORCE_PROBES_M;
    format!(
        r#"name = "force"
[run]
speed_kmh = 100.0
dt_s = 0.002
free_vibration_s = 0.0
[bridge]
{}modes = {FORCE_MODES}
damping_ratio = {FORCE_DAMPING:?}
[train]
kind = "moving_force"
axles = [{{ offset_m = 0.0, load_n = 1.0e5 }}, {{ offset_m = 2.5, load_n = 1.0e5 }}]
[[probe]]
name = "p1"
x_m = {p1:?}
[[probe]]
name = "p2"
x_m = {p2:?}
[[probe]]
name = "p3"
x_m = {p3:?}
"#,
        section()
    )
}

/// One sprung mass (Yang & Yau's vehicle) crossing a 25 m simply supported span, smooth
/// track, five vertical modes, midspan probe; time step `dt_s`.
pub fn sprung_mass(dt_s: f64) -> String {
    format!(
        r#"name = "sprung"
[run]
speed_kmh = 100.0
dt_s = {dt_s:e}
free_vibration_s = 0.1
[bridge]
kind = "simply_supported"
span_m = 25.0
youngs_modulus_pa = 2.87e9
inertia_vertical_m4 = 2.9
mass_per_length_kg_m = 2303.0
modes = 5
damping_ratio = 0.02
[train]
kind = "sprung_mass"
axles = [{{ offset_m = 0.0, sprung_mass_kg = 5750.0, stiffness_n_m = 1.595e6, damping_ns_m = 0.0 }}]
[[probe]]
name = "mid"
x_m = 12.5
"#
    )
}
