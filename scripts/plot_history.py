#!/usr/bin/env python3
"""The deck's absolute acceleration with and without the joint against time,
and the joint's clear sub-gaps.

    python3 scripts/plot_history.py run.h5 [output.png]

Reads a `quakejoint simulate --output run.h5` file (histories with the joint
and the exact linear response without it) or every stored history of a
sweep file (`/histories/job_*`), like Figure 12 of the source paper; a run
outside the model's validity (a collision, say) says so in its title. The
right-hand panel shows the clear sub-gaps (the smaller of the two beam ends)
against time, with zero, where neighbouring beams touch, marked. Writes
run_history.png beside the input unless an output name is given. Headless.
"""
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


# the `not_checked` bit of the validity flags
NOT_CHECKED = 1 << 15


def flagged(attrs):
    """' -- FLAGGED: collision' for a run outside the model's validity, else ''."""
    if "validity" in attrs and int(attrs["validity"]) & ~NOT_CHECKED:
        return f" -- FLAGGED: {attrs['validity_label']}"
    return ""


def panels(f):
    if "history" in f:
        h = f["history"]
        record = f["inputs/records/x"].attrs["name"]
        title = f"{record}, T = {f['result/period'][()]:.4g} s" + flagged(f.attrs)
        gaps = h["subgaps"][:] if "subgaps" in h else None
        yield title, h["t"][:], h["a_abs"][:], h["a_abs_without_joint"][:], gaps
    for name, g in f.get("histories", {}).items():
        title = f"{g.attrs['case']} / {g.attrs['record']} / damping {g['damping'][()]:g} / T = {g['period'][()]:.4g} s"
        gaps = g["subgaps"][:] if "subgaps" in g else None
        yield title + flagged(g.attrs), g["t"][:], g["a_abs"][:], g["a_abs_without_joint"][:], gaps


def main(src, dst=None):
    with h5py.File(src, "r") as f:
        items = list(panels(f))
    if not items:
        sys.exit(f"{src}: no time histories (simulate --output, or sweep.histories in a sweep)")
    fig, axes = plt.subplots(
        len(items), 2, figsize=(14, 3.4 * len(items)), squeeze=False, gridspec_kw={"width_ratios": [3, 2]}
    )
    for (ax, axg), (title, t, with_joint, without, gaps) in zip(axes, items):
        ax.plot(t, without, color="0.5", lw=0.9, label="without joint")
        ax.plot(t, with_joint, color="tab:red", lw=0.7, label="with joint")
        ax.set_title(title, fontsize=9, color="k" if "FLAGGED" not in title else "tab:red")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("deck absolute acceleration [m/s$^2$]")
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
        if gaps is None or len(gaps) == 0:
            axg.set_axis_off()
            continue
        for k, g in enumerate(gaps):
            axg.plot(t, 1e3 * g, lw=0.7, label=f"sub-gap {k + 1}" if len(gaps) <= 8 else None)
        axg.axhline(0, color="k", lw=1.0, ls="--")
        axg.set_title("clear sub-gaps (abutment side first); below 0: beams overlap", fontsize=9)
        axg.set_xlabel("t [s]")
        axg.set_ylabel("clear sub-gap [mm]")
        if len(gaps) <= 8:
            axg.legend(fontsize=7, ncol=2)
        axg.grid(True, alpha=0.3)
    fig.tight_layout()
    out = dst or str(Path(src).with_name(Path(src).stem + "_history.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
