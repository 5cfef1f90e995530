#!/usr/bin/env python3
"""The fragility curves of a multiple-stripe sweep: the fraction of runs
that exceeded each limit state at each stripe, and the fitted lognormal.

    python3 scripts/plot_fragility.py sweep.h5 [output.png] [--hazard]

For a sweep with stripes and `[sweep.fragility]` (the output's group
/fragility): one panel per limit state. At each stripe the fraction
exceeded / runs is a point (the number of runs n is in the legend when
every stripe has the same, else written beside each point); stripes with
failed or flagged runs have a hollow red ring. Where the limit state has a
fit, the lognormal P = Phi(ln(x / median) / beta) is drawn, with a band
between the curves at the ends of the bootstrap intervals (at each
intensity the lowest and highest of the four curves median_lo/hi x
beta_lo/hi), and a box gives the median and beta with their intervals and,
when the file has a hazard curve, the annual frequency of exceedance and
its return period. Where there is no fit the points are still drawn; the
file's note (why no fit, failed and flagged counts) is written in the
panel. Several (case, damping, period) curves get their own colours and
markers. `--hazard` adds a panel with the hazard curve (log-log) and the
fitted medians on it (where each limit state's median meets the hazard
curve; the limit state's own annual frequency is in the list). Intensities
are in the file's units (g). Writes
sweep_fragility.png beside the input unless an output name is given.
Headless (Agg).
"""
import itertools
import math
import sys
import textwrap
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plotlib import incomplete, log_ticks, save, sweep_parser, text  # noqa: E402

FIT = (
    "median",
    "beta",
    "median_lo",
    "median_hi",
    "beta_lo",
    "beta_hi",
    "annual_frequency",
    "return_period",
    "annual_frequency_lo",
    "annual_frequency_hi",
)
COUNTS = ("runs", "exceeded", "failed", "flagged", "not_run", "undetermined")
MARKERS = "osD^vP*X"
#: where a text box may go in a panel: (x, y, ha, va) in axes fractions, in order of preference
CORNERS = {
    "lower right": (0.97, 0.05, "right", "bottom"),
    "upper left": (0.03, 0.95, "left", "top"),
    "center right": (0.97, 0.5, "right", "center"),
    "center left": (0.03, 0.5, "left", "center"),
    "upper right": (0.97, 0.95, "right", "top"),
    "lower left": (0.03, 0.05, "left", "bottom"),
}
RING = "stripe with failed or flagged runs (see the note)"

_erf = np.vectorize(math.erf, otypes=[float])


def lognormal_cdf(x, median, beta):
    """P = Phi(ln(x / median) / beta), 0 at x <= 0; a step at the median
    for beta = 0 (the end of an interval of separated resamples)."""
    x = np.asarray(x, dtype=float)
    if beta == 0:
        return (x >= median).astype(float)
    z = np.full(x.shape, -np.inf)
    positive = x > 0
    z[positive] = np.log(x[positive] / median) / beta
    return 0.5 * (1.0 + _erf(z / math.sqrt(2.0)))


def confidence(config):
    """The bootstrap intervals' confidence from /fragility's `config` TOML."""
    if config is None:
        return None
    try:
        value = tomllib.loads(text(config)).get("confidence")
    except tomllib.TOMLDecodeError:
        return None
    return float(value) if isinstance(value, (int, float)) else None


def curve_labels(f, shape):
    """A label per (case, damping, period) curve, keyed by index, and the
    parts common to all (for the figure title)."""
    s = f.get("spectrum")
    axes = [None, None, None]
    if s is not None:
        axes[0] = [text(c) for c in s["case"][()]] if "case" in s else None
        axes[1] = [f"damping {z:g}" for z in s["damping"][()]] if "damping" in s else None
        if "period" in s:
            axes[2] = [f"T {p:g} s" for p in s["period"][()]]
        elif "period_scale" in s:
            axes[2] = [f"period scale {p:g}" for p in s["period_scale"][()]]
    for i, (name, n) in enumerate(zip(("case", "damping", "period"), shape)):
        if axes[i] is None or len(axes[i]) != n:
            axes[i] = [f"{name} {k}" for k in range(n)]
    varying = [i for i in range(3) if shape[i] > 1]
    common = " / ".join(axes[i][0] for i in range(3) if shape[i] == 1)
    labels = {}
    for idx in itertools.product(*(range(n) for n in shape)):
        labels[idx] = " / ".join(axes[i][idx[i]] for i in varying) or common
    return labels, common


