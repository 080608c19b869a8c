//! The innermost loops of the FMU steps and of the monolithic step, compiled twice — for the
//! baseline x86-64 (two-wide SSE2 vectors) and for AVX2 (four-wide) — and chosen once per call
//! by the processor's features.
//!
//! Each kernel is a set of independent element-wise updates such as `yᵢ ← yᵢ + a·xᵢ`, each
//! element's operations in a fixed order (no sums across elements, and Rust never contracts
//! `a·x + y` into a fused multiply-add), so the wider
//! vectors change only how many elements one instruction updates, not a single rounding:
//! both builds give bitwise the same results (tested below). The AVX2 form of
//! [`axpy_columns_strided`] (and of [`mul_columns`], its sums started from zero) is written
//! out with intrinsics: it keeps up to sixteen elements in four registers through all the
//! columns instead of passing over `y` once per column, the same product and sum per
//! element and column, in column order.

/// `y ← y + a x` (over the shorter of the two).
#[inline]
pub fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { axpy_avx2(y, a, x) };
    }
    axpy_body(y, a, x)
}

/// `y ← y + Σⱼ aⱼ xⱼ`, the columns `xⱼ` of `y.len()` values stored one after the other in
/// `columns`, added in order `j = 0, 1, …` (each `yᵢ` rounds exactly as in one [`axpy`] per
/// column).
#[inline]
pub fn axpy_columns(y: &mut [f64], a: &[f64], columns: &[f64]) {
    axpy_columns_strided(y, a, columns, y.len())
}

/// `y ← Σⱼ aⱼ xⱼ`: [`axpy_columns`] from `y = 0`, bit for bit as `y.fill(0.0)` before it, the
/// sums starting from zero in registers instead of from a cleared `y` in memory.
#[inline]
pub fn mul_columns(y: &mut [f64], a: &[f64], columns: &[f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { axpy_columns_avx2(y, a, columns, y.len(), true) };
    }
    y.fill(0.0);
    axpy_columns_body(y, a, columns, y.len())
}

/// Two [`mul_columns`] at once, `y₁ ← Σⱼ a₁ⱼ x₁ⱼ` and `y₂ ← Σⱼ a₂ⱼ x₂ⱼ`, bit for bit as the
/// two calls: with AVX2, where both have the same number of rows, 1 to 16, and the same
/// number of whole columns, their sums go through the columns side by side (each a chain of
/// dependent additions that the other's fills), otherwise one after the other.
#[inline]
pub fn mul_columns_pair(
    y1: &mut [f64],
    a1: &[f64],
    columns1: &[f64],
    y2: &mut [f64],
    a2: &[f64],
    columns2: &[f64],
) {
    let n = y1.len();
    #[cfg(target_arch = "x86_64")]
    if n == y2.len()
        && (1..=16).contains(&n)
        && a1.len() == a2.len()
        && columns1.len() >= n * a1.len()
        && columns2.len() >= n * a2.len()
        && std::arch::is_x86_feature_detected!("avx2")
    {
        // SAFETY: the processor has AVX2 (checked just above); both columns slices hold
        // a.len() whole columns of the n rows of y1 and y2 (checked above)
        unsafe {
            let (y1, y2) = (y1.as_mut_ptr(), y2.as_mut_ptr());
            let (c1, c2, r) = (columns1.as_ptr(), columns2.as_ptr(), n % 4);
            match (n / 4, r) {
                (0, _) => columns_pair::<0, true>(y1, y2, a1, a2, c1, c2, r),
                (1, 0) => columns_pair::<1, false>(y1, y2, a1, a2, c1, c2, r),
                (1, _) => columns_pair::<1, true>(y1, y2, a1, a2, c1, c2, r),
                (2, 0) => columns_pair::<2, false>(y1, y2, a1, a2, c1, c2, r),
                (2, _) => columns_pair::<2, true>(y1, y2, a1, a2, c1, c2, r),
                (3, 0) => columns_pair::<3, false>(y1, y2, a1, a2, c1, c2, r),
                (3, _) => columns_pair::<3, true>(y1, y2, a1, a2, c1, c2, r),
                _ => columns_pair::<4, false>(y1, y2, a1, a2, c1, c2, r),
            }
        }
        return;
    }
    mul_columns(y1, a1, columns1);
    mul_columns(y2, a2, columns2);
}

