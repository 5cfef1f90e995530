#!/usr/bin/env python3
"""Reference linear response spectra of real records, computed by other
open-source programs, for checking `quakejoint spectrum`.

Programs (each given the same samples, read from the AT2 file by this
script's own reader; values in g times g = 9.80665 m/s^2):

- eqsig 1.2.17 (PyPI), `eqsig.sdof.response_series`: the Nigam & Jennings
  (1969) piecewise-exact recurrence, closed-form coefficients in float64,
  vectorised over periods. The same exact method as quakejoint; it differs
  only by round-off and by eqsig using 6.2831853 for 2 pi (relative error
  1.1e-9 in omega). Its spectrum functions (`true_response_spectra`,
  `pseudo_response_spectra`) replace Sa by the PGA for T < 6 dt, so the
  peaks are taken here from the response histories instead.
- pyrotd 0.6.1 (PyPI), `pyrotd.calc_oscillator_resp`: frequency domain (the
  FFT of the record times the oscillator's transfer function, inverse FFT):
  the exact response to the band-limited (trigonometric) interpolation of
  the samples, not to the piecewise-linear one. Here the record is padded
  with zeros to 2^k samples (at least `PAD_TIME` s of zeros, so that the
  circular convolution's wrap-around has decayed below 1e-9), no
  up-sampling (`max_freq_ratio=0`: the response at the sample times) and
  the peak is taken over the record's samples only (quakejoint's window).
  Sa = max |w^2 u + 2 zeta w u'| from pyrotd's `sd` and `sv` histories:
  pyrotd's own `osc_type="sa"` multiplies the transfer function by
  (1 - w^2) instead of taking 1 + (i w)^2 H, which is not the absolute
  acceleration (see README.md).
- OpenSees 3.7.1 (openseespy 3.7.1.2, PyPI): a transient analysis of an
  elastic single-DOF model (zeroLength, Elastic k = w^2 m, m = 1, damping
  c = 2 zeta w m as mass-proportional Rayleigh damping), UniformExcitation
  of a Path time series (the samples, linear in between, one zero appended
  after the last), Newmark average acceleration (gamma 1/2, beta 1/4),
  `SUBSTEPS` steps per sample interval; the response is read at the sample
  times. Newmark's period elongation is (w h)^2 / 12 for a step h, so its
  error falls as h^2 (`--study` shows it). Sa is OpenSees' relative
  acceleration plus the ground's.

Psa = (2 pi / T)^2 Sd for all three (quakejoint's definition).

Run (a virtual environment of its own; openseespy needs the Debian
packages libblas3 and liblapack3):

    python3 -m venv /tmp/specvenv
    /tmp/specvenv/bin/pip install eqsig==1.2.17 pyrotd==0.6.1 openseespy==3.7.1.2
    /tmp/specvenv/bin/python scripts/reference_spectra.py            # writes tests/data/reference_spectra/*.csv
    /tmp/specvenv/bin/python scripts/reference_spectra.py --compare target/release/quakejoint --no-write
    /tmp/specvenv/bin/python scripts/reference_spectra.py --study --no-write   # refinement tests

Output: tests/data/reference_spectra/<program>_<record stem>.csv with the
columns damping, period_s, sa_m_s2, psa_m_s2, sd_m, sv_m_s (rows
damping-major, like quakejoint's), values as Python's shortest round-trip
repr of the float64 result.
"""
import argparse
import csv
import json
import math
import platform
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import numpy as np

