#!/usr/bin/env python3
"""A parameter study: Sa and its reduction against the parameter the
sweep's cases vary.

    python3 scripts/plot_study.py study.h5 [output.png] [--g]

For a sweep whose cases vary one config value (the friction preload of
configs/preload_study.toml, say) at a few periods: one row per record and
damping ratio; left, Sa with the joint against that value (one series per
period, log axis when the values span more than a decade) with Sa without
the joint as a dashed line of the same colour; right, the reduction
1 - Sa_with / Sa_without. Cases that vary several values, or none, are
drawn as categories named on the axis. Flagged jobs are open black markers
(flags named), failed ones crosses at zero. `--g` gives Sa in g. Writes
study_study.png beside the input unless an output name is given. Headless.
"""
import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import (  # noqa: E402
    accel_units, case_parameter, flag_names, incomplete, job_masks, log_ticks, mark_jobs, refuse_modal, save,
    sweep_parser, text,
)


def figure(src, in_g=False):
    with h5py.File(src, "r") as f:
        refuse_modal(f, src)
        s = f["spectrum"]
        periods, damping = s["period"][:], s["damping"][:]
        records = [text(r) for r in s["record"][:]]
        cases = [text(c) for c in s["case"][:]]
        parameter = case_parameter(s["case_config"][:])
        sa_with, sa_without = s["with_joint/sa"][:], s["without_joint/sa"][:]
        status, validity = s["with_joint/status"][:], s["with_joint/validity"][:]
        names = flag_names(s["with_joint/validity"].attrs["meaning"])
        reduction = s["reduction"][:]
        complete = int(f.attrs.get("complete", 1))
    k, unit = accel_units(in_g)
    if parameter:
        key, x = parameter
        xlabel = key
    else:
        x, xlabel = np.arange(len(cases), dtype=float), "case"
    logx = parameter is not None and x.min() > 0 and x.max() / x.min() > 10
    rows = [(r, z) for r in range(len(records)) for z in range(len(damping))]
    fig, axes = plt.subplots(len(rows), 2, figsize=(11, 3.8 * len(rows)), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (ax, axr), (r, z) in zip(axes, rows):
        for t, period in enumerate(periods):
            colour = colours[t % len(colours)]
            ok, flagged, failed, _ = job_masks(status[:, r, z, t], validity[:, r, z, t])
            sa, red = k * sa_with[:, r, z, t], 100 * reduction[:, r, z, t]
            ax.plot(x[ok], sa[ok], "o-", color=colour, ms=5, label=f"with joint, T = {period:.3g} s")
            ax.axhline(k * sa_without[r, z, t], color=colour, ls="--", lw=1, label=f"without joint, T = {period:.3g} s")
            axr.plot(x[ok], red[ok], "o-", color=colour, ms=5, label=f"T = {period:.3g} s")
            mark_jobs((ax, axr), x, (sa, red), flagged, failed, validity[:, r, z, t], names, ms=8)
        ax.set_title(f"{records[r]} / damping {damping[z]:g}" + incomplete(complete), fontsize=9)
        ax.set_ylabel(f"Sa [{unit}]")
        axr.axhline(0, color="0.6", lw=0.8)
        axr.set_ylabel("reduction of Sa, 1 - with / without [%]")
        axr.set_title("reduction by the joint", fontsize=9)
        for a in (ax, axr):
            a.set_xlabel(xlabel)
            a.grid(True, which="both", alpha=0.3)
            a.legend(fontsize=7)
            if logx:
                a.set_xscale("log")
                log_ticks(a, x)
            elif parameter is None:
                a.set_xticks(x)
                a.set_xticklabels(cases, rotation=30, ha="right", fontsize=7)
    fig.tight_layout()
    return fig


def main(src, dst=None, in_g=False):
    save(figure(src, in_g), src, dst, "study")


if __name__ == "__main__":
    args = sweep_parser(__doc__).parse_args()
    main(args.input, args.output, args.g)
