"""The Python package tbi (python/): the same results as the command line, sweeps on the local
cores and on a Dask cluster (also when a worker process dies), errors by name.

Run by tests/run.sh after tests/python/install-package.sh built the package into the venv:
    target/venv/bin/python -m pytest tests/python/package
"""

import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import pandas as pd
import pytest

import tbi

REPO = Path(__file__).resolve().parents[3]
CLI = REPO / "target" / "release" / "tbi"
DATA = REPO / "master" / "tests" / "data"
SCENARIOS = sorted(DATA.glob("*.toml"))


SPAN_20 = """name = "span-20m"
[run]
speed_kmh = 300.0
solver = "monolithic"
free_vibration_s = 0.0
[bridge]
kind = "simply_supported"
span_m = 20.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 0.9
mass_per_length_kg_m = 12000.0
modes = 3
damping = { rule = "en1991-2", structure = "prestressed_concrete" }
[train]
kind = "hslm_a"
name = "A1"
[[probe]]
name = "mid"
x_m = 10.0
"""


def cli(*args):
    return subprocess.run([str(CLI), *map(str, args)], capture_output=True, text=True)


def comparable(summary):
    """A summary without what differs between two runs of the same case: the wall time, the
    steps made ahead on a second core (chosen by timing) and the folders of the run."""
    s = json.loads(json.dumps(summary))
    s.pop("wall_time_s", None)
    s.pop("steps_ahead", None)
    for key in ("bridge_fmu", "train_fmu"):
        (s.get("coupling") or {}).pop(key, None)
    return s


def test_there_are_test_scenarios():
    assert len(SCENARIOS) >= 3, SCENARIOS


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: p.stem)
@pytest.mark.parametrize("solver", ["monolithic", "cosim"])
def test_run_equals_the_command_line(tmp_path, scenario, solver):
    done = cli("run", scenario, "--solver", solver, "--quiet", "--out", tmp_path / "cli")
    # 3: the run finished and a limit check of its summary FAILs (stiff-20m's deck)
    assert done.returncode in (0, 3), done.stderr
    r = tbi.run(scenario, solver=solver, out=tmp_path / "py")
    with open(tmp_path / "cli" / "summary.json", encoding="utf-8") as f:
        expected = json.load(f)
    assert comparable(r.summary) == comparable(expected)
    assert r.summary["solver"] == solver
    assert (r.coupling is None) == (solver == "monolithic")
    # history.csv: the same bytes, and the DataFrame is that file
    cli_history = (tmp_path / "cli" / "history.csv").read_bytes()
    assert (tmp_path / "py" / "history.csv").read_bytes() == cli_history
    pd.testing.assert_frame_equal(r.history, pd.read_csv(tmp_path / "cli" / "history.csv"))
    # without out: the same results, nothing left behind
    r2 = tbi.run(scenario, solver=solver)
    assert r2.out is None
    assert comparable(r2.summary) == comparable(expected)
    pd.testing.assert_frame_equal(r2.history, r.history)


def test_a_scenario_as_dict_or_text_equals_the_file(tmp_path):
    path = DATA / "yang-yau.toml"
    base, base_dir = tbi.as_dict(path)
    assert base_dir == str(DATA)
    by_path = tbi.run(path)
    by_dict = tbi.run(base)
    by_text = tbi.run(path.read_text(encoding="utf-8"))
    for r in (by_dict, by_text):
        assert comparable(r.summary) == comparable(by_path.summary)
        pd.testing.assert_frame_equal(r.history, by_path.history)


def test_default_scenario_export_and_modes(tmp_path):
    import tomllib

    done = cli("scenario", "show")
    assert done.returncode == 0
    assert tbi.default_scenario() == tomllib.loads(done.stdout)
    paths = tbi.export(DATA / "yang-yau.toml", out=tmp_path)
    assert sorted(paths) == ["bridge", "ssp", "train", "trains"]
    assert [paths[k].name for k in ("bridge", "train", "ssp")] == ["bridge.fmu", "train.fmu", "system.ssp"]
    assert paths["trains"] == [paths["train"]]
    import fmpy

    result = fmpy.simulate_fmu(str(paths["bridge"]), stop_time=0.01)
    assert len(result) > 1
    m = tbi.modes(DATA / "yang-yau.toml")
    assert list(m.columns) == ["mode", "label", "frequency_hz", "damping_ratio"]
    summary = tbi.run(DATA / "yang-yau.toml", solver="monolithic").summary
    assert m["frequency_hz"].tolist() == summary["bridge"]["frequencies_hz"]


