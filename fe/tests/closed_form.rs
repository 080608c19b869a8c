//! The elements and solvers against closed-form solutions.

use std::f64::consts::PI;
use tbi_fe::{BarProps, BeamSection, Dof, NodeId, Structure, System};

/// Horizontal chain of `n` bars of total length `l` along x, tension `h`, mass `m` per length.
fn string(n: usize, l: f64, h: f64, m: f64, ea: f64) -> (Structure, Vec<NodeId>) {
    let mut s = Structure::new();
    let nodes: Vec<NodeId> = (0..=n)
        .map(|i| s.add_point([l * i as f64 / n as f64, 0.0, 0.0]))
        .collect();
    for w in nodes.windows(2) {
        s.add_bar(
            w[0],
            w[1],
            BarProps {
                ea,
                mass_per_length: m,
                tension: h,
            },
        )
        .unwrap();
    }
    s.fix(nodes[0], &Dof::TRANSLATIONS).unwrap();
    s.fix(nodes[n], &Dof::TRANSLATIONS).unwrap();
    (s, nodes)
}

/// Taut string: f_n = n/(2L) √(H/m), each twice (y and z). Lumped masses on a chain of N
/// bars give exactly ω_n = (2N/L) √(H/m) sin(nπ/(2N)), which tends to the continuous value
/// with relative error ≈ (nπ/2N)²/6.
#[test]
fn taut_string_frequencies() {
    let (n, l, h, m) = (80, 300.0, 3.6e8, 6_400.0);
    let (s, _) = string(n, l, h, m, 1.5e11);
    let sys = s.assemble().unwrap();
    let pairs = sys.eigen(8).unwrap();
    let c = (h / m).sqrt();
    for k in 1..=4usize {
        let exact_continuous = k as f64 / (2.0 * l) * c;
        let exact_discrete =
            (2.0 * n as f64 / l) * c * (k as f64 * PI / (2.0 * n as f64)).sin() / (2.0 * PI);
        for w2 in [pairs.omega2[2 * k - 2], pairs.omega2[2 * k - 1]] {
            let f = w2.sqrt() / (2.0 * PI);
            assert!(
                (f / exact_discrete - 1.0).abs() < 1e-9,
                "mode {k}: {f} vs discrete {exact_discrete}"
            );
            let a = k as f64 * PI / (2.0 * n as f64);
            assert!(
                (f / exact_continuous - 1.0).abs() < a * a / 6.0 * 1.01,
                "mode {k}: {f} vs continuous {exact_continuous}"
            );
        }
    }
}

/// A taut cable under its own weight w = m g (linearised about the straight state): the
/// deflection is the parabola u(x) = w x (L − x)/(2H), midspan sag w L²/(8H). Nodal loads
/// w·h on a chain of bars reproduce it exactly at the nodes.
#[test]
fn taut_cable_sag_under_own_weight_is_parabolic() {
    let (n, l, h, m, g) = (50, 400.0, 2.0e8, 6_000.0, 9.81);
    let (s, nodes) = string(n, l, h, m, 1.5e11);
    let sys = s.assemble().unwrap();
    let w = m * g;
    let mut f = vec![0.0; sys.dof_count()];
    for &node in &nodes[1..n] {
        f[sys.dof(node, Dof::Uz).unwrap()] = w * l / n as f64;
    }
    let u = sys.factor_stiffness().unwrap().solve(&f);
    for &node in &nodes[1..n] {
        let x = s.position(node)[0];
        let expected = w * x * (l - x) / (2.0 * h);
        let got = u[sys.dof(node, Dof::Uz).unwrap()];
        assert!(
            (got / expected - 1.0).abs() < 1e-9,
            "x = {x}: {got} vs {expected}"
        );
        assert!(u[sys.dof(node, Dof::Uy).unwrap()].abs() < 1e-12);
    }
    let mid = u[sys.dof(nodes[n / 2], Dof::Uz).unwrap()];
    assert!((mid / (w * l * l / (8.0 * h)) - 1.0).abs() < 1e-9);
}

/// Simply supported beam along x with `n` elements; ends restrain y, z and twist, x at one end.
fn ss_beam(n: usize, l: f64, sec: &BeamSection, tension: f64) -> (Structure, Vec<NodeId>) {
    let mut s = Structure::new();
    let nodes: Vec<NodeId> = (0..=n)
        .map(|i| s.add_node([l * i as f64 / n as f64, 0.0, 0.0]))
        .collect();
    for w in nodes.windows(2) {
        s.add_beam(w[0], w[1], sec, [0.0, 1.0, 0.0], tension)
            .unwrap();
    }
    s.fix(nodes[0], &[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx])
        .unwrap();
    s.fix(nodes[n], &[Dof::Uy, Dof::Uz, Dof::Rx]).unwrap();
    (s, nodes)
}

