"""Simulate an SSP with FMPy's own SSP master and write selected connectors to CSV.

    python ssp_run.py SYSTEM.ssp --stop-time T --step-size H [H ...] --columns C [C ...] --out-dir DIR

For every step size H it runs ``fmpy.ssp.simulation.simulate_ssp(SYSTEM.ssp, stop_time=T,
step_size=H)`` and writes ``DIR/ssp_<k>.csv`` (k = position of H in the list) with the columns
``time`` and C... exactly as FMPy returns them. Note what FMPy 0.3.32 does (see
fmpy/ssp/simulation.py):

* every connector starts at 0.0 (the FMUs' input start values are not used for the first step)
  and ``ParameterBindings`` of the SSD are not applied (only an explicit ``parameter_set``);
* each step calls ``doStep(time, h)`` on every component with the connector values of the
  previous step (Gauss-Jacobi, explicit), then copies outputs along the connections;
* the row stamped ``time`` holds the outputs *after* the step, i.e. the values at ``time + h``.

Exits non-zero with the Python traceback on standard error if FMPy fails.
"""

import argparse
import os
import sys
import traceback

EXPECTED_FMPY = "0.3.32"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("ssp")
    parser.add_argument("--stop-time", type=float, required=True)
    parser.add_argument("--step-size", type=float, nargs="+", required=True)
    parser.add_argument("--columns", nargs="+", required=True)
    parser.add_argument("--out-dir", required=True)
    args = parser.parse_args()

    import fmpy
    from fmpy.ssp.simulation import simulate_ssp

    if fmpy.__version__ != EXPECTED_FMPY:
        sys.exit("expected FMPy %s, found %s" % (EXPECTED_FMPY, fmpy.__version__))

    os.makedirs(args.out_dir, exist_ok=True)
    for k, h in enumerate(args.step_size):
        try:
            result = simulate_ssp(args.ssp, stop_time=args.stop_time, step_size=h)
        except Exception:
            traceback.print_exc()
            sys.exit("fmpy.ssp.simulation.simulate_ssp(%r, stop_time=%r, step_size=%r) failed"
                     % (args.ssp, args.stop_time, h))
        names = result.dtype.names
        missing = [c for c in args.columns if c not in names]
        if missing:
            sys.exit("columns %s not in the SSP result; available: %s" % (missing, list(names)))
        path = os.path.join(args.out_dir, "ssp_%d.csv" % k)
        with open(path, "w") as f:
            f.write(",".join(["time"] + args.columns) + "\n")
            for row in result:
                f.write(",".join(repr(float(row[c])) for c in ["time"] + args.columns) + "\n")
        print(path)


if __name__ == "__main__":
    main()
