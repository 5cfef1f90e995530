#!/usr/bin/env python3
"""Which joint to specify: each candidate's annual frequencies against the
targets (docs/design.md).

    python3 scripts/plot_design.py sweep.h5 [output.png]

For a multiple-stripe sweep whose limit states carry targets (the output's
group /fragility/design): one panel per limit state with a target. Each
candidate (a case of the sweep, labelled with its gaps and fuse) has its
annual frequency of exceedance as a point and the value checked (the upper
end of the bootstrap interval) as the top of a bar, on a log axis; the
target is a dashed line. A candidate that meets the target is drawn green,
one that fails red; a limit state a candidate cannot reach (a fuse's on a
joint without one) is written "cannot happen". The recommended candidate
(the fewest gaps meeting every target) is in bold with its margin in the
title. A sweep of several damping ratios or periods plots the first and
says so. Writes sweep_design.png beside the input unless an output name
is given. Headless (Agg).
"""
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import save, sweep_parser, text  # noqa: E402


def load(src):
    """The design table of `src`, or exits naming what is missing."""
    with h5py.File(src, "r") as f:
        if "fragility/design" not in f:
            sys.exit(f"{src}: no /fragility/design: give the limit states of [sweep.fragility] a `target` "
                     "(and the sweep a hazard curve); docs/design.md")
        g = f["fragility/design"]
        d = {k: g[k][...] for k in ("cells", "target", "annual_frequency", "checked", "pass", "recommended", "margin")}
        for k in ("candidate", "fuse", "target_limit_state", "note", "margin_on"):
            d[k] = np.vectorize(text, otypes=[object])(g[k][...])
        names = {}
        for key in d["target_limit_state"]:
            names[key] = text(f["fragility"][key].attrs["name"])
        d["names"] = [names[k] for k in d["target_limit_state"]]
    return d


def fuse_label(fuse):
    """A candidate's fuse in a few words: 'no fuse', 'box 2 MN', 'element
    2 MN' (the design table's `fuse`, such as 'box 2000 kN, stroke 0.3 m')."""
    if fuse == "none":
        return "no fuse"
    words = fuse.split(",")[0].split()
    if len(words) >= 3 and words[2] == "kN":
        return f"{words[0]} {float(words[1]) / 1e3:g} MN"
    return words[0] if words else "fuse"


def figure(src):
    d = load(src)
    nc, nz, nt, nk = d["checked"].shape
    z, t = 0, 0
    cols = min(nk, 3 if nc <= 4 else 2)
    rows = -(-nk // cols)
    width = max(4.8, 0.95 * nc + 1.8)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, 4.4 * rows + 0.4), squeeze=False)
    for ax in axes.ravel()[nk:]:
        ax.axis("off")
    rec = int(d["recommended"][z, t])
    labels = ["\n".join([*c.split(", "), f"{n} gaps", fuse_label(fz)])
              for c, n, fz in zip(d["candidate"], d["cells"], d["fuse"])]
    for k, ax in enumerate(axes.ravel()[:nk]):
        target = d["target"][k]
        checked, freq, ok = d["checked"][:, z, t, k], d["annual_frequency"][:, z, t, k], d["pass"][:, z, t, k]
        positive = [x for x in np.concatenate([checked, freq, [target]]) if np.isfinite(x) and x > 0]
        floor = min(positive) / 10
        labelled = False
        for c in range(nc):
            colour = "tab:green" if ok[c] else "tab:red"
            if checked[c] == 0:
                ax.text(c, floor * 2, "cannot\nhappen", ha="center", va="bottom", fontsize=7, color="0.3")
                continue
            if not np.isfinite(checked[c]):
                ax.text(c, target, "not\ndetermined", ha="center", va="center", fontsize=7, color=colour)
                continue
            ax.bar(c, checked[c] - floor, bottom=floor, width=0.55, color=colour, alpha=0.35)
            if np.isfinite(freq[c]):
                ax.plot(c, freq[c], "o", color=colour, label=None if labelled else "annual frequency")
                labelled = True
        ax.axhline(target, ls="--", color="k", lw=1, label=f"target {target:.2g}/year")
        ax.set_yscale("log")
        ax.set_ylim(floor, max(positive) * 3)
        ax.set_xticks(range(nc), labels, fontsize=7.5)
        for c, tick in enumerate(ax.get_xticklabels()):
            tick.set_fontweight("bold" if c == rec else "normal")
        ax.set_title(d["names"][k], fontsize=9.5)
        ax.set_ylabel("annual frequency of exceedance [1/year]")
        ax.legend(fontsize=7, loc="upper right")
    if rec >= 0:
        verdict = (f"recommended: {d['candidate'][rec]} ({d['cells'][rec]} gaps), margin "
                   f"{d['margin'][z, t]:.2f} on {d['margin_on'][z, t]}")
    else:
        verdict = "no candidate meets every target"
    several = " (the first damping ratio and period of the sweep)" if nz * nt > 1 else ""
    fig.suptitle(f"which joint: bars up to the upper end of the interval (checked), points the annual frequency"
                 f"{several}\n{verdict}", fontsize=9.5)
    fig.tight_layout()
    return fig


def main(src, dst=None):
    save(figure(src), src, dst, "design")


if __name__ == "__main__":
    args = sweep_parser(__doc__, in_g=False).parse_args()
    main(args.input, args.output)
