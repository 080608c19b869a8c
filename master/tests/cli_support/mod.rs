//! Helpers of the command-line tests that only they use: the scenario files of
//! master/tests/data, scenario variants, and `tbi run` with its outcome. The shared support
//! (the `tbi` binary, scratch folders, `history.csv` as a table, `summary.json`, comparing
//! histories) is the `tbi_tests` library.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use tbi_tests::{read_summary, tbi_command, text, Table};

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

/// Outcome of one `tbi` invocation.
pub struct Run {
    pub out: PathBuf,
    pub status: std::process::ExitStatus,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// The run finished its work: exit code 0 (every check passes) or 3 (a limit check of
    /// the summary FAILs).
    pub fn ok(&self) -> bool {
        matches!(self.status.code(), Some(0 | 3))
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

    pub fn history(&self) -> Table {
        Table::read(&self.out.join("history.csv"))
    }

    pub fn summary(&self) -> serde_json::Value {
        read_summary(&self.out)
    }
}

/// `tbi run SCENARIO --solver SOLVER --out OUT --quiet [EXTRA...]`.
pub fn run(scenario: &Path, solver: &str, out: &Path, extra: &[&str]) -> Run {
    let o = tbi_tests::run(
        tbi_command()
            .arg("run")
            .arg(scenario)
            .args(["--solver", solver, "--quiet", "--out"])
            .arg(out)
            .args(extra),
    );
    Run {
        out: out.to_path_buf(),
        status: o.status,
        stdout: text(&o.stdout),
        stderr: text(&o.stderr),
    }
}

/// A scenario given as TOML text, edited as a table.
#[derive(Clone)]
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

/// The number after `key` in `text` (e.g. `number_after(msg, "t = ")`).
pub fn number_after(text: &str, key: &str) -> Option<f64> {
    let rest = &text[text.find(key)? + key.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+')))
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// `[bridge]` of a 40 m simply supported span with vertical, lateral and torsional modes
/// (the lowest 6, 2 % damping), followed by `tracks` (its track keys or tables).
pub fn span_40m(tracks: &str) -> String {
    format!(
        r#"[bridge]
kind = "simply_supported"
span_m = 40.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 6.0
inertia_lateral_m4 = 40.0
shear_modulus_pa = 1.5e10
torsion_constant_m4 = 12.0
polar_inertia_kg_m = 2.0e5
mass_per_length_kg_m = 1.8e4
modes = 6
damping_ratio = 0.02
{tracks}
"#
    )
}

/// `[coupling]` iterated to 1e-12, stopping rather than accepting a step that does not
/// converge: the co-simulation then equals the monolithic solution to about 1e-8.
pub const TIGHT_COUPLING: &str = r#"[coupling]
scheme = "implicit"
rtol = 1e-12
atol = 1e-12
on_non_convergence = "stop"
"#;

/// Probes at the quarter points and midspan of [`span_40m`]: `p10`, `p20`, `p30`.
pub const PROBES_40M: &str = r#"[[probe]]
name = "p10"
x_m = 10.0
[[probe]]
name = "p20"
x_m = 20.0
[[probe]]
name = "p30"
x_m = 30.0
"#;
