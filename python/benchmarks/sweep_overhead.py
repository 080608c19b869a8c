"""Benchmarks of the Python package (printed, not asserted; machines here are shared):

1. runs in threads: 4 cases one after the other, then in 2 threads (the GIL is released while
   the Rust code runs, so 2 threads take about half the time on 2 free cores);
2. sweep overhead: 64 cases of about 0.2 s each as a local sweep (threads on every core) and on
   a Dask LocalCluster of as many single-threaded worker processes.

    target/venv/bin/python python/benchmarks/sweep_overhead.py
"""

import logging
import os
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import tbi

DATA = Path(__file__).resolve().parents[2] / "master" / "tests" / "data"


def case(dt_s):
    base, _ = tbi.as_dict(DATA / "yang-yau.toml")
    base["run"]["dt_s"] = dt_s
    base["run"]["solver"] = "monolithic"
    return base


def main():
    cores = os.cpu_count() or 1
    print(f"cores: {cores}; load average before: {os.getloadavg()[0]:.2f}")
    # a case of about 0.2 s
    dt = 7.5e-5
    tbi.run(case(dt))  # warm-up: first imports and page-ins
    t = time.perf_counter()
    tbi.run(case(dt))
    one = time.perf_counter() - t
    print(f"one case (Yang-Yau span, monolithic, dt {dt} s): {one:.3f} s")

    cases = [case(dt) for _ in range(4)]
    t = time.perf_counter()
    for c in cases:
        tbi.run(c)
    sequential = time.perf_counter() - t
    t = time.perf_counter()
    with ThreadPoolExecutor(max_workers=2) as pool:
        list(pool.map(tbi.run, cases))
    threaded = time.perf_counter() - t
    print(
        f"4 cases: sequential {sequential:.3f} s, 2 threads {threaded:.3f} s "
        f"(ratio {threaded / sequential:.2f})"
    )

    vary = {"run.speed_kmh": [60.0 + i for i in range(64)]}
    base = case(dt)
    t = time.perf_counter()
    local = tbi.sweep(base, vary=vary)
    local_s = time.perf_counter() - t
    from dask.distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=cores,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,
        silence_logs=logging.ERROR,
    ) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("tbi") and None)
        t = time.perf_counter()
        remote = tbi.sweep(base, vary=vary, client=client)
        dask_s = time.perf_counter() - t
    assert (local["status"] == "ok").all() and (remote["status"] == "ok").all()
    print(
        f"64 cases: local sweep {local_s:.2f} s, Dask LocalCluster ({cores} workers) "
        f"{dask_s:.2f} s, overhead {100 * (dask_s / local_s - 1):+.0f} %"
    )
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
