"""OpenSees' own linear transient analysis of the reference three-span
bridge under a record along x: the independent reference for the modal
bridge.

    python scripts/opensees/transient.py \
        --output tests/data/three_span/opensees_corralitos090.csv

- ground motion: PEER AT2 record (default Loma Prieta, Corralitos 090),
  UniformExcitation along x; a_g as in at2.py (the record, then one zero);
- damping: `modalDamping 0.05` after an eigen analysis (-fullGenLapack) of
  every mode of the model (all 124), so every mode has 5 %;
- Newmark average acceleration (gamma 1/2, beta 1/4), algorithm Linear,
  system FullGeneral: the modal damping matrix is full, and with a banded
  or sparse system OpenSees would drop the terms outside the storage from
  the tangent while keeping them in the residual, and a Linear algorithm
  (one solve per step, no iteration) would then be silently wrong (see
  --system to try);
- time step: the record's DT / substeps (default 10), output every DT;
- duration: the record (NPTS DT) + 5 s;
- initial state: at rest relative to the ground, with the consistent
  initial acceleration (-a_g(0) along x at the DOFs with mass) set by
  setNodeAccel, since the record starts at a_g(0) != 0 and Newmark would
  otherwise start from an inconsistent zero acceleration;
- optionally (--end-springs KL KR) a linear spring along x from each deck
  end to a fixed node (zeroLength, uniaxial Elastic), added after
  modalDamping so the damping stays that of the bridge's own modes and the
  springs have none: the reference for the modal bridge with forces at its
  ends (the static correction, docs/bridge.md);
- optionally (--lagged-spring K LAG) a linear spring along x from the left
  deck end to a node that moves as the ground did LAG seconds before (wave
  passage reaching the left abutment late): relative to the ground of the
  UniformExcitation that node is displaced by d(t) = u_g(t - LAG) - u_g(t)
  (at2.ground_displacement, exact for a_g linear between samples), imposed
  by an sp constraint with a Path series at every analysis step; the
  spring added after modalDamping, undamped;
- output at the points of three_span.py (deck ends, pier tops): u, the
  displacement along x relative to the ground [m], and a_abs, the absolute
  acceleration along x [m/s^2] = OpenSees' relative nodal acceleration +
  a_g(t) added here (checked against the Node recorder's -timeSeries
  option, which adds it inside OpenSees).
"""
import argparse
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import openseespy.opensees as ops

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import three_span  # noqa: E402
from at2 import G, ground_at, ground_displacement, ground_samples, read_at2  # noqa: E402
from export_modes import _quiet, opensees_version  # noqa: E402

ROOT = HERE.parents[1]
RECORD = ROOT / "ground_motions" / "RSN753_LOMAP_CLS090-hor2.AT2"
EXTRA = 5.0  # [s] free vibration after the record
DAMPING = 0.05  # [-] modal damping ratio of every mode


def run(record=RECORD, substeps=10, damping=DAMPING, n_damped=None, system="FullGeneral",
        duration=None, check_recorder=True, consistent_start=True, end_springs=None, lagged_spring=None):
    """Builds the bridge and runs the transient. Returns (names, t, u, a_abs,
    info): u and a_abs are (n_out, n_points); info has the run's facts.
    end_springs: (k_left, k_right) [N/m] of springs from the deck ends to
    the ground, or None; lagged_spring: (k [N/m], lag [s]) of a spring from
    the left deck end to a node moving as the ground lag earlier, or None."""
    dt_rec, acc = read_at2(record)
    model = three_span.build()
    points = model.points
    n_massive = 2 * len(model.nodal_mass) - 2  # x and z at every massive node, less the abutments' z
    n_damped = n_massive if n_damped is None else n_damped

    ends = (model.deck_nodes[0], model.deck_nodes[-1])
    if end_springs is not None:
        # the springs' fixed nodes before the eigen analysis (modalDamping
        # needs every node's eigenvector), the springs after modalDamping:
        # the damping is the bridge's modes', the springs have none
        for i, tag in enumerate(ends):
            ops.node(90001 + i, *ops.nodeCoord(tag))
            ops.fix(90001 + i, 1, 1, 1)

    if duration is None:
        duration = len(acc) * dt_rec + EXTRA
    h = dt_rec / substeps
    n_out = int(round(duration / dt_rec))
    lagged = 90011
    if lagged_spring is not None:
        # the lagged node: its x imposed (sp in a Plain pattern) before the
        # eigen analysis, so that it is no free massless DOF there
        ops.node(lagged, *ops.nodeCoord(ends[0]))
        ops.fix(lagged, 0, 1, 1)
        steps = np.arange(n_out * substeps + 1) * h
        lag = lagged_spring[1]
        d = ground_displacement(steps - lag, dt_rec, acc) - ground_displacement(steps, dt_rec, acc)
        ops.timeSeries("Path", 2, "-dt", h, "-values", *d)
        ops.pattern("Plain", 2, 2)
        ops.sp(lagged, 1, 1.0)

    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    with _quiet():
        lam = ops.eigen("-fullGenLapack", n_damped)
    ops.modalDamping(damping)
    if end_springs is not None:
        for i, (tag, k) in enumerate(zip(ends, end_springs)):
            ops.uniaxialMaterial("Elastic", 90001 + i, float(k))
            ops.element("zeroLength", 90001 + i, 90001 + i, tag, "-mat", 90001 + i, "-dir", 1)
    if lagged_spring is not None:
        ops.uniaxialMaterial("Elastic", lagged, float(lagged_spring[0]))
        ops.element("zeroLength", lagged, lagged, ends[0], "-mat", lagged, "-dir", 1)

    ops.timeSeries("Path", 1, "-dt", dt_rec, "-values", *ground_samples(acc))
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)

    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system(system)
    ops.test("NormDispIncr", 1e-12, 10)
    ops.algorithm("Linear", "-factorOnce")  # linear model, constant step: one factorisation
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")

    ag0 = float(ground_at(0.0, dt_rec, acc))
    if consistent_start:
        for tag in model.nodal_mass:
            ops.setNodeAccel(tag, 1, -ag0, "-commit")

    rec_file = None
    if check_recorder:
        fd, rec_file = tempfile.mkstemp(suffix=".txt")
        os.close(fd)
        ops.recorder("Node", "-file", rec_file, "-timeSeries", 1, "-time",
                     "-node", *[tag for _, tag, _ in points], "-dof", 1, "accel")

    t = np.zeros(n_out + 1)
    u = np.zeros((n_out + 1, len(points)))
    a_rel = np.zeros((n_out + 1, len(points)))
    for j, (_, tag, _) in enumerate(points):
        a_rel[0, j] = ops.nodeAccel(tag, 1)
    t0 = time.perf_counter()
    for k in range(1, n_out + 1):
        if ops.analyze(substeps, h) != 0:
            raise RuntimeError(f"OpenSees failed at t = {ops.getTime()}")
        t[k] = ops.getTime()
        for j, (_, tag, _) in enumerate(points):
            u[k, j] = ops.nodeDisp(tag, 1)
            a_rel[k, j] = ops.nodeAccel(tag, 1)
    wall = time.perf_counter() - t0
    ops.remove("recorders")
    a_abs = a_rel + ground_at(t, dt_rec, acc)[:, None]

    info = {
        "record": Path(record).name,
        "dt_record": dt_rec,
        "npts": len(acc),
        "pga": float(np.max(np.abs(acc))),
        "step": h,
        "steps": n_out * substeps,
        "duration": float(t[-1]),
        "n_damped": n_damped,
        "periods": 2 * math.pi / np.sqrt(np.asarray(lam)),
        "wall": wall,
        "opensees": opensees_version(),
        "system": system,
        "end_springs": end_springs,
        "lagged_spring": lagged_spring,
    }
    if rec_file:
        rec = np.loadtxt(rec_file)
        os.unlink(rec_file)
        # rows at every step; t = 0 (the initial state) is not recorded
        idx = np.arange(1, n_out + 1) * substeps - 1
        rec = rec[idx[idx < len(rec)]]
        m = len(rec)
        info["recorder_time_diff"] = float(np.max(np.abs(rec[:, 0] - t[1:m + 1])))
        info["recorder_abs_acc_diff"] = float(np.max(np.abs(rec[:, 1:] - a_abs[1:m + 1])))
    names = [name for name, _, _ in points]
    return names, t, u, a_abs, info


