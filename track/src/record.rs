//! Irregularity records: reading and writing the CSV record format.
//!
//! # Format
//!
//! A UTF-8 text file of comma-separated values, SI units:
//!
//! ```text
//! # Any line whose first non-blank character is '#' is a comment; blank lines are ignored.
//! x_m,lateral_m,vertical_m,cross_level_rad
//! 0.0,0.0012,-0.0003,0.0004
//! 0.25,0.0011,-0.0002,0.0005
//! ...
//! ```
//!
//! * The first line that is neither blank nor a comment is the header, exactly
//!   `x_m,lateral_m,vertical_m,cross_level_rad` (blanks around names allowed), optionally
//!   followed by the slope columns `,lateral_slope,vertical_slope,cross_level_slope`.
//! * Columns: `x_m` position along the track (m, strictly increasing, any spacing);
//!   `lateral_m` alignment `Y_s` (m, + right); `vertical_m` profile `Z_s` (m, + down);
//!   `cross_level_rad` cross-level angle `θ_s` (rad, right side down +); the optional slopes
//!   are `dY_s/dx` (m/m), `dZ_s/dx` (m/m), `dθ_s/dx` (rad/m).
//! * At least two data rows; every field a finite number.
//! * The comment `# periodic` (the word alone after `#`, anywhere in the file) declares that
//!   the record repeats with period `x_last − x_first`; its last row must then repeat the
//!   first row in every column but `x_m`. Without it the record is held constant beyond its
//!   ends (value of the end row, zero derivatives).
//!
//! Errors name the file, the 1-based line number (comments and blank lines count) and the
//! problem ([`crate::RecordProblem`]).
//!
//! # Slopes
//!
//! Evaluation is the cubic Hermite interpolation of [`Profile`]. Given slope columns are used
//! as they are (this is how a generated sample keeps its exact derivatives, so that a sample
//! written with [`Profile::write_csv`] and read back evaluates bit for bit like the original,
//! at every `x`). Without slope columns the slope at a node is the derivative of the parabola
//! through the node and its two neighbours,
//! `r′_i = (h_{i−1} Δ_i + h_i Δ_{i−1}) / (h_{i−1} + h_i)`, `Δ_i = (r_{i+1} − r_i)/h_i`,
//! `h_i = x_{i+1} − x_i` (second-order accurate on any spacing). At the ends of a
//! non-periodic record the parabola through the three end nodes is used; a periodic record
//! wraps around (its first and last rows are the same point). With only two rows the slope is
//! the secant.

use std::path::Path;

use crate::profile::Profile;
pub use crate::record_format::{HEADER, PERIODIC_DIRECTIVE, SLOPE_HEADER};
use crate::{RailIrregularity, RecordProblem, TrackError};

const COLUMNS: [&str; 7] = [
    HEADER[0],
    HEADER[1],
    HEADER[2],
    HEADER[3],
    SLOPE_HEADER[0],
    SLOPE_HEADER[1],
    SLOPE_HEADER[2],
];

/// A measured (or exported) irregularity record.
#[derive(Clone, Debug)]
pub struct Record {
    source: String,
    slopes_given: bool,
    profile: Profile,
}

