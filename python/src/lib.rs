//! `tbi._native`: the tool's scenarios, runs, exports and modes for the Python package `tbi`
//! (`python/tbi/__init__.py` holds the Python API; this module is its Rust core).
//!
//! Every function that runs Rust code releases the GIL while it does, so that runs in
//! several Python threads proceed in parallel. Errors are raised as `ScenarioError` (the
//! scenario is refused: the message names the file, field and value, as the command line
//! does) or `SimulationError` (anything else: a run that failed, an unwritable folder).

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use tbi::scenario::{Scenario, SolverKind};
use tbi_dynamics::InputError;

create_exception!(
    _native,
    ScenarioError,
    PyValueError,
    "A scenario refused (a ValueError): the message names the file, the field and the value."
);
create_exception!(
    _native,
    SimulationError,
    PyRuntimeError,
    "A run, an export or a modal analysis that failed (a RuntimeError)."
);

/// Why a call failed, before it becomes a Python exception (made with the GIL held).
enum Failure {
    Scenario(String),
    Simulation(String),
}

impl From<Failure> for PyErr {
    fn from(f: Failure) -> PyErr {
        match f {
            Failure::Scenario(m) => ScenarioError::new_err(m),
            Failure::Simulation(m) => SimulationError::new_err(m),
        }
    }
}

/// A boxed error as a [`Failure`]: scenario errors by their type, and an option refused
/// (its message names the option, `--trains A11: …`), as scenario errors; the rest as
/// simulation.
fn classify(e: Box<dyn std::error::Error>) -> Failure {
    match e.downcast_ref::<InputError>() {
        Some(i) => Failure::Scenario(i.to_string()),
        None if e.to_string().starts_with("--") => Failure::Scenario(e.to_string()),
        None => Failure::Simulation(e.to_string()),
    }
}

/// The scenario of a file (`path`) or of TOML text (`text`, named `origin` in messages, its
/// relative file names resolved against `base_dir`), with the solver overridden.
fn load(
    path: Option<&str>,
    text: Option<&str>,
    origin: &str,
    base_dir: &str,
    solver: Option<&str>,
) -> Result<Scenario, Failure> {
    let mut s = match (path, text) {
        (Some(p), _) => Scenario::from_path(Path::new(p)),
        (None, Some(t)) => Scenario::from_toml(t, origin, Path::new(base_dir)),
        (None, None) => Ok(Scenario::default_case()),
    }
    .map_err(|e| Failure::Scenario(e.to_string()))?;
    if let Some(sv) = solver {
        s.run.solver = SolverKind::parse(sv).ok_or_else(|| {
            Failure::Scenario(format!(
                "solver = \"{sv}\": expected \"monolithic\" or \"cosim\""
            ))
        })?;
    }
    Ok(s)
}

/// Run a scenario into `out` (as `tbi run --out OUT`: summary.json, history.csv, plots).
#[pyfunction]
#[pyo3(signature = (out, path=None, text=None, origin="<string>", base_dir=".", solver=None))]
fn run(
    py: Python<'_>,
    out: String,
    path: Option<String>,
    text: Option<String>,
    origin: &str,
    base_dir: &str,
    solver: Option<String>,
) -> PyResult<()> {
    let origin = origin.to_owned();
    let base_dir = base_dir.to_owned();
    py.allow_threads(move || -> Result<(), Failure> {
        let s = load(
            path.as_deref(),
            text.as_deref(),
            &origin,
            &base_dir,
            solver.as_deref(),
        )?;
        tbi::solve::run_scenario(&s, Path::new(&out), false, &tbi::model::Limits::default())
            .map(drop)
            .map_err(classify)
    })?;
    Ok(())
}

/// The EN 1991-2 design check of the scenario file `path` (None: the embedded default) into
/// `out`, as `tbi sweep PATH --trains … --out OUT`: `envelope.csv`, `summary.txt`,
/// `report.html`, `governing/`. Returns whether every check passed and the summary's text.
#[pyfunction]
#[pyo3(signature = (out, trains, path=None, speeds=Vec::new(), track="ballasted", comfort="very-good", alpha=1.0, maintenance="careful", solver=None, all_modes=false, keep_histories=false, allow_large=false))]
#[allow(clippy::too_many_arguments)]
fn design_check(
    py: Python<'_>,
    out: String,
    trains: Vec<String>,
    path: Option<String>,
    speeds: Vec<String>,
    track: &str,
    comfort: &str,
    alpha: f64,
    maintenance: &str,
    solver: Option<String>,
    all_modes: bool,
    keep_histories: bool,
    allow_large: bool,
) -> PyResult<(bool, String)> {
    let args = tbi::design::SweepOptions {
        scenario: path.map(PathBuf::from),
        speeds,
        trains,
        track: track.into(),
        comfort: comfort.into(),
        all_modes,
        keep_histories,
        alpha,
        maintenance: maintenance.into(),
        wind_speeds: Vec::new(),
        wheel_unloading_limit: 0.9,
        solver,
        out: PathBuf::from(out),
        allow_large,
    };
    let done = py.allow_threads(move || -> Result<(bool, String), Failure> {
        let base = tbi::scenario::load(args.scenario.as_deref(), args.solver.as_deref(), None)
            .map_err(Failure::Scenario)?;
        let speeds = tbi::design::speeds::of(&args, &base).map_err(classify)?;
        let done = tbi::design::hslm::run(&args, &speeds).map_err(classify)?;
        Ok((done.passed, done.text))
    })?;
    Ok(done)
}