def test_export_of_two_trains_as_fmi3_gives_every_fmu(tmp_path):
    import fmpy

    paths = tbi.export(TWO_TRAINS, out=tmp_path / "fmus", fmi_version=3)
    assert [p.name for p in paths["trains"]] == ["train.fmu", "train2.fmu"]
    for fmu in [paths["bridge"], *paths["trains"]]:
        assert fmpy.read_model_description(str(fmu)).fmiVersion == "3.0", fmu
    # the command line writes the same FMUs (the same instantiation tokens)
    (tmp_path / "two.toml").write_text(TWO_TRAINS)
    done = cli("export", tmp_path / "two.toml", "--fmi-version", "3", "--out", tmp_path / "cli")
    assert done.returncode == 0, done.stderr
    for fmu in [paths["bridge"], *paths["trains"]]:
        ours = fmpy.read_model_description(str(fmu)).guid
        theirs = fmpy.read_model_description(str(tmp_path / "cli" / fmu.name)).guid
        assert ours == theirs, fmu.name
    with pytest.raises(tbi.ScenarioError, match="fmi_version"):
        tbi.export(TWO_TRAINS, out=tmp_path / "bad", fmi_version=4)


def test_bad_scenarios_raise_scenario_error_with_the_cli_message(tmp_path):
    text = (DATA / "yang-yau.toml").read_text(encoding="utf-8")
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("speed_kmh = 100.0", "speed_kmh = -5.0"), encoding="utf-8")
    done = cli("run", bad, "--quiet", "--out", tmp_path / "cli")
    assert done.returncode == 1
    with pytest.raises(tbi.ScenarioError) as e:
        tbi.run(bad, out=tmp_path / "py")
    assert "run.speed_kmh" in str(e.value) and "-5" in str(e.value)
    assert done.stderr.strip() == f"tbi: error: {e.value}"
    assert not (tmp_path / "py" / "summary.json").exists()
    base, _ = tbi.as_dict(DATA / "yang-yau.toml")
    base["bridge"]["modes"] = 0
    with pytest.raises(tbi.ScenarioError, match="bridge.modes"):
        tbi.run(base)
    base["bridge"]["modes"] = 3
    with pytest.raises(tbi.ScenarioError, match="solver"):
        tbi.run(base, solver="magic")
    with pytest.raises(TypeError):
        tbi.run(42)
    # NaN or an infinity is named by its key, as a scenario file's would be
    base["run"]["speed_kmh"] = float("nan")
    with pytest.raises(tbi.ScenarioError, match=r"<dict>: run.speed_kmh = nan is not a finite number"):
        tbi.run(base)
    base["run"]["speed_kmh"] = 100.0
    base["train"]["axles"] = [{"offset_m": 0.0, "load_n": float("inf")}]
    with pytest.raises(tbi.ScenarioError, match=r"train.axles\[0\].load_n = inf"):
        tbi.run(base)
    with pytest.raises(tbi.ScenarioError, match="run.speed_kmh"):
        tbi.sweep(DATA / "yang-yau.toml", vary={"run.speed_kmh": [80.0, float("nan")]})
    # a long value is not echoed in full
    with pytest.raises(tbi.ScenarioError) as e:
        tbi.run({**tbi.as_dict(DATA / "yang-yau.toml")[0], "name": "x" * (10 << 20)})
    assert len(str(e.value)) < 1000 and "characters)" in str(e.value)


