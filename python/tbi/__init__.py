"""Train–bridge dynamic interaction from Python.

The tool's scenarios, both solvers (monolithic and the co-simulation of the bridge and train
FMUs), the FMU export and the bridge's modes, with the results as pandas DataFrames, and
sweeps over any scenario keys on the local cores or on a Dask cluster::

    import tbi
    r = tbi.run("scenario.toml")                  # or a dict, or TOML text
    r.summary["probes"]["mid"]["vertical_displacement_max_m"]
    r.history["mid.vertical_acceleration_m_s2"].abs().max()
    table = tbi.sweep(r.scenario, vary={"run.speed_kmh": [100, 200, 300]})

A run with ``out=None`` works in a temporary folder that is removed afterwards; with ``out``
it writes the same files as ``tbi run --out OUT`` (``summary.json``, ``history.csv``, the
plots, and for co-simulation the FMUs), and ``Result.summary`` / ``Result.history`` are those
files read back. Errors are :class:`ScenarioError` (the scenario is refused; the message names
the file, field and value as the command line does) and :class:`SimulationError`.

The Rust code runs with the GIL released: runs in several threads proceed in parallel.
"""

import json
import math
import os
import shutil
import tempfile
from pathlib import Path

from . import _native
from ._native import ScenarioError, SimulationError
from ._sweep import sweep

__all__ = [
    "Result",
    "ScenarioError",
    "SimulationError",
    "default_scenario",
    "export",
    "modes",
    "run",
    "sweep",
]

# The FMU libraries co-simulation and export pack into FMUs: the package's own copy, built
# and shipped with the wheel (tbi/_lib).
_native.set_library_dirs([str(Path(__file__).resolve().parent / "_lib")])