G = 9.80665  # [m/s^2] standard gravity: PEER AT2 values are in g
ROOT = Path(__file__).resolve().parent.parent
RECORDS = [
    "RSN753_LOMAP_CLS090-hor2.AT2",  # Loma Prieta 1989, Corralitos 090, dt 0.005 s
    "RSN6_IMPVALL.I_I-ELC180-hor1.AT2",  # Imperial Valley 1940, El Centro 180, dt 0.01 s
]
DAMPINGS = (0.02, 0.05)
SUBSTEPS_H = 1.25e-4  # [s] OpenSees step: dt / SUBSTEPS (40 for dt 0.005 s, 80 for 0.01 s)
PAD_TIME = 1000.0  # [s] at least this much zero padding for pyrotd's FFT
COLUMNS = ["damping", "period_s", "sa_m_s2", "psa_m_s2", "sd_m", "sv_m_s"]
PROGRAMS = ("eqsig", "pyrotd", "opensees")


def periods():
    """20 log-spaced periods 0.05 .. 5 s rounded to 6 significant digits,
    plus 1.0 s exactly (sorted; 21 periods)."""
    grid = np.geomspace(0.05, 5.0, 20)
    grid = {float(f"{p:.6g}") for p in grid} | {1.0}
    return sorted(grid)


def read_at2(path):
    """(dt [s], acceleration [m/s^2]) of a PEER NGA AT2 file: 4 header
    lines (line 3 states the units, line 4 NPTS and DT), then NPTS values."""
    lines = Path(path).read_text().splitlines()
    if "UNITS OF G" not in lines[2].upper():
        raise ValueError(f"{path}: line 3 does not say units of g: {lines[2]!r}")
    words = lines[3].replace(",", " ").replace("=", " ").split()
    npts = int(words[words.index("NPTS") + 1])
    dt = float(words[words.index("DT") + 1])
    values = np.array([float(v) for line in lines[4:] for v in line.split()])
    if len(values) != npts:
        raise ValueError(f"{path}: NPTS = {npts} but {len(values)} values")
    return dt, values * G


def peaks(u, v, a_abs, period):
    """Spectral values from response histories (rows: periods)."""
    sd = np.abs(u).max(axis=-1)
    w = 2 * np.pi / np.asarray(period)
    return {"sa": np.abs(a_abs).max(axis=-1), "psa": w**2 * sd, "sd": sd, "sv": np.abs(v).max(axis=-1)}


def run_eqsig(dt, acc, pers, zeta):
    import eqsig.sdof

    # u'' + 2 zeta w u' + w^2 u = -a_g from rest, exact for linear a_g; the
    # third history is the absolute acceleration -(2 zeta w u' + w^2 u)
    u, v, a_abs = eqsig.sdof.response_series(acc, dt, np.array(pers), zeta)
    return peaks(u, v, a_abs, pers)


def run_pyrotd(dt, acc, pers, zeta, refine=1):
    """refine > 1: give pyrotd the record linearly interpolated at dt/refine
    (a test of the interpolation explanation); peaks still at the samples."""
    import pyrotd

    n = len(acc)
    if refine > 1:
        t = np.arange((n - 1) * refine + 1) * (dt / refine)
        acc = np.interp(t, np.arange(n) * dt, acc)
        dt = dt / refine
    m = len(acc)
    length = 1 << math.ceil(math.log2(m + PAD_TIME / dt))
    padded = np.zeros(length)
    padded[:m] = acc
    fa = np.fft.rfft(padded)
    freq = np.linspace(0, 1.0 / (2 * dt), num=fa.size)  # as pyrotd.calc_spec_accels (exact for even length)
    out = {k: [] for k in ("sa", "psa", "sd", "sv")}
    for T in pers:
        f = 1.0 / T
        w = 2 * np.pi / T
        hist = {
            k: pyrotd.calc_oscillator_resp(freq, fa, zeta, f, max_freq_ratio=0, osc_type=k)[:m:refine]
            for k in ("sd", "sv", "psa")
        }
        out["sd"].append(np.abs(hist["sd"]).max())
        out["sv"].append(np.abs(hist["sv"]).max())
        out["psa"].append(np.abs(hist["psa"]).max())
        out["sa"].append(np.abs(w * w * hist["sd"] + 2 * zeta * w * hist["sv"]).max())
    return {k: np.array(v) for k, v in out.items()}