/// The first `r` (0–4) of four lanes, as the mask of `_mm256_maskload_pd`.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub unsafe fn first_lanes(r: usize) -> std::arch::x86_64::__m256i {
    let on = |j: usize| if j < r { -1 } else { 0 };
    std::arch::x86_64::_mm256_setr_epi64x(on(0), on(1), on(2), on(3))
}

/// [`mul_columns_pair`]'s sums: `n = 4 G (+ r)` rows of each product from zero through its
/// columns (`n` values each, one after the other), the two products' groups side by side;
/// with `TAIL` the last `r` (1–3) rows of each as the masked lanes of one more vector.
///
/// # Safety
/// AVX2; `n` values from `y1`, `y2` writable and not aliased, `n · a.len()` values from
/// `c1`, `c2` readable, `a1.len() == a2.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn columns_pair<const G: usize, const TAIL: bool>(
    y1: *mut f64,
    y2: *mut f64,
    a1: &[f64],
    a2: &[f64],
    c1: *const f64,
    c2: *const f64,
    r: usize,
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_setzero_pd, _mm256_storeu_pd,
    };
    let n = 4 * G + if TAIL { r } else { 0 };
    let mask = first_lanes(r);
    // SAFETY: the rows the caller vouches for; the tail's lanes past n are masked off
    unsafe {
        let (mut acc1, mut acc2) = ([_mm256_setzero_pd(); G], [_mm256_setzero_pd(); G]);
        let (mut last1, mut last2) = (_mm256_setzero_pd(), _mm256_setzero_pd());
        for (j, (&b1, &b2)) in a1.iter().zip(a2).enumerate() {
            let (s1, s2) = (_mm256_set1_pd(b1), _mm256_set1_pd(b2));
            let (x1, x2) = (c1.add(j * n), c2.add(j * n));
            for g in 0..G {
                let v1 = _mm256_loadu_pd(x1.add(4 * g));
                let v2 = _mm256_loadu_pd(x2.add(4 * g));
                acc1[g] = _mm256_add_pd(acc1[g], _mm256_mul_pd(s1, v1));
                acc2[g] = _mm256_add_pd(acc2[g], _mm256_mul_pd(s2, v2));
            }
            if TAIL {
                let v1 = _mm256_maskload_pd(x1.add(4 * G), mask);
                let v2 = _mm256_maskload_pd(x2.add(4 * G), mask);
                last1 = _mm256_add_pd(last1, _mm256_mul_pd(s1, v1));
                last2 = _mm256_add_pd(last2, _mm256_mul_pd(s2, v2));
            }
        }
        for g in 0..G {
            _mm256_storeu_pd(y1.add(4 * g), acc1[g]);
            _mm256_storeu_pd(y2.add(4 * g), acc2[g]);
        }
        if TAIL {
            let mut t = [[0.0; 4]; 2];
            _mm256_storeu_pd(t[0].as_mut_ptr(), last1);
            _mm256_storeu_pd(t[1].as_mut_ptr(), last2);
            for k in 0..r {
                *y1.add(4 * G + k) = t[0][k];
                *y2.add(4 * G + k) = t[1][k];
            }
        }
    }
}

/// [`axpy_columns`] with column `j` the `y.len()` values from `j · stride` of `columns`
/// (`stride ≥ y.len()`): `y ← y + Σⱼ aⱼ xⱼ`, added in order `j = 0, 1, …` over the columns
/// that `columns` holds whole.
#[inline]
pub fn axpy_columns_strided(y: &mut [f64], a: &[f64], columns: &[f64], stride: usize) {
    assert!(
        stride >= y.len(),
        "columns overlap: stride {stride} < {}",
        y.len()
    );
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { axpy_columns_avx2(y, a, columns, stride, false) };
    }
    axpy_columns_body(y, a, columns, stride)
}

