//! Element matrices: the 12-DOF Euler–Bernoulli beam and the tensioned bar.
//!
//! Local beam DOF order per node: `u, v, w, θx, θy, θz` (node i first, then node j), with
//! local x′ along the element, y′ and z′ the principal axes, rotations right-handed. In the
//! x′–y′ plane the slope is `v′ = θz`; in the x′–z′ plane it is `w′ = −θy`, so the x′–z′
//! blocks are the x′–y′ blocks conjugated by `S = diag(1, −1, 1, −1)`.

/// 3-vector.
pub(crate) type V3 = [f64; 3];
/// 3×3 matrix, row-major.
pub(crate) type M3 = [[f64; 3]; 3];
/// 12×12 matrix, row-major.
pub(crate) type M12 = [[f64; 12]; 12];

pub(crate) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Skew matrix `[r]×` with `[r]× v = r × v`.
pub(crate) fn skew(r: V3) -> M3 {
    [[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]]
}

/// Rotation matrix whose rows are the local axes x′, y′, z′ in global coordinates.
///
/// x′ points from `a` to `b`; y′ is the part of `reference` normal to x′; z′ = x′ × y′.
/// Returns `None` if the element has zero length or `reference` is parallel to it.
pub(crate) fn local_axes(a: V3, b: V3, reference: V3) -> Option<M3> {
    let d = sub(b, a);
    let l = norm(d);
    if l <= 0.0 || !l.is_finite() {
        return None;
    }
    let ex = scale(d, 1.0 / l);
    let r = sub(reference, scale(ex, dot(reference, ex)));
    let rn = norm(r);
    if rn <= 1e-9 * norm(reference).max(1e-300) {
        return None;
    }
    let ey = scale(r, 1.0 / rn);
    let ez = cross(ex, ey);
    Some([ex, ey, ez])
}

/// 4×4 Hermite blocks in the x′–y′ plane for DOFs `(v_i, θz_i, v_j, θz_j)`.
fn bending_stiffness(ei: f64, l: f64) -> [[f64; 4]; 4] {
    let c = ei / (l * l * l);
    let (l1, l2) = (l, l * l);
    [
        [12.0 * c, 6.0 * l1 * c, -12.0 * c, 6.0 * l1 * c],
        [6.0 * l1 * c, 4.0 * l2 * c, -6.0 * l1 * c, 2.0 * l2 * c],
        [-12.0 * c, -6.0 * l1 * c, 12.0 * c, -6.0 * l1 * c],
        [6.0 * l1 * c, 2.0 * l2 * c, -6.0 * l1 * c, 4.0 * l2 * c],
    ]
}

fn bending_mass(m: f64, l: f64) -> [[f64; 4]; 4] {
    let c = m * l / 420.0;
    let (l1, l2) = (l, l * l);
    [
        [156.0 * c, 22.0 * l1 * c, 54.0 * c, -13.0 * l1 * c],
        [22.0 * l1 * c, 4.0 * l2 * c, 13.0 * l1 * c, -3.0 * l2 * c],
        [54.0 * c, 13.0 * l1 * c, 156.0 * c, -22.0 * l1 * c],
        [-13.0 * l1 * c, -3.0 * l2 * c, -22.0 * l1 * c, 4.0 * l2 * c],
    ]
}

fn bending_geometric(p: f64, l: f64) -> [[f64; 4]; 4] {
    let c = p / (30.0 * l);
    let (l1, l2) = (l, l * l);
    [
        [36.0 * c, 3.0 * l1 * c, -36.0 * c, 3.0 * l1 * c],
        [3.0 * l1 * c, 4.0 * l2 * c, -3.0 * l1 * c, -l2 * c],
        [-36.0 * c, -3.0 * l1 * c, 36.0 * c, -3.0 * l1 * c],
        [3.0 * l1 * c, -l2 * c, -3.0 * l1 * c, 4.0 * l2 * c],
    ]
}

/// Scatter a 4×4 block into `k` at `idx`; `flip` applies `S = diag(1, −1, 1, −1)` on both sides.
fn scatter4(k: &mut M12, block: &[[f64; 4]; 4], idx: [usize; 4], flip: bool) {
    let s = if flip {
        [1.0, -1.0, 1.0, -1.0]
    } else {
        [1.0; 4]
    };
    for a in 0..4 {
        for b in 0..4 {
            k[idx[a]][idx[b]] += s[a] * s[b] * block[a][b];
        }
    }
}

