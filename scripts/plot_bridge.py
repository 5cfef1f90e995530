#!/usr/bin/env python3
"""The joints on a bridge given by its modes: how the deck moves at each
joint and what each joint does.

    python3 scripts/plot_bridge.py run.h5 [output.png] [--window T0 T1]

Reads a `quakejoint simulate --output run.h5` file of a modal bridge
(`[bridge.modal]`, one joint or several with `[[joints]]`; docs/bridge.md).
Panels sharing the time axis, one line per joint:
1. the displacement of each joint's deck point relative to the ground, in
   the joint's own x (positive opens it: at the bridge's far end the deck
   moving +x closes the joint there);
2. the force of each joint on the deck;
3. the widest cell of each joint (its largest clear sub-gap at either end)
   with the movement capacity drawn (`joint.capacity.max_subgap`);
and a table below: each point of the modes file with its peak displacement
and absolute acceleration with the joints and without them. A joint or run
outside the model's validity says so in red. Writes run_bridge.png beside
the input unless an output name is given. Headless (Agg).
"""
import argparse
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import NOT_CHECKED, text, tomllib  # noqa: E402


def joints(f):
    """(name, history group, validity label, validity bits) of every joint (`/joints/<k>`, k from 0; the
    first joint's history is the run's `/history`)."""
    config = tomllib.loads(text(f.attrs["config"])) if "config" in f.attrs else {}
    out = []
    for k in sorted(f["joints"], key=int) if "joints" in f else []:
        g = f["joints"][k]
        bits = int(g["validity"][()])
        label = text(g.attrs.get("validity_label", "flagged"))
        out.append((text(g.attrs["name"]), g["history"] if "history" in g else f["history"], label, bits))
    return out, config


def capacity(config):
    """joint.capacity.max_subgap [m] of the config, or the default 0.08."""
    return config.get("joint", {}).get("capacity", {}).get("max_subgap", 0.08)


def figure(path, window=None):
    """The figure of a run file (`window`: (t0, t1) [s] or None)."""
    with h5py.File(path, "r") as f:
        if "history" not in f or "points" not in f:
            sys.exit(
                f"{path}: not a run of a bridge given by its modes: this script draws one run of `quakejoint "
                f"simulate CONFIG --output run.h5` with [bridge.modal]; plot_history.py draws a single-DOF run's "
                f"histories and a sweep's"
            )
        if "joint_force" not in f["history"] or np.isnan(f["history/joint_force"][:]).all():
            sys.exit(f"{path}: a run of the bridge alone (--no-joint): there are no joints to draw")
        js, config = joints(f)
        data = []
        for name, g, label, bits in js:
            wide = g["subgaps_wide"][:] if "subgaps_wide" in g else None
            data.append((name, g["t"][:], g["u"][:], g["joint_force"][:], wide, label, bits))
        points = list(
            zip(
                [text(n) for n in f["points/name"][:]],
                f["points/sd"][:],
                f["points/sa"][:],
                f["points/sd_without_joint"][:],
                f["points/sa_without_joint"][:],
            )
        )
    cap = capacity(config)
    fig, axes = plt.subplots(4, 1, figsize=(10, 11), gridspec_kw={"height_ratios": [3, 3, 3, 2]})
    ax_u, ax_f, ax_g, ax_t = axes
    flagged_rows = 0
    for name, t, u, fj, wide, label, bits in data:
        keep = slice(None) if window is None else (t >= window[0]) & (t <= window[1])
        line = ax_u.plot(t[keep], u[keep] * 1e3, lw=0.9, label=name)[0]
        ax_f.plot(t[keep], fj[keep] / 1e3, lw=0.9, color=line.get_color(), label=name)
        if wide is not None:
            ax_g.plot(t[keep], wide.max(axis=0)[keep] * 1e3, lw=0.9, color=line.get_color(), label=name)
        if bits & ~NOT_CHECKED:
            y = 0.03 + 0.08 * flagged_rows
            ax_u.annotate(f"{name}: {label}", xy=(0.01, y), xycoords="axes fraction", color="red", fontsize=8)
            flagged_rows += 1
    ax_g.axhline(cap * 1e3, color="black", ls="--", lw=0.8, label=f"capacity {cap * 1e3:.0f} mm")
    ax_u.set_ylabel("deck point u [mm]\n(the joint's own x: + opens it)")
    ax_f.set_ylabel("joint force on the deck [kN]")
    ax_g.set_ylabel("widest cell [mm]")
    for ax in (ax_u, ax_f, ax_g):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8)
        ax.set_xlabel("t [s]")
    ax_t.axis("off")
    rows = [[n, f"{sd * 1e3:.1f}", f"{sa:.2f}", f"{sd0 * 1e3:.1f}", f"{sa0:.2f}"] for n, sd, sa, sd0, sa0 in points]
    table = ax_t.table(
        cellText=rows,
        colLabels=["point", "Sd [mm]", "Sa [m/s^2]", "Sd alone [mm]", "Sa alone [m/s^2]"],
        loc="center",
    )
    table.auto_set_font_size(False)
    table.set_fontsize(9)
    table.scale(1, 1.3)
    title = f"{Path(path).name}: {len(data)} joint{'s' if len(data) > 1 else ''} on the modal bridge"
    if flagged_rows:
        title += " -- FLAGGED"
    fig.suptitle(title, color="red" if flagged_rows else "black")
    fig.tight_layout()
    return fig


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", type=Path)
    ap.add_argument("output", type=Path, nargs="?")
    ap.add_argument("--window", type=float, nargs=2, metavar=("T0", "T1"))
    a = ap.parse_args(argv)
    fig = figure(a.run, a.window)
    out = a.output or a.run.with_name(a.run.stem + "_bridge.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
