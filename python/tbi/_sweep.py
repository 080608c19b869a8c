"""``tbi.sweep``: one run per combination of scenario values, on the local cores or as the
tasks of a Dask cluster."""

import copy
import itertools
import os
import uuid
from concurrent.futures import ThreadPoolExecutor

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
    """Set the dotted ``key`` (``"run.speed_kmh"``) of a scenario dict to ``value``."""
    from . import ScenarioError

    parts = key.split(".")
    table = scenario
    for i, part in enumerate(parts[:-1]):
        nxt = table.get(part)
        if nxt is None:
            nxt = table[part] = {}
        if not isinstance(nxt, dict):
            where = ".".join(parts[: i + 1])
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


def sweep(base=None, vary=None, client=None, solver=None, retries=3, workers=None):
    """Run every combination of ``vary``'s values on the scenario ``base``.

    Args:
        base: the scenario (dict, path, TOML text or None for the embedded default).
        vary: ``{"run.speed_kmh": [100, 200], "track.irregularity.seed": [1, 2]}``: dotted
            scenario keys and their values; the cases are their Cartesian product, in order.
        client: a ``dask.distributed.Client``: each case is one task on the cluster's
            workers (a lost worker's cases are run again elsewhere; a task that raises is
            retried ``retries`` times). Default None: the local cores, in threads.
        solver: ``"cosim"`` or ``"monolithic"`` (default the scenario's).
        workers: threads for a local sweep (default the number of cores).

    Returns:
        a pandas DataFrame, one row per case: the varied values, ``status`` (``"ok"`` or
        ``"failed"``), ``error``, ``steps``, ``wall_time_s``, and the summary maxima
        (``<probe>.<key>``, ``vehicles.<key>``, ``safety.<key>``, with co-simulation
        ``coupling.iterations_mean``). A failing case is reported in its row and does not
        stop the others.
    """
    import pandas as pd

    from . import as_dict

    vary = dict(vary or {})
    for key, values in vary.items():
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            from . import ScenarioError

            raise ScenarioError(f"vary: {key}: expected a list of values, got {values!r}")
    scenario, base_dir = as_dict(base)
    keys = list(vary)
    cases = [list(zip(keys, combo)) for combo in itertools.product(*(list(vary[k]) for k in keys))]
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
    return pd.DataFrame(rows)
