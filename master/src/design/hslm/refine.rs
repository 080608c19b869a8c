//! Speeds that find the peaks of an envelope rather than sample them.
//!
//! * **The grid with the resonance speeds.** Each train's speeds are the grid asked for plus
//!   its resonance speeds v_i = f₁ D / i (D the train's coach length, f₁ the bridge's first
//!   frequency, i = 1, 2, …) inside the grid's range.
//! * **Refinement.** Around every local maximum of a train's envelope of the deck
//!   acceleration a(v) (a grid point no lower than its neighbours; at an end of the range,
//!   no lower than its one neighbour) the peak is sought by golden-section search on the
//!   bracket [v₋, v₊] of the neighbours: a new speed at 0.381966 of the larger part of the
//!   bracket from the best point; the bracket shrinks to the side of the better of the two.
//!   The search stops when the bracket is at most [`RESOLUTION_KMH`] wide (the peak's speed
//!   known to ±0.1 km/h), or when both ends of the bracket are within [`RESOLVED_FRACTION`]
//!   of the best value (the peak is flat there: its value is known to that fraction), or
//!   after [`MAX_ITERATIONS`] new speeds. (A parabola through the three points is no test of
//!   a resonance peak: its sharp top makes the parabola's vertex fall near the best point
//!   long before the peak is found.)

/// Width of a bracket at which the peak's speed is resolved, km/h.
pub const RESOLUTION_KMH: f64 = 0.2;
/// Fraction of the best value within which both ends of a bracket make the peak resolved.
pub const RESOLVED_FRACTION: f64 = 5e-3;
/// Most new speeds per peak.
pub const MAX_ITERATIONS: usize = 30;

/// How a speed came into a train's envelope.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Point {
    /// The speed grid asked for.
    Grid,
    /// A resonance speed f₁ D / i.
    Resonance,
    /// A speed of the refinement around a peak.
    Refined,
}

impl Point {
    pub fn as_str(self) -> &'static str {
        match self {
            Point::Grid => "grid",
            Point::Resonance => "resonance",
            Point::Refined => "refined",
        }
    }
}

/// The resonance speeds f₁ D / i, km/h, for i = 1, 2, … inside [lo, hi] (km/h).
pub fn resonance_speeds(f1_hz: f64, coach_length_m: f64, lo: f64, hi: f64) -> Vec<f64> {
    let first = f1_hz * coach_length_m * 3.6;
    let mut v = Vec::new();
    if !(first.is_finite() && first > 0.0) {
        return v;
    }
    let mut i = (first / hi).ceil().max(1.0) as usize;
    loop {
        let s = first / i as f64;
        if s < lo {
            break;
        }
        if s <= hi {
            v.push(s);
        }
        i += 1;
    }
    v.reverse();
    v
}