/// Which of (lateral, vertical, torsion, axial) dominates a mode, by nodal amplitude²·mass.
fn dominant(sys: &System, nodes: &[NodeId], sec: &BeamSection, phi: &[f64]) -> usize {
    let mut e = [0.0; 4];
    for &nd in nodes {
        for (k, (d, mass)) in [
            (Dof::Uy, sec.mass_per_length),
            (Dof::Uz, sec.mass_per_length),
            (Dof::Rx, sec.mass_moment_per_length),
            (Dof::Ux, sec.mass_per_length),
        ]
        .iter()
        .enumerate()
        {
            if let Some(i) = sys.dof(nd, *d) {
                e[k] += mass * phi[i] * phi[i];
            }
        }
    }
    (0..4).max_by(|&a, &b| e[a].total_cmp(&e[b])).unwrap()
}

/// Simply supported beam: f_n = (n²π/(2L²)) √(EI/m) for vertical (Iy) and lateral (Iz)
/// bending and f_n = (n/(2L)) √(GJ/I_m) for torsion.
#[test]
fn simply_supported_beam_frequencies() {
    let sec = BeamSection {
        e: 2.0e11,
        g: 8.0e10,
        area: 1.0,
        iy: 2.0,
        iz: 9.0,
        j: 0.5,
        mass_per_length: 10_000.0,
        mass_moment_per_length: 4.0e5,
    };
    let (n, l) = (40, 120.0);
    let (s, nodes) = ss_beam(n, l, &sec, 0.0);
    let sys = s.assemble().unwrap();
    let pairs = sys.eigen(40).unwrap();
    let bend =
        |ei: f64, k: usize| (k * k) as f64 * PI / (2.0 * l * l) * (ei / sec.mass_per_length).sqrt();
    let tors =
        |k: usize| k as f64 / (2.0 * l) * (sec.g * sec.j / sec.mass_moment_per_length).sqrt();
    let mut seen = [0usize; 4];
    let mut checked = 0;
    for (k, &w2) in pairs.omega2.iter().enumerate() {
        let f = w2.sqrt() / (2.0 * PI);
        let phi: Vec<f64> = (0..sys.dof_count())
            .map(|i| pairs.vectors[(i, k)])
            .collect();
        let kind = dominant(&sys, &nodes, &sec, &phi);
        seen[kind] += 1;
        let order = seen[kind];
        let (expected, tol) = match kind {
            0 => (bend(sec.e * sec.iz, order), 1e-5),
            1 => (bend(sec.e * sec.iy, order), 1e-5),
            2 => {
                // linear twist elements with consistent mass: error ≈ (kh)²/24
                let kh = order as f64 * PI / n as f64;
                (tors(order), kh * kh / 24.0 * 1.2)
            }
            _ => continue,
        };
        if order > 3 {
            continue;
        }
        assert!(
            (f / expected - 1.0).abs() < tol,
            "mode {k} (kind {kind}, order {order}): {f} Hz vs {expected} Hz"
        );
        checked += 1;
    }
    assert_eq!(
        checked, 9,
        "found lateral/vertical/torsional orders {seen:?}"
    );
}

/// A simply supported beam under tension P: f_n = (n/(2L)) √(P/m) √(1 + n²π² EI/(P L²)).
/// Checks the beam's geometric stiffness (used for the compressed tower legs).
#[test]
fn tensioned_beam_frequencies() {
    let sec = BeamSection {
        iy: 0.5,
        iz: 0.5,
        j: 5.0,
        mass_per_length: 5_000.0,
        ..BeamSection::default()
    };
    let (l, p) = (200.0, 5.0e7);
    let (s, _) = ss_beam(60, l, &sec, p);
    let sys = s.assemble().unwrap();
    let pairs = sys.eigen(6).unwrap();
    for k in 1..=3usize {
        let kf = k as f64;
        let expected = kf / (2.0 * l)
            * (p / sec.mass_per_length).sqrt()
            * (1.0 + kf * kf * PI * PI * sec.e * sec.iy / (p * l * l)).sqrt();
        for w2 in [pairs.omega2[2 * k - 2], pairs.omega2[2 * k - 1]] {
            let f = w2.sqrt() / (2.0 * PI);
            assert!(
                (f / expected - 1.0).abs() < 2e-4,
                "order {k}: {f} vs {expected}"
            );
        }
    }
}

