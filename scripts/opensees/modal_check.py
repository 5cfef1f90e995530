"""Independent check (numpy only, no OpenSees): does a modes file reproduce
OpenSees' transient?

    python scripts/opensees/modal_check.py \
        --modes tests/data/three_span/modes.toml \
        --csv tests/data/three_span/opensees_corralitos090.csv

Reads the modes file (docs/bridge.md, "The modes file") and the record,
integrates every mode

    q'' + 2 zeta w q' + w^2 q = -Gamma_x a_g(t),   q(0) = q'(0) = 0,

exactly for the piecewise-linear a_g of at2.py (the Nigam-Jennings
recurrence, Chopra "Dynamics of Structures" sec. 5.2, on the record's own
samples, where a_g is linear between them: no discretisation error), and
sums over the n lowest modes at the points:

    u     = sum phi q                    (relative to the ground)
    a_abs = sum phi q'' + a_g            (absolute)

optionally with the static correction for the modes left out:

    u += (ground_x + sum_kept phi Gamma_x / w^2) a_g(t)

(ground_x = -K^-1 M r_x is the full model's quasi-static response to
a_g = +1 m/s^2, = -sum_all phi Gamma_x / w^2; a mode far above the
excitation follows q = -Gamma_x a_g / w^2, so the left-out modes add
-sum_left phi Gamma_x / w^2 a_g = (ground_x + sum_kept ...) a_g; with
every mode kept the correction is zero). No correction is needed for a_abs:
a_g = sum_all phi Gamma_x a_g already carries the left-out modes' rigid
motion, their q'' being small.

Then error = max |modal - OpenSees| / max |OpenSees| per point, for u and
a_abs, against the number of modes.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from at2 import ground_at, ground_samples, read_at2  # noqa: E402

ROOT = HERE.parents[1]
RECORD = ROOT / "ground_motions" / "RSN753_LOMAP_CLS090-hor2.AT2"
COUNTS = (1, 2, 3, 5, 10, 20, None)  # None: all


def read_modes(path, default_damping=0.05):
    """The modes file as arrays, modes sorted by period (longest first)."""
    with open(path, "rb") as f:
        d = tomllib.load(f)
    if d.get("format") != "quakejoint-modes-1":
        raise ValueError(f"{path}: format {d.get('format')!r}")
    points = [(p["name"], p["direction"]) for p in d["point"]]
    modes = sorted(d["mode"], key=lambda m: -m["period"])
    out = {
        "points": points,
        "period": np.array([m["period"] for m in modes]),
        "damping": np.array([m.get("damping", default_damping) for m in modes]),
        "gamma_x": np.array([m["participation_x"] for m in modes]),
        "gamma_y": np.array([m.get("participation_y", 0.0) for m in modes]),
        "shape": np.array([m["shape"] for m in modes]),  # n_modes x n_points
        "total_mass_x": d.get("total_mass_x"),
    }
    if out["shape"].shape[1] != len(points):
        raise ValueError(f"{path}: a shape has not one value per point")
    if "static" in d:
        out["flexibility"] = np.array(d["static"]["flexibility"])
        out["ground_x"] = np.array(d["static"]["ground_x"])
    return out


def nigam_jennings(omega, zeta, h):
    """Coefficients of the exact one-step recurrence of q'' + 2 zeta w q' +
    w^2 q = p(t) with p linear over the step h (arrays over modes, 0 <=
    zeta < 1):
        q1 = A q0 + B v0 + C p0 + D p1,  v1 = A' q0 + B' v0 + C' p0 + D' p1."""
    w, z = np.asarray(omega, float), np.asarray(zeta, float)
    k = w * w
    sq = np.sqrt(1.0 - z * z)
    wd = w * sq
    e = np.exp(-z * w * h)
    s, c = np.sin(wd * h), np.cos(wd * h)
    A = e * (z / sq * s + c)
    B = e * s / wd
    C = (2 * z / (w * h) + e * (((1 - 2 * z * z) / (wd * h) - z / sq) * s - (1 + 2 * z / (w * h)) * c)) / k
    D = (1 - 2 * z / (w * h) + e * ((2 * z * z - 1) / (wd * h) * s + 2 * z / (w * h) * c)) / k
    Ap = -e * (w / sq * s)
    Bp = e * (c - z / sq * s)
    Cp = (-1 / h + e * ((w / sq + z / (h * sq)) * s + c / h)) / k
    Dp = (1 - e * (z / sq * s + c)) / (k * h)
    return A, B, C, D, Ap, Bp, Cp, Dp


def modal_response(omega, zeta, gamma, dt, acc, n_steps):
    """q, q', q'' (n_steps+1 x n_modes) at t = k dt, under p = -gamma a_g,
    a_g the record's samples (then one zero, then zeros) every dt."""
    samples = ground_samples(acc)
    ag = np.zeros(n_steps + 1)
    m = min(len(samples), n_steps + 1)
    ag[:m] = samples[:m]
    A, B, C, D, Ap, Bp, Cp, Dp = nigam_jennings(omega, zeta, dt)
    n = len(omega)
    q = np.zeros((n_steps + 1, n))
    v = np.zeros((n_steps + 1, n))
    qk = np.zeros(n)
    vk = np.zeros(n)
    for k in range(n_steps):
        p0 = -gamma * ag[k]
        p1 = -gamma * ag[k + 1]
        qk, vk = A * qk + B * vk + C * p0 + D * p1, Ap * qk + Bp * vk + Cp * p0 + Dp * p1
        q[k + 1] = qk
        v[k + 1] = vk
    acc_q = -gamma[None, :] * ag[:, None] - 2 * zeta * omega * v - omega ** 2 * q
    return q, v, acc_q, ag


