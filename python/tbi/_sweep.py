"""``tbi.sweep``: one run per combination of scenario values, on the local cores or as the
tasks of a Dask cluster."""

import copy
import itertools
import os
import re
import shutil
import uuid
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

# The most cases of one sweep (as the command line's --speeds ranges).
MAX_CASES = 100_000

# Summary keys of a row besides the varied values (probe maxima are `<probe>.<key>`).
_VEHICLE_KEYS = ("vertical_acceleration_max_m_s2", "lateral_acceleration_max_m_s2")
_SAFETY_KEYS = (
    "derail_factor_max",
    "offload_factor_max",
    "derail_factor_wheel_max",
    "offload_factor_wheel_max",
    "lateral_force_max_n",
)


def _assign(scenario, key, value):
    """Set the dotted ``key`` (``"run.speed_kmh"``) of a scenario dict to ``value``; a part
    ``name[k]`` is the k-th (1-based) table of an array of tables (``"train[2].speed_kmh"``,
    as the scenario's messages name it)."""
    from . import ScenarioError

    parts = key.split(".")
    table = scenario
    for i, part in enumerate(parts[:-1]):
        where = ".".join(parts[: i + 1])
        name, k = part, None
        if part.endswith("]") and "[" in part:
            name, index = part[:-1].split("[", 1)
            if not index.isdigit() or int(index) < 1:
                raise ScenarioError(f"vary: {key}: {where}: the index must be 1, 2, …")
            k = int(index)
        nxt = table.get(name)
        if nxt is None and k is None:
            nxt = table[name] = {}
        if k is not None:
            if isinstance(nxt, dict) and k == 1:
                nxt = [nxt]
                table[name] = nxt
            if not isinstance(nxt, list) or k > len(nxt):
                n = len(nxt) if isinstance(nxt, list) else 0
                raise ScenarioError(f"vary: {key}: {where}: there are {n} tables [[{name}]]")
            nxt = nxt[k - 1]
        if not isinstance(nxt, dict):
            raise ScenarioError(f"vary: {key}: {where} = {nxt!r} is not a table")
        table = nxt
    table[parts[-1]] = value


def _row(values, summary):
    row = dict(values)
    row["status"] = summary.get("status")
    row["error"] = summary.get("error")
    row["steps"] = summary.get("steps")
    row["wall_time_s"] = summary.get("wall_time_s")
    for probe, m in sorted(summary.get("probes", {}).items()):
        for k, v in m.items():
            if k != "x_m":
                row[f"{probe}.{k}"] = v
    for k in _VEHICLE_KEYS:
        row[f"vehicles.{k}"] = summary.get("vehicles", {}).get(k)
    for k in _SAFETY_KEYS:
        row[f"safety.{k}"] = summary.get("safety", {}).get(k)
    for t in summary.get("trains", []):
        k = t.get("train")
        for group in ("car_bodies", "safety"):
            for key, v in (t.get(group) or {}).items():
                row[f"train{k}.{key}"] = v
    coupling = summary.get("coupling")
    if coupling:
        row["coupling.iterations_mean"] = coupling.get("iterations_mean")
    return row


def run_case(payload):
    """One case of a sweep (a Dask task): the row of its varied values and summary maxima;
    a refused or failed case is a row with ``status = "failed"`` and the message in
    ``error``."""
    from . import ScenarioError, SimulationError, _summary

    base, base_dir, values, solver = payload
    scenario = copy.deepcopy(base)
    try:
        for key, value in values:
            _assign(scenario, key, value)
        summary = _summary(scenario, solver=solver, base_dir=base_dir)
    except (ScenarioError, SimulationError) as e:
        row = dict(values)
        row.update(status="failed", error=f"{type(e).__name__}: {e}")
        return row
    return _row(values, summary)


def _check_vary(scenario, base_dir, vary, solver):
    """Refuse a ``vary`` whose keys or values the scenario refuses, before any case runs:
    every value of every key set on the scenario (the other keys at their first values) and
    checked as a scenario file is (the message names the field, the value and the close
    valid name)."""
    from . import ScenarioError, _native, _source

    firsts = {k: v[0] for k, v in vary.items() if v}
    for key, values in vary.items():
        for value in values:
            case = copy.deepcopy(scenario)
            for k, v in firsts.items():
                _assign(case, k, value if k == key else v)
            try:
                _native.check(solver=solver, **_source(case, base_dir))
            except ScenarioError as e:
                # the line of the TOML made from the dict means nothing to the caller
                message = re.sub(r"^<dict>(:\d+)?: ", "", str(e))
                raise ScenarioError(f"vary: {key} = {value!r}: {message}") from None