def load(src):
    with h5py.File(src, "r") as f:
        if "fragility" not in f:
            raise SystemExit(f"{src}: no /fragility group (a sweep with [sweep.stripes] and [sweep.fragility])")
        fr = f["fragility"]
        a = fr.attrs
        d = {
            "measure_label": text(a.get("measure_label", a.get("measure", "intensity"))),
            "units": text(a.get("units", "g")),
            "failed": text(a.get("failed", "")),
            "hazard_source": text(a["hazard_source"]) if "hazard_source" in a else None,
            "confidence": confidence(a.get("config")),
            "levels": fr["levels"][()],
            "records": [text(r) for r in fr["ground_record"][()]],
            "complete": int(f.attrs.get("complete", 1)),
            "hazard": None,
            "states": [],
        }
        if "hazard_intensity" in fr and "hazard_frequency" in fr:
            d["hazard"] = (fr["hazard_intensity"][()], fr["hazard_frequency"][()])
        shape = None
        # in the config's order (the attribute index); /fragility/design is
        # the choice among the cases (scripts/plot_design.py), no limit state
        groups = [(k, g) for k, g in fr.items() if isinstance(g, h5py.Group) and "kind" in g.attrs]
        for key, g in sorted(groups, key=lambda kg: int(kg[1].attrs.get("index", 0))):
            state = {
                "key": key,
                "name": text(g.attrs.get("name", key)),
                "kind": text(g.attrs.get("kind", "")),
                "definition": text(g.attrs.get("definition", "")),
            }
            for n in COUNTS:
                state[n] = g[n][()] if n in g else None
            for n in FIT:
                state[n] = g[n][()] if n in g else np.full(g["runs"].shape[:3], np.nan)
            state["note"] = (
                np.vectorize(lambda b: text(b).rstrip("\0").strip(), otypes=[object])(g["note"][()])
                if "note" in g else np.full(g["runs"].shape[:3], "", dtype=object)
            )
            shape = g["runs"].shape[:3]
            d["states"].append(state)
        if not d["states"]:
            raise SystemExit(f"{src}: /fragility has no limit state")
        d["labels"], d["common"] = curve_labels(f, shape)
    return d


def fmt(x, digits=3):
    return f"{float(f'{x:.{digits}g}'):g}"


def fit_lines(st, idx, units, prefix=""):
    """The text box lines of one curve's fit (empty when there is none)."""
    m, b = st["median"][idx], st["beta"][idx]
    if not (np.isfinite(m) and np.isfinite(b)):
        return []
    lo, hi, blo, bhi = (st[n][idx] for n in ("median_lo", "median_hi", "beta_lo", "beta_hi"))
    interval = f" ({fmt(lo)}–{fmt(hi)})" if np.isfinite(lo) and np.isfinite(hi) else ""
    binterval = f" ({fmt(blo, 2)}–{fmt(bhi, 2)})" if np.isfinite(blo) and np.isfinite(bhi) else ""
    lines = [f"{prefix}median {fmt(m)} {units}{interval}", f"{prefix}β {fmt(b, 2)}{binterval}"]
    lam, rp = st["annual_frequency"][idx], st["return_period"][idx]
    if np.isfinite(lam):
        rp = rp if np.isfinite(rp) else 1.0 / lam
        llo, lhi = st["annual_frequency_lo"][idx], st["annual_frequency_hi"][idx]
        linterval = f" ({llo:.2g}–{lhi:.2g})" if np.isfinite(llo) and np.isfinite(lhi) else ""
        lines.append(f"{prefix}λ = {lam:.2g} /yr{linterval}")
        lines.append(f"{prefix}return period {fmt(rp, 3)} y")
    return lines


