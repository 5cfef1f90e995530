#!/usr/bin/env python3
"""Plan view of a joint at rest, from `quakejoint model <config> --json`.

    quakejoint model configs/paper.toml --json > model.json
    python3 scripts/plot_geometry.py model.json docs/figures/geometry.png

Draws the abutment and deck edge lines, the center beams, the guide(s) and
swivel joists (pivot on the abutment, box on the deck) and a dot at every
bearing. Headless (Agg backend).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def figure(src):
    with open(src) as f:
        model = json.load(f)
    g = model["geometry"]
    if g is None:
        sys.exit("the model has no joint (joint.enabled = false)")
    gap, half = g["gap"], g["center_beam_length"] / 2
    fig, ax = plt.subplots(figsize=(7.5, 8))
    for x, label in [(0.0, "abutment edge"), (gap, "deck edge")]:
        ax.plot([x, x], [-half - 0.3, half + 0.3], color="0.3", lw=3)
        ax.text(x, half + 0.45, label, ha="right" if x == 0.0 else "left", fontsize=8)
    for x in g["center_x"]:
        ax.plot([x, x], [-half, half], color="tab:blue", lw=1.2)
    for s in g["supports"]:
        if s["kind"] == "guide":
            ax.plot([0, gap], [s["y0"], s["y0"]], color="tab:green", lw=2.5, label="guide")
        else:
            ax.plot([0, gap], [s["y0"], s["y0"] + s["box_dy"]], color="tab:red", lw=2)
            ax.plot([0], [s["y0"]], "o", color="tab:red", ms=5)
            ax.plot([gap], [s["y0"] + s["box_dy"]], "s", color="tab:red", ms=5)
    xs, ys = zip(*g["bearings"])
    ax.plot(xs, ys, ".", color="k", ms=3)
    ax.plot([], [], color="tab:blue", label="center beams")
    ax.plot([], [], color="tab:red", label="joists (o pivot, s box)")
    ax.plot([], [], ".", color="k", label="bearings")
    ax.set_xlabel("x [m] (bridge axis, gap opens in +x)")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{model['center_beams']} center beams, {model['support_beams']} support beams, "
                 f"{model['bodies']} bodies", fontsize=9)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8)
    ax.set_aspect("equal")
    fig.tight_layout()
    return fig


def main(src, dst):
    figure(src).savefig(dst, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
