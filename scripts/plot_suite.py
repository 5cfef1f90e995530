#!/usr/bin/env python3
"""A ground-motion suite: the statistics of Sa over the records with and
without the joint, and of the reduction.

    python3 scripts/plot_suite.py suite.h5 [output.png] [--g]

For a sweep of several records (a suite, `[sweep.suite]`): one row per case
and damping ratio. Left: each record's Sa with the joint (thin lines), the
mean with the joint and without it, the median x/÷ exp(dispersion) band
with the joint, and the target spectrum the suite was scaled to (solid
blue, with the fit range shaded and the 90 % Eurocode 8 bound dotted). Right: each
record's reduction (thin), their mean with a +-1 standard deviation band,
and the reduction of the mean spectrum 1 - mean with / mean without.
Periods where a record's job failed or has not run have no statistic (a
gap); the count of flagged records is written above such periods. `--g`
gives Sa in g. Writes suite_suite.png beside the input unless an output
name is given. Headless (Agg).
"""
import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import accel_units, incomplete, period_axes, refuse_modal, save, sweep_parser, text  # noqa: E402

def load(src):
    with h5py.File(src, "r") as f:
        refuse_modal(f, src)
        s = f["spectrum"]
        if "statistics" not in s or s["record"].shape[0] < 2:
            raise SystemExit(f"{src}: no statistics over records (a sweep of one record)")
        g = s["statistics"]
        d = {
            "periods": s["period"][()],
            "damping": s["damping"][()],
            "cases": [text(c) for c in s["case"][()]],
            "records": [text(r) for r in s["record"][()]],
            "sa": s["with_joint/sa"][()],
            "reduction": s["reduction"][()],
            "stats": {k: {n: g[k][n][()] for n in g[k]} for k in ("with_joint", "without_joint", "reduction")},
            "flagged": g["flagged"][()],
            "complete": int(f.attrs.get("complete", 1)),
            "suite": None,
        }
        if "suite" in f:
            su = f["suite"]
            d["suite"] = {
                "target": text(su.attrs["target"]),
                "target_sa": su["target_sa"][()],
                "range": su["range"][()],
                "fit_period": su["fit/period"][()],
                "fit_target": su["fit/target"][()],
                "factor": su["factor"][()],
                "ec8_satisfied": bool(su.attrs["ec8_satisfied"]),
            }
    return d


def figure(src, in_g=False):
    d = load(src)
    k, unit = accel_units(in_g)
    periods, st = d["periods"], d["stats"]
    rows = [(c, z) for c in range(len(d["cases"])) for z in range(len(d["damping"]))]
    fig, axes = plt.subplots(len(rows), 2, figsize=(12, 4.2 * len(rows)), squeeze=False)
    n = len(d["records"])
    for (ax, axr), (c, z) in zip(axes, rows):
        for r in range(n):
            ax.plot(periods, k * d["sa"][c, r, z], "-", color="0.75", lw=0.7,
                    label=f"{n} records, with joint" if r == 0 else None)
            axr.plot(periods, 100 * d["reduction"][c, r, z], "-", color="0.75", lw=0.7,
                     label=f"{n} records" if r == 0 else None)
        w, wo, red = st["with_joint"], st["without_joint"], st["reduction"]
        med, disp = w["median"][c, z], w["dispersion"][c, z]
        ax.fill_between(periods, k * med * np.exp(-disp), k * med * np.exp(disp), color="tab:red", alpha=0.15,
                        label="median x/÷ exp(dispersion), with joint")
        ax.plot(periods, k * w["mean"][c, z], "o-", color="tab:red", ms=4, label="mean with joint")
        ax.plot(periods, k * wo["mean"][z], "s--", color="k", ms=3, lw=1, label="mean without joint")
        suite = d["suite"]
        if suite is not None:
            ax.plot(suite["fit_period"], k * suite["fit_target"], "-", color="tab:blue", lw=1.5,
                    label=f"target: {suite['target']}")
            ax.plot(suite["fit_period"], 0.9 * k * suite["fit_target"], ":", color="tab:blue", lw=1,
                    label="90 % of the target (Eurocode 8)" + ("" if suite["ec8_satisfied"] else ": NOT MET"))
            ax.axvspan(*suite["range"], color="tab:blue", alpha=0.05)
        flagged = d["flagged"][c, z]
        for t, nf in zip(periods, flagged):
            if nf:
                ax.annotate(f"{nf} flagged", (t, k * w["mean"][c, z][list(periods).index(t)]), fontsize=7,
                            textcoords="offset points", xytext=(0, 8), ha="center", color="tab:red")
        rm, rs = 100 * red["mean"][c, z], 100 * red["std"][c, z]
        axr.fill_between(periods, rm - rs, rm + rs, color="tab:blue", alpha=0.15, label="mean +- 1 std of the records")
        axr.plot(periods, rm, "o-", color="tab:blue", ms=4, label="mean reduction")
        axr.plot(periods, 100 * red["of_mean"][c, z], "s--", color="k", ms=3, lw=1,
                 label="reduction of the mean, 1 - mean with / mean without")
        axr.axhline(0, color="0.5", lw=0.8)
        title = f"{d['cases'][c]} / damping {d['damping'][z]:g} / suite of {n} records" + incomplete(d["complete"])
        ax.set_title(title, fontsize=9)
        ax.set_ylabel(f"Sa [{unit}]")
        axr.set_ylabel("reduction of Sa, 1 - with / without [%]")
        axr.set_title("reduction by the joint over the suite", fontsize=9)
        period_axes((ax, axr), periods)
    fig.tight_layout()
    return fig


def main(src, dst=None, in_g=False):
    save(figure(src, in_g), src, dst, "suite")


if __name__ == "__main__":
    args = sweep_parser(__doc__).parse_args()
    main(args.input, args.output, args.g)
