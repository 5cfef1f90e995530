"""The reference three-span bridge of the modal-bridge tests, in openseespy.

A planar (x along the bridge, z vertical) continuous girder of spans
40-60-40 m on two piers, all elastic beam-columns (elasticBeamColumn,
Linear geometric transformation), masses lumped at the nodes in x and z.

    import openseespy.opensees as ops
    from three_span import build
    model = build()          # wipes the OpenSees domain and builds the bridge
    model.points             # [("left end", node tag, "x"), ...]

OpenSees' 2-D frame has its coordinates (X, Y) and three DOFs per node
(1: ux, 2: uy, 3: rz); here X is x along the bridge and Y is z, vertical
(up). The export (export_modes.py) and the reference transient
(transient.py) both build the bridge with `build()`.

Units: N, kg, m, s throughout.
"""
from dataclasses import dataclass, field

import openseespy.opensees as ops

# ---- geometry -------------------------------------------------------------
SPANS = (40.0, 60.0, 40.0)  # [m] span lengths, abutment to abutment (140 m)
MAX_DECK_ELEMENT = 2.5  # [m] longest deck element (the mesh is uniform per span)
PIER_HEIGHT = 12.0  # [m] pier: base (fixed) to the deck axis; 12 m puts the
#   longitudinal fundamental period at 0.74 s (8 m would give 0.43 s, below
#   the 0.5-1.5 s wanted for the reference bridge)
PIER_ELEMENTS = 4  # [-] elements per pier

# ---- deck: concrete box girder ---------------------------------------------
DECK_E = 34e9  # [Pa] Young's modulus
DECK_A = 6.5  # [m2] cross-section area
DECK_I = 4.0  # [m4] second moment of area (vertical bending)
DECK_MASS = 17_000.0  # [kg/m] mass per length (structure and superimposed)

# ---- piers: two circular columns of 1.5 m diameter per pier, as one element
PIER_E = 30e9  # [Pa] Young's modulus
PIER_A = 2 * 1.77  # [m2] area of the two columns
PIER_I = 2 * 0.25  # [m4] second moment of area of the two columns (bending in x-z)
PIER_MASS = 2 * 1.77 * 2500.0  # [kg/m] mass per length (density 2500 kg/m3)

# ---- node tags -----------------------------------------------------------
# deck nodes 1, 2, ... from x = 0; pier p (1, 2): base 100 p + 1, then
# 100 p + 2 ... upwards; its top node is the deck node above it (monolithic)
PIER_BASE_TAG = 100


@dataclass
class Model:
    """What build() made: node tags and the masses it assigned."""

    deck_nodes: list = field(default_factory=list)  # deck node tags, x ascending
    deck_x: list = field(default_factory=list)  # [m] their x
    pier_nodes: list = field(default_factory=list)  # per pier: tags base..top
    nodal_mass: dict = field(default_factory=dict)  # tag -> [kg] lumped mass (x and z)
    points: list = field(default_factory=list)  # [(name, tag, direction)] of the modes file

    @property
    def total_mass_x(self):
        """[kg] mass that a ground acceleration along x excites: the sum of
        the lumped masses at the free nodes (the pier bases are fixed and
        carry none)."""
        return sum(self.nodal_mass.values())


def _deck_stations():
    """x of the deck nodes [m]: each span cut into equal elements of at most
    MAX_DECK_ELEMENT."""
    xs = [0.0]
    for span in SPANS:
        n = -int(-span // MAX_DECK_ELEMENT)  # ceil
        x0 = xs[-1]
        xs += [x0 + span * (k + 1) / n for k in range(n)]
    return xs


def build():
    """Wipes the OpenSees domain and builds the bridge. Returns a Model."""
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    m = Model()

    xs = _deck_stations()
    for i, x in enumerate(xs):
        tag = i + 1
        ops.node(tag, x, 0.0)
        m.deck_nodes.append(tag)
        m.deck_x.append(x)
    # abutments: vertical support only (free along x and in rotation)
    ops.fix(m.deck_nodes[0], 0, 1, 0)
    ops.fix(m.deck_nodes[-1], 0, 1, 0)

    ops.geomTransf("Linear", 1)
    # deck elements, lumped mass: half of each element's mass to each end
    for i in range(len(xs) - 1):
        ops.element("elasticBeamColumn", i + 1, i + 1, i + 2, DECK_A, DECK_E, DECK_I, 1)
        half = 0.5 * DECK_MASS * (xs[i + 1] - xs[i])
        for tag in (i + 1, i + 2):
            m.nodal_mass[tag] = m.nodal_mass.get(tag, 0.0) + half

    # piers at the two interior supports
    pier_x = [SPANS[0], SPANS[0] + SPANS[1]]
    ele = 1000
    hp = PIER_HEIGHT / PIER_ELEMENTS
    for p, x in enumerate(pier_x, start=1):
        top = m.deck_nodes[min(range(len(xs)), key=lambda k: abs(xs[k] - x))]
        assert abs(ops.nodeCoord(top, 1) - x) < 1e-9, "a deck node must sit on each pier"
        tags = [PIER_BASE_TAG * p + 1 + k for k in range(PIER_ELEMENTS)] + [top]
        for k, tag in enumerate(tags[:-1]):
            ops.node(tag, x, -PIER_HEIGHT + k * hp)
        ops.fix(tags[0], 1, 1, 1)  # fixed base
        for k in range(PIER_ELEMENTS):
            ele += 1
            ops.element("elasticBeamColumn", ele, tags[k], tags[k + 1], PIER_A, PIER_E, PIER_I, 1)
            half = 0.5 * PIER_MASS * hp
            for tag in (tags[k], tags[k + 1]):
                if tag != tags[0]:  # the base's share goes into the ground
                    m.nodal_mass[tag] = m.nodal_mass.get(tag, 0.0) + half
        m.pier_nodes.append(tags)

    # mass in x and z, none in rotation
    for tag, mass in m.nodal_mass.items():
        ops.mass(tag, mass, mass, 0.0)

    m.points = [
        ("left end", m.deck_nodes[0], "x"),
        ("right end", m.deck_nodes[-1], "x"),
        ("pier 1 top", m.pier_nodes[0][-1], "x"),
        ("pier 2 top", m.pier_nodes[1][-1], "x"),
    ]
    return m


def summary(m):
    """One paragraph describing the model (for file headers and READMEs)."""
    n_deck = len(m.deck_nodes) - 1
    return (
        f"three-span continuous girder {'-'.join(f'{s:g}' for s in SPANS)} m, "
        f"{n_deck} deck elements (<= {MAX_DECK_ELEMENT:g} m), deck E = {DECK_E:.3g} Pa, "
        f"A = {DECK_A:g} m2, I = {DECK_I:g} m4, {DECK_MASS:g} kg/m; two piers "
        f"{PIER_HEIGHT:g} m high ({PIER_ELEMENTS} elements each), E = {PIER_E:.3g} Pa, "
        f"A = {PIER_A:g} m2, I = {PIER_I:g} m4, {PIER_MASS:g} kg/m, fixed base, monolithic "
        f"with the deck; abutments: vertical support only; lumped masses in x and z, "
        f"total {m.total_mass_x:.6g} kg"
    )
