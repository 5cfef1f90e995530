#!/usr/bin/env python3
"""Sparsity pattern of a model's iteration matrix (the paper's Figure 7).

    quakejoint model configs/paper.toml --sparsity sparsity.h5
    python3 scripts/plot_sparsity.py sparsity.h5 [output.png]

Rows and columns: the coordinates of the bodies in order, then the
constraint equations. Writes sparsity.png beside the input unless an output
name is given. Headless (Agg backend).
"""
import sys
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def figure(src):
    with h5py.File(src, "r") as f:
        g = f["sparsity"]
        rows, cols = g["row"][:], g["col"][:]
        n, m, nnz = int(g.attrs["coordinates"]), int(g.attrs["equations"]), int(g.attrs["nnz"])
    size = n + m
    fig, ax = plt.subplots(figsize=(7, 7))
    if size <= 300:  # a small model: one visible square per non-zero
        ax.plot(cols, rows, "s", color="k", markersize=300 / size, markeredgewidth=0)
    else:
        ax.plot(cols, rows, ",", color="k", markersize=1)
    ax.axhline(n - 0.5, color="tab:red", lw=0.6)
    ax.axvline(n - 0.5, color="tab:red", lw=0.6)
    ax.set_xlim(-0.5, size - 0.5)
    ax.set_ylim(size - 0.5, -0.5)
    ax.set_aspect("equal")
    ax.set_title(f"{n} coordinates + {m} constraint equations, {nnz} non-zeros "
                 f"({100 * nnz / size**2:.2f} % dense)", fontsize=9)
    ax.set_xlabel("column (coordinates | equations)")
    ax.set_ylabel("row")
    fig.tight_layout()
    return fig


def main(src, dst=None):
    fig = figure(src)
    out = dst or str(Path(src).with_name(Path(src).stem + ".png"))
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(*sys.argv[1:])