/// The coefficients of the columns that `columns` holds whole (`stride ≥ n > 0`).
#[inline(always)]
fn whole_columns(a: &[f64], n: usize, len: usize, stride: usize) -> &[f64] {
    let m = if len < n { 0 } else { (len - n) / stride + 1 };
    &a[..a.len().min(m)]
}

/// `acc[k][d] ← acc[k][d] + Σₙ psi[n][k] · modal[n][d]`, summed over `n` in order: the rail
/// motion (component `k`, derivative `d`) from the rail shapes and `(q, q̇, q̈, 0)` of each
/// mode.
#[inline]
pub fn rail_accumulate(acc: &mut [[f64; 4]; 3], psi: &[[f64; 3]], modal: &[[f64; 4]]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { rail_accumulate_avx2(acc, psi, modal) };
    }
    rail_accumulate_body(acc, psi, modal)
}

/// `y[n] ← y[n] + ((psi[n][0] f[0] + psi[n][1] f[1]) + psi[n][2] f[2])` (over the shorter of
/// the two): the generalised forces `Σ Ψᵀ f` of one wheelset's force `f`.
#[inline]
pub fn project_force(y: &mut [f64], psi: &[[f64; 3]], f: [f64; 3]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { project_force_avx2(y, psi, f) };
    }
    project_force_body(y, psi, f)
}

/// [`project_force`] of shapes stored as three rows, `rows = [r₀ | r₁ | r₂]` of `y.len()`
/// values each: `y[n] ← y[n] + ((r₀[n] f[0] + r₁[n] f[1]) + r₂[n] f[2])`, the same roundings.
#[inline]
pub fn project_rows(y: &mut [f64], rows: &[f64], f: [f64; 3]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { project_rows_avx2(y, rows, f) };
    }
    project_rows_body(y, rows, f)
}

/// Runs `$kernel::<G, TAIL>(y, x, args…, r)` over `$n` rows from the pointers `$y`, `$x`:
/// sixteen rows at a time (`G = 4`), then the rest as up to three groups of four and, with
/// `TAIL`, a masked tail of `r` (1–3) rows. The kernels keep each group's sums in a register
/// through all their terms ([`columns_groups`], [`rows_groups`]).
#[cfg(target_arch = "x86_64")]
macro_rules! in_row_groups {
    ($n:expr, $kernel:ident, $y:expr, $x:expr, ($($arg:expr),*)) => {{
        let (n, y, x) = ($n, $y, $x);
        let mut i = 0;
        while n - i >= 16 {
            $kernel::<4, false>(y.add(i), x.add(i), $($arg,)* 0);
            i += 16;
        }
        let (y, x) = (y.add(i), x.add(i));
        match ((n - i) / 4, (n - i) % 4) {
            (0, 0) => {}
            (0, r) => $kernel::<0, true>(y, x, $($arg,)* r),
            (1, 0) => $kernel::<1, false>(y, x, $($arg,)* 0),
            (1, r) => $kernel::<1, true>(y, x, $($arg,)* r),
            (2, 0) => $kernel::<2, false>(y, x, $($arg,)* 0),
            (2, r) => $kernel::<2, true>(y, x, $($arg,)* r),
            (3, 0) => $kernel::<3, false>(y, x, $($arg,)* 0),
            (_, r) => $kernel::<3, true>(y, x, $($arg,)* r),
        }
    }};
}

