"""The joint's link element exported by `quakejoint calibrate`, run by
OpenSees on a single-DOF deck: the proof that the exported element does in
OpenSees what quakejoint's `joint.model = "link"` does (docs/link.md).

    python scripts/opensees/link_sdof.py --link out/link_opensees.py \
        --mass 1e6 --period 1.0 --record ground_motions/RSN753_LOMAP_CLS090-hor2.AT2

The model (2D, ndf 3, units N, m, kg, s):
- node 1: the ground and abutment (fixed); node 2: the deck, its mass M
  along x (y and rotation fixed);
- the bridge: a zeroLength from 1 to 2 along x with Parallel(Elastic K,
  Viscous C) materials, K = M (2 pi / T)^2, C = 2 zeta sqrt(K M);
- the link: `add_link(ops, 1, 2, 3, 100)` of the exported file (node 3 the
  joint's moving mass);
- UniformExcitation along x with the record's acceleration (a Path series
  of its samples, then one zero, as scripts/opensees/at2.py reads them);
- Newmark average acceleration, DT / substeps (default 20), Newton with
  NormDispIncr 1e-10, output every DT for the record's length + extra.

Reported: Sa (the deck's peak absolute acceleration), the peak force of
the link on the deck (its spring and damper element's plus its gap
element's basic forces; at the output times as quakejoint takes it, and
at every step with its time: `peak_joint_force_steps`, `peak_time`), the slider's friction energy (its force times
its slip, summed over the steps), and the histories; for a link with a
fuse box (`FUSE` in the exported file) also when it broke, the stroke
used, the residual offset, the fuse's friction energy and whether the
stroke was exhausted (`fuse_*`); for a link with a fuse element
(`ELEMENT`) when its gap let go (`fuse_broke`, `fuse_break_time`), the
second gap's force counted in the force on the deck.
"""
import argparse
import importlib.util
import json
import math
import sys
from pathlib import Path

import numpy as np
import openseespy.opensees as ops

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from at2 import ground_at, ground_samples, read_at2  # noqa: E402


def load_link(path):
    """The exported openseespy module (link_opensees.py)."""
    spec = importlib.util.spec_from_file_location("quakejoint_link", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run(link_path, mass, period, damping, record, scale=1.0, substeps=20, extra=0.0):
    link = load_link(link_path)
    dt, acc = read_at2(record)
    acc = np.asarray(acc) * scale
    k = mass * (2 * math.pi / period) ** 2
    c = 2 * damping * math.sqrt(k * mass)

    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)
    ops.fix(1, 1, 1, 1)
    ops.node(2, 0.0, 0.0, "-mass", mass, 0.0, 0.0)
    ops.fix(2, 0, 1, 1)
    ops.uniaxialMaterial("Elastic", 1, k)
    ops.uniaxialMaterial("Viscous", 2, c, 1.0)
    ops.uniaxialMaterial("Parallel", 3, 1, 2)
    ops.element("zeroLength", 1, 1, 2, "-mat", 3, "-dir", 1)
    link.add_link(ops, 1, 2, 3, 100)

    ops.timeSeries("Path", 1, "-dt", dt, "-values", *ground_samples(acc))
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")

    n_out = int(round((len(acc) * dt + extra) / dt))
    h = dt / substeps
    t = np.zeros(n_out + 1)
    u = np.zeros(n_out + 1)
    a_rel = np.zeros(n_out + 1)
    force = np.zeros(n_out + 1)
    friction_energy = 0.0
    slip_prev = ops.nodeDisp(3, 1)
    fuse = getattr(link, "FUSE", None)
    element = getattr(link, "ELEMENT", None)
    edge = {"broke": False, "break_time": math.nan, "stroke_used": 0.0, "energy": 0.0, "exhausted": False}
    released = {"broke": False, "break_time": math.nan}
    second = element is not None
    x_prev = 0.0
    peak, peak_time = 0.0, 0.0
    for j in range(1, n_out + 1):
        for _ in range(substeps):
            advance(h)
            if abs(deck_force(second)) > peak:
                peak, peak_time = abs(deck_force(second)), ops.getTime()
            if second and not released["broke"] and ops.nodeDisp(2, 1) < -element["release_closing"]:
                # (the gap's MinMax failed: the beam left)
                released["broke"], released["break_time"] = True, ops.getTime()
            slip = ops.nodeDisp(3, 1)
            f_slider = ops.eleResponse(101, "basicForce")[0]
            friction_energy += abs(f_slider * (slip - slip_prev)) if abs(f_slider) >= 0.999 * link.FRICTION else 0.0
            slip_prev = slip
            if fuse is not None:
                watch_fuse(fuse, edge, x_prev)
                x_prev = ops.nodeDisp(4, 1)
        t[j] = ops.getTime()
        u[j] = ops.nodeDisp(2, 1)
        a_rel[j] = ops.nodeAccel(2, 1)
        force[j] = deck_force(second)
    a_abs = a_rel + ground_at(t, dt, acc)
    m = len(acc)
    fuse_results = {}
    if fuse is not None:
        edge["residual_offset"] = -ops.nodeDisp(4, 1)
        fuse_results = {f"fuse_{k}": v for k, v in edge.items()}
    if element is not None:
        fuse_results = {f"fuse_{k}": v for k, v in released.items()}
    return {
        **fuse_results,
        "sa": float(np.max(np.abs(a_abs[:m]))),
        "sd": float(np.max(np.abs(u[:m]))),
        "peak_joint_force": float(np.max(np.abs(force))),
        "peak_joint_force_steps": peak,
        "peak_time": peak_time,
        "friction_energy": friction_energy,
        "t": t,
        "u": u,
        "a_abs": a_abs,
        "force": force,
    }


