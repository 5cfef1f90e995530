#!/usr/bin/env python3
"""Spectral acceleration with and without the joint, and the reduction.

    python3 scripts/plot_spectrum.py out.h5 [output.png] [--g]

One row of panels per record and damping ratio of a sweep file
(`quakejoint sweep`), every case of the sweep in it: Sa against the bridge
period with the joint (markers, one colour per case) and without it (the
exact spectrum, a grey line), and the reduction 1 - Sa_with / Sa_without.
Jobs outside the model's validity (a collision, say) are drawn as open
markers (black, or the case's colour when there are several) and their
flags named in the legend; failed jobs as crosses
on the axis, counted in the legend. A sweep of several cases at three
periods or fewer is a parameter study: it is drawn by plot_study.py
instead, and a suite (`[sweep.suite]`) by plot_suite.py (statistics over
the records); `--records` draws one row per record for them too. `--g`
gives Sa in g. Writes out_spectrum.png beside the input
unless an output name is given. Headless (Agg backend).
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import plot_study  # noqa: E402
import plot_suite  # noqa: E402
from plotlib import (  # noqa: E402
    accel_units, flag_names, incomplete, job_masks, mark_jobs, period_axes, refuse_modal, save, sweep_parser, text,
)


def read(src):
    with h5py.File(src, "r") as f:
        refuse_modal(f, src)
        if "fragility" in f:
            # (one period, a record per stripe: a spectrum would be one point per panel)
            sys.exit(
                f"{src}: a multiple-stripe sweep ([sweep.stripes]): its records are scaled copies at one period; "
                f"plot it with scripts/plot_fragility.py {src}"
            )
        s = f["spectrum"]
        return {
            "periods": s["period"][:],
            "damping": s["damping"][:],
            "records": [text(r) for r in s["record"][:]],
            "cases": [text(c) for c in s["case"][:]],
            "sa_with": s["with_joint/sa"][:],
            "status": s["with_joint/status"][:],
            "validity": s["with_joint/validity"][:],
            "meaning": text(s["with_joint/validity"].attrs["meaning"]),
            "sa_without": s["without_joint/sa"][:],
            "reduction": s["reduction"][:],
            "complete": int(f.attrs.get("complete", 1)),
            # a suite's statistics view needs a spread (two records or more)
            "suite": "suite" in f and "statistics" in s and s["record"].shape[0] >= 2,
        }


def is_study(d):
    return len(d["cases"]) > 1 and len(d["periods"]) <= 3


def figure(src, in_g=False, per_record=False):
    """The figure of a sweep file: the suite's statistics for a suite, a
    study figure for a parameter study, else (or with `per_record`) one row
    per record and damping."""
    d = read(src)
    if d["suite"] and not per_record:
        return plot_suite.figure(src, in_g)
    if is_study(d) and not per_record:
        return plot_study.figure(src, in_g)
    k, unit = accel_units(in_g)
    periods, cases = d["periods"], d["cases"]
    rows = [(r, z) for r in range(len(d["records"])) for z in range(len(d["damping"]))]
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, 3.6 * len(rows)), squeeze=False)
    names = flag_names(d["meaning"])
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (ax, axr), (r, z) in zip(axes, rows):
        ax.plot(periods, k * d["sa_without"][r, z], "-", color="0.45", label="without joint (exact)")
        for c, case in enumerate(cases):
            colour = colours[(c + 3) % len(colours)]
            ok, flagged, failed, _ = job_masks(d["status"][c, r, z], d["validity"][c, r, z])
            label = "with joint" if len(cases) == 1 else f"with joint: {case}"
            sa, red = k * d["sa_with"][c, r, z], 100 * d["reduction"][c, r, z]
            ax.plot(periods[ok], sa[ok], "o", ms=4, color=colour, label=label)
            axr.plot(periods[ok], red[ok], "o-", ms=4, color=colour, label=label)
            # open markers in the case's colour when there are several
            mark_jobs((ax, axr), periods, (sa, red), flagged, failed, d["validity"][c, r, z], names,
                      prefix=f"{case}: " if len(cases) > 1 else "", edge="k" if len(cases) == 1 else colour)
        ax.set_title(f"{d['records'][r]} / damping {d['damping'][z]:g}" + incomplete(d["complete"]), fontsize=9)
        ax.set_ylabel(f"Sa [{unit}]")
        axr.axhline(0, color="0.6", lw=0.8)
        axr.set_ylabel("reduction of Sa, 1 - with / without [%]")
        axr.set_title("reduction by the joint", fontsize=9)
        period_axes((ax, axr), periods)
    fig.tight_layout()
    return fig


def main(src, dst=None, in_g=False, per_record=False):
    save(figure(src, in_g, per_record), src, dst, "spectrum")


if __name__ == "__main__":
    parser = sweep_parser(__doc__)
    parser.add_argument("--records", action="store_true", help="one row per record, also for a suite or a study")
    args = parser.parse_args()
    main(args.input, args.output, args.g, args.records)
