"""A plain Gauss-Jacobi co-simulation loop over FMPy's FMU2Slave, written independently of
``tbi cosim`` as the reference for its ``--scheme jacobi``.

    python jacobi_loop.py SystemStructure.ssd --step-size H --stop-time T --output CSV

Reads the SSD's components (FMUs next to the .ssd, by ``source``) and Real connections, and
runs, with the initialisation and recording order ``tbi cosim`` documents:

1. every FMU: instantiate, setupExperiment(startTime, stopTime), enterInitializationMode;
2. the connected values are passed along the connections, in connection order (get the
   output, set the input), until a round passes the same values as the one before (at most
   50 rounds); then every FMU exitInitializationMode;
3. the connected outputs are read and passed to the inputs once more; row 0 is recorded;
4. each step t -> t + h: read every connected output (values at t), set every input from
   them, fmi2DoStep(t, h) on every FMU in component order, record a row at t + h.

Rows: ``time``, then every connected output once as ``component.variable`` in connection
order, every number written with repr(). Parameter bindings are not read (the script refuses
an SSD that has any).
"""

import argparse
import os
import shutil
import sys
import xml.etree.ElementTree as ET

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ssd")
    ap.add_argument("--step-size", type=float, required=True)
    ap.add_argument("--stop-time", type=float, required=True)
    ap.add_argument("--output", required=True)
    a = ap.parse_args()

    root = ET.parse(a.ssd).getroot()
    folder = os.path.dirname(os.path.abspath(a.ssd))
    if list(root.iter(SSD + "ParameterBindings")):
        sys.exit(f"{a.ssd}: parameter bindings are not supported by this reference loop")
    experiment = root.find(SSD + "DefaultExperiment")
    start = float(experiment.get("startTime", "0")) if experiment is not None else 0.0
    stop = a.stop_time

    names, slaves, descriptions, scratch = [], [], [], []
    for c in root.iter(SSD + "Component"):
        path = os.path.join(folder, c.get("source"))
        md = read_model_description(path)
        unzipped = extract(path)
        scratch.append(unzipped)
        s = FMU2Slave(
            guid=md.guid,
            unzipDirectory=unzipped,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=c.get("name"),
        )
        s.instantiate()
        s.setupExperiment(startTime=start, stopTime=stop * (1.0 + 1e-12) + 1e-9)
        s.enterInitializationMode()
        names.append(c.get("name"))
        slaves.append(s)
        descriptions.append({v.name: v.valueReference for v in md.modelVariables})

    def vr(component, variable):
        return descriptions[names.index(component)][variable]

    connections = [
        (
            names.index(c.get("startElement")),
            vr(c.get("startElement"), c.get("startConnector")),
            names.index(c.get("endElement")),
            vr(c.get("endElement"), c.get("endConnector")),
        )
        for c in root.iter(SSD + "Connection")
    ]
    outputs = []
    for c in root.iter(SSD + "Connection"):
        name = c.get("startElement") + "." + c.get("startConnector")
        key = (names.index(c.get("startElement")), vr(c.get("startElement"), c.get("startConnector")))
        if key not in [o[1] for o in outputs]:
            outputs.append((name, key))

    # 2. inputs start from the outputs they are connected to
    last = None
    for _ in range(50):
        now = []
        for f, fv, t, tv in connections:
            v = slaves[f].getReal([fv])[0]
            slaves[t].setReal([tv], [v])
            now.append(v)
        if now == last:
            break
        last = now
    for s in slaves:
        s.exitInitializationMode()

    def transfer():
        values = {key: slaves[key[0]].getReal([key[1]])[0] for _, key in outputs}
        for f, fv, t, tv in connections:
            slaves[t].setReal([tv], [values[(f, fv)]])

    def row(time):
        return [time] + [slaves[p].getReal([v])[0] for _, (p, v) in outputs]

    # 3. the initial exchange and row 0
    transfer()
    rows = [row(start)]
    # 4. the steps
    h = a.step_size
    steps = int(round((stop - start) / h))
    if abs(start + steps * h - stop) > 1e-9 * h:
        sys.exit(f"the stop time {stop} is not a whole number of steps {h} after {start}")
    for k in range(1, steps + 1):
        t = start + (k - 1) * h
        t1 = min(start + k * h, stop)
        transfer()
        for s in slaves:
            # the nominal step, as FMPy's simulate_fmu passes it (t1 - t jitters with the
            # rounding of t)
            s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        rows.append(row(t1))

    for s in slaves:
        s.terminate()
        s.freeInstance()
    for d in scratch:
        shutil.rmtree(d, ignore_errors=True)

    with open(a.output, "w") as out:
        out.write(",".join(["time"] + [n for n, _ in outputs]) + "\n")
        for r in rows:
            out.write(",".join(repr(float(x)) for x in r) + "\n")


if __name__ == "__main__":
    main()