class Placer:
    """Puts text boxes in a panel where they cover no point, curve or band
    (tried at the corners and sides, the widest wrapping first)."""

    def __init__(self, ax):
        self.ax = ax
        self.segments = []  # (x, y_lo, y_hi) in data coordinates
        self.boxes = []  # placed boxes in axes fractions

    def occupy(self, x, lo, hi=None):
        x, lo = np.atleast_1d(x), np.atleast_1d(lo)
        hi = lo if hi is None else np.atleast_1d(hi)
        self.segments.extend(zip(x, lo, hi))

    def _collisions(self, bb, margin=0.015):
        x0, x1, y0, y1 = bb.x0 - margin, bb.x1 + margin, bb.y0 - margin, bb.y1 + margin
        hits = 0
        if x0 < 0 or x1 > 1 or y0 < -0.01 or y1 > 1.01:
            hits += 1000
        if self.segments:
            seg = np.array(self.segments, dtype=float)
            to_axes = self.ax.transData + self.ax.transAxes.inverted()
            lo = to_axes.transform(seg[:, [0, 1]])
            hi = to_axes.transform(seg[:, [0, 2]])
            r = 0.025  # about a marker's radius
            inside = (lo[:, 0] >= x0 - r) & (lo[:, 0] <= x1 + r) & (hi[:, 1] >= y0 - r) & (lo[:, 1] <= y1 + r)
            hits += int(inside.sum())
        for b in self.boxes:
            if b.x0 < x1 and x0 < b.x1 and b.y0 < y1 and y0 < b.y1:
                hits += 1000
        return hits

    def place(self, make_text, widths, corners=tuple(CORNERS), **kw):
        """Places make_text(width) for each wrapping width until it fits
        somewhere; failing that, where it covers the least."""
        renderer = self.ax.figure.canvas.get_renderer()
        best = None
        for width in widths:
            s = make_text(width)
            for corner in corners:
                x, y, ha, va = CORNERS[corner]
                t = self.ax.text(x, y, s, transform=self.ax.transAxes, ha=ha, va=va, ma="left", zorder=5, **kw)
                bb = t.get_window_extent(renderer).transformed(self.ax.transAxes.inverted())
                hits = self._collisions(bb)
                t.remove()
                if best is None or hits < best[0]:
                    best = (hits, s, corner, bb)
                if hits == 0:
                    break
            if best[0] == 0:
                break
        hits, s, corner, bb = best
        x, y, ha, va = CORNERS[corner]
        self.boxes.append(bb)
        return self.ax.text(x, y, s, transform=self.ax.transAxes, ha=ha, va=va, ma="left", zorder=5, **kw)