def test_folders_of_killed_runs_are_removed():
    import tempfile

    stale = Path(tempfile.gettempdir()) / "tbi-run-4194399-abc"
    (stale / "run").mkdir(parents=True, exist_ok=True)
    tbi.run(DATA / "yang-yau.toml", solver="monolithic")
    assert not stale.exists()
    assert not list(Path(tempfile.gettempdir()).glob(f"tbi-run-{os.getpid()}-*"))


def test_a_failing_case_is_reported_in_its_row():
    # a track record that is missing fails when its case runs
    missing = {"file": "missing.csv"}
    rows = tbi.sweep(
        DATA / "yang-yau.toml",
        vary={"track.irregularity": ["none", missing, "none"]},
        solver="monolithic",
    )
    assert rows["status"].tolist() == ["ok", "failed", "ok"]
    assert "ScenarioError" in rows["error"][1] and "missing.csv" in rows["error"][1]
    assert rows["error"][0] is None and rows["error"][2] is None
    assert rows["mid.vertical_displacement_max_m"][0] > 0


def test_vary_is_checked_before_any_case_runs():
    # a misspelled key: refused with the close name, a ValueError
    with pytest.raises(tbi.ScenarioError, match="did you mean `speed_kmh`") as e:
        tbi.sweep(DATA / "yang-yau.toml", vary={"run.sped_kmh": [80.0, 120.0]})
    assert isinstance(e.value, ValueError)
    assert "<dict>" not in str(e.value)
    # a value the scenario refuses, by key and value
    with pytest.raises(tbi.ScenarioError, match=r"vary: run.speed_kmh = -5.0: .*run.speed_kmh"):
        tbi.sweep(DATA / "yang-yau.toml", vary={"run.speed_kmh": [80.0, -5.0]})
    # a key that is not a table is named
    with pytest.raises(tbi.ScenarioError, match="run.speed_kmh"):
        tbi.sweep(DATA / "yang-yau.toml", vary={"run.speed_kmh.x": [1]})
    # as many cases as the command line takes at most
    with pytest.raises(tbi.ScenarioError, match="more than 100000"):
        tbi.sweep(DATA / "yang-yau.toml", vary={"run.speed_kmh": list(range(1, 400)), "run.dt_s": [0.001] * 400})


def test_the_design_check_equals_the_command_line(tmp_path):
    span = tmp_path / "span.toml"
    span.write_text(SPAN_20)
    done = cli("sweep", span, "--trains", "hslm-a", "--speeds", "300:340:10", "--out", tmp_path / "cli")
    assert done.returncode in (0, 3), done.stderr
    want = pd.read_csv(tmp_path / "cli" / "envelope.csv", keep_default_na=False,
                       na_values={"car_body_acceleration_max_m_s2": [""]})
    got = tbi.sweep(span, trains="hslm-a", speeds="300:340:10")
    pd.testing.assert_frame_equal(got, want)
    assert got.attrs["passed"] == (done.returncode == 0)
    assert "deck vertical acceleration" in got.attrs["summary"]
    assert got.attrs["out"] is None
    kept = tbi.sweep(span, trains=["A1", "A2"], speeds=[300, 310], out=tmp_path / "py")
    assert (tmp_path / "py" / "report.html").is_file()
    assert set(kept["train"]) == {"A1", "A2"}
    with pytest.raises(tbi.ScenarioError, match="--trains A11"):
        tbi.sweep(span, trains="A11", speeds=[300])


def test_a_local_sweep_equals_single_runs():
    speeds = [60.0, 100.0]
    rows = tbi.sweep(DATA / "yang-yau.toml", vary={"run.speed_kmh": speeds}, solver="monolithic")
    for speed, (_, row) in zip(speeds, rows.iterrows()):
        base, _ = tbi.as_dict(DATA / "yang-yau.toml")
        base["run"]["speed_kmh"] = speed
        s = tbi.run(base, solver="monolithic", base_dir=DATA).summary
        assert row["mid.vertical_displacement_max_m"] == s["probes"]["mid"]["vertical_displacement_max_m"]
        assert row["steps"] == s["steps"]


