//! Shared helpers of the command-line tests: scratch folders, scenario variants, running
//! `tbi run`, reading `history.csv` / `summary.json`, and comparing histories column by
//! column.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The `tbi` binary under test.
pub fn tbi() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_tbi"))
}

/// A scenario file of `master/tests/data`.
pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("data")
        .join(name)
}

/// Text of a scenario file of `master/tests/data`.
pub fn data_text(name: &str) -> String {
    let p = data(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A fresh empty directory under Cargo's per-target test temp dir (emptied, not piled up, by
/// the next run of the same test binary).
pub fn scratch(label: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let binary = std::env::current_exe()
        .ok()
        .and_then(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_default();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli-tests")
        .join(format!("{binary}-{label}-{n}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Co-simulation exports the scenario's FMUs from `libbridge.so` / `libtrain.so`, which `tbi`
/// finds next to itself; `cargo test -p tbi` alone does not build them.
pub fn require_fmu_libraries() {
    let dir = tbi().parent().expect("the binary has a folder");
    for lib in ["libbridge.so", "libtrain.so"] {
        assert!(
            dir.join(lib).is_file(),
            "{} is missing: run `cargo build --release --workspace` (same target dir and \
             profile) before these tests",
            dir.join(lib).display()
        );
    }
}

/// Outcome of one `tbi` invocation.
pub struct Run {
    pub out: PathBuf,
    pub status: std::process::ExitStatus,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    pub fn ok(&self) -> bool {
        self.status.success()
    }

    /// Panics with stderr unless the run succeeded.
    pub fn expect_ok(&self, what: &str) -> &Self {
        assert!(
            self.ok(),
            "{what}: tbi failed ({}):\n{}",
            self.status,
            self.stderr
        );
        self
    }

    pub fn history(&self) -> History {
        History::read(&self.out.join("history.csv"))
    }

    pub fn summary(&self) -> serde_json::Value {
        read_summary(&self.out)
    }
}

fn from_output(out: PathBuf, o: Output) -> Run {
    Run {
        out,
        status: o.status,
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

/// `tbi ARGS...` (for arguments other than a plain run).
pub fn tbi_with(args: &[&str]) -> Output {
    Command::new(tbi())
        .args(args)
        .output()
        .expect("tbi can be started")
}

/// `tbi run SCENARIO --solver SOLVER --out OUT --quiet [EXTRA...]`.
pub fn run(scenario: &Path, solver: &str, out: &Path, extra: &[&str]) -> Run {
    let o = Command::new(tbi())
        .arg("run")
        .arg(scenario)
        .args(["--solver", solver, "--quiet", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .expect("tbi can be started");
    from_output(out.to_path_buf(), o)
}

pub fn read_summary(out: &Path) -> serde_json::Value {
    let p = out.join("summary.json");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A scenario given as TOML text, edited as a table.
pub struct Scenario(pub toml::Table);

impl Scenario {
    pub fn parse(text: &str) -> Self {
        Scenario(toml::from_str(text).expect("valid TOML"))
    }

    pub fn from_data(name: &str) -> Self {
        Self::parse(&data_text(name))
    }

    fn table(&mut self, name: &str) -> &mut toml::Table {
        self.0
            .entry(name)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()
            .expect("a table")
    }

    /// Sets `[section] key = value`.
    pub fn set(mut self, section: &str, key: &str, value: impl Into<toml::Value>) -> Self {
        self.table(section).insert(key.into(), value.into());
        self
    }

    /// Sets the `[coupling]` table from TOML text (replacing an earlier one).
    pub fn coupling(mut self, text: &str) -> Self {
        let t: toml::Table = toml::from_str(text).expect("valid coupling TOML");
        self.0.insert("coupling".into(), toml::Value::Table(t));
        self
    }

    pub fn text(&self) -> String {
        toml::to_string(&self.0).expect("serialisable")
    }

    /// Writes `dir/name`; returns its path.
    pub fn write(&self, dir: &Path, name: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, self.text()).unwrap();
        p
    }
}

/// `history.csv`: column names and rows.
#[derive(Debug, Clone)]
pub struct History {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl History {
    pub fn read(path: &Path) -> History {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .unwrap_or_else(|| panic!("{}: empty", path.display()))
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .enumerate()
            .map(|(i, l)| {
                let row: Vec<f64> = l
                    .split(',')
                    .map(|c| {
                        c.parse().unwrap_or_else(|_| {
                            panic!("{}:{}: `{c}` is not a number", path.display(), i + 2)
                        })
                    })
                    .collect();
                assert_eq!(
                    row.len(),
                    columns.len(),
                    "{}:{}: column count",
                    path.display(),
                    i + 2
                );
                row
            })
            .collect();
        History { columns, rows }
    }

    pub fn index(&self, name: &str) -> usize {
        self.columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.columns))
    }

    pub fn column(&self, name: &str) -> Vec<f64> {
        let j = self.index(name);
        self.rows.iter().map(|r| r[j]).collect()
    }

    pub fn max_abs(&self, name: &str) -> f64 {
        self.column(name).iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// Difference of one column of two histories.
#[derive(Debug, Clone)]
pub struct ColumnDiff {
    pub name: String,
    /// max |reference|.
    pub scale: f64,
    /// max |other|.
    pub other_scale: f64,
    /// max |other − reference|.
    pub max_diff: f64,
}

impl ColumnDiff {
    /// max |difference| / max |reference|; for an all-zero reference column, 0 if the other
    /// is all zero too, infinity otherwise.
    pub fn relative(&self) -> f64 {
        if self.scale > 0.0 {
            self.max_diff / self.scale
        } else if self.other_scale == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// Column-by-column differences of `other` against `reference` (same columns and times).
pub fn compare(reference: &History, other: &History) -> Vec<ColumnDiff> {
    assert_eq!(reference.columns, other.columns, "history columns differ");
    assert_eq!(
        reference.rows.len(),
        other.rows.len(),
        "history row counts differ"
    );
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
                d.max_diff = d.max_diff.max((a[j] - b[j]).abs());
            }
            d
        })
        .collect()
}

/// The largest relative difference over all columns (NaN counts as infinite).
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
pub fn assert_same_history(reference: &History, other: &History, tol: f64, what: &str) {
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

/// The number after `key` in `text` (e.g. `number_after(msg, "t = ")`).
pub fn number_after(text: &str, key: &str) -> Option<f64> {
    let rest = &text[text.find(key)? + key.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+')))
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}