fn scatter2(k: &mut M12, c: [[f64; 2]; 2], idx: [usize; 2]) {
    for a in 0..2 {
        for b in 0..2 {
            k[idx[a]][idx[b]] += c[a][b];
        }
    }
}

const XY: [usize; 4] = [1, 5, 7, 11];
const XZ: [usize; 4] = [2, 4, 8, 10];

/// Elastic stiffness of a 3-D Euler–Bernoulli beam in local axes.
pub(crate) fn beam_stiffness_local(ea: f64, gj: f64, ei_y: f64, ei_z: f64, l: f64) -> M12 {
    let mut k = [[0.0; 12]; 12];
    let a = ea / l;
    scatter2(&mut k, [[a, -a], [-a, a]], [0, 6]);
    let t = gj / l;
    scatter2(&mut k, [[t, -t], [-t, t]], [3, 9]);
    scatter4(&mut k, &bending_stiffness(ei_z, l), XY, false);
    scatter4(&mut k, &bending_stiffness(ei_y, l), XZ, true);
    k
}

/// Consistent mass of a 3-D beam in local axes (translational mass `m` per length, polar mass
/// moment `jm` per length for the twist; rotary inertia of the bending rotations neglected).
pub(crate) fn beam_mass_local(m: f64, jm: f64, l: f64) -> M12 {
    let mut k = [[0.0; 12]; 12];
    let a = m * l / 6.0;
    scatter2(&mut k, [[2.0 * a, a], [a, 2.0 * a]], [0, 6]);
    let t = jm * l / 6.0;
    scatter2(&mut k, [[2.0 * t, t], [t, 2.0 * t]], [3, 9]);
    let mb = bending_mass(m, l);
    scatter4(&mut k, &mb, XY, false);
    scatter4(&mut k, &mb, XZ, true);
    k
}

/// Geometric (initial-stress) stiffness of a beam carrying axial force `p` (tension > 0),
/// consistent with the cubic Hermite deflection shapes.
pub(crate) fn beam_geometric_local(p: f64, l: f64) -> M12 {
    let mut k = [[0.0; 12]; 12];
    let g = bending_geometric(p, l);
    scatter4(&mut k, &g, XY, false);
    scatter4(&mut k, &g, XZ, true);
    k
}

/// `Tᵀ K T` with `T = diag(λ, λ, λ, λ)` (λ rows = local axes): local → global.
pub(crate) fn rotate12(k: &M12, lam: &M3) -> M12 {
    // tmp = K T
    let mut tmp = [[0.0; 12]; 12];
    for r in 0..12 {
        for blk in 0..4 {
            for c in 0..3 {
                let mut s = 0.0;
                for q in 0..3 {
                    s += k[r][3 * blk + q] * lam[q][c];
                }
                tmp[r][3 * blk + c] = s;
            }
        }
    }
    let mut out = [[0.0; 12]; 12];
    for blk in 0..4 {
        for r in 0..3 {
            for c in 0..12 {
                let mut s = 0.0;
                for q in 0..3 {
                    s += lam[q][r] * tmp[3 * blk + q][c];
                }
                out[3 * blk + r][c] = s;
            }
        }
    }
    out
}

/// 3×3 stiffness block of a bar between two points: `EA/L n nᵀ + T/L (I − n nᵀ)`.
///
/// The element matrix on the end-point translations is `[[k, −k], [−k, k]]`.
pub(crate) fn bar_block(ea: f64, tension: f64, a: V3, b: V3) -> M3 {
    let d = sub(b, a);
    let l = norm(d);
    let n = scale(d, 1.0 / l);
    let mut k = [[0.0; 3]; 3];
    for (r, row) in k.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            let nn = n[r] * n[c];
            let id = if r == c { 1.0 } else { 0.0 };
            *v = ea / l * nn + tension / l * (id - nn);
        }
    }
    k
}

