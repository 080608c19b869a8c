//! Numerical kernels shared by the solvers (`tbi-dynamics`) and the coupling library
//! (`tbi-coupling`): element-wise vector updates whose results do not depend on the
//! processor's vector width ([`simd`]).

// Index loops over several parallel slices read as the formulas do.
#![allow(clippy::needless_range_loop)]

pub mod simd;
