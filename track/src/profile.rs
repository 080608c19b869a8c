//! Tabulated profile with cubic Hermite interpolation, shared by generated samples and records.

use std::io;

use crate::record_format::{HEADER, PERIODIC_DIRECTIVE, SLOPE_HEADER};
use crate::{Component, RailIrregularity};

/// The three irregularity components tabulated at strictly increasing nodes `x_i`, with
/// values `r_i` and slopes `r′_i`, evaluated by cubic Hermite interpolation.
///
/// On `[x_i, x_{i+1}]`, with `s = x − x_i`, `h = x_{i+1} − x_i`, `Δ = (r_{i+1} − r_i)/h`:
/// `r(x) = r_i + r′_i s + c₂ s² + c₃ s³`, `c₂ = (3Δ − 2r′_i − r′_{i+1})/h`,
/// `c₃ = (r′_i + r′_{i+1} − 2Δ)/h²`. The interpolant matches value and slope at both nodes
/// (C¹); its second derivative is linear in each interval and may jump at nodes, where the
/// value from the interval to the right is returned (at the last node: the left limit).
/// At a node the returned value and slope are the stored ones, bit for bit.
///
/// The coefficients are a pure function of `(x_i, r_i, r′_i)`, so two profiles built from the
/// same nodes evaluate identically everywhere.
///
/// Beyond the nodes: a *periodic* profile repeats with period `x_last − x_first` (its last node
/// repeats the first); otherwise the end value is held, with zero first and second derivatives.
/// A NaN `x` gives NaN everywhere.
#[derive(Clone, Debug)]
pub struct Profile {
    x: Vec<f64>,
    /// Per node, per component: `[r_i, r′_i, c₂, c₃]`.
    coef: Vec<[[f64; 4]; 3]>,
    periodic: bool,
    inv_mean_spacing: f64,
}

impl Profile {
    /// Builds the table. Caller guarantees: `x.len() ≥ 2`, strictly increasing finite `x`,
    /// all columns of equal length and finite, and for `periodic` a closing last node.
    pub(crate) fn from_validated(
        x: Vec<f64>,
        values: [&[f64]; 3],
        slopes: [&[f64]; 3],
        periodic: bool,
    ) -> Profile {
        let n = x.len();
        debug_assert!(n >= 2);
        let mut coef = vec![[[0.0; 4]; 3]; n];
        for i in 0..n - 1 {
            let h = x[i + 1] - x[i];
            for c in 0..3 {
                let (r0, r1) = (values[c][i], values[c][i + 1]);
                let (m0, m1) = (slopes[c][i], slopes[c][i + 1]);
                let d = (r1 - r0) / h;
                let c2 = (3.0 * d - 2.0 * m0 - m1) / h;
                let c3 = (m0 + m1 - 2.0 * d) / (h * h);
                coef[i][c] = [r0, m0, c2, c3];
            }
        }
        let h_last = x[n - 1] - x[n - 2];
        for c in 0..3 {
            let [_, _, c2, c3] = coef[n - 2][c];
            coef[n - 1][c] = [
                values[c][n - 1],
                slopes[c][n - 1],
                c2 + 3.0 * c3 * h_last,
                0.0,
            ];
        }
        let inv_mean_spacing = (n - 1) as f64 / (x[n - 1] - x[0]);
        Profile {
            x,
            coef,
            periodic,
            inv_mean_spacing,
        }
    }

    /// Value, first and second derivative of all components at `x` (m).
    #[inline]
    pub fn at(&self, x: f64) -> RailIrregularity {
        let n = self.x.len();
        let (x0, x1) = (self.x[0], self.x[n - 1]);
        if x >= x0 && x <= x1 {
            return self.eval_inside(x);
        }
        if x.is_nan() {
            return RailIrregularity {
                lateral: [f64::NAN; 3],
                vertical: [f64::NAN; 3],
                cross_level: [f64::NAN; 3],
            };
        }
        if self.periodic {
            let u = (x0 + (x - x0).rem_euclid(x1 - x0)).clamp(x0, x1);
            self.eval_inside(u)
        } else {
            let c = if x < x0 {
                &self.coef[0]
            } else {
                &self.coef[n - 1]
            };
            RailIrregularity {
                lateral: [c[0][0], 0.0, 0.0],
                vertical: [c[1][0], 0.0, 0.0],
                cross_level: [c[2][0], 0.0, 0.0],
            }
        }
    }

    /// Third derivative `d³r/dx³` of each component at `x`, indexed by
    /// [`Component::index`](crate::Component::index) (1/m², 1/m², rad/m³): constant on each
    /// interval of the cubic (that of the interval to the right at a node), zero beyond the
    /// ends of a non-periodic profile — the derivative of [`Profile::at`]'s second
    /// derivative wherever that is differentiable.
    pub fn third_derivative(&self, x: f64) -> [f64; 3] {
        let n = self.x.len();
        let (x0, x1) = (self.x[0], self.x[n - 1]);
        let u = if x >= x0 && x <= x1 {
            x
        } else if x.is_nan() {
            return [f64::NAN; 3];
        } else if self.periodic {
            (x0 + (x - x0).rem_euclid(x1 - x0)).clamp(x0, x1)
        } else {
            return [0.0; 3];
        };
        let c = &self.coef[self.locate(u)];
        [6.0 * c[0][3], 6.0 * c[1][3], 6.0 * c[2][3]]
    }