/// A mass hung on two vertical hangers (length L_h, tension m g/2 each) through rigid arms
/// at y = ±b, with its mass split at y = ±c: lateral pendulum ω² = g/L_h, vertical
/// ω² = 2EA/(L_h m), roll ω² = 2EA b²/(L_h m c²).
#[test]
fn mass_hung_on_two_hangers_through_rigid_arms() {
    let (m, g, lh, b, c, ea) = (2.0e4, 9.81, 30.0, 6.0, 9.0, 4.0e7);
    let mut s = Structure::new();
    let deck = s.add_node([0.0, 0.0, 0.0]);
    s.fix(deck, &[Dof::Ux, Dof::Ry, Dof::Rz]).unwrap();
    for side in [-1.0, 1.0] {
        let top = s.add_point([0.0, side * b, -lh]);
        s.fix(top, &Dof::TRANSLATIONS).unwrap();
        s.add_bar_with_arms(
            top,
            [0.0; 3],
            deck,
            [0.0, side * b, 0.0],
            BarProps {
                ea,
                mass_per_length: 0.0,
                tension: 0.5 * m * g,
            },
        )
        .unwrap();
        s.add_point_mass(deck, 0.5 * m, [0.0, side * c, 0.0])
            .unwrap();
    }
    let sys = s.assemble().unwrap();
    assert_eq!(sys.dof_count(), 3);
    let pairs = sys.eigen(3).unwrap();
    let mut expected = [
        g / lh,
        2.0 * ea / (lh * m),
        2.0 * ea * b * b / (lh * m * c * c),
    ];
    expected.sort_by(f64::total_cmp);
    for (got, want) in pairs.omega2.iter().zip(expected) {
        assert!((got / want - 1.0).abs() < 1e-10, "ω² = {got} vs {want}");
    }
}

/// The same mass hung from anchors a height d **above** its centre (arms (0, ±b, −d), z
/// down): lateral sway and roll couple. With hanger length L, T = m g / 2 per hanger and
/// θ the roll, the anchors move by (v + d θ, w ± b θ); the potential
/// ½ m g ((v + d θ)²/L + d θ²) (string and compound pendulum) + ½ (2 EA/L)(b θ)² + … gives
///
/// ```text
/// K = [ m g/L      m g d/L                   ]   M = [ m  0    ]
///     [ m g d/L    m g d²/L + m g d + 2EA b²/L ]       [ 0  m c² ]
/// ```
///
/// on (v, θ), and ω² = 2EA/(L m) vertically.
#[test]
fn mass_hung_from_anchors_above_its_centre_sways_and_rolls_together() {
    let (m, g, lh, b, c, d, ea) = (2.0e4, 9.81, 30.0, 6.0, 9.0, 4.0, 4.0e5);
    let mut s = Structure::new();
    let deck = s.add_node([0.0, 0.0, 0.0]);
    s.fix(deck, &[Dof::Ux, Dof::Ry, Dof::Rz]).unwrap();
    for side in [-1.0, 1.0] {
        let top = s.add_point([0.0, side * b, -(lh + d)]);
        s.fix(top, &Dof::TRANSLATIONS).unwrap();
        s.add_bar_with_arms(
            top,
            [0.0; 3],
            deck,
            [0.0, side * b, -d],
            BarProps {
                ea,
                mass_per_length: 0.0,
                tension: 0.5 * m * g,
            },
        )
        .unwrap();
        s.add_point_mass(deck, 0.5 * m, [0.0, side * c, 0.0])
            .unwrap();
    }
    let sys = s.assemble().unwrap();
    assert_eq!(sys.dof_count(), 3);
    let pairs = sys.eigen(3).unwrap();
    // Generalised 2×2 eigenvalues of (K, M) in closed form.
    let (kvv, kvt, ktt) = (
        m * g / lh,
        m * g * d / lh,
        m * g * d * d / lh + m * g * d + 2.0 * ea * b * b / lh,
    );
    let (mv, mt) = (m, m * c * c);
    let tr = kvv / mv + ktt / mt;
    let det = (kvv * ktt - kvt * kvt) / (mv * mt);
    let disc = (tr * tr - 4.0 * det).sqrt();
    let mut expected = [0.5 * (tr - disc), 0.5 * (tr + disc), 2.0 * ea / (lh * m)];
    expected.sort_by(f64::total_cmp);
    for (got, want) in pairs.omega2.iter().zip(expected) {
        assert!((got / want - 1.0).abs() < 1e-10, "ω² = {got} vs {want}");
    }
    // The coupling is real: the sway mode differs from the plain pendulum g/L.
    assert!((pairs.omega2[0] / (g / lh) - 1.0).abs() > 1e-2);
}