def _design_check(base, trains, speeds, out, solver, options):
    """``tbi.sweep(trains=…)``: the design check, its ``envelope.csv`` as a DataFrame."""
    import pandas as pd

    from . import ScenarioError, _native, _source, _temporary_folder

    if isinstance(trains, str):
        trains = [trains]
    if isinstance(speeds, str):
        speeds = [speeds]
    speeds = [str(v) for v in (speeds or [])]
    work = Path(_temporary_folder("tbi-check")) if out is None else Path(out)
    try:
        src = _source(base)
        path = src.get("path")
        if "text" in src:
            # a dict or text: checked as a file beside the results
            work.mkdir(parents=True, exist_ok=True)
            path = work / "scenario.toml"
            path.write_text(src["text"], encoding="utf-8")
        passed, text = _native.design_check(
            os.fspath(work),
            list(trains),
            path=None if path is None else os.fspath(path),
            speeds=speeds,
            solver=solver,
            **options,
        )
        table = pd.read_csv(work / "envelope.csv", keep_default_na=False, na_values={
            "car_body_acceleration_max_m_s2": [""],
        })
        table.attrs.update(passed=passed, summary=text, out=None if out is None else work)
        return table
    except TypeError as e:
        raise ScenarioError(f"sweep: {e}") from None
    finally:
        if out is None:
            shutil.rmtree(work, ignore_errors=True)


def sweep(
    base=None,
    vary=None,
    client=None,
    solver=None,
    retries=3,
    workers=None,
    *,
    trains=None,
    speeds=None,
    out=None,
    track="ballasted",
    comfort="very-good",
    alpha=1.0,
    maintenance="careful",
):
    """Run every combination of ``vary``'s values on the scenario ``base``.

    Args:
        base: the scenario (dict, path, TOML text or None for the embedded default).
        vary: ``{"run.speed_kmh": [100, 200], "track.irregularity.seed": [1, 2]}``: dotted
            scenario keys and their values; the cases are their Cartesian product, in order.
            ``train[2].speed_kmh`` is a key of the second of several trains (``[[train]]``);
            the rows then also hold each train's maxima as ``train2.derail_factor_max``, …
        client: a ``dask.distributed.Client``: each case is one task on the cluster's
            workers (a lost worker's cases are run again elsewhere; a task that raises is
            retried ``retries`` times). Default None: the local cores, in threads.
        solver: ``"cosim"`` or ``"monolithic"`` (default the scenario's).
        workers: threads for a local sweep (default the number of cores).
        trains: ``"hslm-a"`` (A1–A10) or names such as ``["A1", "A4"]``: instead of ``vary``,
            the EN 1991-2 design check of ``tbi sweep --trains`` (``speeds``, ``out``,
            ``track``, ``comfort``, ``alpha``, ``maintenance`` as its options; ``speeds``
            default 144 km/h to 1.2 × the scenario's speed). Returns the rows of its
            ``envelope.csv``; ``.attrs`` holds ``passed`` (every check), ``summary`` (the
            printed summary) and ``out`` (the folder with ``report.html`` and
            ``governing/``, or None when ``out`` was not given and the folder is removed).
            A dict or TOML text is checked as ``scenario.toml`` in that folder.

    Returns:
        a pandas DataFrame, one row per case: the varied values, ``status`` (``"ok"`` or
        ``"failed"``), ``error``, ``steps``, ``wall_time_s``, and the summary maxima
        (``<probe>.<key>``, ``vehicles.<key>``, ``safety.<key>``, with co-simulation
        ``coupling.iterations_mean``). A failing case is reported in its row and does not
        stop the others.
    """
    import pandas as pd

    from . import ScenarioError, as_dict

    if trains is not None:
        if vary:
            raise ScenarioError("sweep: give vary or trains, not both")
        options = dict(track=track, comfort=comfort, alpha=float(alpha), maintenance=maintenance)
        return _design_check(base, trains, speeds, out, solver, options)
    vary = dict(vary or {})
    for key, values in vary.items():
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            raise ScenarioError(f"vary: {key}: expected a list of values, got {values!r}")
    vary = {k: list(v) for k, v in vary.items()}
    count = 1
    for values in vary.values():
        count *= len(values)
    if count > MAX_CASES:
        raise ScenarioError(f"vary: {count} cases, more than {MAX_CASES}; split the sweep")
    scenario, base_dir = as_dict(base)
    _check_vary(scenario, base_dir, vary, solver)
    keys = list(vary)
    cases = [list(zip(keys, combo)) for combo in itertools.product(*(vary[k] for k in keys))]
    payloads = [(scenario, base_dir, values, solver) for values in cases]
    if client is None:
        with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
            rows = list(pool.map(run_case, payloads))
    else:
        token = uuid.uuid4().hex
        futures = client.map(
            run_case,
            payloads,
            key=[f"tbi-case-{i}-{token}" for i in range(len(payloads))],
            retries=retries,
            pure=False,
        )
        rows = client.gather(futures)
    table = pd.DataFrame(rows)
    if "error" in table:
        # None or a message, never NaN
        table["error"] = table["error"].astype(object).where(table["error"].notna(), None)
    return table