def draw_state(ax, st, d, colours, several):
    levels, units = d["levels"], d["units"]
    xmax = 1.3 * levels.max()
    grid = np.linspace(0.0, xmax, 400)
    placer = Placer(ax)
    fits, notes = [], []
    conf = d["confidence"]
    band_label = (f"{conf * 100:g} % interval" if conf else "interval") + " (ends of median and beta intervals)"
    for k, (idx, label) in enumerate(d["labels"].items()):
        colour = colours[k % len(colours)]
        marker = MARKERS[k % len(MARKERS)] if several else "o"
        runs = st["runs"][idx].astype(int)
        exceeded = st["exceeded"][idx].astype(int)
        ran = runs > 0
        frac = np.where(ran, exceeded / np.maximum(runs, 1), np.nan)
        same_n = len(set(runs[ran])) == 1
        what = f"{label}: " if several else ""
        n_text = f" (n = {runs[ran][0]} runs each)" if ran.any() and same_n else " (n runs written beside)"
        ax.plot(levels[ran], frac[ran], marker, color=colour, ms=6, ls="none", zorder=4,
                label=f"{what}exceeded / runs at a stripe{n_text}")
        placer.occupy(levels[ran], frac[ran])
        if ran.any() and not same_n:
            for x, y, n in zip(levels[ran], frac[ran], runs[ran]):
                ax.annotate(f"n={n}", (x, y), textcoords="offset points", xytext=(5, -9 if y > 0.5 else 4),
                            fontsize=6.5, color=colour)
        bad = np.zeros(levels.shape, dtype=bool)
        for n in ("failed", "flagged"):
            if st[n] is not None:
                bad |= st[n][idx] > 0
        bad &= ran
        if bad.any():
            ax.plot(levels[bad], frac[bad], "o", ms=13, mfc="none", mec="red", mew=1.3, zorder=4, label=RING)
        m, b = st["median"][idx], st["beta"][idx]
        if np.isfinite(m) and np.isfinite(b):
            p = lognormal_cdf(grid, m, b)
            ax.plot(grid, p, "-", color=colour, lw=1.6, zorder=3, label=f"{what}fitted lognormal")
            placer.occupy(grid, p)
            ends = [st[n][idx] for n in ("median_lo", "median_hi", "beta_lo", "beta_hi")]
            if all(np.isfinite(ends)) and min(ends[:2]) > 0 and min(ends[2:]) >= 0:
                curves = np.array([lognormal_cdf(grid, mm, bb) for mm in ends[:2] for bb in ends[2:]])
                lo, hi = curves.min(axis=0), curves.max(axis=0)
                ax.fill_between(grid, lo, hi, color=colour, alpha=0.2, lw=0, zorder=2,
                                label=f"{what}{band_label}")
                placer.occupy(grid, lo, hi)
        lines = fit_lines(st, idx, units, "  " if several else "")
        fits.append([f"{label}:"] + lines if several and lines else lines)
        note = st["note"][idx]
        if note:
            notes.append(f"{label}: {note}" if several else note)
    ax.set_xlim(0, xmax)
    ax.set_ylim(-0.04, 1.04)
    ax.set_title(st["name"], fontsize=9.5)
    ax.set_xlabel(f"{d['measure_label']} [{units}]", fontsize=8.5)
    ax.set_ylabel("probability of exceedance", fontsize=8.5)
    ax.tick_params(labelsize=8)
    ax.grid(True, alpha=0.3)
    return placer, "\n".join(line for lines in fits for line in lines), notes


def write_boxes(placer, fit_text, notes):
    """The fit box and the notes, once the panel has its final size."""
    if fit_text:
        placer.place(lambda w: fit_text, [None], fontsize=7.5,
                     bbox=dict(boxstyle="round,pad=0.3", fc="white", ec="0.6", alpha=0.9))
    elif not any("no fit" in n for n in notes):
        notes.insert(0, "no fit")
    if notes:
        joined = list(dict.fromkeys(notes))

        def wrapped(width):
            return "\n".join(textwrap.fill(n, width) for n in joined)

        placer.place(wrapped, [64, 56, 48, 42, 36, 31, 27], fontsize=6.5, color="0.15",
                     bbox=dict(boxstyle="round,pad=0.3", fc="#fff8e6", ec="0.75", alpha=0.9))


