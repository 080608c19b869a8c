//! CSV files written by `tbi` and FMPy: a numeric [`Table`] (`history.csv`, result files), a
//! text [`TextCsv`] (for comparisons down to the number formatting), and column-by-column
//! comparison of two tables.

use std::path::Path;

/// A CSV table: column names (surrounding quotes removed) and numeric rows. Blank lines are
/// skipped; every row must have one value per column.
#[derive(Debug, Clone)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    pub fn read(path: &Path) -> Table {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text.lines().enumerate();
        let columns: Vec<String> = lines
            .next()
            .unwrap_or_else(|| panic!("{} is empty", path.display()))
            .1
            .split(',')
            .map(|n| n.trim().trim_matches('"').to_string())
            .collect();
        let rows = lines
            .filter(|(_, l)| !l.trim().is_empty())
            .map(|(i, l)| {
                let row: Vec<f64> = l
                    .split(',')
                    .map(|v| {
                        v.trim().parse::<f64>().unwrap_or_else(|e| {
                            panic!("{}:{}: {v:?} is not a number: {e}", path.display(), i + 1)
                        })
                    })
                    .collect();
                assert_eq!(
                    row.len(),
                    columns.len(),
                    "{}:{}: {} values for {} columns",
                    path.display(),
                    i + 1,
                    row.len(),
                    columns.len()
                );
                row
            })
            .collect();
        Table { columns, rows }
    }

    /// Index of column `name`.
    pub fn col(&self, name: &str) -> usize {
        self.columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name:?} in {:?}", self.columns))
    }

    /// The values of column `name`.
    pub fn column(&self, name: &str) -> Vec<f64> {
        let j = self.col(name);
        self.rows.iter().map(|r| r[j]).collect()
    }

    /// max |value| of column `name`.
    pub fn max_abs(&self, name: &str) -> f64 {
        self.column(name).iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// A CSV as written by `tbi simulate` / `fmpy simulate`: the header line as it is, and the
/// fields of each row as text.
#[derive(Debug)]
pub struct TextCsv {
    pub header: String,
    pub rows: Vec<Vec<String>>,
}

impl TextCsv {
    pub fn read(path: &Path) -> TextCsv {
        let content =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = content.lines();
        let header = lines
            .next()
            .unwrap_or_else(|| panic!("{} is empty", path.display()))
            .to_owned();
        let rows = lines
            .map(|l| l.split(',').map(str::to_owned).collect())
            .collect();
        TextCsv { header, rows }
    }
}

/// Asserts equal headers and row counts, identical non-numeric fields, and numbers equal to
/// `rel` relative to max(1, |value of `b`|).
pub fn assert_text_csv_match(a: &TextCsv, b: &TextCsv, rel: f64) {
    assert_eq!(a.header, b.header, "headers differ");
    assert_eq!(
        a.rows.len(),
        b.rows.len(),
        "row counts differ: {} vs {}",
        a.rows.len(),
        b.rows.len()
    );
    for (i, (ra, rb)) in a.rows.iter().zip(&b.rows).enumerate() {
        assert_eq!(ra.len(), rb.len(), "row {i}: field counts differ");
        for (j, (x, y)) in ra.iter().zip(rb).enumerate() {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => assert!(
                    (x - y).abs() <= rel * y.abs().max(1.0),
                    "row {i}, column {j} ({}): {x} vs {y}",
                    a.header
                ),
                _ => assert_eq!(x, y, "row {i}, column {j}"),
            }
        }
    }
}

/// Difference of one column of two tables.
#[derive(Debug, Clone)]
pub struct ColumnDiff {
    pub name: String,
    /// max |reference|.
    pub scale: f64,
    /// max |other|.
    pub other_scale: f64,
    /// max |other − reference| (NaN when a value of either column is NaN).
    pub max_diff: f64,
}

impl ColumnDiff {
    /// max |difference| / max |reference|; for an all-zero reference column, 0 if the other
    /// is all zero too, infinity otherwise; NaN when either column holds a NaN.
    pub fn relative(&self) -> f64 {
        if self.max_diff.is_nan() {
            f64::NAN
        } else if self.scale > 0.0 {
            self.max_diff / self.scale
        } else if self.other_scale == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// Column-by-column differences of `other` against `reference` (same columns and rows).
pub fn compare(reference: &Table, other: &Table) -> Vec<ColumnDiff> {
    assert_eq!(reference.columns, other.columns, "columns differ");
    assert_eq!(reference.rows.len(), other.rows.len(), "row counts differ");
    reference
        .columns
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let mut d = ColumnDiff {
                name: name.clone(),
                scale: 0.0,
                other_scale: 0.0,
                max_diff: 0.0,
            };
            for (a, b) in reference.rows.iter().zip(&other.rows) {
                d.scale = d.scale.max(a[j].abs());
                d.other_scale = d.other_scale.max(b[j].abs());
                // `f64::max` drops a NaN; a NaN on either side must stay in the difference
                let diff = (a[j] - b[j]).abs();
                if diff.is_nan() || d.max_diff.is_nan() {
                    d.max_diff = f64::NAN;
                } else {
                    d.max_diff = d.max_diff.max(diff);
                }
            }
            d
        })
        .collect()
}

