//! Text for messages: numbers as a reader writes them, and the closest valid name to a
//! misspelled one ("did you mean …?").

/// A number for messages: plain for ordinary magnitudes, in scientific notation otherwise
/// (so 1e-300 is not printed with 300 digits).
pub fn num(v: f64) -> String {
    if v == 0.0 || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

pub use fmi_import::names::{closest, did_you_mean};