/// The `G` groups of four values from `yp` and, with `TAIL`, the `r` (1–3) after them in the
/// first lanes of one more vector (the others zero), or zeros without `from_y`: the tail
/// through memory as scalars, which a store just before forwards element by element (a
/// loop over them becomes a call of memcpy).
///
/// # Safety
/// AVX2; with `from_y`, `4 G` (`+ r` with `TAIL`) values from `yp` readable.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn load_groups<const G: usize, const TAIL: bool>(
    yp: *const f64,
    r: usize,
    from_y: bool,
) -> ([std::arch::x86_64::__m256d; G], std::arch::x86_64::__m256d) {
    use std::arch::x86_64::{_mm256_loadu_pd, _mm256_setzero_pd};
    let mut acc = [_mm256_setzero_pd(); G];
    let mut tail = [0.0; 4];
    if from_y {
        // SAFETY: the values the caller vouches for
        unsafe {
            for (g, acc) in acc.iter_mut().enumerate() {
                *acc = _mm256_loadu_pd(yp.add(4 * g));
            }
            if TAIL {
                let yt = yp.add(4 * G);
                tail[0] = *yt;
                if r > 1 {
                    tail[1] = *yt.add(1);
                }
                if r > 2 {
                    tail[2] = *yt.add(2);
                }
            }
        }
    }
    // SAFETY: a local array of four
    (acc, unsafe { _mm256_loadu_pd(tail.as_ptr()) })
}

/// The `G` groups `acc` to `yp`, `yp + 4`, …, and with `TAIL` the first `r` (1–3) lanes of
/// `last` after them, as scalars.
///
/// # Safety
/// AVX2; `4 G` (`+ r` with `TAIL`) values from `yp` writable.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn store_groups<const G: usize, const TAIL: bool>(
    yp: *mut f64,
    acc: &[std::arch::x86_64::__m256d; G],
    last: std::arch::x86_64::__m256d,
    r: usize,
) {
    use std::arch::x86_64::_mm256_storeu_pd;
    // SAFETY: the values the caller vouches for
    unsafe {
        for (g, acc) in acc.iter().enumerate() {
            _mm256_storeu_pd(yp.add(4 * g), *acc);
        }
        if TAIL {
            let mut tail = [0.0; 4];
            _mm256_storeu_pd(tail.as_mut_ptr(), last);
            let yt = yp.add(4 * G);
            *yt = tail[0];
            if r > 1 {
                *yt.add(1) = tail[1];
            }
            if r > 2 {
                *yt.add(2) = tail[2];
            }
        }
    }
}

