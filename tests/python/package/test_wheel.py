"""The wheel installs anywhere: copied to an empty folder and installed into a fresh venv, it
runs ``tbi.run`` with both solvers and ``tbi.export`` from a working folder outside the
checkout, with the FMU libraries it ships (``tbi/_lib``): the shared objects ``tbi.export``
packs into the FMUs are byte for byte the files inside the installed package.
"""

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]

SCRIPT = r'''
import json, pathlib, sys, zipfile
import tbi
here = pathlib.Path(tbi.__file__).resolve().parent
scenario = pathlib.Path(sys.argv[1]).read_text()
for solver in ("monolithic", "cosim"):
    r = tbi.run(scenario, solver=solver)
    assert r.summary["status"] == "ok", r.summary
    print(solver, r.summary["probes"]["mid"]["vertical_displacement_max_m"])
tbi.export(scenario, out="fmus")
for name, lib in (("bridge", "libbridge.so"), ("train", "libtrain.so")):
    with zipfile.ZipFile(f"fmus/{name}.fmu") as z:
        packed = z.read(f"binaries/linux64/{name}.so")
    assert packed == (here / "_lib" / lib).read_bytes(), name
print("package", here)
'''


def test_the_wheel_runs_in_a_fresh_venv_outside_the_checkout(tmp_path):
    wheels = sorted((REPO / "target" / "wheels").glob("tbi-*.whl"))
    assert len(wheels) == 1, wheels
    with zipfile.ZipFile(wheels[0]) as z:
        names = z.namelist()
    for lib in ("libbridge.so", "libtrain.so", "libwind.so"):
        assert f"tbi/_lib/{lib}" in names, names
    empty = tmp_path / "empty"
    empty.mkdir()
    wheel = Path(shutil.copy(wheels[0], empty))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("TBI_FMU_LIB_DIR", "PYTHONPATH")}
    subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(wheel)],
        check=True,
        env=env,
    )
    work = tmp_path / "work"
    work.mkdir()
    scenario = REPO / "master" / "tests" / "data" / "yang-yau.toml"
    shutil.copy(scenario, work / "yang-yau.toml")
    (work / "check.py").write_text(SCRIPT)
    done = subprocess.run(
        [str(python), "check.py", "yang-yau.toml"],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert "monolithic" in done.stdout and "cosim" in done.stdout
    package = Path(done.stdout.split("package ", 1)[1].strip())
    assert venv in package.parents, package
    assert REPO not in package.parents


def test_the_exceptions_are_value_and_runtime_errors():
    import tbi

    assert issubclass(tbi.ScenarioError, ValueError)
    assert issubclass(tbi.SimulationError, RuntimeError)
