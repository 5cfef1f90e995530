"""Helpers shared by the plotting scripts (imported from scripts/): reading
strings and validity flags of quakejoint's HDF5 files, acceleration units,
readable log-axis ticks, and the parameter a sweep's cases vary."""
import argparse
import math
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

import matplotlib.ticker
import numpy as np

#: the `not_checked` bit of the validity flags
NOT_CHECKED = 1 << 15
#: standard gravity [m/s^2]
G = 9.80665


def text(x):
    """A string from an h5py value (the files store text fixed-length, which h5py gives as bytes; files before schema 12 kept attribute text variable-length, given as str)."""
    return x.decode() if isinstance(x, bytes) else str(x)


def flag_names(meaning):
    """(bit, name) pairs from a `validity_meaning`/`meaning` attribute."""
    pairs = []
    for part in text(meaning).split(";")[-1].split(","):
        bit, _, name = part.strip().partition(" ")
        if bit.isdigit():
            pairs.append((int(bit), name))
    return pairs


def flagged_bits(validity):
    """The validity bits that are findings (not_checked is not one)."""
    return np.asarray(validity).astype(np.int64) & ~NOT_CHECKED


def job_masks(status, validity):
    """(ok, flagged, failed, not_run) boolean arrays of a sweep's jobs."""
    status = np.asarray(status)
    done = status == 0
    flagged = done & (flagged_bits(validity) != 0)
    return done & ~flagged, flagged, (status != 0) & (status != -1), status == -1


def mark_jobs(axes, x, values, flagged, failed, validity, names, prefix="", edge="k", ms=7):
    """Marks a series' jobs that are not plain results, on each axis with
    its values: flagged ones (outside the model's validity) as open markers
    labelled with their flags, failed ones as crosses at zero."""
    if flagged.any():
        bits = np.bitwise_or.reduce(np.asarray(validity)[flagged])
        label = prefix + "flagged: " + ", ".join(n for b, n in names if bits & b and n != "not_checked")
        for ax, v in zip(axes, values):
            ax.plot(x[flagged], v[flagged], "o", ms=ms, mfc="none", mec=edge, mew=1.5, label=label)
    if failed.any():
        for ax in axes:
            ax.plot(x[failed], np.zeros(failed.sum()), "x", color="k", ms=8, mew=1.5,
                    label=f"failed ({failed.sum()} jobs)")


def incomplete(complete):
    """What a title adds for a file whose jobs have not all run."""
    return "" if complete else " (INCOMPLETE: some jobs have not run)"


def refuse_modal(f, src):
    """Stops with a message for a sweep over a bridge given by its modes
    (`/spectrum/period_scale`), whose period axis is a factor, not a
    period: the spectrum, study and suite figures do not draw it yet."""
    if "period_scale" in f.get("spectrum", {}):
        raise SystemExit(
            f"{src}: a sweep over a bridge given by its modes (its axis is sweep.period_scales, a factor on the "
            "modes' periods): the spectrum, study and suite figures are not drawn for it yet; read it with "
            "quakejoint.read_sweep (or h5py: /spectrum/period_scale, /spectrum/longest_period), and its stored "
            "histories with scripts/plot_history.py"
        )


def sweep_parser(doc, in_g=True):
    """The command line of a sweep plot: input, optional output, and --g
    where the plot has accelerations in m/s^2 to give in g."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", help="sweep HDF5 file")
    parser.add_argument("output", nargs="?", help="PNG to write (default: beside the input)")
    if in_g:
        parser.add_argument("--g", action="store_true", help="Sa in g instead of m/s^2")
    return parser


def save(fig, src, dst, suffix, dpi=110):
    """Writes `fig` to `dst`, or beside `src` as <stem>_<suffix>.png, and
    prints the name."""
    out = dst or str(Path(src).with_name(f"{Path(src).stem}_{suffix}.png"))
    fig.savefig(out, dpi=dpi)
    print(out)


def accel_units(in_g):
    """(factor from m/s^2, axis unit) for accelerations."""
    return (1 / G, "g") if in_g else (1.0, "m/s$^2$")


def log_ticks(ax, values, axis="x"):
    """Plain-number ticks on a log axis that stay readable when the range
    spans less than a decade: 1-2-5 per decade, refined to 1-1.5-2-3-5-7
    (or finer) until at least three ticks fall inside, no minor labels."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values) & (values > 0)]
    if values.size == 0:
        return
    lo, hi = values.min(), values.max()
    if hi <= lo:
        lo, hi = lo / 1.5, hi * 1.5
    ticks = []
    for mantissas in ((1, 2, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 9)):
        decades = range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1)
        ticks = sorted({round(m * 10.0**d, 12) for d in decades for m in mantissas})
        ticks = [t for t in ticks if lo / 1.05 <= t <= hi * 1.05]
        if len(ticks) >= 3:
            break
    if len(ticks) < 3:
        ticks = sorted({float(f"{v:.2g}") for v in np.geomspace(lo, hi, 4)})
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
    a.set_major_formatter(matplotlib.ticker.FixedFormatter([compact(t) for t in ticks]))
    a.set_minor_formatter(matplotlib.ticker.NullFormatter())


def period_axes(axes, periods):
    """Logarithmic bridge-period axes with readable ticks, grid and legend
    (the spectrum and suite panels)."""
    for a in axes:
        a.set_xscale("log")
        a.set_xlabel("bridge period T [s]")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
        log_ticks(a, periods)


def compact(value):
    """A short label: 0.5, 2, 150, 20k, 2.5M (SI prefixes from 10^4 up)."""
    for factor, prefix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(value) >= max(factor, 1e4):
            return f"{value / factor:g}{prefix}"
    return f"{value:g}"


def _flatten(table, prefix=""):
    out = {}
    for k, v in table.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flatten(v, key + "."))
        elif not isinstance(v, list):
            out[key] = v
    return out


def case_parameter(case_configs):
    """The one numeric config key a sweep's cases vary, as (key, values),
    or None when they vary none or several (then cases are categories)."""
    if len(case_configs) < 2:
        return None
    flat = [_flatten(tomllib.loads(text(c))) for c in case_configs]
    keys = set().union(*flat)
    varying = [k for k in sorted(keys) if len({repr(f.get(k)) for f in flat}) > 1 and not k.startswith("sweep.")]
    if len(varying) != 1:
        return None
    key = varying[0]
    values = [f.get(key) for f in flat]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return None
    return key, np.array(values, dtype=float)
