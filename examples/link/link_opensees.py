# quakejoint link element, calibrated from configs/paper.toml
# units: N, m, kg, s
# spring (stuck joint)      k   = 5.690202e7 N/m
# slider (friction)         F   = 2.573247e5 N
# moving mass               m   = 4.974967e3 kg
# damper with the spring    c   = 1.000000e5 N s/m
# closing movement (gap)    g   = 1.120000e0 m  (28 cells)
# closed-joint stiffness    k_c = 5.165160e7 N/m (the closed cells' Hertz law as a secant at 1.000e6 N: rerun `quakejoint calibrate --contact-force` with the closed joint's force your model finds, until the two agree; docs/link.md)
# opening capacity              = 1.120000e0 m  (cells at joint.capacity.max_subgap)
# the opening u is the deck's displacement away from the abutment; the element acts along it
"""The quakejoint link for openseespy (units N, m, kg, s)."""

STIFFNESS = 5.690202221956255e7  # [N/m] spring (stuck joint)
FRICTION = 2.5732466057310026e5  # [N] slider
MASS = 4.974967377404348e3  # [kg] moving mass
DAMPING = 1e5  # [N s/m] damper with the spring
GAP = 1.12e0  # [m] closing movement until every cell is closed
GAP_STIFFNESS = 5.1651597924325414e7  # [N/m] closed joint
STICK_FACTOR = 1000  # the slider's stick stiffness over STIFFNESS


def add_link(ops, abut_node, deck_node, new_node, first_tag):
    """Adds the link between two existing nodes at the same place, the deck lying
    toward +X of the joint (not for a deck toward -X: swapping the nodes reverses the
    chain, the slider on the deck; docs/link.md); new_node: a new node tag (the
    moving mass); first_tag: the first of 5 free material tags (and of 3 element tags).
    2D or 3D: the new node takes the deck node's coordinates and DOFs, its mass
    and freedom along the first (global X)."""
    ndf = len(ops.nodeDisp(deck_node))
    ops.node(new_node, *ops.nodeCoord(deck_node), "-mass", MASS, *([0.0] * (ndf - 1)))
    ops.fix(new_node, 0, *([1] * (ndf - 1)))
    k_stick = STICK_FACTOR * STIFFNESS
    ops.uniaxialMaterial("Elastic", first_tag + 3, STIFFNESS)
    ops.uniaxialMaterial("Viscous", first_tag + 4, DAMPING, 1.0)
    ops.uniaxialMaterial("Parallel", first_tag, first_tag + 3, first_tag + 4)
    ops.uniaxialMaterial("ElasticPP", first_tag + 1, k_stick, FRICTION / k_stick)
    ops.uniaxialMaterial("ElasticPPGap", first_tag + 2, GAP_STIFFNESS, -1.0e20, -GAP)
    ops.element("zeroLength", first_tag, new_node, deck_node, "-mat", first_tag, "-dir", 1)
    ops.element("zeroLength", first_tag + 1, abut_node, new_node, "-mat", first_tag + 1, "-dir", 1)
    ops.element("zeroLength", first_tag + 2, abut_node, deck_node, "-mat", first_tag + 2, "-dir", 1)