def _non_finite(value, key=""):
    """The first (dotted key, value) of a scenario table holding NaN or an infinity, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return key, value
    if isinstance(value, dict):
        items = ((f"{key}.{k}" if key else str(k), v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        items = ((f"{key}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for k, v in items:
        found = _non_finite(v, k)
        if found is not None:
            return found
    return None


def _source(scenario, base_dir=None):
    """The keyword arguments naming a scenario for the native functions.

    ``scenario`` is a dict (the TOML structure), a path (``str`` ending in ``.toml`` or any
    ``os.PathLike``), TOML text, or None (the embedded default scenario). Relative file names
    in a dict or text are resolved against ``base_dir`` (default the working folder).
    """
    if scenario is None:
        return {}
    base_dir = os.fspath(base_dir) if base_dir is not None else os.getcwd()
    if isinstance(scenario, dict):
        where = _non_finite(scenario)
        if where is not None:
            key, value = where
            raise ScenarioError(f"<dict>: {key} = {value!r} is not a finite number")
        try:
            text = _native.toml_from_json(json.dumps(scenario, allow_nan=False))
        except (TypeError, ValueError) as e:
            raise ScenarioError(f"<dict>: not a scenario table: {e}") from None
        return {"text": text, "origin": "<dict>", "base_dir": base_dir}
    if isinstance(scenario, os.PathLike) or (
        isinstance(scenario, str) and "\n" not in scenario and scenario.strip().endswith(".toml")
    ):
        return {"path": os.fspath(scenario)}
    if isinstance(scenario, str):
        return {"text": scenario, "origin": "<string>", "base_dir": base_dir}
    raise TypeError(
        f"scenario: expected a dict, a path, TOML text or None, not {type(scenario).__name__}"
    )


def default_scenario():
    """The embedded default scenario (the Tsing Ma case of Xia, Xu & Chan 2000) as a dict."""
    return json.loads(_native.toml_to_json(_native.default_scenario(), "<embedded default scenario>"))


def as_dict(scenario):
    """A scenario (dict, path, TOML text or None) as a dict, and the folder its relative
    file names are resolved against."""
    src = _source(scenario)
    if not src:
        return default_scenario(), os.getcwd()
    if "path" in src:
        path = Path(src["path"])
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as e:
            raise ScenarioError(f"{path}: cannot read scenario: {e}") from None
        return json.loads(_native.toml_to_json(text, str(path))), str(path.resolve().parent)
    return json.loads(_native.toml_to_json(src["text"], src["origin"])), src["base_dir"]


class Result:
    """The result of :func:`run`.

    Attributes:
        summary: dict, the keys of ``summary.json`` (maxima per probe, vehicles, safety,
            bridge, train, wall time, and for co-simulation ``coupling``).
        history: pandas DataFrame with the columns of ``history.csv`` (SI units in the names).
        coupling: dict of how the co-simulation converged (``summary["coupling"]``), or None
            for the monolithic solver.
        out: the output folder when one was given, else None.
    """

    def __init__(self, summary, history, out):
        self.summary = summary
        self.history = history
        self.coupling = summary.get("coupling")
        self.out = out

    def __repr__(self):
        s = self.summary
        return (
            f"<tbi.Result {s.get('name')!r}: {s.get('solver')}, {s.get('steps')} steps, "
            f"{s.get('speed_kmh')} km/h, status {s.get('status')!r}>"
        )


def _read_summary(out):
    with open(Path(out) / "summary.json", encoding="utf-8") as f:
        return json.load(f)


def _read(out):
    import pandas as pd

    return _read_summary(out), pd.read_csv(Path(out) / "history.csv")


def _temporary_folder(prefix):
    """A new folder ``<prefix>-<pid>-…`` in the temporary directory, after removing those
    of the same prefix whose process is gone (a run killed before it could clean up)."""
    root = Path(tempfile.gettempdir())
    if Path("/proc").is_dir():
        for folder in root.glob(f"{prefix}-*-*"):
            pid = folder.name[len(prefix) + 1 :].split("-", 1)[0]
            if pid.isdigit() and int(pid) != os.getpid() and not Path(f"/proc/{pid}").exists():
                shutil.rmtree(folder, ignore_errors=True)
    return tempfile.mkdtemp(prefix=f"{prefix}-{os.getpid()}-")


def _in_temporary_folder(src, solver, read):
    """Run into a temporary folder, return `read(folder)`, and remove the folder."""
    tmp = _temporary_folder("tbi-run")
    try:
        folder = os.path.join(tmp, "run")
        _native.run(folder, solver=solver, **src)
        return read(folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def run(scenario=None, solver=None, out=None, base_dir=None):
    """Run a scenario.

    Args:
        scenario: a dict (the TOML structure), a path to a TOML file, TOML text, or None
            for the embedded default (the Tsing Ma case).
        solver: ``"cosim"`` or ``"monolithic"``; default the scenario's ``run.solver``
            (which defaults to ``"cosim"``).
        out: output folder (as ``tbi run --out``); default a temporary folder removed after
            the results are read.
        base_dir: the folder relative file names of a dict or TOML text are resolved
            against (default the working folder; a file's own folder for a path).

    Returns:
        :class:`Result`. Raises :class:`ScenarioError` or :class:`SimulationError`.
    """
    src = _source(scenario, base_dir)
    if out is not None:
        _native.run(os.fspath(out), solver=solver, **src)
        summary, history = _read(out)
        return Result(summary, history, Path(out))
    summary, history = _in_temporary_folder(src, solver, _read)
    return Result(summary, history, None)


def _summary(scenario, solver=None, base_dir=None):
    """The summary of a run in a temporary folder (a sweep's case: no history read)."""
    return _in_temporary_folder(_source(scenario, base_dir), solver, _read_summary)


def export(scenario=None, out=".", fmi_version=2):
    """Export a scenario's ``bridge.fmu``, ``train.fmu`` and ``system.ssp`` into ``out``
    (as ``tbi export``); their paths as a dict ``{"bridge", "train", "ssp"}``, with
    ``"trains"`` (every train's FMU: ``train.fmu``, ``train2.fmu``, … for a scenario of
    several trains) and ``"wind"`` (``wind.fmu`` in a turbulent wind, else absent).

    ``fmi_version``: 2 (default) for FMI 2.0 Co-Simulation FMUs, 3 for FMI 3.0 ones (as
    ``tbi export --fmi-version 3``). ``fmpy.simulate_fmu`` runs either in the same process.
    """
    bridge, trains, wind, ssp = _native.export(
        os.fspath(out), fmi_version=fmi_version, **_source(scenario)
    )
    paths = {"bridge": Path(bridge), "train": Path(trains[0]), "ssp": Path(ssp)}
    paths["trains"] = [Path(t) for t in trains]
    if wind is not None:
        paths["wind"] = Path(wind)
    return paths


def modes(scenario=None):
    """The scenario bridge's modes as a DataFrame: ``mode``, ``label``, ``frequency_hz``,
    ``damping_ratio`` (as ``tbi modes``)."""
    import pandas as pd

    columns = ["mode", "label", "frequency_hz", "damping_ratio"]
    return pd.DataFrame(json.loads(_native.modes(**_source(scenario))), columns=columns)