TWO_TRAINS = """name = "two-trains"
[run]
speed_kmh = 160.0
dt_s = 0.002
solver = "monolithic"
free_vibration_s = 0.2
[bridge]
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
[[bridge.track]]
eccentricity_m = 2.05
height_m = 1.25
[[bridge.track]]
eccentricity_m = -2.05
height_m = 1.25
[[train]]
kind = "coach_27dof"
track = 1
[[train]]
kind = "coach_27dof"
track = 2
direction = "backward"
meet_at_x_m = 25.0
[[probe]]
name = "mid"
x_m = 20.0
"""


def test_a_sweep_of_two_trains_varies_the_second_and_reports_both(tmp_path):
    speeds = [120.0, 200.0]
    rows = tbi.sweep(TWO_TRAINS, vary={"train[2].speed_kmh": speeds})
    assert list(rows["train[2].speed_kmh"]) == speeds
    for speed, (_, row) in zip(speeds, rows.iterrows()):
        base, _ = tbi.as_dict(TWO_TRAINS)
        base["train"][1]["speed_kmh"] = speed
        s = tbi.run(base).summary
        assert [t["speed_kmh"] for t in s["trains"]] == pytest.approx([160.0, speed])
        for k, t in enumerate(s["trains"], start=1):
            want = t["car_bodies"]["vertical_acceleration_max_m_s2"]
            assert row[f"train{k}.vertical_acceleration_max_m_s2"] == want
            assert row[f"train{k}.derail_factor_max"] == t["safety"]["derail_factor_max"]
        assert row["mid.torsion_max_rad"] == s["probes"]["mid"]["torsion_max_rad"]
    with pytest.raises(tbi.ScenarioError, match=r"train\[3\].*2 tables"):
        tbi.sweep(TWO_TRAINS, vary={"train[3].speed_kmh": [100.0]})


def without_wall_time(frame):
    return frame.drop(columns=["wall_time_s"]).reset_index(drop=True)


def local_cluster():
    import logging

    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    )
    return cluster, Client(cluster)


def test_a_sweep_on_a_local_dask_cluster_equals_the_local_sweep():
    vary = {"run.speed_kmh": [60.0, 80.0, 100.0, 120.0], "bridge.damping_ratio": [0.0, 0.02]}
    local = tbi.sweep(DATA / "yang-yau.toml", vary=vary, solver="monolithic")
    assert len(local) == 8 and (local["status"] == "ok").all()
    cluster, client = local_cluster()
    try:
        remote = tbi.sweep(DATA / "yang-yau.toml", vary=vary, solver="monolithic", client=client)
    finally:
        client.close()
        cluster.close()
    pd.testing.assert_frame_equal(without_wall_time(remote), without_wall_time(local))


def test_a_worker_killed_during_a_sweep_loses_no_case():
    # 16 co-simulation cases of about half a second each on two single-threaded workers
    vary = {"run.speed_kmh": [60.0 + 5.0 * i for i in range(16)]}
    local = tbi.sweep(DATA / "yang-yau.toml", vary=vary, solver="cosim")
    assert len(local) == 16 and (local["status"] == "ok").all()
    cluster, client = local_cluster()
    killed = {}

    def kill_one_busy_worker():
        deadline = time.time() + 60
        while time.time() < deadline and not killed:
            busy = {w: keys for w, keys in client.processing().items() if keys}
            if busy and sum(1 for f in client.futures.values() if f.status == "finished") >= 1:
                worker = sorted(busy)[0]
                pid = client.run(os.getpid, workers=[worker])[worker]
                os.kill(pid, signal.SIGKILL)
                killed.update(worker=worker, pid=pid, processing=len(busy[worker]))
                return
            time.sleep(0.05)

    killer = threading.Thread(target=kill_one_busy_worker)
    try:
        killer.start()
        remote = tbi.sweep(DATA / "yang-yau.toml", vary=vary, solver="cosim", client=client)
        killer.join()
    finally:
        client.close()
        cluster.close()
    assert killed, "no worker was killed during the sweep"
    assert killed["processing"] >= 1
    with pytest.raises(ProcessLookupError):
        os.kill(killed["pid"], 0)
    assert len(remote) == 16
    pd.testing.assert_frame_equal(without_wall_time(remote), without_wall_time(local))
