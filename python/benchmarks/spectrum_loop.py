#!/usr/bin/env python3
"""Benchmark: exact linear spectra of a thousand records from Python.

    python3 python/benchmarks/spectrum_loop.py [--records 1000]

Loops over the shipped PEER records (ground_motions/*.AT2, 1,000 to 8,000
samples each, 4,600 on average) until `--records` spectra are done, 60 log-spaced periods
from 0.05 to 5 s x 2 damping ratios each, in one Python thread (the engine
is single-threaded). Reading the files is outside the timing; making each
Record from its array is inside. Prints the total and the time per record;
docs/performance.md records the result.
"""
import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

import quakejoint as qj

ROOT = Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--records", type=int, default=1000)
    args = parser.parse_args()
    files = sorted((ROOT / "ground_motions").glob("*.AT2"))
    arrays = [(r.acceleration, r.dt) for r in map(qj.Record.read, files)]
    periods = np.geomspace(0.05, 5.0, 60)
    damping = [0.02, 0.05]
    samples = 0
    start = time.perf_counter()
    for i in range(args.records):
        a, dt = arrays[i % len(arrays)]
        spec = qj.spectrum(a, periods, damping, dt=dt, units="m/s2")
        samples += len(a)
        assert spec.sa.shape == (2, 60)
    wall = time.perf_counter() - start
    print(f"{args.records} records ({samples / args.records:.0f} samples on average), 60 periods x 2 dampings: "
          f"{wall:.2f} s, {1e3 * wall / args.records:.2f} ms per record")
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}")


if __name__ == "__main__":
    main()
