#!/usr/bin/env python3
"""The mass study from Python: how much the reference joint reduces the
deck's spectral acceleration when the deck is lighter.

    python3 examples/mass_study.py [--periods N] [--duration S] [--output mass_study.png]

The joint's friction forces are fixed; the deck's inertia falls from 1e8 kg
(the paper's) to 1e6 kg, so the same joint matters more. Each (mass,
period) is one coupled run; runs go on a thread pool, which works because
`quakejoint.simulate` releases the GIL. The bridge alone is the exact
linear spectrum of the same record over the same window. Defaults: 8
periods from 0.2 to 5 s, the whole record (3 x 8 runs, about a minute on
2 cores). Needs the package with matplotlib (`pip install ".[plot]"` from
the checkout).
"""
import argparse
import os
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

try:
    import matplotlib
    import matplotlib.ticker
except ImportError:
    sys.exit('examples/mass_study.py needs matplotlib, which `pip install quakejoint` does not bring: '
             'pip install "quakejoint[plot]" (from the checkout: pip install ".[plot]")')

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import quakejoint as qj  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
MASSES = [1e8, 1e7, 1e6]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--periods", type=int, default=8, help="number of periods from 0.2 to 5 s")
    parser.add_argument("--duration", type=float, help="simulated time [s] (default: the record)")
    parser.add_argument("--output", default="mass_study.png")
    args = parser.parse_args()

    base = qj.Config.from_file(ROOT / "configs" / "paper.toml")
    if args.duration:
        base = base.replace({"simulation.duration": args.duration})
    periods = np.geomspace(0.2, 5.0, args.periods)
    configs = {m: base.replace({"bridge.mass": m}) for m in MASSES}
    jobs = [(m, t) for m in MASSES for t in periods]
    with ThreadPoolExecutor(os.cpu_count()) as pool:
        runs = list(pool.map(lambda job: qj.simulate(configs[job[0]], period=job[1], history=False), jobs))
    without = [qj.simulate(base, period=t, joint=False, history=False).sa for t in periods]

    sa = np.array([r.sa for r in runs]).reshape(len(MASSES), len(periods))
    flagged = np.array([r.flagged for r in runs]).reshape(sa.shape)
    reduction = 100 * (1 - sa / np.array(without))
    for m, row, bad in zip(MASSES, reduction, flagged):
        print(f"deck {m:.0e} kg: reduction of Sa {np.nanmin(row):+.2f} % to {np.nanmax(row):+.2f} %"
              + (f" ({bad.sum()} runs flagged)" if bad.any() else ""))

    fig, (ax, axr) = plt.subplots(1, 2, figsize=(11, 4))
    ax.plot(periods, without, "-", color="0.4", label="without joint (exact)")
    for i, m in enumerate(MASSES):
        ax.plot(periods, sa[i], "o", ms=4, color=f"C{i}", label=f"with joint, deck {m:.0e} kg")
        axr.plot(periods, reduction[i], "o-", ms=4, color=f"C{i}", label=f"deck {m:.0e} kg")
        if flagged[i].any():
            axr.plot(periods[flagged[i]], reduction[i][flagged[i]], "o", ms=8, mfc="none", mec="k",
                     label="flagged (outside the model's validity)")
    ax.set_ylabel("Sa [m/s$^2$]")
    axr.set_ylabel("reduction of Sa [%]")
    axr.axhline(0, color="0.6", lw=0.8)
    for a in (ax, axr):
        a.set_xscale("log")
        ticks = [t for t in (0.2, 0.5, 1, 2, 5) if periods[0] * 0.95 <= t <= periods[-1] * 1.05]
        a.set_xticks(ticks, labels=[f"{t:g}" for t in ticks])
        a.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        a.set_xlabel("bridge period T [s]")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(args.output)


if __name__ == "__main__":
    main()