impl Record {
    /// Reads a record file.
    pub fn read(path: impl AsRef<Path>) -> Result<Record, TrackError> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = tbi_modes::input::read_text(path, tbi_modes::input::MAX_DATA_FILE_BYTES)
            .map_err(|source| TrackError::Io {
                file: name.clone(),
                source,
            })?;
        Record::parse(&text, &name)
    }

    /// Parses record text; `source` names it in errors (usually the file name).
    pub fn parse(text: &str, source: &str) -> Result<Record, TrackError> {
        let line_err = |line: usize, problem| TrackError::RecordLine {
            file: source.to_owned(),
            line,
            problem,
        };
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut periodic = false;
        let mut ncol = 0usize;
        let mut x = Vec::new();
        let mut cols: [Vec<f64>; 6] = Default::default();
        let mut last_line = 0usize;
        for (idx, raw) in text.lines().enumerate() {
            let line = idx + 1;
            let t = raw.trim();
            if t.is_empty() {
                continue;
            }
            if let Some(comment) = t.strip_prefix('#') {
                if comment.trim() == PERIODIC_DIRECTIVE {
                    periodic = true;
                }
                continue;
            }
            if ncol == 0 {
                let fields: Vec<&str> = t.split(',').map(str::trim).collect();
                let with_slopes = fields.len() == 7 && fields[..] == COLUMNS[..];
                if !(with_slopes || fields[..] == HEADER[..]) {
                    return Err(line_err(
                        line,
                        RecordProblem::BadHeader {
                            found: t.to_owned(),
                        },
                    ));
                }
                ncol = fields.len();
                continue;
            }
            let row = match fast_row(raw, ncol) {
                Some(row) => row,
                None => parse_row(t, ncol, line, &line_err)?,
            };
            if let Some(&previous) = x.last() {
                if row[0] <= previous {
                    return Err(line_err(
                        line,
                        RecordProblem::NonIncreasingX {
                            x: row[0],
                            previous,
                        },
                    ));
                }
            }
            last_line = line;
            x.push(row[0]);
            for k in 1..ncol {
                cols[k - 1].push(row[k]);
            }
        }
        let file_err = |problem| TrackError::RecordFile {
            file: source.to_owned(),
            problem,
        };
        if ncol == 0 {
            return Err(file_err(RecordProblem::MissingHeader));
        }
        if x.len() < 2 {
            return Err(file_err(RecordProblem::TooFewRows { found: x.len() }));
        }
        let n = x.len();
        if periodic && cols[..ncol - 1].iter().any(|c| c[0] != c[n - 1]) {
            return Err(line_err(last_line, RecordProblem::PeriodicNotClosed));
        }
        let [l, v, c, ls, vs, cs] = cols;
        let slopes = (ncol == 7).then_some([ls, vs, cs]);
        Ok(Record::build(
            source.to_owned(),
            x,
            [l, v, c],
            slopes,
            periodic,
        ))
    }

    /// Builds a record from columns: nodes `x_m` (m, strictly increasing, at least 2), values
    /// in [`crate::Component::ALL`] order (m, m, rad), optional slopes (m/m, m/m, rad/m; finite
    /// differences are used when `None`, see the module docs), and whether it is periodic
    /// (last node repeating the first).
    pub fn from_columns(
        source: &str,
        x_m: Vec<f64>,
        values: [Vec<f64>; 3],
        slopes: Option<[Vec<f64>; 3]>,
        periodic: bool,
    ) -> Result<Record, TrackError> {
        let invalid = |field: &'static str, value: String, reason: &str| TrackError::Invalid {
            field,
            value,
            reason: reason.to_owned(),
        };
        let n = x_m.len();
        if n < 2 {
            return Err(invalid(
                "x_m",
                format!("{n} nodes"),
                "at least 2 nodes needed",
            ));
        }
        if let Some(i) = (0..n).find(|&i| !x_m[i].is_finite() || (i > 0 && x_m[i] <= x_m[i - 1])) {
            return Err(invalid(
                "x_m",
                format!("{} at index {i}", x_m[i]),
                "must be finite and strictly increasing",
            ));
        }
        let mut all: Vec<(&'static str, &Vec<f64>)> =
            HEADER[1..].iter().copied().zip(&values).collect();
        if let Some(s) = &slopes {
            all.extend(SLOPE_HEADER.iter().copied().zip(s));
        }
        for (name, col) in &all {
            if col.len() != n {
                return Err(invalid(
                    name,
                    format!("{} entries", col.len()),
                    &format!("must have one entry per node ({n})"),
                ));
            }
            if let Some(i) = col.iter().position(|v| !v.is_finite()) {
                return Err(invalid(
                    name,
                    format!("{} at index {i}", col[i]),
                    "must be finite",
                ));
            }
            if periodic && col[0] != col[n - 1] {
                return Err(invalid(
                    name,
                    format!("{} / {}", col[0], col[n - 1]),
                    "a periodic record's last node must repeat the first",
                ));
            }
        }
        Ok(Record::build(
            source.to_owned(),
            x_m,
            values,
            slopes,
            periodic,
        ))
    }

    fn build(
        source: String,
        x: Vec<f64>,
        values: [Vec<f64>; 3],
        slopes: Option<[Vec<f64>; 3]>,
        periodic: bool,
    ) -> Record {
        let slopes_given = slopes.is_some();
        let slopes =
            slopes.unwrap_or_else(|| values.each_ref().map(|r| fd_slopes(&x, r, periodic)));
        let profile = Profile::from_validated(
            x,
            values.each_ref().map(Vec::as_slice),
            slopes.each_ref().map(Vec::as_slice),
            periodic,
        );
        Record {
            source,
            slopes_given,
            profile,
        }
    }

    /// Value, first and second derivative of all components at `x` (m).
    #[inline]
    pub fn at(&self, x: f64) -> RailIrregularity {
        self.profile.at(x)
    }

    /// Where the record came from (file name or the `source` given when parsing).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Whether the slopes were given (slope columns) rather than finite differences.
    pub fn slopes_given(&self) -> bool {
        self.slopes_given
    }

    /// The interpolation table.
    pub fn profile(&self) -> &Profile {
        &self.profile
    }
}