/// The largest relative difference over all columns and its column (NaN counts as
/// infinite).
pub fn worst(diffs: &[ColumnDiff]) -> (String, f64) {
    diffs
        .iter()
        .map(|d| {
            let r = d.relative();
            (d.name.clone(), if r.is_nan() { f64::INFINITY } else { r })
        })
        .fold((String::new(), 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

/// Asserts max |difference| / max |value| ≤ `tol` in every column, and exact zeros where the
/// reference column is all zero.
pub fn assert_same_table(reference: &Table, other: &Table, tol: f64, what: &str) {
    let diffs = compare(reference, other);
    let bad: Vec<String> = diffs
        .iter()
        .filter(|d| d.relative().is_nan() || d.relative() > tol)
        .map(|d| {
            format!(
                "  {}: max|ref| = {:.3e}, max|other| = {:.3e}, max|diff| = {:.3e}, relative {:.3e}",
                d.name,
                d.scale,
                d.other_scale,
                d.max_diff,
                d.relative()
            )
        })
        .collect();
    assert!(
        bad.is_empty(),
        "{what}: {} of {} columns differ by more than {tol:e} (relative to the column's max |value|):\n{}",
        bad.len(),
        diffs.len(),
        bad.join("\n")
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(columns: &[&str], rows: &[&[f64]]) -> Table {
        Table {
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: rows.iter().map(|r| r.to_vec()).collect(),
        }
    }

    #[test]
    fn reads_quoted_headers_and_skips_blank_lines() {
        let dir = crate::scratch("table-read");
        let path = dir.join("t.csv");
        std::fs::write(&path, "\"time\",\"x\"\n0.0,1.5\n\n0.1, -2e-3\n").unwrap();
        let t = Table::read(&path);
        assert_eq!(t.columns, ["time", "x"]);
        assert_eq!(t.rows, vec![vec![0.0, 1.5], vec![0.1, -2e-3]]);
        assert_eq!(t.col("x"), 1);
        assert_eq!(t.max_abs("x"), 1.5);
        let text = TextCsv::read(&path);
        assert_eq!(text.header, "\"time\",\"x\"");
        assert_eq!(text.rows[0], ["0.0", "1.5"]);
    }

    #[test]
    #[should_panic(expected = "1 values for 2 columns")]
    fn a_short_row_is_refused() {
        let dir = crate::scratch("table-short");
        let path = dir.join("t.csv");
        std::fs::write(&path, "a,b\n1,2\n3\n").unwrap();
        Table::read(&path);
    }

    #[test]
    fn differences_are_relative_to_the_reference_column() {
        let r = table(&["a", "zero", "z2"], &[&[2.0, 0.0, 0.0], &[-4.0, 0.0, 0.0]]);
        let o = table(
            &["a", "zero", "z2"],
            &[&[2.0, 0.0, 0.0], &[-4.2, 1e-30, 0.0]],
        );
        let d = compare(&r, &o);
        assert!((d[0].relative() - 0.05).abs() < 1e-12);
        assert_eq!(
            d[1].relative(),
            f64::INFINITY,
            "all-zero reference, other not"
        );
        assert_eq!(d[2].relative(), 0.0);
        assert_eq!(worst(&d).0, "zero");
        // a NaN on either side is the worst difference, also beside an all-zero column
        let one = table(&["a"], &[&[1.0], &[0.0]]);
        let nan = table(&["a"], &[&[f64::NAN], &[0.0]]);
        assert_eq!(worst(&compare(&one, &nan)).1, f64::INFINITY);
        assert_eq!(worst(&compare(&nan, &one)).1, f64::INFINITY);
        let zeros = table(&["a"], &[&[0.0], &[0.0]]);
        assert!(compare(&zeros, &nan)[0].relative().is_nan());
        assert_same_table(&r, &r, 0.0, "itself");
    }
}
