#!/usr/bin/env python3
"""Cost per step against the number of coordinates (the paper's Figure 3).

    python3 scripts/plot_scaling.py [target/bench-runs/scaling.json] [docs/figures/scaling.png]

Reads the table written by `cargo bench -p quakejoint-model --bench runs --
scaling` (Nc = 3, 9, 27, 81 center beams) and plots the wall time per step
and per Newton iteration against the number of coordinates, log-log, with a
line of slope 1 through the Nc = 27 point for reference. Headless (Agg).
"""
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def figure(src):
    rows = json.loads(Path(src).read_text())
    if not rows:
        raise SystemExit(f"{src}: no rows")
    n = [r["coordinates"] for r in rows]
    per_step = [r["wall_time_s"] / r["steps"] * 1e6 for r in rows]
    per_newton = [r["wall_time_s"] / r["newton_iterations"] * 1e6 for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.loglog(n, per_step, "o-", label="per step")
    ax.loglog(n, per_newton, "s--", label="per Newton iteration")
    ref = next((i for i, r in enumerate(rows) if r["nc"] == 27), len(rows) // 2)
    ax.loglog(n, [per_step[ref] * x / n[ref] for x in n], ":", color="grey", label="linear (slope 1)")
    for r, x, y in zip(rows, n, per_step):
        # (left of the point and above it: the last one stays inside the axes)
        ax.annotate(f"Nc = {r['nc']}", (x, y), textcoords="offset points", xytext=(-8, 8), ha="right", fontsize=8)
    ax.margins(x=0.08, y=0.12)
    ax.set_xlabel("coordinates")
    ax.set_ylabel("wall time [us]")
    ax.set_title("Earthquake run cost against model size (one core)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def main(src="target/bench-runs/scaling.json", dst="docs/figures/scaling.png"):
    fig = figure(src)
    Path(dst).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(dst, dpi=120)
    print(f"wrote {dst}")


if __name__ == "__main__":
    main(*sys.argv[1:3])
