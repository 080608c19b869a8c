//! Newmark's average-acceleration method (β = 1/4, γ = 1/2), as used in the paper.
//!
//! ```text
//! x_{n+1} = x_n + h ẋ_n + h²/4 (ẍ_n + ẍ_{n+1})
//! ẋ_{n+1} = ẋ_n + h/2 (ẍ_n + ẍ_{n+1})
//! ```
//!
//! Solved for the new displacement: `(a0 M + a1 C + K) x_{n+1} = F_{n+1} + M (a0 x_n + a2 ẋ_n +
//! ẍ_n) + C (a1 x_n + ẋ_n)`, with `a0 = 4/h²`, `a1 = 2/h`, `a2 = 4/h`; then
//! `ẍ_{n+1} = a0 (x_{n+1} − x_n) − a2 ẋ_n − ẍ_n` and `ẋ_{n+1} = a1 (x_{n+1} − x_n) − ẋ_n`.
//! Unconditionally stable, second-order accurate, no numerical damping; for a linear
//! undamped system it conserves the discrete energy exactly.

/// The method's coefficients for one step size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Newmark {
    /// Step size h, s.
    pub h: f64,
    /// 4/h², 1/s².
    pub a0: f64,
    /// 2/h, 1/s.
    pub a1: f64,
    /// 4/h, 1/s.
    pub a2: f64,
}

impl Newmark {
    pub fn new(h: f64) -> Self {
        Newmark {
            h,
            a0: 4.0 / (h * h),
            a1: 2.0 / h,
            a2: 4.0 / h,
        }
    }

    /// Inertia predictor `a0 x + a2 ẋ + ẍ`.
    #[inline]
    pub fn mass_pred(&self, x: f64, xd: f64, xdd: f64) -> f64 {
        self.a0 * x + self.a2 * xd + xdd
    }

    /// Damping predictor `a1 x + ẋ`.
    #[inline]
    pub fn damp_pred(&self, x: f64, xd: f64) -> f64 {
        self.a1 * x + xd
    }

    /// Velocity and acceleration at the new step from the new displacement.
    #[inline]
    pub fn update(&self, x_new: f64, x: f64, xd: f64, xdd: f64) -> (f64, f64) {
        let dx = x_new - x;
        (self.a1 * dx - xd, self.a0 * dx - self.a2 * xd - xdd)
    }

    /// The predictors `(x + h ẋ + h²/4 ẍ, ẋ + h/2 ẍ)`: the new displacement and velocity
    /// without the new acceleration's share.
    #[inline]
    pub fn predict(&self, x: f64, xd: f64, xdd: f64) -> (f64, f64) {
        let h = self.h;
        (x + h * xd + 0.25 * h * h * xdd, xd + 0.5 * h * xdd)
    }

    /// Displacement and velocity from the predictors and the new acceleration `a`.
    #[inline]
    pub fn correct(&self, (xp, xdp): (f64, f64), a: f64) -> (f64, f64) {
        let h = self.h;
        (xp + 0.25 * h * h * a, xdp + 0.5 * h * a)
    }
}
