"""Run an SSP system in libcosim (libcosimpy) with a fixed step and write a `tbi cosim` CSV.

    python libcosim_run.py SYSTEM.ssp --step-size H --stop-time T --output CSV

The CSV has the header of ``tbi cosim``: ``time``, then ``component.variable`` for every
connected output once, in the order of the SSD's ``ssd:Connections``; one row after
initialisation and one after each communication step; every number written with repr().

What libcosim 0.11.2 (libcosimpy 0.0.6) does, read from its source:

* ``CosimExecution.from_ssp_file(SYSTEM.ssp, step_size=ns)`` unzips the archive, starts at the
  SSD's ``DefaultExperiment startTime`` (0 when absent) and uses its ``fixed_step_algorithm``
  with the given base step. It ignores ``stopTime`` and our ``org.tbi.coupling`` annotation
  (it reads only an OSP annotation for the step), so the step size must come from here.
  It applies only the *first* ``ParameterBinding`` of each component. Times are integer
  nanoseconds, so H is rounded to a whole number of ns, and (T - start) must be a whole number
  of steps: libcosim cannot shorten the last step the way ``tbi cosim`` does.
* Initialisation: parameter values are set in the instantiated state, then
  fmi2SetupExperiment (no stop time) and fmi2EnterInitializationMode; then N rounds (N = number
  of FMUs) of "set inputs, get outputs, transfer along the connections"; then
  fmi2ExitInitializationMode, get outputs, transfer once more. ``tbi cosim`` instead repeats
  the exchange until the values stop changing (at most 50 rounds), sets parameters in
  initialisation mode and gives a stop time. Both start the first step from the outputs after
  exitInitializationMode.
* Each step is Gauss-Jacobi: every FMU gets the inputs transferred at the end of the previous
  step and does fmi2DoStep(t, H) (in a thread pool), its outputs are read, then all connections
  transfer. That is ``tbi cosim --scheme jacobi``, where each step reads all outputs at t,
  writes the inputs, then steps every FMU.

Rows: the first row (time = start) is the time-series observer's sample taken when libcosim
finished initialising (step 0); the row after step k is the last-value observer read after
``execution.step()`` returns, stamped with libcosim's clock (start + k*H). Both are outputs
right after doStep / exitInitializationMode, exactly what ``tbi cosim`` records, so row k of
both files holds the same values with no shift.

Communication points: libcosim keeps time in integer nanoseconds and calls
fmi2DoStep(t_k, t_k+1 - t_k) with t_k = (start_ns + k*H_ns)/1e9, while ``tbi cosim`` calls
fmi2DoStep(start + k*H, H) in floating point; for H = 0.001 the times differ by one ulp at about
one step in seven (351*0.001 = 0.35100000000000003, libcosim 0.351). When a wheelset
sits exactly on a switching point of a model at a communication point (say, on the bridge
entry x = 0) that ulp decides the side and the runs part by up to ~1e-2 of a column's range.
With a step whose multiples are exact in binary and whole in nanoseconds (H = 2^-9 s =
0.001953125 s) the time arguments are identical and so are the two results.

Exits non-zero with a message when libcosim cannot load the system or a step fails.
"""

import argparse
import sys
import xml.etree.ElementTree as ET
import zipfile

SSD_NS = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"


def read_ssd(path):
    """(start time, [(component, connector)] of the connected outputs in connection order)."""
    if path.endswith(".ssd"):
        root = ET.parse(path).getroot()
    else:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("SystemStructure.ssd"))
    start = 0.0
    experiment = root.find(SSD_NS + "DefaultExperiment")
    if experiment is not None and experiment.get("startTime") is not None:
        start = float(experiment.get("startTime"))
    outputs = []
    for c in root.iter(SSD_NS + "Connection"):
        key = (c.get("startElement"), c.get("startConnector"))
        if key not in outputs:
            outputs.append(key)
    return start, outputs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ssp")
    parser.add_argument("--step-size", type=float, required=True, help="s")
    parser.add_argument("--stop-time", type=float, required=True, help="s")
    parser.add_argument("--output", required=True, help="result CSV")
    args = parser.parse_args()

    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy._internal import get_last_error_message

    log_output_level(CosimLogLevel.ERROR)
    start, outputs = read_ssd(args.ssp)
    h_ns = round(args.step_size * 1e9)
    steps = round((args.stop_time - start) / args.step_size)
    if h_ns <= 0 or abs(h_ns / 1e9 - args.step_size) > 1e-12 * args.step_size:
        sys.exit("libcosim_run.py: --step-size %r s is not a whole number of nanoseconds" % args.step_size)
    if steps < 1 or abs(steps * h_ns * 1e-9 - (args.stop_time - start)) > 1e-9 * max(1.0, abs(args.stop_time)):
        sys.exit("libcosim_run.py: --stop-time minus the start time (%r s) must be a positive whole "
                 "number of steps (--step-size %r s)" % (args.stop_time - start, args.step_size))

    try:
        execution = CosimExecution.from_ssp_file(args.ssp, step_size=h_ns)
    except AssertionError:
        sys.exit("libcosim_run.py: libcosim could not load %s: %s" % (args.ssp, get_last_error_message()))

    # (slave index, value reference) of every column.
    columns = []
    for component, variable in outputs:
        slave = execution.slave_index_from_instance_name(component)
        if slave is None:
            sys.exit("libcosim_run.py: libcosim has no slave named %r" % component)
        refs = [v.reference for v in execution.slave_variables(slave)
                if v.name.decode() == variable and v.type == CosimVariableType.REAL.value]
        if len(refs) != 1:
            sys.exit("libcosim_run.py: slave %r has no Real variable %r" % (component, variable))
        columns.append((slave, refs[0]))
    by_slave = {}
    for k, (slave, ref) in enumerate(columns):
        by_slave.setdefault(slave, []).append((k, ref))

    last = CosimObserver.create_last_value()
    initial = CosimObserver.create_time_series(buffer_size=2)
    if not (execution.add_observer(last) and execution.add_observer(initial)):
        sys.exit("libcosim_run.py: could not add the observers: %s" % get_last_error_message())
    for slave, ref in columns:
        initial.start_time_series(slave, ref, CosimVariableType.REAL)

    def row(values):
        return ",".join(repr(float(v)) for v in values) + "\n"

    with open(args.output, "w") as f:
        f.write(",".join(["time"] + ["%s.%s" % o for o in outputs]) + "\n")
        first = [None] * len(columns)
        for k in range(1, steps + 1):
            if not execution.step():
                sys.exit("libcosim_run.py: step %d (t = %r s) failed: %s"
                         % (k, start + (k - 1) * args.step_size, get_last_error_message()))
            if k == 1:
                # Step 0, sampled at the end of initialisation. (The wrapper drops as many
                # trailing samples as there are zero step numbers, hence two requested.)
                t0 = None
                for col, (slave, ref) in enumerate(columns):
                    times, numbers, samples = initial.time_series_real_samples(slave, ref, 0, 2)
                    if not numbers or numbers[0] != 0:
                        sys.exit("libcosim_run.py: no initial sample of %s.%s" % outputs[col])
                    t0 = times[0] / 1e9
                    first[col] = samples[0]
                f.write(row([t0] + first))
            values = [None] * len(columns)
            for slave, items in by_slave.items():
                got = last.last_real_values(slave, [ref for _, ref in items])
                for (col, _), v in zip(items, got):
                    values[col] = v
            f.write(row([execution.status().current_time / 1e9] + values))


if __name__ == "__main__":
    main()
