"""PEER NGA AT2 records and the ground acceleration both engines see.

The ground acceleration a_g(t) of the OpenSees reference and of the numpy
check is one function: the record's samples a_k at t_k = k DT (k = 0 ..
NPTS-1), then one zero at t = NPTS DT, linear in between, zero after.
(OpenSees' Path time series is given exactly these values: without the
appended zero it would drop to 0 at the last sample instead of using it.)
"""
import numpy as np

G = 9.80665  # [m/s^2] standard gravity: AT2 values are in g


def read_at2(path):
    """Returns (dt [s], acceleration [m/s^2]) of a PEER AT2 file: four header
    lines, the fourth with NPTS and DT, then the values in g."""
    with open(path) as f:
        lines = f.read().splitlines()
    head = lines[3].replace(",", " ").split()
    npts = dt = None
    for i, word in enumerate(head):
        key = word.upper().rstrip("=")
        if key.startswith("NPTS"):
            npts = int(word.split("=")[1] if "=" in word and word.split("=")[1] else head[i + 1])
        if key.startswith("DT"):
            dt = float(word.split("=")[1] if "=" in word and word.split("=")[1] else head[i + 1])
    values = np.array([float(v) for line in lines[4:] for v in line.split()])
    if npts is None or dt is None or len(values) != npts:
        raise ValueError(f"{path}: NPTS {npts}, DT {dt}, {len(values)} values")
    return dt, values * G


def ground_samples(acc):
    """The samples given to OpenSees' Path series: the record plus one zero."""
    return np.append(acc, 0.0)


def ground_at(t, dt, acc):
    """a_g(t) [m/s^2] at times t [s] (the function described above)."""
    samples = ground_samples(acc)
    times = dt * np.arange(len(samples))
    return np.interp(np.asarray(t, dtype=float), times, samples, left=0.0, right=0.0)


def ground_displacement(t, dt, acc):
    """u_g(t) [m]: the ground's displacement from rest (zero before t = 0),
    integrated exactly from a_g of ground_at (linear between samples, so u_g
    is cubic between them; after the last sample, uniform motion at the
    final velocity)."""
    a = ground_samples(acc)
    h = dt
    v = np.concatenate([[0.0], np.cumsum(h * (a[:-1] + a[1:]) / 2)])
    # u_{j+1} = u_j + h v_j + h^2 (2 a_j + a_{j+1}) / 6
    u = np.concatenate([[0.0], np.cumsum(h * v[:-1] + h * h * (2 * a[:-1] + a[1:]) / 6)])
    t = np.asarray(t, dtype=float)
    j = np.clip(np.floor(t / h).astype(int), 0, len(a) - 2)
    s = t - j * h
    da = (a[j + 1] - a[j]) / h
    inside = u[j] + v[j] * s + a[j] * s ** 2 / 2 + da * s ** 3 / 6
    end = (len(a) - 1) * h
    after = u[-1] + v[-1] * (t - end)
    return np.where(t <= 0, 0.0, np.where(t > end, after, inside))