/// Second-order work of a constant force `f` acting at the end of a rigid arm `r` on a node
/// that rotates by the small rotation vector θ: `½ θᵀ [(f·r) I − sym(r fᵀ)] θ` is the
/// potential-energy increment, so this returns `(f·r) I − ½ (r fᵀ + f rᵀ)`.
pub(crate) fn arm_force_stiffness(f: V3, r: V3) -> M3 {
    let fr = dot(f, r);
    let mut k = [[0.0; 3]; 3];
    for (a, row) in k.iter_mut().enumerate() {
        for (b, v) in row.iter_mut().enumerate() {
            let id = if a == b { fr } else { 0.0 };
            *v = id - 0.5 * (r[a] * f[b] + f[a] * r[b]);
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_symmetric(k: &M12) -> bool {
        (0..12).all(|a| (0..12).all(|b| (k[a][b] - k[b][a]).abs() <= 1e-9 * k[a][a].abs().max(1.0)))
    }

    /// Rigid-body motions produce no elastic forces.
    #[test]
    fn beam_stiffness_annihilates_rigid_body_modes() {
        let l = 7.0;
        let k = beam_stiffness_local(3.0, 2.0, 5.0, 11.0, l);
        assert!(is_symmetric(&k));
        // translations along x, y, z; rotations about x, y (w = -θy x), z (v = θz x)
        let mut modes: Vec<[f64; 12]> = Vec::new();
        for d in 0..3 {
            let mut m = [0.0; 12];
            m[d] = 1.0;
            m[6 + d] = 1.0;
            modes.push(m);
        }
        let mut rx = [0.0; 12];
        rx[3] = 1.0;
        rx[9] = 1.0;
        modes.push(rx);
        let mut ry = [0.0; 12];
        ry[4] = 1.0;
        ry[10] = 1.0;
        ry[8] = -l;
        modes.push(ry);
        let mut rz = [0.0; 12];
        rz[5] = 1.0;
        rz[11] = 1.0;
        rz[7] = l;
        modes.push(rz);
        for m in modes {
            for row in &k {
                let f: f64 = row.iter().zip(m.iter()).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-9, "rigid mode {m:?} gives force {f}");
            }
        }
    }

    /// The consistent mass reproduces the element's total mass under a rigid translation
    /// and the geometric stiffness gives `P θ² L` work for a rigid rotation (string limit).
    #[test]
    fn mass_and_geometric_stiffness_rigid_checks() {
        let (m, jm, l, p) = (3.0, 0.7, 2.5, 10.0);
        let mm = beam_mass_local(m, jm, l);
        assert!(is_symmetric(&mm));
        for d in 0..3 {
            let mut u = [0.0; 12];
            u[d] = 1.0;
            u[6 + d] = 1.0;
            let e: f64 = (0..12)
                .map(|a| (0..12).map(|b| u[a] * mm[a][b] * u[b]).sum::<f64>())
                .sum();
            assert!((e - m * l).abs() < 1e-12, "direction {d}: {e}");
        }
        let mut tw = [0.0; 12];
        tw[3] = 1.0;
        tw[9] = 1.0;
        let e: f64 = (0..12)
            .map(|a| (0..12).map(|b| tw[a] * mm[a][b] * tw[b]).sum::<f64>())
            .sum();
        assert!((e - jm * l).abs() < 1e-12);
        // rigid rotation about z by θ: v = θ x, slope θ, uᵀ K_G u = P θ² L
        let kg = beam_geometric_local(p, l);
        let th = 0.01;
        let mut u = [0.0; 12];
        u[5] = th;
        u[11] = th;
        u[7] = th * l;
        let e: f64 = (0..12)
            .map(|a| (0..12).map(|b| u[a] * kg[a][b] * u[b]).sum::<f64>())
            .sum();
        assert!((e - p * th * th * l).abs() < 1e-12 * p);
    }

    #[test]
    fn rotation_is_orthogonal_and_preserves_energy() {
        let lam = local_axes([1.0, 2.0, 3.0], [4.0, -1.0, 7.0], [0.0, 0.0, 1.0]).unwrap();
        for a in 0..3 {
            for b in 0..3 {
                let d = dot(lam[a], lam[b]);
                assert!((d - if a == b { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        let k = beam_stiffness_local(3.0, 2.0, 5.0, 11.0, 5.0);
        let kg = rotate12(&k, &lam);
        let tr = |m: &M12| (0..12).map(|i| m[i][i]).sum::<f64>();
        assert!((tr(&k) - tr(&kg)).abs() < 1e-9 * tr(&k));
        assert!(is_symmetric(&kg));
    }
}