/// The grid `speeds` with the resonance speeds inside its range added (those within 1e-9
/// km/h of a grid speed are not added twice), ascending, each with how it came in.
pub fn with_resonances(speeds: &[f64], resonances: &[f64]) -> Vec<(f64, Point)> {
    let mut all: Vec<(f64, Point)> = speeds.iter().map(|&v| (v, Point::Grid)).collect();
    for &r in resonances {
        if !speeds.iter().any(|&v| (v - r).abs() < 1e-9) {
            all.push((r, Point::Resonance));
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    all
}

/// The brackets (v₋, v_best, v₊) of the local maxima of `points` (speed, value), ascending
/// in speed. An end of the range is a maximum when no lower than its neighbour; its bracket
/// is the end and the neighbour (v₋ = v_best or v₊ = v_best).
pub fn peaks(points: &[(f64, f64)]) -> Vec<(f64, f64, f64)> {
    let n = points.len();
    let mut out = Vec::new();
    if n < 2 {
        return out;
    }
    for i in 0..n {
        let y = points[i].1;
        let left = i == 0 || points[i - 1].1 <= y;
        let right = i == n - 1 || points[i + 1].1 <= y;
        // a plateau counts once, at its first point
        let plateau = i > 0 && points[i - 1].1 == y;
        if left && right && !plateau {
            let lo = if i == 0 { points[0].0 } else { points[i - 1].0 };
            let hi = if i == n - 1 {
                points[n - 1].0
            } else {
                points[i + 1].0
            };
            out.push((lo, points[i].0, hi));
        }
    }
    out
}

/// Golden-section search for the peak of `f` in the bracket `(a, c, b)` with values
/// `(fa, fc, fb)` (fc no lower than fa and fb); the speeds evaluated with their values, in
/// order. `f` errors end the search with the error.
pub fn refine<E>(
    (mut a, mut c, mut b): (f64, f64, f64),
    (mut fa, mut fc, mut fb): (f64, f64, f64),
    mut f: impl FnMut(f64) -> Result<f64, E>,
) -> Result<Vec<(f64, f64)>, E> {
    const G: f64 = 0.381_966_011_250_105_1;
    let mut evaluated = Vec::new();
    for _ in 0..MAX_ITERATIONS {
        if b - a <= RESOLUTION_KMH || resolved((fa, fc, fb)) {
            break;
        }
        let right = b - c >= c - a;
        let x = if right {
            c + G * (b - c)
        } else {
            c - G * (c - a)
        };
        let fx = f(x)?;
        evaluated.push((x, fx));
        match (right, fx > fc) {
            (true, true) => (a, fa, c, fc) = (c, fc, x, fx),
            (true, false) => (b, fb) = (x, fx),
            (false, true) => (b, fb, c, fc) = (c, fc, x, fx),
            (false, false) => (a, fa) = (x, fx),
        }
    }
    Ok(evaluated)
}

/// Whether both ends of the bracket are within [`RESOLVED_FRACTION`] of the best value.
fn resolved((fa, fc, fb): (f64, f64, f64)) -> bool {
    fc > 0.0 && fa.min(fb) >= (1.0 - RESOLVED_FRACTION) * fc
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The resonance speeds are f₁ D / i inside the range, ascending.
    #[test]
    fn resonance_speeds_inside_the_range() {
        // f₁ D = 5 Hz × 20 m = 100 m/s = 360 km/h
        let v = resonance_speeds(5.0, 20.0, 100.0, 400.0);
        assert_eq!(v.len(), 3);
        for (got, want) in v.iter().zip([120.0, 180.0, 360.0]) {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
        let all = with_resonances(&[100.0, 180.0, 400.0], &v);
        let kinds: Vec<_> = all.iter().map(|p| p.1).collect();
        assert_eq!(
            kinds,
            [
                Point::Grid,
                Point::Resonance,
                Point::Grid,
                Point::Resonance,
                Point::Grid
            ]
        );
    }

    /// Local maxima with their brackets, ends included, a plateau once.
    #[test]
    fn local_maxima_and_their_brackets() {
        let p = [
            (1.0, 3.0),
            (2.0, 1.0),
            (3.0, 2.0),
            (4.0, 2.0),
            (5.0, 1.0),
            (6.0, 4.0),
        ];
        assert_eq!(
            peaks(&p),
            [(1.0, 1.0, 2.0), (2.0, 3.0, 4.0), (5.0, 6.0, 6.0)]
        );
    }

    /// On a narrow resonance curve the search finds the peak's speed to the resolution and
    /// its value to the resolved fraction, from a bracket 20 km/h wide.
    #[test]
    fn golden_section_finds_a_narrow_peak() {
        // a damped oscillator's amplification near resonance, ζ = 0.5 %, peak at 253.7
        let f = |v: f64| {
            let r = v / 253.7;
            1.0 / ((1.0 - r * r).powi(2) + (2.0 * 0.005 * r).powi(2)).sqrt()
        };
        let (a, c, b) = (240.0, 250.0, 260.0);
        let found = refine((a, c, b), (f(a), f(c), f(b)), |v| Ok::<_, ()>(f(v))).unwrap();
        let best = found
            .iter()
            .copied()
            .chain([(c, f(c))])
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        let exact = f(253.7);
        assert!(best.1 >= (1.0 - 5e-3) * exact, "{best:?} vs {exact}");
        assert!(found.len() <= MAX_ITERATIONS);
    }
}
