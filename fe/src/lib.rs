//! Three-dimensional finite-element model generator for three-span suspension bridges and
//! its modal analysis, with a calibrated Tsing Ma preset (Xia, Xu & Chan 2000).
//!
//! ```no_run
//! use tbi_fe::{tsing_ma, FeModel};
//! let model = FeModel::build(&tsing_ma())?;
//! let modal = model.modes(20)?;             // lowest 20 modes, mass-normalised, labelled
//! let deck = model.deck_modes(20)?;         // lowest 20 modes with deck participation
//! deck.write("modes.csv".as_ref())?;        // mode file for the dynamics crate
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Axes (project-wide): x along the deck from the left abutment (direction of travel), y
//! lateral to the right looking in +x, z vertical **downward**; rotations right-handed
//! about x (torsion, right side down), y and z. SI units.
//!
//! # The model
//!
//! * **Deck**: a spine of 12-DOF Euler–Bernoulli beams along the shear centre (level, at
//!   z = 0), one node per hanger station, plus nodes at the supports and every
//!   ≤ `element_length` where no hanger fixes the mesh. Deck mass and dead load both act at
//!   the shear centre (centre of mass = shear centre).
//! * **Hangers**: one axial bar per cable at each hanger station, from the cable node down to
//!   its anchor on the deck, attached to the deck node by the rigid arm
//!   `(0, ∓cable_spacing/2, −hanger_anchor_elevation)`. With the anchors above the shear
//!   centre the deck hangs like a pendulum: lateral sway and torsion couple, so the eccentric
//!   train load (torque e·P) also moves the deck sideways.
//! * **Main cables**: two chains of tensioned bars (3 DOF nodes) at y = ∓ `cable_spacing`/2 in
//!   the dead-load (funicular) geometry: left anchorage → pier saddle → left tower saddle →
//!   main span → right tower saddle → right anchorage. Saddles on the towers move with the
//!   tower tops; the pier saddle and the anchorages are fixed.
//! * **Towers**: two vertical legs of 3-D beams per tower, fixed at the base, joined by portal
//!   beams (each split at y = 0); the cable saddle is the leg's top node.
//! * **Supports** of the deck: bearings restraining lateral, vertical and torsional motion at
//!   both abutments, at the cable pier, at the extra deck piers and at the towers (there the
//!   deck node shares those three DOFs with the centre node of the deck-level portal beam);
//!   longitudinal restraint at one abutment only.
//! * **Mass**: consistent for beams (deck, towers, portals), lumped (half to each end) for
//!   cables and hangers. Hanger mass at the deck end enters through the rigid arm.
//!
//! # Mathematics
//!
//! **Beam element** (local x′ along the member; DOFs `u, v, w, θx, θy, θz` per node). Axial
//! `EA/L [1 −1; −1 1]`, torsion `GJ/L [1 −1; −1 1]`, bending in x′–y′ (`v′ = θz`) on
//! `(v₁, θz₁, v₂, θz₂)`:
//!
//! ```text
//! K_b = EI_z/L³ [ 12   6L  −12   6L ;  6L  4L²  −6L  2L² ; −12  −6L  12  −6L ;  6L  2L²  −6L  4L² ]
//! M_b = mL/420  [ 156  22L  54  −13L ;  22L 4L²  13L −3L² ;  54  13L  156 −22L ; −13L −3L² −22L 4L² ]
//! G_b = P/(30L) [ 36   3L  −36   3L ;  3L  4L²  −3L  −L² ; −36  −3L  36  −3L ;  3L  −L²  −3L  4L² ]
//! ```
//!
//! and in x′–z′ (`w′ = −θy`) the same blocks with `EI_y`, conjugated by `S = diag(1, −1, 1, −1)`.
//! Consistent axial and twist masses `mL/6 [2 1; 1 2]`, `I_m L/6 [2 1; 1 2]` (I_m: polar mass
//! moment per length). `G_b` is the geometric stiffness of an axial force P (tension > 0)
//! from the Hermite shapes; it is used for the tower legs (compression). Global matrices are
//! `Tᵀ K T` with `T = diag(Λ, Λ, Λ, Λ)`, Λ's rows the local axes.
//!
//! **Tensioned bar** (cable segment, hanger) between end points a, b with unit vector
//! `n = (b − a)/L` and dead-load tension T: on the end translations
//!
//! ```text
//! K = [k −k; −k k],   k = (EA/L) n nᵀ + (T/L) (I − n nᵀ)
//! ```
//!
//! The second term is the geometric (initial-stress) stiffness: a transverse end offset δ
//! rotates the force T by δ/L. It is what makes the cables stiff transversally ("string"
//! stiffness `H w″`) and gives the hangers their pendulum stiffness. Gravity loads keep
//! their direction, so they contribute no load stiffness and `K = K_E + K_G` is the
//! tangent stiffness about the dead-load state.
//!
//! **Rigid arm**: an end point at arm r from a frame node moves by `u + θ × r`, i.e.
//! `[I | −[r]×] (u, θ)`; element matrices are transformed with it. The force F the bar
//! applies at the arm adds the second-order term `K_θθ = (F·r) I − ½ (r Fᵀ + F rᵀ)`
//! (from `u₂ = ½ θ × (θ × r)`). For a hanger arm `r = (0, ±b, −d)` pulled up with tension T
//! (F = (0, 0, −T)) it adds `T d` to the torsional stiffness (the deck hangs below its
//! anchors) and a θy–θz coupling that cancels between the two cables. A closed-form test
//! (a mass hung from anchors above its centre) checks the coupled sway–roll frequencies.
//!
//! **Dead-load state**. The deck weight `w_d = m_d g` goes to the hangers and bearings by
//! tributary length ℓ: each hanger pulls the deck with `T_h = w_d ℓ / 2`; its own weight
//! `w_h L_h` adds at the top, so the bar carries `T_h + ½ w_h L_h`. Cable node i then carries
//! `P_i = T_h + w_h L_h + ½ w_c (ℓ_{i−1} + ℓ_i)` (ℓ: segment lengths along the cable). With one
//! horizontal tension H in all spans (saddles in horizontal equilibrium, towers unbent),
//! each span between fixed points a, b is the funicular polygon of its loads,
//!
//! ```text
//! z_i = z_a + (z_b − z_a)(x_i − x_a)/(x_b − x_a) + M(x_i)/H,
//! ```
//!
//! M the simply supported moment of the nodal loads, and H = M(x_mid)/f fixes the main-span
//! sag f = (f/L)·L. Since P_i depends on the geometry (cable weight along the arc, hanger
//! lengths), this is iterated to convergence (|ΔH| ≤ 10⁻¹³ H). For uniform loads the polygon
//! is the parabola and H = w L²/(8 f). Segment tensions are `T = H ℓ/Δx`. Tower legs carry
//! the saddle reaction, their own weight, the portal beams and the deck bearing reaction as
//! compression in `G_b`. The deck is taken stress-free (no geometric stiffness).
//!
//! **Assembly.** K and M are assembled as triplets and compressed by columns
//! ([`sparse::SparseMatrix`]), each entry summed in the element order of a dense `+=`
//! assembly (bit for bit the same entries), never held dense: the Tsing Ma model's pair
//! would take 135 MB dense.
//!
//! **Eigen-solution** (`K φ = ω² M φ`). Mass-normalised: `φᵢᵀ M φⱼ = δᵢⱼ`,
//! `φᵢᵀ K φⱼ = ωᵢ² δᵢⱼ` (M in kg and kg·m², so deck components are in kg^-1/2 and
//! rad·kg^-1/2·m^-1), each vector's sign fixed by a generic reference vector. Large models (the
//! Tsing Ma model has ≈ 2 200 free DOFs) by a block Krylov subspace of the shift-invert
//! operator `K⁻¹ M` with a sparse Cholesky factor of `K` and Rayleigh–Ritz in the M-inner
//! product (`krylov.rs`: the lowest 60 modes in about 0.3 s); small models by the dense
//! reduction `M = L Lᵀ`, `A = L⁻¹ K L⁻ᵀ`, `A y = λ y`, `φ = L⁻ᵀ y`
//! ([`structure::System::eigen_dense`], the reference of the test that compares the two).
//!
//! **Classification.** Kinetic-energy shares of a mode (total 1): deck lateral
//! `Σ m ℓᵢ φ_h,ᵢ²`, vertical `Σ m ℓᵢ φ_v,ᵢ²`, torsional `Σ I_m ℓᵢ φ_θ,ᵢ²` (ℓᵢ: tributary
//! length of deck node i), cables `Σ m_c |φ|²`. A mode whose deck share is below
//! [`modal::DECK_SHARE_MIN`] (0.2) is `C-k` (cable or tower mode); otherwise its type V/L/T
//! is the largest deck share, and it is symmetric (S) if, over the main span with x′ the
//! mirror point about its centre, `Σ ℓ (φ(x) + φ(x′))² ≥ Σ ℓ (φ(x) − φ(x′))²` for the
//! dominant component, antisymmetric (A) otherwise. Modes are numbered per class in
//! ascending frequency: `V-S-1`, `L-A-1`, `T-S-1`, `C-1`…
//! [`FeModel::deck_modes`] / [`ModalResult::to_deck_mode_set`] return the lowest `n` modes
//! with deck participation (all but the `C-k` modes) as a mode file for the dynamics crate.
//!
//! **Static deck response** ([`FeModel::static_deck_deflection`], [`StaticSolver`]):
//! point loads on the deck become consistent nodal loads (cubic Hermite shapes for the
//! lateral and vertical forces, linear for torques), `K u = f` is solved with the sparse
//! Cholesky factor of K, and the deck displacement at any x is interpolated with the same shapes.
//!
//! # Tsing Ma preset ([`tsing_ma`]) and calibration
//!
//! | item | value | source / reason |
//! |---|---|---|
//! | left anchorage, pier M2, Ma Wan tower | x = 0, 97, 452.5 m | paper (355.5 m side span over the M2 saddles) |
//! | Tsing Yi tower, right anchorage | x = 1829.5, 2129.5 m | 1377 m main span, 300 m side span |
//! | deck ends | x = 0 and 2160 m | overall length 2160 m |
//! | Tsing Yi side deck | on 3 piers, evenly spaced (82.6 m bays) | assumed: deck not hung there, cable free |
//! | Ma Wan side span | deck hung between M2 and the tower | |
//! | tower height | 206 m (base to saddle) | paper |
//! | deck above tower base | 75 m | puts the cable low point 5.8 m above the deck shear centre, 2.0 m above the hanger anchors (the shortest hanger) |
//! | **hanger anchors** | **3.8 m above the shear centre** | the hangers hold the top chords of the 7.643 m deep truss; the shear centre is taken at mid-depth (estimate: the section is not published). It couples lateral sway and torsion: the largest static lateral displacement at mid-main-span under the train goes from 0.1 mm (anchors level with the shear centre) to 1.1 mm |
//! | **main sag ratio** | **1/11** (f = 125.2 m) | the notes' value (≈ 1/11, unconfirmed), confirmed by the calibration: a free fit of deck mass, I_y, I_z, J and f/L to the six frequencies and the 0.49 m deflection gives f/L = 1/10.9. The sag sets the string frequency and the elastic–gravity parameter λ² ∝ (f/L)² EA/H, hence V-S-1/V-A-1 (model 1.22, measured 1.23). With the heavier deck H is larger and λ² smaller, so 1/12 (the value for a 22.5 t/m deck) now fits at best with V-S-1/V-A-1 = 1.16 (V-A-1 +2.8 %, V-S-1 −2.8 %) |
//! | M2 saddle, anchorages | 50 m, 0 m, 0 m above the deck | assumed; the six frequencies move < 0.2 % |
//! | cable E, areas | 1.96e11 Pa; 0.759 m² main, 0.801 m² side | parallel wire; areas from the wire counts |
//! | cable mass | 6 400 / 6 750 kg/m per cable | steel area × 7 850 kg/m³ × 1.074 (wrapping, bands) |
//! | hangers | A = 0.011 m², E = 1.4e11 Pa, 95 kg/m | assumed wire-rope hangers; negligible influence |
//! | **deck mass** | **32.0 t/m** | calibrated on the static deflection under the project's train (see below): H grows with the total dead weight (deck 32.0 + cables 2 × 6.4 t/m in the main span), so the deck mass sets the cable stiffness against live load while the cable-governed frequencies hardly move (H/m fixed). This is the full dead load of the deck, not its structural steel: the "equivalent steel weight 22.7 t/m" of the notes is the 49 000 t of structural steel over 2 160 m, without the surfacing of the eight road lanes on two decks, the two railway tracks, parapets, wind shields and services; the published erection figures (deck sections generally 36 m long of about 1 000 t, ≈ 28 t/m) already exceed it. Check: the largest dead-load cable tension is 4.74e8 N (48 300 t) per cable, below the 53 000 t published as the load in each cable |
//! | **deck I_y (vertical)** | **18.5 m⁴** | calibrated on V-A-1 (0.113 Hz) and V-S-2 (0.184 Hz); the deck bending term E I_y k⁴ competes with the cable term H k², so I_y grows with H |
//! | **deck I_z (lateral)** | **205 m⁴** | calibrated on L-S-1 (0.069 Hz) and L-A-1 (0.164 Hz) |
//! | **deck J** | **34 m⁴** | calibrated on T-S-1 (0.267 Hz) with the anchors at 3.8 m (their pendulum stiffness T d adds to G J); near J ≈ 32 m⁴ T-S-1 and L-S-2 veer, so J stays clear of that |
//! | deck mass moment | 6.4e6 kg·m²/m | radius of gyration 14.1 m for the 41 m wide deck (estimate, kept from the lighter deck) |
//! | deck A, E, G | 1.2 m², 2.0e11, 8.0e10 Pa | not calibrated (axial only) |
//! | tower legs | A = 40 m², I = 200 (long.) / 900 (lat.) m⁴, J = 500 m⁴, 100 t/m, E = 3.4e10 Pa | estimates for the hollow concrete legs |
//! | portal beams | at 0, 40, 80, 115 m above the deck; A = 20 m², I = 60/100 m⁴, J = 80 m⁴, 50 t/m | estimates |
//! | track e, h4 | 2.05 m, 1.25 m | paper Table 1 (used by the consumer) |
//!
//! Result of the preset (checked by the tests against 5 % and 0.45–0.52 m):
//!
//! | mode | measured (Hz) | model (Hz) |
//! |---|---|---|
//! | L-S-1 | 0.069 | 0.0692 (+0.3 %) |
//! | V-A-1 | 0.113 | 0.1153 (+2.0 %) |
//! | V-S-1 | 0.139 | 0.1387 (−0.2 %) |
//! | L-A-1 | 0.164 | 0.1653 (+0.8 %) |
//! | V-S-2 | 0.184 | 0.1843 (+0.2 %) |
//! | T-S-1 | 0.267 | 0.2713 (+1.6 %) |
//!
//! V-A-1 rose from +0.5 % to +2.0 % when the anchors moved up: the short hangers near
//! mid-span tie the deck's longitudinal motion to the cable's in the antisymmetric mode.
//!
//! **Static deflection.** The project's train is 8 coaches of the paper's Table 1 (crush
//! masses: car body 50 990 kg, two bogies of 4 360 kg, four wheelsets of 1 770 kg), coaches
//! 22.5 m apart, axles 0, 2.5, 15.6 and 18.1 m behind each coach's first axle: a static axle
//! load of 16 697.5 kg (163 802.5 N). The paper's text quotes 13 250 kg (crush), which its own
//! Table 1 does not reproduce; the project follows Table 1. With the vertical loads at the
//! track (e = 2.05 m) the largest static deflection of the shear centre over all train
//! positions is 0.478, 0.464, 0.464 and 0.480 m at x = 1012.5, 1138.0, 1174.0 and 1498.5 m
//! (paper, Table 2: 49.4 cm at 20 km/h, a nearly quasi-static case).
//!
//! **Modes below 0.4 Hz.** The 20 lowest modes of the model reach 0.389 Hz, as the paper's
//! "first 20 modes up to 0.38 Hz"; eight of them are cable or tower modes (`C-k`): the two
//! main cables swinging laterally against each other with the deck at rest, the free Tsing Yi
//! side-span cables, and tower modes, with deck components zero or nearly so. The lowest 20
//! modes *with deck participation* ([`FeModel::deck_modes`]) are L-S-1 0.069, V-A-1 0.115,
//! V-S-1 0.139, L-A-1 0.165, V-S-2 0.184, V-A-2 0.243, L-S-2 0.247, L-A-2 0.253, T-S-1 0.271,
//! V-S-3 0.281, L-S-3 0.303, V-S-4 0.335, T-A-1 0.380, V-A-3 0.421, V-S-5 0.526,
//! L-A-3 0.535, T-S-2 0.563, T-S-3 0.579, L-A-4 0.608 and V-A-4 0.632 Hz: 13 of them lie
//! below 0.4 Hz (the lighter 22.5 t/m calibration had 15). The higher deck modes follow
//! from the cable (H, sag) and the deck stiffnesses, and these are fixed by the six
//! frequencies and the deflection: the free five-parameter fit lands on the values above.

pub mod beam;
pub mod bridge;
mod elements;
pub mod error;
pub mod influence;
mod krylov;
pub mod modal;
pub mod params;
pub mod sparse;
pub mod statics;
pub mod structure;

pub use bridge::{CableStation, CableStationKind, DeadLoadState, FeModel};
pub use error::FeError;
pub use modal::{EnergyShares, ModalResult, ModeInfo, ModeKind};
pub use params::{
    tsing_ma, CableParams, HangerParams, LongitudinalRestraint, SuspensionBridgeParams,
};
pub use statics::{DeckDisplacement, DeckLoad, StaticSolver};
pub use structure::{BarProps, BeamSection, Dof, EigenPairs, NodeId, Structure, System};
