#!/usr/bin/env python3
"""Spectral acceleration with and without the joint, and the reduction.

    python3 scripts/plot_spectrum.py out.h5 [output.png]

One row of panels per case, record and damping ratio of a sweep file
(`quakejoint sweep`): Sa against the bridge period with the joint (markers)
and without it (line), and the reduction 1 - Sa_with / Sa_without. Jobs
flagged as outside the model's validity (a collision, say) are drawn as open
black markers and named in the legend; failed jobs as crosses on the axis.
Writes out_spectrum.png beside the input unless an output name is given.
Headless (Agg backend).
"""
import sys
from pathlib import Path

import h5py
import matplotlib
import matplotlib.ticker
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def text(x):
    return x.decode() if isinstance(x, bytes) else str(x)


def flag_names(meaning):
    """(bit, name) pairs from the `meaning` attribute of the validity dataset."""
    pairs = []
    for part in meaning.split(";")[-1].split(","):
        bit, _, name = part.strip().partition(" ")
        if bit.isdigit():
            pairs.append((int(bit), name))
    return pairs


# the `not_checked` bit of the validity flags
NOT_CHECKED = 1 << 15


def period_ticks(ax, periods):
    """Plain-number period ticks (0.2, 0.5, 1, 2 s) on a log axis, no minor labels."""
    lo, hi = periods.min(), periods.max()
    ticks = [t for d in (0.01, 0.1, 1, 10) for t in (d, 2 * d, 5 * d) if lo * 0.9 <= t <= hi * 1.1]
    ax.set_xticks(ticks)
    ax.set_xticklabels([f"{t:g}" for t in ticks])
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())


def main(src, dst=None):
    with h5py.File(src, "r") as f:
        s = f["spectrum"]
        periods = s["period"][:]
        damping = s["damping"][:]
        records = [text(r) for r in s["record"][:]]
        cases = [text(c) for c in s["case"][:]]
        sa_with = s["with_joint/sa"][:]
        status = s["with_joint/status"][:]
        validity = s["with_joint/validity"][:]
        meaning = text(s["with_joint/validity"].attrs["meaning"])
        sa_without = s["without_joint/sa"][:]
        reduction = s["reduction"][:]
    rows = [(c, r, z) for c in range(len(cases)) for r in range(len(records)) for z in range(len(damping))]
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 3.2 * len(rows)), squeeze=False)
    names = flag_names(meaning)
    for row, (c, r, z) in enumerate(rows):
        done = status[c, r, z] == 0
        # not_checked (a job that did not finish) is not a finding
        flagged = done & ((validity[c, r, z].astype(np.int64) & ~NOT_CHECKED) != 0)
        ok = done & ~flagged
        failed = (status[c, r, z] != 0) & (status[c, r, z] != -1)
        ax, axr = axes[row]
        ax.plot(periods, sa_without[r, z], "-", color="0.4", label="without joint (exact)")
        ax.plot(periods[ok], sa_with[c, r, z][ok], "o", ms=4, color="tab:red", label="with joint")
        if flagged.any():
            bits = np.bitwise_or.reduce(validity[c, r, z][flagged])
            label = "flagged: " + ", ".join(n for b, n in names if bits & b)
            ax.plot(periods[flagged], sa_with[c, r, z][flagged], "o", ms=6, mfc="none", mec="k", label=label)
            axr.plot(periods[flagged], 100 * reduction[c, r, z][flagged], "o", ms=6, mfc="none", mec="k", label=label)
        if failed.any():
            ax.plot(periods[failed], np.zeros(failed.sum()), "x", color="k", ms=7, label=f"failed ({failed.sum()})")
        ax.set_xscale("log")
        ax.set_ylabel("Sa [m/s$^2$]")
        ax.set_title(f"{cases[c]} / {records[r]} / damping {damping[z]:g}", fontsize=9)
        ax.legend(fontsize=8)
        axr.plot(periods[ok], 100 * reduction[c, r, z][ok], "o-", ms=4, color="tab:blue", label="1 - Sa with / Sa without")
        axr.set_xscale("log")
        axr.legend(fontsize=8)
        axr.axhline(0, color="0.6", lw=0.8)
        axr.set_ylabel("reduction of Sa [%]")
        for a in (ax, axr):
            a.set_xlabel("bridge period T [s]")
            a.grid(True, which="both", alpha=0.3)
            period_ticks(a, periods)
    fig.tight_layout()
    out = dst or str(Path(src).with_name(Path(src).stem + "_spectrum.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
