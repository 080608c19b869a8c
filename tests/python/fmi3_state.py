"""An FMI 3.0 FMU's state through FMPy's FMI 3.0 API: step, save the state, serialize
it, step on (the uninterrupted run); then deserialize the bytes, set the state and step
the same steps again (resumed); then step on without restoring (continued, which must
differ, or the check proves nothing). Every input follows the same small signal of the
step number in each run, so the FMU moves. Prints one JSON line: the outputs of the
three continuations as the hex of their doubles, so the caller compares them bit for bit.

usage: fmi3_state.py FMU STEP STEPS_BEFORE STEPS_AFTER
"""
import json
import math
import shutil
import struct
import sys

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

fmu, h, before, after = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
md = read_model_description(fmu)
outputs = [v.valueReference for v in md.modelVariables if v.causality == 'output']
inputs = [v.valueReference for v in md.modelVariables
          if v.causality == 'input' and v.type == 'Float64']
unzipdir = extract(fmu)
try:
    slave = FMU3Slave(guid=md.guid, unzipDirectory=unzipdir,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName='a')
    slave.instantiate()
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()

    def run(t, n):
        rows = []
        for _ in range(n):
            k = round(t / h)
            slave.setFloat64(inputs, [1e-3 * (1 + 0.5 * math.sin(0.1 * k + i))
                                      for i in range(len(inputs))])
            slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t += h
            rows.append(''.join(struct.pack('<d', x).hex() for x in slave.getFloat64(outputs)))
        return t, rows

    t, _ = run(0.0, before)
    state = slave.getFMUState()
    blob = slave.serializeFMUState(state)
    slave.freeFMUState(state)
    _, uninterrupted = run(t, after)
    restored = slave.deserializeFMUState(blob)
    slave.setFMUState(restored)
    slave.freeFMUState(restored)
    t2, resumed = run(t, after)
    _, continued = run(t2, after)
    slave.terminate()
    slave.freeInstance()
finally:
    shutil.rmtree(unzipdir, ignore_errors=True)
print(json.dumps({'bytes': len(blob), 'outputs': len(outputs),
                  'uninterrupted': uninterrupted, 'resumed': resumed,
                  'continued': continued}))