/// [`project_rows`] of many points, in order: `y[n] ← y[n] + ((r₀[n] f₀ + r₁[n] f₁) + r₂[n] f₂)`
/// for each point's three rows (`rows`: the points' `3 y.len()` values one after the other)
/// and its `f` (`fs`, one per point), bit for bit as one [`project_rows`] per point. With
/// AVX2 each group of four `yᵢ` stays in a register through all the points (up to four
/// groups at once) instead of being loaded and stored at every point.
#[inline]
pub fn project_rows_many(y: &mut [f64], rows: &[f64], fs: &[[f64; 3]]) {
    let n = y.len();
    assert!(
        rows.len() >= 3 * n * fs.len(),
        "{} points of 3 × {n} values",
        fs.len()
    );
    if n == 0 {
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY (each call): the processor has AVX2 (checked above); rows i..i + 4G (+ the
        // masked tail) ≤ n of y and of each point's three rows (3 n values a point, the
        // points inside `rows`, checked above)
        unsafe { in_row_groups!(n, rows_groups, y.as_mut_ptr(), rows.as_ptr(), (n, fs)) };
        return;
    }
    for (point, &f) in rows.chunks_exact(3 * n).zip(fs) {
        project_rows_body(y, point, f);
    }
}

/// [`project_rows_many`]'s sums: `G` groups of four `yᵢ` from `yp` (and with `TAIL` the `r`
/// (1–3) after them as masked lanes), each through all the points in order; point `j`'s
/// row `c` of these values from `rp + (3 j + c) n`.
///
/// # Safety
/// AVX2; values `0..4G` (`+ r` with `TAIL`) from `yp` writable and not aliased, and from
/// `rp + (3 j + c) n` readable for every point `j < fs.len()` and `c < 3`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn rows_groups<const G: usize, const TAIL: bool>(
    yp: *mut f64,
    rp: *const f64,
    n: usize,
    fs: &[[f64; 3]],
    r: usize,
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd,
    };
    let mask = first_lanes(r);
    // SAFETY: the values the caller vouches for
    unsafe {
        let (mut acc, mut last) = load_groups::<G, TAIL>(yp, r, true);
        for (j, f) in fs.iter().enumerate() {
            let (f0, f1, f2) = (
                _mm256_set1_pd(f[0]),
                _mm256_set1_pd(f[1]),
                _mm256_set1_pd(f[2]),
            );
            let (r0, r1, r2) = (
                rp.add(3 * j * n),
                rp.add((3 * j + 1) * n),
                rp.add((3 * j + 2) * n),
            );
            let term = |a: std::arch::x86_64::__m256d,
                        b: std::arch::x86_64::__m256d,
                        c: std::arch::x86_64::__m256d| {
                _mm256_add_pd(
                    _mm256_add_pd(_mm256_mul_pd(a, f0), _mm256_mul_pd(b, f1)),
                    _mm256_mul_pd(c, f2),
                )
            };
            for (g, acc) in acc.iter_mut().enumerate() {
                let o = 4 * g;
                let t = term(
                    _mm256_loadu_pd(r0.add(o)),
                    _mm256_loadu_pd(r1.add(o)),
                    _mm256_loadu_pd(r2.add(o)),
                );
                *acc = _mm256_add_pd(*acc, t);
            }
            if TAIL {
                let o = 4 * G;
                let t = term(
                    _mm256_maskload_pd(r0.add(o), mask),
                    _mm256_maskload_pd(r1.add(o), mask),
                    _mm256_maskload_pd(r2.add(o), mask),
                );
                last = _mm256_add_pd(last, t);
            }
        }
        store_groups::<G, TAIL>(yp, &acc, last, r);
    }
}

#[inline(always)]
fn project_rows_body(y: &mut [f64], rows: &[f64], f: [f64; 3]) {
    let n = y.len();
    let (r0, r12) = rows[..3 * n].split_at(n);
    let (r1, r2) = r12.split_at(n);
    for (((o, a), b), c) in y.iter_mut().zip(r0).zip(r1).zip(r2) {
        *o += a * f[0] + b * f[1] + c * f[2];
    }
}

#[inline(always)]
fn project_force_body(y: &mut [f64], psi: &[[f64; 3]], f: [f64; 3]) {
    for (o, p) in y.iter_mut().zip(psi) {
        *o += p[0] * f[0] + p[1] * f[1] + p[2] * f[2];
    }
}

/// [`rail_accumulate`] for two wheelsets at once, `acc[i]` with `psi[i]` (the same sums in
/// the same order for each; the two chains of additions run side by side instead of one
/// after the other).
#[inline]
pub fn rail_accumulate_pair(
    acc: &mut [[[f64; 4]; 3]; 2],
    psi: [&[[f64; 3]]; 2],
    modal: &[[f64; 4]],
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { rail_accumulate_pair_avx2(acc, psi, modal) };
    }
    rail_accumulate_pair_body(acc, psi, modal)
}

#[inline(always)]
fn rail_accumulate_pair_body(
    acc: &mut [[[f64; 4]; 3]; 2],
    psi: [&[[f64; 3]]; 2],
    modal: &[[f64; 4]],
) {
    let [a0, a1] = acc;
    for ((p0, p1), m) in psi[0].iter().zip(psi[1]).zip(modal) {
        for k in 0..3 {
            for d in 0..4 {
                a0[k][d] += p0[k] * m[d];
                a1[k][d] += p1[k] * m[d];
            }
        }
    }
}