/// The paths an export wrote: the bridge FMU, every train FMU, the wind FMU (in a turbulent
/// wind) and the SSP.
type Written = (String, Vec<String>, Option<String>, String);

/// Export a scenario's FMUs and SSP into `out` (as `tbi export --fmi-version V`); their
/// paths.
#[pyfunction]
#[pyo3(signature = (out, path=None, text=None, origin="<string>", base_dir=".", fmi_version=2))]
fn export(
    py: Python<'_>,
    out: String,
    path: Option<String>,
    text: Option<String>,
    origin: &str,
    base_dir: &str,
    fmi_version: u8,
) -> PyResult<Written> {
    let origin = origin.to_owned();
    let base_dir = base_dir.to_owned();
    Ok(py.allow_threads(move || -> Result<_, Failure> {
        let version = tbi::fmus::export::FmiVersion::from_major(fmi_version)
            .map_err(|e| Failure::Scenario(format!("fmi_version: {e}")))?;
        let s = load(path.as_deref(), text.as_deref(), &origin, &base_dir, None)?;
        let e =
            tbi::fmus::export::export_scenario(&s, Path::new(&out), version).map_err(classify)?;
        let show = |p: &Path| p.display().to_string();
        let trains = std::iter::once(show(&e.train))
            .chain(e.more_trains.iter().map(|t| show(&t.path)))
            .collect();
        let wind = e.wind.as_ref().map(|w| show(&w.0));
        Ok((show(&e.bridge), trains, wind, show(&e.ssp)))
    })?)
}

/// The scenario bridge's modes as JSON: `[{"mode", "label", "frequency_hz",
/// "damping_ratio"}, …]` (as `tbi modes`).
#[pyfunction]
#[pyo3(signature = (path=None, text=None, origin="<string>", base_dir="."))]
fn modes(
    py: Python<'_>,
    path: Option<String>,
    text: Option<String>,
    origin: &str,
    base_dir: &str,
) -> PyResult<String> {
    let origin = origin.to_owned();
    let base_dir = base_dir.to_owned();
    Ok(py.allow_threads(move || -> Result<_, Failure> {
        let s = load(path.as_deref(), text.as_deref(), &origin, &base_dir, None)?;
        let set = tbi::model::modes::mode_set(&s).map_err(Failure::Scenario)?;
        let bridge = tbi::model::build_bridge(&s).map_err(|e| Failure::Scenario(e.to_string()))?;
        let rows: Vec<serde_json::Value> = set
            .modes
            .iter()
            .enumerate()
            .map(|(k, m)| {
                serde_json::json!({
                    "mode": k + 1,
                    "label": m.label,
                    "frequency_hz": m.frequency_hz,
                    "damping_ratio": bridge.damping.get(k).copied(),
                })
            })
            .collect();
        serde_json::to_string(&rows).map_err(|e| Failure::Simulation(e.to_string()))
    })?)
}

/// Check a scenario (as every command does before it runs); raises `ScenarioError`.
#[pyfunction]
#[pyo3(signature = (path=None, text=None, origin="<string>", base_dir=".", solver=None))]
fn check(
    path: Option<String>,
    text: Option<String>,
    origin: &str,
    base_dir: &str,
    solver: Option<String>,
) -> PyResult<()> {
    load(
        path.as_deref(),
        text.as_deref(),
        origin,
        base_dir,
        solver.as_deref(),
    )?;
    Ok(())
}

/// The embedded default scenario (the Tsing Ma case), TOML.
#[pyfunction]
fn default_scenario() -> &'static str {
    tbi::scenario::DEFAULT_SCENARIO
}

/// TOML text of a JSON object (a scenario given as a Python dict).
#[pyfunction]
fn toml_from_json(json: &str) -> PyResult<String> {
    let value: toml::Value = serde_json::from_str(json)
        .map_err(|e| ScenarioError::new_err(format!("<dict>: not a scenario table: {e}")))?;
    toml::to_string(&value)
        .map_err(|e| ScenarioError::new_err(format!("<dict>: not a scenario table: {e}")))
}

/// JSON of TOML text, named `origin` in messages.
#[pyfunction]
fn toml_to_json(text: &str, origin: &str) -> PyResult<String> {
    let value: toml::Value = toml::from_str(text)
        .map_err(|e| ScenarioError::new_err(format!("{origin}: {}", e.message())))?;
    serde_json::to_string(&value).map_err(|e| SimulationError::new_err(e.to_string()))
}

/// The folders holding the FMU libraries `libbridge.so`, `libtrain.so`, `libwind.so` that
/// co-simulation and export pack into FMUs: the package's own copy (`tbi/_lib`; set once).
#[pyfunction]
fn set_library_dirs(dirs: Vec<String>) {
    tbi::fmus::export::set_library_dirs(dirs.into_iter().map(PathBuf::from).collect());
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(default_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(toml_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(toml_to_json, m)?)?;
    m.add_function(wrap_pyfunction!(set_library_dirs, m)?)?;
    m.add_function(wrap_pyfunction!(design_check, m)?)?;
    Ok(())
}