def write_csv(path, names, t, u, a_abs, info):
    cols = ["time [s]"]
    for name in names:
        cols += [f"{name} u [m]", f"{name} a_abs [m/s^2]"]
    data = np.zeros((len(t), 1 + 2 * len(names)))
    data[:, 0] = t
    data[:, 1::2] = u
    data[:, 2::2] = a_abs
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        f.write(",".join(cols) + "\n")
        for row in data:
            f.write(",".join(f"{v:.10g}" for v in row) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--output", help="CSV to write (time, then u and a_abs per point)")
    ap.add_argument("--record", default=str(RECORD), help="PEER AT2 record (default Corralitos 090)")
    ap.add_argument("--substeps", type=int, default=10, help="time steps per record step (default 10)")
    ap.add_argument("--damping", type=float, default=DAMPING, help="modal damping ratio (default 0.05)")
    ap.add_argument("--damped-modes", type=int, default=None,
                    help="modes given to modalDamping (default: all of the model's)")
    ap.add_argument("--system", default="FullGeneral",
                    help="OpenSees system (default FullGeneral; BandGeneral shows the banded-tangent pitfall)")
    ap.add_argument("--duration", type=float, default=None, help="[s] default: record + 5 s")
    ap.add_argument("--end-springs", type=float, nargs=2, metavar=("KL", "KR"), default=None,
                    help="[N/m] springs along x from the left and right deck ends to the ground")
    ap.add_argument("--lagged-spring", type=float, nargs=2, metavar=("K", "LAG"), default=None,
                    help="[N/m, s] a spring along x from the left deck end to a node moving as the ground did LAG "
                         "seconds before")
    ap.add_argument("--inconsistent-start", action="store_true",
                    help="start from zero acceleration (OpenSees' default) instead of the consistent one")
    a = ap.parse_args(argv)
    names, t, u, a_abs, info = run(a.record, a.substeps, a.damping, a.damped_modes, a.system,
                                   a.duration, consistent_start=not a.inconsistent_start,
                                   end_springs=a.end_springs, lagged_spring=a.lagged_spring)
    print(f"{info['opensees']}: {info['record']}, PGA {info['pga'] / G:.4f} g, {info['steps']} steps of "
          f"{info['step']:.3g} s to t = {info['duration']:.4f} s, {info['n_damped']} modes damped, "
          f"system {info['system']}, end springs {info['end_springs']}, lagged spring {info['lagged_spring']}: "
          f"{info['wall']:.1f} s")
    print(f"  T1 = {info['periods'][0]:.5f} s; recorder -timeSeries check: time {info.get('recorder_time_diff')}, "
          f"a_abs {info.get('recorder_abs_acc_diff')} m/s^2")
    for j, name in enumerate(names):
        print(f"  {name:12s} max|u| = {np.max(np.abs(u[:, j])):.6e} m, max|a_abs| = "
              f"{np.max(np.abs(a_abs[:, j])):.6e} m/s^2")
    if a.output:
        write_csv(a.output, names, t, u, a_abs, info)
        print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
