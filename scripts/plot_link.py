"""The detailed joint's hysteresis against its link element's, from the
loops.csv that `quakejoint calibrate` writes (docs/link.md).

    python3 scripts/plot_link.py paper_link/loops.csv --output link.png

One panel per amplitude: the detailed joint's force on the deck against
the opening over every cycle of its service loop (the first from rest), and
the link's elastic-perfectly-plastic force over the same opening.
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    loops = defaultdict(lambda: ([], [], []))
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            u, detailed, link = loops[float(row["amplitude [m]"])]
            u.append(float(row["u [m]"]))
            detailed.append(float(row["detailed force [N]"]))
            link.append(float(row["link force [N]"]))
    if not loops:
        raise SystemExit(f"{path}: no loops (is it a loops.csv of quakejoint calibrate?)")
    return dict(sorted(loops.items()))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("loops", help="loops.csv written by quakejoint calibrate")
    ap.add_argument("--output", default="link.png", help="image to write (default link.png)")
    a = ap.parse_args(argv)
    loops = read(a.loops)
    n = len(loops)
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows), squeeze=False)
    for ax, (amp, (u, detailed, link)) in zip(axes.flat, loops.items()):
        mm = [x * 1e3 for x in u]
        ax.plot(mm, [f / 1e3 for f in detailed], lw=1.0, label="detailed joint")
        ax.plot(mm, [f / 1e3 for f in link], lw=1.2, ls="--", label="link element")
        ax.set_title(f"amplitude {amp * 1e3:g} mm")
        ax.set_xlabel("deck opening u [mm]")
        ax.set_ylabel("force on the deck [kN]")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    axes.flat[0].legend(loc="best", fontsize=8)
    fig.suptitle("service loops: the detailed joint and its calibrated link")
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