    #[inline]
    fn eval_inside(&self, x: f64) -> RailIrregularity {
        let i = self.locate(x);
        let s = x - self.x[i];
        let c = &self.coef[i];
        let e = |k: [f64; 4]| {
            let [a0, a1, a2, a3] = k;
            [
                a0 + s * (a1 + s * (a2 + s * a3)),
                a1 + s * (2.0 * a2 + 3.0 * a3 * s),
                2.0 * a2 + 6.0 * a3 * s,
            ]
        };
        RailIrregularity {
            lateral: e(c[0]),
            vertical: e(c[1]),
            cross_level: e(c[2]),
        }
    }

    /// A hint that [`Self::at`] at `x` follows soon: starts loading the node and coefficients
    /// it reads into the cache, so that a caller that knows where the wheelsets will be next
    /// (the table of a long track does not fit the cache) does not wait for them then.
    /// Reads nothing and changes nothing; outside the table, nothing.
    #[inline]
    pub fn prefetch(&self, x: f64) {
        let n = self.x.len();
        let g = (x - self.x[0]) * self.inv_mean_spacing;
        if !(g >= 0.0 && g < n as f64) {
            return;
        }
        let i = g as usize;
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            // SAFETY: a prefetch only hints the cache; both addresses are inside the tables
            // (i < n = coef.len() = x.len()), and SSE is part of x86_64.
            #[allow(unused_unsafe)]
            unsafe {
                // an entry is 96 bytes: its first and last byte
                let c = self.coef.as_ptr().add(i).cast::<i8>();
                _mm_prefetch::<_MM_HINT_T0>(c);
                _mm_prefetch::<_MM_HINT_T0>(c.add(95));
                _mm_prefetch::<_MM_HINT_T0>(self.x.as_ptr().add(i).cast());
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = i;
    }

    /// The unique `i` with `x_i ≤ x < x_{i+1}` (`n − 1` at the last node), for
    /// `x_0 ≤ x ≤ x_{n−1}`. Guesses from the mean spacing (exact on a uniform grid), then
    /// falls back to bisection.
    #[inline]
    fn locate(&self, x: f64) -> usize {
        let n = self.x.len();
        let mut i = (((x - self.x[0]) * self.inv_mean_spacing) as usize).min(n - 1);
        for _ in 0..3 {
            if x < self.x[i] {
                i -= 1;
            } else if i + 1 < n && x >= self.x[i + 1] {
                i += 1;
            } else {
                return i;
            }
        }
        self.x.partition_point(|&xi| xi <= x) - 1
    }

    /// The nodes `x_i`, m.
    pub fn nodes(&self) -> &[f64] {
        &self.x
    }

    /// Node values `r_i` of `component` (m or rad).
    pub fn values(&self, component: Component) -> Vec<f64> {
        let c = component.index();
        self.coef.iter().map(|k| k[c][0]).collect()
    }

    /// Node slopes `r′_i` of `component` (m/m or rad/m).
    pub fn slopes(&self, component: Component) -> Vec<f64> {
        let c = component.index();
        self.coef.iter().map(|k| k[c][1]).collect()
    }

    /// Whether the profile repeats beyond its nodes (otherwise the end values are held).
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }

    /// First and last node, m.
    pub fn domain(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// Bytes that identify the profile: the periodic flag and the bits of every node's `x`,
    /// value and slope, i.e. everything [`Profile::write_csv`] writes apart from comments.
    /// Reading that text back gives the same bits, so the writer and the reader of a record
    /// compute the same bytes; a digest of them (the bridge FMU's GUID) identifies the record
    /// without formatting or hashing its text.
    pub fn identity_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(1 + 56 * self.x.len());
        out.push(u8::from(self.periodic));
        for (x, k) in self.x.iter().zip(&self.coef) {
            out.extend_from_slice(&x.to_bits().to_le_bytes());
            for v in [k[0][0], k[1][0], k[2][0], k[0][1], k[1][1], k[2][1]] {
                out.extend_from_slice(&v.to_bits().to_le_bytes());
            }
        }
        out
    }

    /// Writes the profile in the record format (see [`crate::record`]) with slope columns,
    /// the `# periodic` directive if periodic, and `comments` as leading `#` lines.
    /// Numbers are written in Rust's shortest round-trip form, so reading the file back gives
    /// the same nodes, values and slopes bit for bit.
    pub fn write_csv<W: io::Write>(&self, mut out: W, comments: &[String]) -> io::Result<()> {
        for c in comments {
            for line in c.lines() {
                writeln!(out, "# {line}")?;
            }
        }
        if self.periodic {
            writeln!(out, "# {PERIODIC_DIRECTIVE}")?;
        }
        writeln!(out, "{},{}", HEADER.join(","), SLOPE_HEADER.join(","))?;
        for (x, k) in self.x.iter().zip(&self.coef) {
            writeln!(
                out,
                "{x},{:e},{:e},{:e},{:e},{:e},{:e}",
                k[0][0], k[1][0], k[2][0], k[0][1], k[1][1], k[2][1]
            )?;
        }
        Ok(())
    }
}