/// Parabolic finite-difference slopes (see the module docs).
fn fd_slopes(x: &[f64], r: &[f64], periodic: bool) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (r[i + 1] - r[i]) / h[i]).collect();
    if n == 2 {
        return vec![d[0]; 2];
    }
    // Parabola through (x−hl, x, x+hr) with left/right secants dl, dr.
    let centred = |hl: f64, dl: f64, hr: f64, dr: f64| (hl * dr + hr * dl) / (hl + hr);
    let mut m = vec![0.0; n];
    for i in 1..n - 1 {
        m[i] = centred(h[i - 1], d[i - 1], h[i], d[i]);
    }
    if periodic {
        m[0] = centred(h[n - 2], d[n - 2], h[0], d[0]);
        m[n - 1] = m[0];
    } else {
        m[0] = d[0] - h[0] * (d[1] - d[0]) / (h[0] + h[1]);
        m[n - 1] = d[n - 2] + h[n - 2] * (d[n - 2] - d[n - 3]) / (h[n - 3] + h[n - 2]);
    }
    m
}

/// A data row of exactly `ncol` finite numbers separated by bare commas (no blanks), as
/// [`Profile::write_csv`] writes them; `None` for anything else, which [`parse_row`] then
/// reads or reports. One pass over the bytes: the numbers are read where they stand
/// (`fast_float2`, correctly rounded like `str::parse`, so the values are the same).
#[inline]
fn fast_row(line: &str, ncol: usize) -> Option<[f64; 7]> {
    let mut rest = line.as_bytes();
    let mut row = [0.0; 7];
    for (k, v) in row[..ncol].iter_mut().enumerate() {
        let (value, used) = fast_float2::parse_partial::<f64, _>(rest).ok()?;
        if used == 0 || !value.is_finite() {
            return None;
        }
        *v = value;
        rest = &rest[used..];
        if k + 1 < ncol {
            rest = rest.strip_prefix(b",")?;
        }
    }
    rest.is_empty().then_some(row)
}

/// A data row of `ncol` fields (blanks around fields allowed), or the error naming the line,
/// the column and the text.
fn parse_row(
    t: &str,
    ncol: usize,
    line: usize,
    line_err: &impl Fn(usize, RecordProblem) -> TrackError,
) -> Result<[f64; 7], TrackError> {
    let fields: Vec<&str> = t.split(',').map(str::trim).collect();
    if fields.len() != ncol {
        return Err(line_err(
            line,
            RecordProblem::ColumnCount {
                expected: ncol,
                found: fields.len(),
            },
        ));
    }
    let mut row = [0.0; 7];
    for (k, text) in fields.iter().enumerate() {
        let column = COLUMNS[k];
        let v: f64 = text.parse().map_err(|_| {
            line_err(
                line,
                RecordProblem::NotANumber {
                    column,
                    text: (*text).to_owned(),
                },
            )
        })?;
        if !v.is_finite() {
            return Err(line_err(
                line,
                RecordProblem::NotFinite {
                    column,
                    text: (*text).to_owned(),
                },
            ));
        }
        row[k] = v;
    }
    Ok(row)
}
