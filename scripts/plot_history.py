#!/usr/bin/env python3
"""The deck's absolute acceleration with and without the joint against time.

    python3 scripts/plot_history.py run.h5 [output.png]

Reads a `quakejoint simulate --output run.h5` file (histories with the joint
and the exact linear response without it) or every stored history of a
sweep file (`/histories/job_*`), like Figure 12 of the source paper. Writes
run_history.png beside the input unless an output name is given. Headless.
"""
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def panels(f):
    if "history" in f:
        h = f["history"]
        record = f["inputs/records/x"].attrs["name"]
        title = f"{record}, T = {f['result/period'][()]:.4g} s"
        if f.attrs["validity"] != 0:
            title += f" -- FLAGGED: {f.attrs['validity_label']}"
        yield title, h["t"][:], h["a_abs"][:], h["a_abs_without_joint"][:]
    for name, g in f.get("histories", {}).items():
        title = f"{g.attrs['case']} / {g.attrs['record']} / damping {g['damping'][()]:g} / T = {g['period'][()]:.4g} s"
        yield title, g["t"][:], g["a_abs"][:], g["a_abs_without_joint"][:]


def main(src, dst=None):
    with h5py.File(src, "r") as f:
        items = list(panels(f))
    if not items:
        sys.exit(f"{src}: no time histories (simulate --output, or sweep.histories in a sweep)")
    fig, axes = plt.subplots(len(items), 1, figsize=(10, 3.2 * len(items)), squeeze=False)
    for ax, (title, t, with_joint, without) in zip(axes[:, 0], items):
        ax.plot(t, without, color="0.5", lw=0.9, label="without joint")
        ax.plot(t, with_joint, color="tab:red", lw=0.7, label="with joint")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("deck absolute acceleration [m/s$^2$]")
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    out = dst or str(Path(src).with_name(Path(src).stem + "_history.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
