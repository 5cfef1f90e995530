#!/usr/bin/env python3
"""Time histories of runs: the deck's acceleration with and without the
joint and their difference, the joint's force, its sub-gaps and, when its
beams pound, the contact forces.

    python3 scripts/plot_history.py run.h5 [output.png] [--window T0 T1] [--g]

Reads a `quakejoint simulate --output run.h5` file or every stored history
of a sweep file (`/histories/job_*`, in job order). One column per run (at
most three side by side, then another row), panels sharing the time axis:
1. the deck's absolute acceleration with the joint and without it (the
   exact linear response over the same window), like Figure 12 of the
   source paper;
2. their difference, with - without: the joint's effect, which the first
   panel cannot show when it is a fraction of a percent;
3. the force of the joint on the deck, with the instant its seismic fuse
   broke (a fuse element: its beam left the plane) marked on this panel
   and the next where it broke;
4. the clear sub-gaps (abutment side first) at the wider end of each cell
   (solid: how far it opens) and at the narrower end (dotted: how close
   the beams come), with zero (the beams touch) and the joint's movement
   capacity (`joint.capacity.max_subgap`) drawn, and the largest opening
   marked and labelled when it goes beyond the capacity (after a fuse
   element's beam left, its two cells' halves have half its width more:
   drawn from then on);
5. the largest contact force across each sub-gap per time step (only for
   runs with contacts).
A run without the joint (`simulate --no-joint`) shows the bridge alone and
says so; a run outside the model's validity says so in red in its title.
`--window 2 8` shows 2 s to 8 s (impacts last milliseconds); `--g` gives
accelerations in g. Writes run_history.png beside the input unless an
output name is given. Headless (Agg).
"""
import argparse
import sys
from pathlib import Path

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import NOT_CHECKED, accel_units, text, tomllib  # noqa: E402


def flagged(attrs):
    """' -- FLAGGED: collision' for a run outside the model's validity, else ''."""
    if "validity" in attrs and int(attrs["validity"]) & ~NOT_CHECKED:
        return f" -- FLAGGED: {text(attrs['validity_label'])}"
    return ""


def series(g):
    """The arrays of one run's history group (None where absent)."""
    get = lambda k: g[k][:] if k in g else None  # noqa: E731
    names = ("t", "a_abs", "a_abs_without_joint", "joint_force", "subgaps", "subgaps_wide", "contact_force")
    return {k: get(k) for k in names}


def capacity(config_text):
    """joint.capacity.max_subgap [m] of a config as used (TOML, defaults filled in), or None."""
    try:
        return float(tomllib.loads(text(config_text))["joint"]["capacity"]["max_subgap"])
    except (KeyError, ValueError, TypeError, tomllib.TOMLDecodeError):
        return None


def fuse_break(results, config_text):
    """(time, label, element) of the first joint's fuse where it broke in a
    run whose results group is `results`, else None: a fuse box broke, or a
    fuse element's beam left the plane (then `element` is (its beam, 1 to
    Nc, and its width [m]): its two cells are one, each reported as half
    of it, their capacity max_subgap plus half the beam's width)."""
    if "fuse_broken" not in results or not results["fuse_broken"][()] == 1:
        return None
    try:
        joint = tomllib.loads(text(config_text))["joint"]
        fuse = joint["fuse"]
        element = (int(fuse["beam"]), float(joint["center_beam"]["width"])) if fuse.get("kind") == "element" else None
    except (KeyError, ValueError, TypeError, tomllib.TOMLDecodeError):
        fuse, element = {}, None
    what = f"beam {fuse.get('beam', '?')} left the plane" if fuse.get("kind") == "element" else "fuse broke"
    return float(results["fuse_break_time"][()]), what, element


def runs(f):
    """(title, joint, series) of every run in a file."""
    if "history" in f:
        record = text(f["inputs/records/x"].attrs["name"])
        joint = not text(f.attrs.get("method", "multibody")).startswith("exact")
        what = "" if joint else " -- bridge alone (--no-joint), exact linear"
        title = f"{record}, T = {f['result/period'][()]:.4g} s{what}" + flagged(f.attrs)
        config = f.attrs.get("config", "")
        fuse = fuse_break(f["result"], config)
        yield title, joint, dict(series(f["history"]), capacity=capacity(config), fuse=fuse)
    jobs = f.get("histories", {})
    configs = {}
    if "spectrum/case_config" in f:
        configs = dict(zip(f["spectrum/case"].asstr()[()], f["spectrum/case_config"].asstr()[()]))
    number = lambda n: int(n.rsplit("_", 1)[-1]) if n.rsplit("_", 1)[-1].isdigit() else -1  # noqa: E731
    for name in sorted(jobs, key=number):
        g = jobs[name]
        # a sweep over a bridge given by its modes stores its period scale
        axis = f"period scale {g['period_scale'][()]:g}" if "period_scale" in g else f"T = {g['period'][()]:.4g} s"
        title = f"{text(g.attrs['case'])} / {text(g.attrs['record'])} / damping {g['damping'][()]:g} / {axis}"
        config = configs.get(text(g.attrs["case"]), "")
        yield title + flagged(g.attrs), True, dict(series(g), capacity=capacity(config), fuse=fuse_break(g, config))


