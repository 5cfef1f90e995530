#!/usr/bin/env python3
"""The service hysteresis loop: the joint's force on the deck against the
deck's opening, and the center beams' motion.

    python3 scripts/plot_service.py loop.h5 [output.png]

Reads a `quakejoint service --output loop.h5` file. Left: joint force
against opening over every cycle (earlier cycles grey, the last one, whose
work is reported, in colour), with the loop's area, the friction work and
the hand calculation per cycle in the legend. Right: each center beam's x
displacement against time. A loop outside the model's validity says so in
red in its title. Writes loop_service.png beside the input unless an output
name is given. Headless (Agg).
"""
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import NOT_CHECKED, text  # noqa: E402


def figure(src):
    with h5py.File(src, "r") as f:
        if "service" not in f:
            raise SystemExit(f"{src}: not a service loop (quakejoint service --output)")
        s = f["service"]
        t, u, force = s["t"][:], s["u"][:], s["joint_force"][:]
        dx = s["center_beam_dx"][:]
        period = s["period"][()]
        work = {k: s[k][()] for k in ("loop_work_per_cycle", "friction_work_per_cycle", "hand_calculation")}
        cycles = int(s.attrs["cycles"])
        validity = int(f.attrs.get("validity", 0))
        label = text(f.attrs.get("validity_label", "ok"))
    last = t >= t[-1] - period * (1 + 1e-9)
    fig, (ax, axb) = plt.subplots(1, 2, figsize=(12, 4.8))
    if (~last).any():
        ax.plot(1e3 * u[~last], 1e-3 * force[~last], color="0.7", lw=0.8, label="cycle 1" if cycles == 2 else f"cycles 1 to {cycles - 1}")
    ax.plot(
        1e3 * u[last],
        1e-3 * force[last],
        color="tab:red",
        lw=1.2,
        label=(
            f"last cycle: loop area {1e-3 * work['loop_work_per_cycle']:.1f} kJ\n"
            f"friction work {1e-3 * work['friction_work_per_cycle']:.1f} kJ "
            f"(hand calculation {1e-3 * work['hand_calculation']:.1f} kJ)"
        ),
    )
    ax.axhline(0, color="0.5", lw=0.6)
    ax.set_xlabel("deck opening u [mm]")
    ax.set_ylabel("force of the joint on the deck [kN]")
    title = f"service hysteresis loop, {cycles} cycles of {period:.4g} s"
    bad = validity & ~NOT_CHECKED
    ax.set_title(title + (f" -- FLAGGED: {label}" if bad else ""), fontsize=9, color="tab:red" if bad else "k")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    for i, x in enumerate(dx):
        named = len(dx) <= 8 or i in (0, len(dx) - 1)
        axb.plot(t, 1e3 * x, lw=0.8, label=f"center beam {i + 1}" if named else None)
    axb.plot(t, 1e3 * u, color="k", lw=1.0, ls="--", label="deck opening")
    axb.set_xlabel("t [s]")
    axb.set_ylabel("x displacement [mm]")
    axb.set_title("center beams and the deck against time", fontsize=9)
    axb.legend(fontsize=7, ncol=2)
    axb.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def main(src, dst=None):
    fig = figure(src)
    out = dst or str(Path(src).with_name(Path(src).stem + "_service.png"))
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
