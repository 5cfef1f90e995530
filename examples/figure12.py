#!/usr/bin/env python3
"""Figure 12 of the source paper from Python: the deck's absolute
acceleration with and without the expansion joint under Loma Prieta
Corralitos, at the reference bridge's period.

    python3 examples/figure12.py [figure12.png]

Runs the reference model (configs/paper.toml: 27 center beams, 1e8 kg deck,
T = 0.997 s) once, about 4 s, and plots the two histories and their
difference. Needs the package with matplotlib (`pip install ".[plot]"` from
the checkout).
"""
import sys
from pathlib import Path

try:
    import matplotlib
except ImportError:
    sys.exit('examples/figure12.py needs matplotlib, which `pip install quakejoint` does not bring: '
             'pip install "quakejoint[plot]" (from the checkout: pip install ".[plot]")')

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import quakejoint as qj  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main(out="figure12.png"):
    config = qj.Config.from_file(ROOT / "configs" / "paper.toml")
    run = qj.simulate(config)  # the config's record and period, histories included
    h = run.history
    print(f"T = {run.period:.4f} s: Sa with the joint {run.sa:.4f} m/s^2, without "
          f"{np.abs(h['a_abs_without_joint']).max():.4f} m/s^2; friction dissipated {run.friction_energy / 1e3:.0f} kJ;"
          f" validity: {run.validity_label}")

    fig, (ax, axd) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    ax.plot(h["t"], h["a_abs_without_joint"], color="0.5", lw=0.9, label="without joint")
    ax.plot(h["t"], h["a_abs"], color="tab:red", lw=0.6, label="with joint")
    ax.set_ylabel("deck absolute acceleration [m/s$^2$]")
    ax.set_title(f"{run.record}, T = {run.period:.3f} s ({run.validity_label})", fontsize=10)
    ax.legend()
    axd.plot(h["t"], h["a_abs"] - h["a_abs_without_joint"], color="tab:purple", lw=0.7)
    axd.set_ylabel("with - without [m/s$^2$]")
    axd.set_xlabel("t [s]")
    for a in (ax, axd):
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main(*sys.argv[1:2])
