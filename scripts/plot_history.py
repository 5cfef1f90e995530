#!/usr/bin/env python3
"""The deck's absolute acceleration with and without the joint against time,
and the joint's clear sub-gaps.

    python3 scripts/plot_history.py run.h5 [output.png] [--window T0 T1]

Reads a `quakejoint simulate --output run.h5` file (histories with the joint
and the exact linear response without it) or every stored history of a
sweep file (`/histories/job_*`), like Figure 12 of the source paper; a run
outside the model's validity (a collision, say) says so in its title. The
middle panel shows the clear sub-gaps (the smaller of the two beam ends)
against time, with zero, where neighbouring beams touch, marked; the right
one the contact force across each sub-gap when the beams pound. Writes
run_history.png beside the input unless an output name is given;
`--window 2 8` shows only 2 s to 8 s (impacts last milliseconds). Headless.
"""
import argparse
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
        forces = h["contact_force"][:] if "contact_force" in h else None
        yield title, h["t"][:], h["a_abs"][:], h["a_abs_without_joint"][:], gaps, forces
    jobs = f.get("histories", {})
    # in the sweep's job order (job_10 after job_9)
    for name in sorted(jobs, key=lambda n: int(n.rsplit("_", 1)[-1]) if n.rsplit("_", 1)[-1].isdigit() else n):
        g = jobs[name]
        title = f"{g.attrs['case']} / {g.attrs['record']} / damping {g['damping'][()]:g} / T = {g['period'][()]:.4g} s"
        gaps = g["subgaps"][:] if "subgaps" in g else None
        forces = g["contact_force"][:] if "contact_force" in g else None
        yield title + flagged(g.attrs), g["t"][:], g["a_abs"][:], g["a_abs_without_joint"][:], gaps, forces


def contact_panel(ax, t, forces):
    """Contact force across each sub-gap against time (an empty panel says
    there was no contact or no pounding)."""
    if forces is None or len(forces) == 0:
        ax.text(0.5, 0.5, "no contact in this model", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return
    if not forces.any():
        ax.text(0.5, 0.5, "no pounding: no sub-gap closed", ha="center", va="center", transform=ax.transAxes)
    closed = [k for k, f in enumerate(forces) if f.any()]
    for k in closed:
        ax.plot(t, 1e-3 * forces[k], lw=0.8, label=f"sub-gap {k + 1}")
    ax.set_title("contact force across each sub-gap (pounding; peak per time step)", fontsize=9)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("contact force [kN]")
    if 0 < len(closed) <= 8:
        ax.legend(fontsize=7, ncol=2)
    elif closed:
        ax.text(0.98, 0.95, f"{len(closed)} of {len(forces)} sub-gaps closed", ha="right", va="top",
                transform=ax.transAxes, fontsize=8)
    ax.grid(True, alpha=0.3)


def main(src, dst=None, window=None):
    with h5py.File(src, "r") as f:
        items = list(panels(f))
    if not items:
        sys.exit(f"{src}: no time histories (simulate --output, or sweep.histories in a sweep)")
    fig, axes = plt.subplots(
        len(items), 3, figsize=(18, 3.4 * len(items)), squeeze=False, gridspec_kw={"width_ratios": [3, 2, 2]}
    )
    for (ax, axg, axf), (title, t, with_joint, without, gaps, forces) in zip(axes, items):
        ax.plot(t, without, color="0.5", lw=0.9, label="without joint")
        ax.plot(t, with_joint, color="tab:red", lw=0.7, label="with joint")
        ax.set_title(title, fontsize=9, color="k" if "FLAGGED" not in title else "tab:red")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("deck absolute acceleration [m/s$^2$]")
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
        contact_panel(axf, t, forces)
        if gaps is None or len(gaps) == 0:
            axg.set_axis_off()
            continue
        for k, g in enumerate(gaps):
            axg.plot(t, 1e3 * g, lw=0.7, label=f"sub-gap {k + 1}" if len(gaps) <= 8 else None)
        axg.axhline(0, color="k", lw=1.0, ls="--")
        axg.set_title("clear sub-gaps (abutment side first); below 0: beams touch", fontsize=9)
        axg.set_xlabel("t [s]")
        axg.set_ylabel("clear sub-gap [mm]")
        if len(gaps) <= 8:
            axg.legend(fontsize=7, ncol=2)
        axg.grid(True, alpha=0.3)
    if window:
        for row in axes:
            for a in row:
                if a.axison:
                    a.set_xlim(*window)
    fig.tight_layout()
    out = dst or str(Path(src).with_name(Path(src).stem + "_history.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", help="simulate or sweep HDF5 file")
    parser.add_argument("output", nargs="?", help="PNG to write (default: beside the input)")
    parser.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"), help="time window [s]")
    args = parser.parse_args()
    if args.window and not args.window[0] < args.window[1]:
        parser.error(f"--window {args.window[0]:g} {args.window[1]:g}: T0 must be below T1")
    main(args.input, args.output, args.window)
