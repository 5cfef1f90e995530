# quakejoint link element, calibrated from configs/paper.toml
# units: N, m, kg, s
# spring (stuck joint)      k   = 5.690202e7 N/m
# slider (friction)         F   = 2.573247e5 N
# moving mass               m   = 5.969961e3 kg
# damper with the spring    c   = 1.138040e4 N s/m
# closing movement (gap)    g   = 1.120000e0 m  (28 cells)
# closed-joint stiffness    k_c = 5.165160e7 N/m (the closed cells' Hertz law as a secant at 1.000e6 N, a default: the detailed joint did not close under the calibration suite: where your model's closed joint meets another force, rerun `quakejoint calibrate --contact-force` with it until the two agree; docs/link.md)
# first cell closes at          = 9.760989e-1 m  (the narrowest cell, racked 5.1 mm behind the average: the beams strike there; the element's force waits for g)
# opening capacity              = 9.493967e-1 m  (the widest cell, racked 6.1 mm ahead of the average, at joint.capacity.max_subgap)
# racking from the largest of the service loops (4.4 / 4.1 mm closing / opening) and the calibration suite (5.1 / 6.1 mm)
# the opening u is the deck's displacement away from the abutment; the element acts along it
"""The quakejoint link for openseespy (units N, m, kg, s)."""

STIFFNESS = 5.690202221956255e7  # [N/m] spring (stuck joint)
FRICTION = 2.5732466057310026e5  # [N] slider
MASS = 5.969960852885217e3  # [kg] moving mass
DAMPING = 1.138040444391251e4  # [N s/m] damper with the spring
GAP = 1.12e0  # [m] closing movement until every cell is closed
GAP_STIFFNESS = 5.1651597924325414e7  # [N/m] closed joint
STICK_FACTOR = 1000  # the slider's stick stiffness over STIFFNESS
FUSE = None  # the joint has no fuse box
ELEMENT = None  # the joint has no fuse element


def _mass_node(ops, deck_node, node, mass):
    ndf = len(ops.nodeDisp(deck_node))
    ops.node(node, *ops.nodeCoord(deck_node), "-mass", mass, *([0.0] * (ndf - 1)))
    ops.fix(node, *([1] * ndf))


def add_link_node(ops, deck_node, new_node, fuse_node=None):
    """The link's mass node at the deck node, held along X until add_link frees it
    (and, with a FUSE, the edge beam's node fuse_node, new_node + 1 by default).
    With modalDamping, call it before the eigen analysis and add_link after
    modalDamping: a node with mass added after modalDamping makes OpenSees 3.7.1 end
    the process without an error, and a link present at the eigen analysis has its
    modes damped too (docs/link.md)."""
    _mass_node(ops, deck_node, new_node, MASS)
    if FUSE is not None:
        _mass_node(ops, deck_node, new_node + 1 if fuse_node is None else fuse_node, FUSE["mass"])


def add_link(ops, abut_node, deck_node, new_node, first_tag, side=1, fuse_node=None):
    """Adds the link between two existing nodes at the same place (never swap
    them). side: +1 where the deck lies toward +X (global X) of the joint, the
    bridge's first end; -1 where it lies toward -X, the far end: the chain stays
    abutment - slider - mass - spring - deck and the gap closes as the deck moves
    toward the abutment. new_node: the moving mass's node tag (made here unless
    add_link_node made it); first_tag: the first of 10 free material tags (and of 7
    element tags, and with a FUSE on a ramp of a time series and a load pattern).
    With a FUSE the gap closes on the edge beam's node fuse_node (new_node + 1 by
    default), held on the abutment by a weld that breaks (MinMax), its friction
    (ElasticPP), its seat and its stop (ElasticPPGap), and pushed back by the lift.
    2D or 3D: the new nodes take the deck node's coordinates and DOFs, their mass
    and freedom along the first (global X)."""
    if side not in (1, -1):
        raise ValueError(f"add_link: side must be 1 or -1, not {side!r}")
    if FUSE is not None and fuse_node is None:
        fuse_node = new_node + 1
    if new_node not in ops.getNodeTags():
        add_link_node(ops, deck_node, new_node, fuse_node)
    ops.remove("sp", new_node, 1)
    k_stick = STICK_FACTOR * STIFFNESS
    ops.uniaxialMaterial("Elastic", first_tag + 3, STIFFNESS)
    ops.uniaxialMaterial("Viscous", first_tag + 4, DAMPING, 1.0)
    ops.uniaxialMaterial("Parallel", first_tag, first_tag + 3, first_tag + 4)
    ops.uniaxialMaterial("ElasticPP", first_tag + 1, k_stick, FRICTION / k_stick)
    ops.uniaxialMaterial("ElasticPPGap", first_tag + 2, GAP_STIFFNESS, -1.0e20, -GAP)
    gap_mat = first_tag + 2
    if ELEMENT is not None:
        # the fuse element: the gap fails for good at its release (MinMax), a second gap
        # closes the beam's width later
        ops.uniaxialMaterial("MinMax", first_tag + 6, first_tag + 2, "-min", -ELEMENT["release_closing"])
        ops.uniaxialMaterial("ElasticPPGap", first_tag + 5, ELEMENT["stiffness_after"], -1.0e20, -ELEMENT["gap_after"])
        gap_mat = first_tag + 6
    ops.element("zeroLength", first_tag, new_node, deck_node, "-mat", first_tag, "-dir", 1)
    ops.element("zeroLength", first_tag + 1, abut_node, new_node, "-mat", first_tag + 1, "-dir", 1)
    # (each element's deformation is the opening's sign: it closes toward the abutment)
    base = abut_node if FUSE is None else fuse_node
    gap_nodes = (base, deck_node) if side == 1 else (deck_node, base)
    ops.element("zeroLength", first_tag + 2, *gap_nodes, "-mat", gap_mat, "-dir", 1)
    if ELEMENT is not None:
        ops.element("zeroLength", first_tag + 3, *gap_nodes, "-mat", first_tag + 5, "-dir", 1)
    if FUSE is None:
        return
    ops.remove("sp", fuse_node, 1)
    kw, ks = FUSE["weld_stiffness"], FUSE["stop_stiffness"]
    ops.uniaxialMaterial("Elastic", first_tag + 5, kw)
    ops.uniaxialMaterial("MinMax", first_tag + 6, first_tag + 5, "-min", -FUSE["break_strain"])
    ops.uniaxialMaterial("ElasticPP", first_tag + 7, kw, FUSE["friction"] / kw)
    ops.uniaxialMaterial("ElasticPPGap", first_tag + 8, ks, 1.0e20, 0.0)
    ops.uniaxialMaterial("ElasticPPGap", first_tag + 9, ks, -1.0e20, -FUSE["stroke"])
    fuse_nodes = (abut_node, fuse_node) if side == 1 else (fuse_node, abut_node)
    # weld, friction, seat, stop
    for i in range(4):
        if i == 1 and FUSE["friction"] <= 0.0:
            continue
        ops.element("zeroLength", first_tag + 3 + i, *fuse_nodes, "-mat", first_tag + 6 + i, "-dir", 1)
    if FUSE["lift"] != 0.0:
        ndf = len(ops.nodeDisp(deck_node))
        ops.timeSeries("Constant", first_tag)
        ops.pattern("Plain", first_tag, first_tag)
        ops.load(fuse_node, side * FUSE["lift"], *([0.0] * (ndf - 1)))