def deck_force(second=False):
    """The link's force on the deck: its spring's (the deck its j node)
    and its gap's (and with a fuse element the second gap's, element
    103)."""
    force = -ops.eleResponse(100, "basicForce")[0] - ops.eleResponse(102, "basicForce")[0]
    return force - ops.eleResponse(103, "basicForce")[0] if second else force


def advance(h):
    """One step of `h`; where Newton does not converge (a fuse's weld
    breaking, its beam striking its stop), the step in ten and then a
    hundred parts."""
    if ops.analyze(1, h) == 0:
        return
    for parts in (10, 100):
        if ops.analyze(parts, h / parts) == 0:
            return
    raise RuntimeError(f"OpenSees failed at t = {ops.getTime()}")


def watch_fuse(fuse, edge, x_prev):
    """The fuse box of the link (node 4, elements 103 weld, 104 friction,
    106 stop): the break (the weld compressed beyond its break strain),
    the freed beam's travel, its friction's work and whether it reached
    its stop, into `edge`."""
    x = ops.nodeDisp(4, 1)
    if not edge["broke"] and -x > fuse["break_strain"]:
        edge["broke"], edge["break_time"] = True, ops.getTime()
    edge["stroke_used"] = max(edge["stroke_used"], -x)
    if fuse["friction"] > 0.0:
        f = ops.eleResponse(104, "basicForce")[0]
        edge["energy"] += abs(f * (x - x_prev)) if abs(f) >= 0.999 * fuse["friction"] else 0.0
    if -x >= fuse["stroke"]:
        edge["exhausted"] = True


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--link", required=True, help="link_opensees.py written by quakejoint calibrate")
    ap.add_argument("--mass", type=float, required=True, help="[kg] deck mass")
    ap.add_argument("--period", type=float, required=True, help="[s] deck period")
    ap.add_argument("--damping", type=float, default=0.05, help="deck damping ratio (default 0.05)")
    ap.add_argument("--record", required=True, help="PEER AT2 record")
    ap.add_argument("--scale", type=float, default=1.0, help="factor on the record")
    ap.add_argument("--substeps", type=int, default=20, help="time steps per record step (default 20)")
    ap.add_argument("--json", action="store_true", help="print the peaks as JSON")
    a = ap.parse_args(argv)
    r = run(a.link, a.mass, a.period, a.damping, a.record, a.scale, a.substeps)
    peaks = {k: r[k] for k in ("sa", "sd", "peak_joint_force", "friction_energy") + tuple(x for x in r if x.startswith("fuse_"))}
    print(json.dumps(peaks) if a.json else "\n".join(f"{k:18s} {v:.6g}" for k, v in peaks.items()))


if __name__ == "__main__":
    main()