def hazard_panel(ax, d):
    intensity, frequency = d["hazard"]
    ax.loglog(intensity, frequency, "o-", color="k", ms=4, lw=1.2, label="hazard curve")
    keep = (intensity > 0) & (frequency > 0)
    li, lf = np.log(intensity[keep]), np.log(frequency[keep])
    marks = []
    for st in d["states"]:
        for idx in d["labels"]:
            m = st["median"][idx]
            if np.isfinite(m) and m > 0 and li.size > 1:
                name = f"{st['name']} ({d['labels'][idx]})" if len(d["labels"]) > 1 else st["name"]
                marks.append((m, math.exp(np.interp(math.log(m), li, lf)), name, st["annual_frequency"][idx]))
    marks.sort()
    lines = []
    for k, (m, h, name, lam) in enumerate(marks, start=1):
        label = "a limit state's median on the hazard curve (its own λ in the list)"
        ax.plot(m, h, "v", color="tab:red", ms=7, label=None if k > 1 else label)
        # numbers alternate above-left and below-right, so that close medians stay apart
        ax.annotate(str(k), (m, h), textcoords="offset points", xytext=(-9, 5) if k % 2 else (6, -12), fontsize=7.5,
                    color="tab:red", fontweight="bold")
        lam_text = f", λ = {lam:.2g} /yr" if np.isfinite(lam) else ""
        lines.append(f"{k}  {name}: median {fmt(m)} {d['units']}{lam_text}")
    if lines:
        ax.text(0.03, 0.04, "\n".join(lines), transform=ax.transAxes, fontsize=7, color="tab:red", va="bottom",
                bbox=dict(boxstyle="round,pad=0.3", fc="white", ec="0.75", alpha=0.9))
    ax.set_xlabel(f"{d['measure_label']} [{d['units']}]", fontsize=8.5)
    ax.set_ylabel("annual frequency of exceedance [1/yr]", fontsize=8.5)
    ax.set_title("hazard curve" + (f" ({d['hazard_source']})" if d["hazard_source"] else ""), fontsize=9.5)
    ax.tick_params(labelsize=8)
    ax.grid(True, which="both", alpha=0.3)
    log_ticks(ax, intensity)


def figure(src, hazard=False):
    d = load(src)
    panels = list(d["states"])
    if hazard and d["hazard"] is None:
        print(f"{src}: no hazard curve in /fragility: --hazard adds no panel", file=sys.stderr)
        hazard = False
    n = len(panels) + int(hazard)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    spare = rows * cols - n
    fig, axes = plt.subplots(rows, cols, figsize=(5.4 * cols, 4.1 * rows + 0.6), squeeze=False)
    axes = axes.ravel()
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    several = len(d["labels"]) > 1
    stripes, per = len(d["levels"]), len(d["records"])
    failed = {"exclude": "failed runs left out", "exceed": "failed runs counted as exceeding"}.get(d["failed"], "")
    title = (f"fragility: {d['measure_label']}, {stripes} stripes x {per} records per stripe"
             + (f" ({d['common']})" if d["common"] else "") + (f", {failed}" if failed else "")
             + f" — {Path(src).name}" + incomplete(d["complete"]))
    fig.suptitle(title, fontsize=10.5)
    boxes = [draw_state(ax, st, d, colours, several) for ax, st in zip(axes, panels)]
    if hazard:
        hazard_panel(axes[len(panels)], d)
    handles = {}
    for ax in axes[:n]:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    for ax in axes[n:]:
        ax.axis("off")
    ncol = min(3, len(handles))
    legend_height = 0.0 if spare else 0.3 + 0.22 * math.ceil(len(handles) / max(ncol, 1))
    fig.set_figheight(4.1 * rows + 0.6 + legend_height)
    top = 1 - 0.45 / fig.get_figheight()
    fig.tight_layout(rect=(0, legend_height / fig.get_figheight(), 1, top), h_pad=1.5, w_pad=1.5)
    for box in boxes:
        write_boxes(*box)
    if spare:
        axes[n].legend(handles.values(), handles.keys(), loc="center left", fontsize=8, frameon=False)
    elif handles:
        fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=ncol, fontsize=8, frameon=False)
    return fig


def main(src, dst=None, hazard=False):
    save(figure(src, hazard), src, dst, "fragility")


if __name__ == "__main__":
    parser = sweep_parser(__doc__, in_g=False)
    parser.add_argument("--hazard", action="store_true", help="add a panel with the hazard curve")
    args = parser.parse_args()
    main(args.input, args.output, args.hazard)
