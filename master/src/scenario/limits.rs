//! Limits on scenario values (documented in docs/scenario.md, "Limits"). Values outside them are
//! not physically meaningful for a railway bridge or would exhaust the machine.

/// Time step range, s.
pub const DT_S: (f64, f64) = (1e-6, 0.1);
/// Longest free vibration after the train has left, s.
pub const FREE_VIBRATION_S: f64 = 3600.0;
/// Most bridge modes.
pub const MODES: usize = 2000;
/// Most coaches.
pub const VEHICLES: usize = 1000;
/// Most axles of a moving-force or sprung-mass train.
pub const AXLES: usize = 4000;
/// Most probes.
pub const PROBES: usize = 1000;
/// Longest scenario name, characters.
pub const NAME_CHARS: usize = 100;
/// Simply supported section data: (field, lowest, highest), SI units.
pub const SECTION: [(&str, f64, f64); 8] = [
    ("span_m", 0.5, 1e5),
    ("youngs_modulus_pa", 1e6, 1e13),
    ("inertia_vertical_m4", 1e-8, 1e5),
    ("inertia_lateral_m4", 1e-8, 1e5),
    ("shear_modulus_pa", 1e5, 1e13),
    ("torsion_constant_m4", 1e-10, 1e5),
    ("polar_inertia_kg_m", 1e-3, 1e10),
    ("mass_per_length_kg_m", 1.0, 1e7),
];