def opensees_history(dt, acc, period, zeta, substeps):
    import openseespy.opensees as ops

    w = 2 * np.pi / period
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    ops.node(1, 0.0)
    ops.node(2, 0.0)
    ops.fix(1, 1)
    ops.mass(2, 1.0)
    ops.uniaxialMaterial("Elastic", 1, w * w)
    ops.element("zeroLength", 1, 1, 2, "-mat", 1, "-dir", 1)
    # the samples, then one zero: without it the Path series may read 0 at
    # the last sample time (time accumulated in floating point beyond it)
    ops.timeSeries("Path", 1, "-dt", dt, "-values", *acc.tolist(), 0.0)
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.rayleigh(2 * zeta * w, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.algorithm("Linear")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n = len(acc)
    u = np.zeros(n)
    v = np.zeros(n)
    a_rel = np.zeros(n)
    h = dt / substeps
    for i in range(1, n):
        if ops.analyze(substeps, h) != 0:
            raise RuntimeError(f"OpenSees failed at sample {i}, T = {period}")
        u[i] = ops.nodeDisp(2, 1)
        v[i] = ops.nodeVel(2, 1)
        a_rel[i] = ops.nodeAccel(2, 1)
    ops.wipe()
    a_abs = a_rel + acc
    a_abs[0] = 0.0  # at rest at t = 0 (OpenSees' initial acceleration is 0, not -a_g(0))
    return u, v, a_abs


def substeps_for(dt):
    return max(1, round(dt / SUBSTEPS_H))


def run_opensees(dt, acc, pers, zeta, substeps=None):
    substeps = substeps or substeps_for(dt)
    rows = [peaks(*opensees_history(dt, acc, T, zeta, substeps), T) for T in pers]
    return {k: np.array([r[k] for r in rows]) for k in ("sa", "psa", "sd", "sv")}


RUN = {"eqsig": run_eqsig, "pyrotd": run_pyrotd, "opensees": run_opensees}


def spectra(program, dt, acc, pers):
    """Rows (damping, period, sa, psa, sd, sv), damping-major."""
    rows = []
    for zeta in DAMPINGS:
        res = RUN[program](dt, acc, pers, zeta)
        for j, T in enumerate(pers):
            rows.append([zeta, T] + [float(res[k][j]) for k in ("sa", "psa", "sd", "sv")])
    return rows


def csv_path(outdir, program, record):
    return Path(outdir) / f"{program}_{Path(record).stem}.csv"


def write_csv(path, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(repr(float(x)) for x in r) + "\n")


def read_csv(path):
    with open(path) as f:
        rd = csv.reader(f)
        head = next(rd)
        assert head == COLUMNS, head
        return [[float(x) for x in r] for r in rd]


def quakejoint(binary, record, pers):
    cmd = [
        str(binary), "spectrum", str(ROOT / "ground_motions" / record),
        "--damping", ",".join(str(z) for z in DAMPINGS),
        "--periods", ",".join(repr(p) for p in pers), "--json",
    ]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return {(r["damping"], r["period"]): r for r in json.loads(out)}


def compare(binary, outdir, programs, records):
    """Largest relative difference |x - x_qj| / x_qj per program, record,
    damping and quantity, with the period where it occurs."""
    pers = periods()
    print(f"{'program':9} {'record':34} {'zeta':>5}  " + "  ".join(f"{q:>20}" for q in ("sa", "psa", "sd", "sv")))
    for record in records:
        qj = quakejoint(binary, record, pers)
        for program in programs:
            rows = read_csv(csv_path(outdir, program, record))
            for zeta in DAMPINGS:
                cells = []
                for col, q in ((2, "sa"), (3, "psa"), (4, "sd"), (5, "sv")):
                    worst = max(
                        (abs(r[col] - qj[(zeta, r[1])][q]) / qj[(zeta, r[1])][q], r[1])
                        for r in rows if r[0] == zeta
                    )
                    cells.append(f"{worst[0]:9.2e} @ {worst[1]:<8g}")
                print(f"{program:9} {Path(record).stem:34} {zeta:5.2f}  " + "  ".join(cells))


def study(binary, records):
    """Refinement tests behind the explanations in README.md."""
    pers = periods()
    for record in records:
        dt, acc = read_at2(ROOT / "ground_motions" / record)
        qj = quakejoint(binary, record, pers)
        print(f"\n== {record} (dt = {dt} s)")

        def worst(res, zeta, keys=("sa", "psa", "sd")):
            return max(
                (abs(res[k][j] - qj[(zeta, T)][k]) / qj[(zeta, T)][k], T, k)
                for j, T in enumerate(pers) for k in keys
            )

        for zeta in DAMPINGS:
            # eqsig with omega exactly 2 pi / T: ask for T' = T * 6.2831853 / (2 pi)
            import eqsig.sdof

            tp = np.array(pers) * 6.2831853 / (2 * np.pi)
            u, v, a = eqsig.sdof.response_series(acc, dt, tp, zeta)
            res = peaks(u, v, a, tp)
            res["psa"] = (2 * np.pi / np.array(pers)) ** 2 * res["sd"]
            print(f"eqsig, omega exact, zeta {zeta}: worst {worst(res, zeta)}")
            # OpenSees: Newmark's error ~ h^2
            for k in (substeps_for(dt) // 4, substeps_for(dt) // 2, substeps_for(dt), 2 * substeps_for(dt)):
                res = run_opensees(dt, acc, pers, zeta, substeps=k)
                print(f"opensees substeps {k:4d} (h = {dt / k:.3g} s), zeta {zeta}: worst {worst(res, zeta)}")
            # pyrotd: band-limited vs piecewise-linear interpolation
            for m in (1, 2, 4, 8):
                res = run_pyrotd(dt, acc, pers, zeta, refine=m)
                print(f"pyrotd on the record linearly refined x{m}, zeta {zeta}: worst {worst(res, zeta)}")


def versions():
    v = {"python": platform.python_version(), "numpy": metadata.version("numpy")}
    for p in ("eqsig", "pyrotd", "openseespy", "scipy"):
        try:
            v[p] = metadata.version(p)
        except metadata.PackageNotFoundError:
            v[p] = None
    return v


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=str(ROOT / "tests" / "data" / "reference_spectra"))
    ap.add_argument("--programs", default=",".join(PROGRAMS), help="comma-separated: " + ",".join(PROGRAMS))
    ap.add_argument("--records", default=",".join(RECORDS), help="AT2 files in ground_motions/")
    ap.add_argument("--no-write", action="store_true", help="do not (re)compute the CSV files")
    ap.add_argument("--compare", metavar="QUAKEJOINT", help="compare the CSV files with this quakejoint binary")
    ap.add_argument("--study", action="store_true", help="refinement tests (needs --compare's binary)")
    args = ap.parse_args()
    programs = [p for p in args.programs.split(",") if p]
    records = [r for r in args.records.split(",") if r]
    for p in programs:
        if p not in RUN:
            ap.error(f"unknown program {p}")
    print("versions:", json.dumps(versions()), file=sys.stderr)
    if not args.no_write:
        pers = periods()
        for record in records:
            dt, acc = read_at2(ROOT / "ground_motions" / record)
            for program in programs:
                path = csv_path(args.out, program, record)
                write_csv(path, spectra(program, dt, acc, pers))
                print(f"wrote {path}", file=sys.stderr)
    if args.compare:
        compare(args.compare, args.out, programs, records)
    if args.study:
        if not args.compare:
            ap.error("--study needs --compare QUAKEJOINT")
        study(args.compare, records)


if __name__ == "__main__":
    main()
