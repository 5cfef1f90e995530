"""The exported link at both abutments of the reference three-span bridge
(three_span.py), run by OpenSees: the check that `add_link(..., side=-1)`
builds the element at a deck lying toward -X as quakejoint does
(docs/link.md, "Both abutments").

    python scripts/opensees/link_two_ends.py --link out/link_opensees.py \
        --record ground_motions/RSN77_SFERN_PUL164-hor1.AT2 --scale 2 --duration 12

The model: the bridge of three_span.build(); at each deck end a fixed
abutment node and the link (left: side +1, right: side -1); damping
`modalDamping 0.05` of the bridge's own modes, as the modal bridge of
quakejoint has it: the links' mass nodes are made before the eigen
analysis and held along X there (`add_link_node`), the links added after
modalDamping (`add_link` frees the node). UniformExcitation along X,
Newmark average acceleration at DT / substeps with KrylovNewton (the
FullGeneral system: the modal damping matrix is full).

Reported per deck end: u (the displacement along X relative to the ground)
and the link's force on the deck (its spring-and-damper element's basic
force plus its gap element's, the gap's sign set by the side) at every
record step.
"""
import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np
import openseespy.opensees as ops

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import three_span  # noqa: E402
from at2 import ground_samples, read_at2  # noqa: E402

ABUTMENTS = (90001, 90002)  # fixed abutment nodes at the left and right deck ends
MASS_NODES = (90011, 90012)  # the links' moving masses
FIRST_TAGS = (5000, 6000)  # the links' material and element tags
SIDES = (1, -1)  # the deck lies toward +X of the left joint, toward -X of the right one


def load_link(path, gap=None):
    """The exported openseespy module; `gap` [m] replaces its closing
    movement (to match a config whose joint closes sooner)."""
    spec = importlib.util.spec_from_file_location("quakejoint_link", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if gap is not None:
        module.GAP = gap
    return module


def run(link_path, record, scale=1.0, duration=None, substeps=10, gap=None, damping=0.05):
    """Returns (t, u, force): u and force of shape (steps, 2), left and
    right deck end."""
    link = load_link(link_path, gap)
    dt, acc = read_at2(record)
    acc = np.asarray(acc) * scale
    model = three_span.build()
    ends = (model.deck_nodes[0], model.deck_nodes[-1])
    for abut, end, mass_node in zip(ABUTMENTS, ends, MASS_NODES):
        ops.node(abut, *ops.nodeCoord(end))
        ops.fix(abut, 1, 1, 1)
        link.add_link_node(ops, end, mass_node)
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    # every mode: x and z at every massive node, less the abutments' z
    ops.eigen("-fullGenLapack", 2 * len(model.nodal_mass) - 2)
    ops.modalDamping(damping)
    for abut, end, mass_node, tag, side in zip(ABUTMENTS, ends, MASS_NODES, FIRST_TAGS, SIDES):
        link.add_link(ops, abut, end, mass_node, tag, side=side)
    ops.timeSeries("Path", 1, "-dt", dt, "-values", *ground_samples(acc))
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.wipeAnalysis()
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("FullGeneral")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("KrylovNewton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    n = int(round((duration if duration is not None else len(acc) * dt + 5.0) / dt))
    t, u, force = np.zeros(n + 1), np.zeros((n + 1, 2)), np.zeros((n + 1, 2))
    for k in range(1, n + 1):
        if ops.analyze(substeps, dt / substeps) != 0:
            raise RuntimeError(f"OpenSees failed at t = {ops.getTime()}")
        t[k] = ops.getTime()
        for j, (end, tag, side) in enumerate(zip(ends, FIRST_TAGS, SIDES)):
            u[k, j] = ops.nodeDisp(end, 1)
            # the spring's basic force is its deformation's (deck - mass); the
            # gap element runs abutment -> deck at side +1, deck -> abutment at -1
            force[k, j] = abs(ops.basicForce(tag)[0] + side * ops.basicForce(tag + 2)[0])
    return t, u, force


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--link", required=True, help="the exported link_opensees.py")
    ap.add_argument("--record", required=True, help="a PEER .AT2 record")
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--duration", type=float, help="[s] (default: the record + 5 s)")
    ap.add_argument("--gap", type=float, help="[m] the links' closing movement instead of the export's")
    a = ap.parse_args(argv)
    t, u, force = run(a.link, a.record, a.scale, a.duration, gap=a.gap)
    for j, name in enumerate(("left end", "right end")):
        print(f"{name}: peak |u| {np.abs(u[:, j]).max():.5f} m, peak link force {force[:, j].max():.1f} N")


if __name__ == "__main__":
    main()