def note(ax, message):
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, fontsize=9, color="0.3")
    ax.set_yticks([])


def figure(src, window=None, in_g=False):
    with h5py.File(src, "r") as f:
        items = list(runs(f))
    if not items:
        raise SystemExit(f"{src}: no time histories (simulate --output, or sweep.histories in a sweep)")
    k, unit = accel_units(in_g)
    contacts = any(s["contact_force"] is not None for _, _, s in items)
    # runs without the joint (simulate --no-joint) have the first panel only
    nrows = (5 if contacts else 4) if any(joint for _, joint, _ in items) else 1
    # one column of panels per run, at most three runs side by side
    ncols = min(len(items), 3)
    blocks = -(-len(items) // ncols)
    grid = plt.subplots(
        nrows * blocks, ncols, figsize=(7.5 * ncols, (2.3 * nrows + 0.6) * blocks), squeeze=False, sharex="col"
    )
    fig, every = grid
    for extra in range(len(items), blocks * ncols):
        for a in every[(extra // ncols) * nrows:(extra // ncols + 1) * nrows, extra % ncols]:
            a.set_axis_off()
    for i, (title, joint, s) in enumerate(items):
        block, col = divmod(i, ncols)
        axes = every[block * nrows:(block + 1) * nrows]
        ax = axes[0, col]
        t = s["t"]
        ax.plot(t, k * s["a_abs_without_joint"], color="0.45", lw=0.9, label="without joint (exact)")
        if joint:
            ax.plot(t, k * s["a_abs"], color="tab:red", lw=0.7, label="with joint")
        ax.set_title(title, fontsize=9, color="tab:red" if "FLAGGED" in title else "k")
        ax.set_ylabel(f"deck abs. acc. [{unit}]")
        ax.legend(fontsize=8, loc="upper right", framealpha=0.8)
        for a in axes[:, col]:
            a.grid(True, alpha=0.3)
        axes[-1, col].set_xlabel("t [s]")
        axes[-1, col].xaxis.set_tick_params(labelbottom=True)
        if window:
            ax.set_xlim(*window)
        if nrows == 1:
            continue
        axd, axf, axg = axes[1:4, col]
        if joint:
            diff = k * (s["a_abs"] - s["a_abs_without_joint"])
            axd.plot(t, diff, color="tab:purple", lw=0.7, label="with - without")
            peak = np.abs(s["a_abs_without_joint"]).max()
            axd.set_title(
                f"difference: largest {np.abs(diff).max():.3g} {unit.replace('$', '')}, "
                f"{100 * np.abs(diff).max() / (k * peak):.2g} % of the peak without the joint",
                fontsize=8,
            )
            axf.plot(t, 1e-3 * s["joint_force"], color="tab:green", lw=0.7)
            axf.set_title("force of the joint on the deck", fontsize=8)
            if s.get("fuse"):
                # (the fuse's break, on the force and the sub-gaps)
                t_break, what, _ = s["fuse"]
                for a in (axf, axg):
                    a.axvline(t_break, color="0.35", lw=1.4, ls="-.", label=f"{what}, {t_break:.2f} s")
                axf.legend(fontsize=8, loc="upper right", framealpha=0.8)
        else:
            note(axd, "no joint in this run: nothing to compare")
            note(axf, "no joint in this run")
        axd.set_ylabel(f"difference [{unit}]")
        axf.set_ylabel("joint force [kN]")
        gaps, wide = s["subgaps"], s["subgaps_wide"]
        if gaps is None or len(gaps) == 0:
            note(axg, "no sub-gaps (no joint)")
        else:
            if wide is None:  # a file of an earlier version: the narrower end only
                wide = gaps
            for j, (g, w) in enumerate(zip(gaps, wide)):
                label = f"sub-gap {j + 1}" if len(gaps) <= 8 else None
                axg.plot(t, 1e3 * w, lw=0.8, color=f"C{j % 10}", label=label)
                axg.plot(t, 1e3 * g, lw=0.6, ls=":", color=f"C{j % 10}")
            axg.axhline(0, color="k", lw=1.0, ls="--", label="beams touch")
            cap = s.get("capacity")
            title = "clear sub-gaps (abutment side first): wider end solid, narrower dotted"
            if cap is not None:
                axg.axhline(1e3 * cap, color="tab:red", lw=1.2, ls="--", label=f"capacity {1e3 * cap:.0f} mm")
                # the largest opening inside the window shown (the whole run
                # without a window); one beyond it is named in the title
                shown = (t >= window[0]) & (t <= window[1]) if window else np.ones(len(t), bool)
                # (a fuse element's merged cell: its halves' capacity has half
                # the beam's width more)
                excess = wide - cap
                element = s["fuse"][2] if s.get("fuse") else None
                after = t >= s["fuse"][0] if s.get("fuse") else np.zeros(len(t), bool)
                if element is not None and element[0] < len(wide) and after.any():
                    k, w = element
                    excess[k - 1:k + 1, after] -= 0.5 * w
                    axg.hlines(1e3 * (cap + 0.5 * w), t[after][0], t[-1], color="tab:red", lw=1.0, ls=":",
                               label=f"sub-gaps {k}, {k + 1} after: {1e3 * (cap + 0.5 * w):.0f} mm")
                finite_excess = np.where(np.isfinite(excess), excess, -np.inf)
                j_all, i_all = np.unravel_index(np.argmax(finite_excess), wide.shape)
                if excess[j_all, i_all] > 0 and not shown[i_all]:
                    title += f"\nlargest opening {1e3 * wide[j_all, i_all]:.1f} mm at t = {t[i_all]:.2f} s, outside the window"
                masked = np.where(shown[np.newaxis, :], finite_excess, -np.inf)
                j, i = np.unravel_index(np.argmax(masked), wide.shape)
                if shown.any() and excess[j, i] > 0:
                    axg.plot(t[i], 1e3 * wide[j, i], "o", color="tab:red", ms=6, zorder=5)
                    axg.annotate(
                        f"sub-gap {j + 1} opens to {1e3 * wide[j, i]:.1f} mm at t = {t[i]:.2f} s",
                        (t[i], 1e3 * wide[j, i]),
                        xytext=(10, 4),
                        textcoords="offset points",
                        fontsize=8,
                        color="tab:red",
                        bbox={"boxstyle": "round", "fc": "white", "ec": "tab:red", "alpha": 0.9},
                    )
                    title += " -- beyond the capacity" if shown[i_all] else ""
            # room above the largest opening for the legend and the label
            finite = np.isfinite(wide).any() and np.isfinite(gaps).any()
            top = 1e3 * max(np.nanmax(wide) if finite else 0.0, cap if cap is not None else 0.0)
            if finite and top > 0:
                axg.set_ylim(min(-0.05 * top, 1e3 * np.nanmin(gaps)), 1.45 * top)
            axg.set_title(title, fontsize=8)
            axg.legend(fontsize=8, ncol=3, loc="upper right", framealpha=0.9)
        axg.set_ylabel("sub-gap [mm]")
        if contacts:
            axc = axes[4, col]
            forces = s["contact_force"]
            if forces is None or len(forces) == 0:
                note(axc, "no contacts in this model")
            elif not forces.any():
                note(axc, "no pounding: no sub-gap closed")
            else:
                closed = [i for i, fc in enumerate(forces) if fc.any()]
                for j in closed:
                    axc.plot(t, 1e-3 * forces[j], lw=0.8, color=f"C{j % 10}", label=f"sub-gap {j + 1}")
                if len(closed) <= 8:
                    axc.legend(fontsize=8, ncol=3, loc="upper right", framealpha=0.8)
                axc.set_title(f"contact force, peak per time step ({len(closed)} of {len(forces)} sub-gaps closed)",
                              fontsize=8)
            axc.set_ylabel("contact force [kN]")
    fig.tight_layout()
    return fig


def main(src, dst=None, window=None, in_g=False):
    fig = figure(src, window, in_g)
    out = dst or str(Path(src).with_name(Path(src).stem + "_history.png"))
    fig.savefig(out, dpi=100)
    print(out)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", help="simulate or sweep HDF5 file")
    parser.add_argument("output", nargs="?", help="PNG to write (default: beside the input)")
    parser.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"), help="time window [s]")
    parser.add_argument("--g", action="store_true", help="accelerations in g instead of m/s^2")
    args = parser.parse_args()
    if args.window and not args.window[0] < args.window[1]:
        parser.error(f"--window {args.window[0]:g} {args.window[1]:g}: T0 must be below T1")
    try:
        main(args.input, args.output, args.window, args.g)
    except SystemExit as e:
        sys.exit(e.code)