#[inline(always)]
fn axpy_body(y: &mut [f64], a: f64, x: &[f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

#[inline(always)]
fn axpy_columns_body(y: &mut [f64], a: &[f64], columns: &[f64], stride: usize) {
    let n = y.len();
    if n == 0 {
        return;
    }
    for (j, &aj) in whole_columns(a, n, columns.len(), stride)
        .iter()
        .enumerate()
    {
        axpy_body(y, aj, &columns[j * stride..j * stride + n]);
    }
}

#[inline(always)]
fn rail_accumulate_body(acc: &mut [[f64; 4]; 3], psi: &[[f64; 3]], modal: &[[f64; 4]]) {
    for (p, m) in psi.iter().zip(modal) {
        for (a, pk) in acc.iter_mut().zip(p) {
            for (ad, md) in a.iter_mut().zip(m) {
                *ad += pk * md;
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn axpy_avx2(y: &mut [f64], a: f64, x: &[f64]) {
    axpy_body(y, a, x)
}

/// [`axpy_columns_body`] sixteen rows at a time: each group of four `yᵢ` is loaded once,
/// takes `+ aⱼ xⱼᵢ` (a product, then a sum: the same two roundings) for `j = 0, 1, …` in a
/// register and is stored once, instead of one pass over `y` per column. Up to four groups go
/// through the columns together, so that their sums, each a chain of dependent additions,
/// overlap; the last `n mod 4` rows are one more group, its columns' values read as masked
/// lanes and its `yᵢ` as scalars. Every `yᵢ` rounds exactly as in the column-by-column loop.
/// With `zero` the sums start from zero instead of from `y` (which is not read).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn axpy_columns_avx2(y: &mut [f64], a: &[f64], columns: &[f64], stride: usize, zero: bool) {
    let n = y.len();
    if n == 0 {
        return;
    }
    // the columns present (no division in the usual case, all of them)
    let a = if a.is_empty() || (a.len() - 1) * stride + n <= columns.len() {
        a
    } else {
        whole_columns(a, n, columns.len(), stride)
    };
    // SAFETY (each call): rows i..i + 4G (+ the masked tail) ≤ n of y and of each column j
    // (values j·stride .. j·stride + n, inside `columns` for the columns kept above).
    unsafe {
        in_row_groups!(
            n,
            columns_groups,
            y.as_mut_ptr(),
            columns.as_ptr(),
            (a, stride, zero)
        )
    };
}

/// `G` groups of four rows from `yp` (column j's from `xp + j·stride`), and with `TAIL` the
/// `r` (1–3) rows after them as the masked lanes of one more vector (the lanes masked off
/// are neither read nor written), each through all the columns in order, from zero instead
/// of from the rows of `y` with `zero`.
///
/// # Safety
/// Rows `0..4G` (and `4G..4G + r` with `TAIL`) from `yp` and from `xp + j·stride` for every
/// `j < a.len()` must be valid, those from `yp` writable and not aliased.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn columns_groups<const G: usize, const TAIL: bool>(
    yp: *mut f64,
    xp: *const f64,
    a: &[f64],
    stride: usize,
    zero: bool,
    r: usize,
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd,
    };
    let mask = first_lanes(r);
    // SAFETY: the rows the caller vouches for.
    unsafe {
        let (mut acc, mut last) = load_groups::<G, TAIL>(yp, r, !zero);
        for (j, &aj) in a.iter().enumerate() {
            let s = _mm256_set1_pd(aj);
            let col = xp.add(j * stride);
            for (g, acc) in acc.iter_mut().enumerate() {
                let xv = _mm256_loadu_pd(col.add(4 * g));
                *acc = _mm256_add_pd(*acc, _mm256_mul_pd(s, xv));
            }
            if TAIL {
                let xv = _mm256_maskload_pd(col.add(4 * G), mask);
                last = _mm256_add_pd(last, _mm256_mul_pd(s, xv));
            }
        }
        store_groups::<G, TAIL>(yp, &acc, last, r);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn project_rows_avx2(y: &mut [f64], rows: &[f64], f: [f64; 3]) {
    project_rows_body(y, rows, f)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn project_force_avx2(y: &mut [f64], psi: &[[f64; 3]], f: [f64; 3]) {
    project_force_body(y, psi, f)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn rail_accumulate_pair_avx2(
    acc: &mut [[[f64; 4]; 3]; 2],
    psi: [&[[f64; 3]]; 2],
    modal: &[[f64; 4]],
) {
    rail_accumulate_pair_body(acc, psi, modal)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn rail_accumulate_avx2(acc: &mut [[f64; 4]; 3], psi: &[[f64; 3]], modal: &[[f64; 4]]) {
    rail_accumulate_body(acc, psi, modal)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values whose products and sums round (not small integers).
    fn values(n: usize, seed: f64) -> Vec<f64> {
        (0..n)
            .map(|i| ((i as f64 + seed) * 0.618_033_988_749_895).sin() * 1e3 / (1.0 + i as f64))
            .collect()
    }

    #[test]
    fn both_builds_give_bitwise_the_same_results() {
        for n in [
            0, 1, 2, 3, 4, 5, 8, 12, 14, 15, 16, 17, 20, 27, 31, 33, 60, 61,
        ] {
            let x = values(n, 0.3);
            let (mut a, mut b) = (values(n, 1.7), values(n, 1.7));
            axpy_body(&mut a, 0.377, &x);
            axpy(&mut b, 0.377, &x);
            assert!(
                a.iter().zip(&b).all(|(a, b)| a.to_bits() == b.to_bits()),
                "axpy, n = {n}"
            );
            // m columns at once against one axpy per column
            for m in [1, 3, 6, 24] {
                let cols: Vec<f64> = (0..m).flat_map(|j| values(n, 2.0 + j as f64)).collect();
                let coeffs: Vec<f64> = (0..m).map(|j| 0.377 - 1.25 * j as f64).collect();
                let (mut c, mut d) = (values(n, 1.7), values(n, 1.7));
                if n > 0 {
                    for (&aj, col) in coeffs.iter().zip(cols.chunks_exact(n)) {
                        axpy(&mut c, aj, col);
                    }
                }
                axpy_columns(&mut d, &coeffs, &cols);
                assert!(
                    c.iter().zip(&d).all(|(c, d)| c.to_bits() == d.to_bits()),
                    "axpy_columns, n = {n}, m = {m}"
                );
                // from zero: as a cleared y, whatever y held (not read)
                let (mut z, mut w) = (vec![0.0; n], vec![f64::NAN; n]);
                axpy_columns(&mut z, &coeffs, &cols);
                mul_columns(&mut w, &coeffs, &cols);
                assert!(
                    z.iter().zip(&w).all(|(z, w)| z.to_bits() == w.to_bits()),
                    "mul_columns, n = {n}, m = {m}"
                );
                // two at once, the second with its columns reversed: as one call each
                let rev: Vec<f64> = cols.iter().rev().copied().collect();
                let coeffs2: Vec<f64> = coeffs.iter().map(|c| 1.5 - c).collect();
                let (mut p1, mut p2) = (vec![f64::NAN; n], vec![f64::NAN; n]);
                mul_columns_pair(&mut p1, &coeffs, &cols, &mut p2, &coeffs2, &rev);
                let mut q2 = vec![0.0; n];
                mul_columns(&mut q2, &coeffs2, &rev);
                assert!(
                    (w.iter().zip(&p1).chain(q2.iter().zip(&p2)))
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "mul_columns_pair, n = {n}, m = {m}"
                );
                // the first n - 2 values of each column, columns n apart
                let k = n.saturating_sub(2);
                let (mut e, mut f) = (values(k, 0.4), values(k, 0.4));
                if n > 0 {
                    for (&aj, col) in coeffs.iter().zip(cols.chunks_exact(n)) {
                        axpy(&mut e, aj, &col[..k]);
                    }
                }
                axpy_columns_strided(&mut f, &coeffs, &cols, n.max(1));
                assert!(
                    e.iter().zip(&f).all(|(e, f)| e.to_bits() == f.to_bits()),
                    "axpy_columns_strided, n = {n}, m = {m}"
                );
            }
            let psi: Vec<[f64; 3]> = (0..n)
                .map(|i| [x[i], 0.5 * x[i] - 1.0, (i as f64).sqrt()])
                .collect();
            let modal: Vec<[f64; 4]> = (0..n).map(|i| [x[i], -x[i], 2.5, 0.0]).collect();
            let f = [2.3e5, -7.7e3, 1.9e4];
            let (mut e, mut g) = (values(n, 0.9), values(n, 0.9));
            project_force_body(&mut e, &psi, f);
            project_force(&mut g, &psi, f);
            assert!(
                e.iter().zip(&g).all(|(e, g)| e.to_bits() == g.to_bits()),
                "project_force, n = {n}"
            );
            // the same shapes as rows: the same values bit for bit, either build
            let rows: Vec<f64> = (0..3).flat_map(|k| psi.iter().map(move |p| p[k])).collect();
            let (mut h, mut i) = (values(n, 0.9), values(n, 0.9));
            project_rows(&mut h, &rows, f);
            project_rows_body(&mut i, &rows, f);
            assert!(
                e.iter()
                    .zip(&h)
                    .chain(e.iter().zip(&i))
                    .all(|(e, h)| e.to_bits() == h.to_bits()),
                "project_rows, n = {n}"
            );
            // many points at once: as one project_rows per point, in order
            let points = 7;
            let many: Vec<f64> = (0..points)
                .flat_map(|j| values(3 * n, 3.1 + j as f64))
                .collect();
            let fs: Vec<[f64; 3]> = (0..points)
                .map(|j| [1.5e4 - 3e3 * j as f64, -2.2e3 * j as f64, 7.7e2 + j as f64])
                .collect();
            let (mut one, mut all) = (values(n, 0.2), values(n, 0.2));
            if n > 0 {
                for (point, &f) in many.chunks_exact(3 * n).zip(&fs) {
                    project_rows(&mut one, point, f);
                }
            }
            project_rows_many(&mut all, &many, &fs);
            assert!(
                one.iter()
                    .zip(&all)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "project_rows_many, n = {n}"
            );
            let mut acc_a = [[0.1, 0.2, 0.3, 0.0], [1.0, -2.0, 3.0, 0.0], [0.0; 4]];
            let mut acc_b = acc_a;
            rail_accumulate_body(&mut acc_a, &psi, &modal);
            rail_accumulate(&mut acc_b, &psi, &modal);
            assert!(
                acc_a
                    .iter()
                    .flatten()
                    .zip(acc_b.iter().flatten())
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "rail_accumulate, n = {n}"
            );
            // a pair against one call each (the second wheelset's shapes reversed)
            let psi1: Vec<[f64; 3]> = psi.iter().rev().copied().collect();
            let mut single = [[[0.1, 0.2, 0.3, 0.0], [1.0, -2.0, 3.0, 0.0], [0.0; 4]]; 2];
            single[1][2] = [7.0, -0.5, 1e-3, 0.0];
            let mut pair = single;
            rail_accumulate_body(&mut single[0], &psi, &modal);
            rail_accumulate_body(&mut single[1], &psi1, &modal);
            rail_accumulate_pair(&mut pair, [&psi, &psi1], &modal);
            let bits = |a: &[[[f64; 4]; 3]; 2]| -> Vec<u64> {
                a.iter().flatten().flatten().map(|v| v.to_bits()).collect()
            };
            assert_eq!(bits(&single), bits(&pair), "rail_accumulate_pair, n = {n}");
        }
    }
}