def rk4_response(omega, zeta, gamma, dt, acc, n_steps, sub=200):
    """The same by RK4 with `sub` steps per record step (for checking the
    recurrence; slow)."""
    def f(y, p):
        return np.array([y[1], p - 2 * zeta * omega * y[1] - omega ** 2 * y[0]])
    h = dt / sub
    y = np.zeros((2, len(omega)))
    out = [y[0].copy()]
    for k in range(n_steps):
        for j in range(sub):
            t0 = k * dt + j * h
            pa = -gamma * ground_at(t0, dt, acc)
            pm = -gamma * ground_at(t0 + h / 2, dt, acc)
            pb = -gamma * ground_at(t0 + h, dt, acc)
            k1 = f(y, pa)
            k2 = f(y + h / 2 * k1, pm)
            k3 = f(y + h / 2 * k2, pm)
            k4 = f(y + h * k3, pb)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(y[0].copy())
    return np.array(out)


def newmark_response(omega, zeta, gamma, dt, acc, n_steps, substeps):
    """q, q'' (n_steps+1 x n_modes) at t = k dt by Newmark's average
    acceleration with `substeps` steps per dt, each mode on its own, from the
    consistent start q'' = -gamma a_g(0): the very scheme OpenSees runs
    (transient.py). If OpenSees' damping is modal, its response equals the
    sum of these to round-off, whatever the step: a sharper test of
    `modalDamping` than against the exact solution, which differs by
    Newmark's own O(h^2) error."""
    h = dt / substeps
    c = 2 * zeta * omega
    k = omega ** 2
    keff = 4 / h ** 2 + 2 * c / h + k
    q = np.zeros(len(omega))
    v = np.zeros(len(omega))
    a = -gamma * ground_at(0.0, dt, acc)
    qs = [q.copy()]
    accs = [a.copy()]
    for n in range(n_steps * substeps):
        p1 = -gamma * ground_at((n + 1) * h, dt, acc)
        q1 = (p1 + 4 / h ** 2 * q + 4 / h * v + a + c * (2 / h * q + v)) / keff
        a1 = 4 / h ** 2 * (q1 - q) - 4 / h * v - a
        v = v + h / 2 * (a + a1)
        q, a = q1, a1
        if (n + 1) % substeps == 0:
            qs.append(q.copy())
            accs.append(a.copy())
    return np.array(qs), np.array(accs)


