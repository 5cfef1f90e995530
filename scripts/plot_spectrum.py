#!/usr/bin/env python3
"""Spectral acceleration with and without the joint, and the reduction.

    python3 scripts/plot_spectrum.py out.h5 [output.png]

One row of panels per case, record and damping ratio of a sweep file
(`quakejoint sweep`): Sa against the bridge period with the joint (markers,
failed jobs left out) and without it (line), and the reduction
1 - Sa_with / Sa_without. Writes out_spectrum.png beside the input unless an
output name is given. Headless (Agg backend).
"""
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def text(x):
    return x.decode() if isinstance(x, bytes) else str(x)


def main(src, dst=None):
    with h5py.File(src, "r") as f:
        s = f["spectrum"]
        periods = s["period"][:]
        damping = s["damping"][:]
        records = [text(r) for r in s["record"][:]]
        cases = [text(c) for c in s["case"][:]]
        sa_with = s["with_joint/sa"][:]
        status = s["with_joint/status"][:]
        sa_without = s["without_joint/sa"][:]
        reduction = s["reduction"][:]
    rows = [(c, r, z) for c in range(len(cases)) for r in range(len(records)) for z in range(len(damping))]
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 3.2 * len(rows)), squeeze=False)
    for row, (c, r, z) in enumerate(rows):
        ok = status[c, r, z] == 0
        ax, axr = axes[row]
        ax.plot(periods, sa_without[r, z], "-", color="0.4", label="without joint (exact)")
        ax.plot(periods[ok], sa_with[c, r, z][ok], "o", ms=4, color="tab:red", label="with joint")
        ax.set_xscale("log")
        ax.set_ylabel("Sa [m/s$^2$]")
        ax.set_title(f"{cases[c]} / {records[r]} / damping {damping[z]:g}", fontsize=9)
        ax.legend(fontsize=8)
        axr.plot(periods[ok], 100 * reduction[c, r, z][ok], "o-", ms=4, color="tab:blue")
        axr.set_xscale("log")
        axr.axhline(0, color="0.6", lw=0.8)
        axr.set_ylabel("reduction of Sa [%]")
        for a in (ax, axr):
            a.set_xlabel("bridge period T [s]")
            a.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    out = dst or str(Path(src).with_name(Path(src).stem + "_spectrum.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
