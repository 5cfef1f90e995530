"""The link element without regularisation: a single-DOF deck and the
rigid-plastic link (spring k to a mass m that sticks on the abutment until
the force it needs exceeds F, then slides against F), integrated event to
event with scipy (DOP853 between the events where the mass starts or stops
sliding, the record's linear pieces integrated one by one). The third
method beside quakejoint's regularised link and OpenSees' ElasticPP slider
(docs/link.md, "A run of links is integrated in short steps").

    python3 scripts/link_exact.py --link examples/link/link.toml \
        --mass 1e7 --period 1.0 --record ground_motions/RSN6_IMPVALL.I_I-ELC180-hor1.AT2

The damper beside the spring is left out (c = 0): give quakejoint and
OpenSees the same. Reported: the link's force on the deck at every record
step (and its peak), relative coordinates, the ground acceleration linear
between samples as scripts/opensees/at2.py reads it.
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent / "opensees"))
from at2 import ground_samples, read_at2  # noqa: E402

TOL = dict(method="DOP853", rtol=1e-12, atol=1e-14)


def read_link(path):
    """stiffness, friction and mass of a link.toml."""
    values = {}
    for line in Path(path).read_text().splitlines():
        if "=" in line and not line.lstrip().startswith(("#", "[")):
            key, value = line.split("#")[0].split("=")
            values[key.strip()] = float(value)
    return values["stiffness"], values["friction"], values["mass"]


def forces(stiffness, friction, mass, deck_mass, period, record, damping=0.05, extra=5.0):
    """The link's force on the deck at every record step [N] (t = 0, dt, ...)."""
    k, f_c, m = stiffness, friction, mass
    kb = deck_mass * (2 * math.pi / period) ** 2
    cb = 2 * damping * math.sqrt(kb * deck_mass)
    dt, acc = read_at2(record)
    g = np.asarray(ground_samples(acc))

    def ag(t):
        i = min(int(t / dt), len(g) - 2)
        return g[i] + (g[i + 1] - g[i]) * (t / dt - i)

    def rhs(mode):
        def f(t, y):
            xd, vd, xm, vm = y
            a_deck = (-kb * xd - cb * vd - k * (xd - xm)) / deck_mass - ag(t)
            a_mass = 0.0 if mode == 0 else (k * (xd - xm) - mode * f_c) / m - ag(t)
            return [vd, a_deck, vm if mode else 0.0, a_mass]
        return f

    def needed(t, y):
        """The friction force the mass needs to stay stuck [N]."""
        return k * (y[0] - y[2]) - m * ag(t)

    y, mode, out = np.zeros(4), 0, [0.0]
    steps = int(round((len(acc) * dt + extra) / dt))
    for j in range(steps):
        t, t1 = j * dt, (j + 1) * dt
        while t < t1:
            if mode == 0:
                def event(t, y):
                    return abs(needed(t, y)) - f_c
                event.direction = 1
            else:
                def event(t, y):
                    return y[3]
            event.terminal = True
            sol = solve_ivp(rhs(mode), (t, t1), y, events=event, **TOL)
            y, t = sol.y[:, -1].copy(), sol.t[-1]
            if sol.status != 1:
                break
            # an event: the mass starts sliding, or stops (and sticks, or
            # slides back at once)
            need = needed(t, y)
            if mode != 0:
                y[3] = 0.0
            mode = 0 if (mode != 0 and abs(need) <= f_c) else (1 if need > 0 else -1)
            # past the event, so that it is not found again at once
            t_next = min(t + 1e-9, t1)
            y = solve_ivp(rhs(mode), (t, t_next), y, **TOL).y[:, -1].copy()
            t = t_next
        out.append(k * (y[0] - y[2]))
    return np.asarray(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--link", required=True, help="link.toml (stiffness, friction, mass)")
    ap.add_argument("--mass", type=float, required=True, help="[kg] deck mass")
    ap.add_argument("--period", type=float, required=True, help="[s] deck period")
    ap.add_argument("--record", required=True, help="a PEER .AT2 record")
    a = ap.parse_args(argv)
    f = np.abs(forces(*read_link(a.link), a.mass, a.period, a.record))
    dt, _ = read_at2(a.record)
    print(f"peak force on the deck {f.max():.2f} N at {f.argmax() * dt:.2f} s")


if __name__ == "__main__":
    main()