def read_csv(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return header, data


def superpose(modes, q, qdd, ag, n, static):
    """u and a_abs at the points from the n lowest modes."""
    phi = modes["shape"][:n]  # n x points
    u = q[:, :n] @ phi
    a_abs = qdd[:, :n] @ phi + ag[:, None]
    if static:
        if "ground_x" not in modes:
            raise ValueError("the modes file has no [static] table")
        w2 = (2 * math.pi / modes["period"][:n]) ** 2
        corr = modes["ground_x"] + (modes["gamma_x"][:n] / w2) @ phi
        u = u + ag[:, None] * corr[None, :]
    return u, a_abs


def check(modes_path, csv_path, record=RECORD, window=None, counts=COUNTS, default_damping=0.05,
          reference="opensees"):
    """Errors against OpenSees' CSV (reference "opensees") or, to see the
    truncation alone without Newmark's error in OpenSees' response, against
    the exact modal sum of every mode in the file (reference "modal").
    Returns a dict: points, rows [(n, static, err_u per point, err_a per
    point)], the static correction left with every mode [s^2], ..."""
    modes = read_modes(modes_path, default_damping)
    header, os_data = read_csv(csv_path)
    dt, acc = read_at2(record)
    t = os_data[:, 0]
    if not np.allclose(t, dt * np.arange(len(t)), atol=1e-9):
        raise ValueError("the CSV's times are not the record's steps")
    if window is not None:
        keep = t <= window + 1e-9
        os_data, t = os_data[keep], t[keep]
    n_steps = len(t) - 1
    omega = 2 * math.pi / modes["period"]
    q, v, qdd, ag = modal_response(omega, modes["damping"], modes["gamma_x"], dt, acc, n_steps)
    u_os = os_data[:, 1::2]
    a_os = os_data[:, 2::2]
    if reference == "modal":
        u_os, a_os = superpose(modes, q, qdd, ag, len(omega), False)
    elif reference != "opensees":
        raise ValueError(f"reference {reference!r}")
    names = [p[0] for p in modes["points"]]
    n_all = len(omega)
    rows = []
    for n in counts:
        n = n_all if n is None else min(n, n_all)
        for static in ((False, True) if "ground_x" in modes else (False,)):
            u, a = superpose(modes, q, qdd, ag, n, static)
            err_u = np.max(np.abs(u - u_os), axis=0) / np.max(np.abs(u_os), axis=0)
            err_a = np.max(np.abs(a - a_os), axis=0) / np.max(np.abs(a_os), axis=0)
            rows.append((n, static, err_u, err_a))
    out = {"points": names, "rows": rows, "n_modes": n_all, "steps": n_steps,
           "peak_u": np.max(np.abs(u_os), axis=0), "peak_a": np.max(np.abs(a_os), axis=0)}
    if "ground_x" in modes:
        w2 = omega ** 2
        out["static_left_all"] = modes["ground_x"] + (modes["gamma_x"] / w2) @ modes["shape"]
        out["ground_x"] = modes["ground_x"]
    if modes.get("total_mass_x"):
        out["mass_ratio_x"] = float(np.sum(modes["gamma_x"] ** 2) / modes["total_mass_x"])
    return out


def table(res, points=None):
    """Markdown table of the errors (in % of the peak)."""
    idx = [i for i, n in enumerate(res["points"]) if points is None or n in points]
    head = "| modes | static correction | " + " | ".join(
        f"{res['points'][i]} u | {res['points'][i]} a_abs" for i in idx) + " |"
    lines = [head, "|" + "---|" * (2 + 2 * len(idx))]
    for n, static, eu, ea in res["rows"]:
        label = f"{n} (all)" if n == res["n_modes"] else str(n)
        cells = " | ".join(f"{100 * eu[i]:.4f} % | {100 * ea[i]:.4f} %" for i in idx)
        lines.append(f"| {label} | {'yes' if static else 'no'} | {cells} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--modes", required=True, help="modes file (TOML)")
    ap.add_argument("--csv", required=True, help="OpenSees' transient (transient.py)")
    ap.add_argument("--record", default=str(RECORD), help="the record of the CSV (AT2)")
    ap.add_argument("--window", type=float, default=None, help="[s] compare over the first WINDOW s only")
    ap.add_argument("--damping", type=float, default=0.05, help="damping of modes without one (default 0.05)")
    ap.add_argument("--counts", default="1,2,3,5,10,20,all", help="numbers of modes kept, comma-separated")
    ap.add_argument("--truncation", action="store_true",
                    help="compare with the exact sum of every mode in the file instead of OpenSees "
                         "(the truncation error alone; the CSV still gives the time window)")
    a = ap.parse_args(argv)
    counts = tuple(None if c == "all" else int(c) for c in a.counts.split(","))
    res = check(a.modes, a.csv, a.record, a.window, counts, a.damping,
                "modal" if a.truncation else "opensees")
    print(f"{res['n_modes']} modes, {res['steps']} steps; sum Gamma_x^2 / total_mass_x = "
          f"{res.get('mass_ratio_x', float('nan')):.10f}")
    if "static_left_all" in res:
        rel = np.max(np.abs(res["static_left_all"])) / np.max(np.abs(res["ground_x"]))
        print(f"static correction with every mode kept: {rel:.2e} of ground_x")
    print("peaks (OpenSees): " + ", ".join(
        f"{n}: u {pu:.5e} m, a_abs {pa:.5e} m/s^2" for n, pu, pa in zip(res["points"], res["peak_u"], res["peak_a"])))
    what = "the modal sum of every mode" if a.truncation else "OpenSees"
    print(f"error = max |modal - {what}| / max |{what}|:")
    print(table(res))


if __name__ == "__main__":
    main()
