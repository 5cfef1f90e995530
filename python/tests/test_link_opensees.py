"""The joint's link element (docs/link.md) proven in the engine its users
run: `quakejoint.calibrate` on the reference joint (configs/paper.toml,
calibration suite Corralitos 000, Pacoima Dam 164 and El Centro 270), its
exported openseespy element on a single-DOF deck run by OpenSees itself
(scripts/opensees/link_sdof.py) and at both abutments of the three-span
bridge (scripts/opensees/link_two_ends.py), against quakejoint's own
`joint.model = "link"` and against the detailed joint, under records not
used in the calibration.

OpenSees parts need openseespy (`pip install openseespy`; on Debian libblas3
and liblapack3); the README's test command installs it.
"""
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

import quakejoint as qj
from conftest import TWO_ABUTMENTS

ROOT = Path(__file__).resolve().parents[2]
GM = ROOT / "ground_motions"
sys.path.insert(0, str(ROOT / "scripts" / "opensees"))


SUITE = ("RSN753_LOMAP_CLS000-hor1.AT2", "RSN77_SFERN_PUL164-hor1.AT2", "RSN6_IMPVALL.I_I-ELC270-hor2.AT2")


def _openseespy():
    try:
        import openseespy.opensees  # noqa: F401
    except Exception as e:  # ImportError, or a missing libblas/liblapack
        message = f"openseespy is not importable ({e}): pip install -r scripts/opensees/requirements.txt"
        if os.environ.get("QJ_REQUIRE_OPENSEES"):
            pytest.fail(message)
        pytest.skip(message)


@pytest.fixture(scope="module")
def link(tmp_path_factory):
    """The reference joint's calibration and its exported files."""
    cfg = qj.Config.from_file(ROOT / "configs" / "paper.toml")
    suite = [qj.Record.read(GM / name) for name in SUITE]
    c = qj.calibrate(cfg, record=suite)
    out = tmp_path_factory.mktemp("link")
    for name, text in c["exports"].items():
        (out / name).write_text(text)
    c["dir"] = out
    return c


def deck(link, mass, period, model, record):
    """configs/paper.toml on a deck of `mass` and `period`, its joint
    detailed or the calibrated link, under `record`."""
    cfg = qj.Config.from_file(ROOT / "configs" / "paper.toml")
    changes = {"bridge.mass": mass, "bridge.w0": 2 * math.pi / period, "record.file": str(GM / record)}
    if model == "link":
        changes["joint.model"] = "link"
        for k in ("stiffness", "friction", "mass", "damping", "gap_stiffness", "gap_hertz"):
            if link[k] is not None:
                changes[f"joint.link.{k}"] = link[k]
    return cfg.replace(changes)


def test_calibration_of_the_reference_joint(link):
    # the slider within 10 % of the hand calculation (below it: the beams
    # lag at reversals), the closing movement 28 cells of 40 mm
    assert 0.85 * link["hand_friction"] < link["friction"] < link["hand_friction"]
    assert link["cells"] == 28 and abs(link["gap"] - 1.12) < 1e-9
    # the damper the stuck joint's own (the bushings' cx / kx = 2e-4 s times
    # k); the mass at most the whole joint sliding at once; every record of
    # the suite reported with the mass it alone calls for
    assert link["damping"] == pytest.approx(link["stiffness"] * 2.0e3 / 1.0e7, rel=1e-12)
    assert 0.25 * link["kinetic_mass"] <= link["mass"] <= link["kinetic_mass"]
    assert [e["record"] for e in link["suite"]] == [name.removesuffix(".AT2") for name in SUITE]
    for e in link["suite"]:
        assert 0.25 * link["kinetic_mass"] <= e["own_mass"] <= link["kinetic_mass"]
        error = e["peak_link"] / e["peak_detailed"] - 1
        # a force more than 5 % below the detailed joint's is said, with the record
        below = [w for w in link["warnings"] if e["record"] in w and "below the detailed joint's" in w]
        assert (error < -0.05) == bool(below), (e, link["warnings"])
        # (the band is -5 % to +10 %; on the paper's deck Pacoima Dam 164
        # stays at -8.5 %, said above, and El Centro 270 at +10 %)
        assert -0.10 < error < 0.15, e
    # the joint never closed under the suite: the exports' secant at the default, said so
    assert link["contact_force"] == 1e6
    assert "did not close under the calibration suite" in link["exports"]["link.toml"]
    # the equivalent damping ratio of the joint's own loop grows with the
    # amplitude towards 2 / pi (rigid-plastic), while what it adds to the
    # bridge falls: no single damping ratio stands for it
    joint = [p["damping_joint"] for p in link["loops"]]
    assert joint == sorted(joint) and joint[-1] < 2 / math.pi
    bridge = [p["damping_bridge"] for p in link["loops"]]
    assert max(bridge) > 2 * bridge[-1]
    mantissa, exponent = f"{link['friction']:.6e}".split("e")
    for name in ("link.toml", "link.tcl", "link_opensees.py", "link_sap2000.txt"):
        text = link["exports"][name]
        assert "units: N, m, kg, s" in text and f"{mantissa}e{int(exponent)}" in text


@pytest.mark.parametrize(
    "mass, period, record",
    [
        (1e6, 1.0, "RSN753_LOMAP_CLS090-hor2.AT2"),
        (1e7, 0.5, "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
        (3e6, 0.7, "RSN77_SFERN_PUL254-hor2.AT2"),  # pulse-like, 1.2 g
        (1e6, 1.0, "RSN1690_NORTH151_SYL360-hor2.AT2"),  # weak: the joint mostly sticks
        (1e7, 2.0, "RSN1690_NORTH151_SYL090-hor1.AT2"),
    ],
)
def test_the_exported_element_in_opensees_is_quakejoints_link(link, mass, period, record):
    """The same element in two engines, on every class of record (strong,
    pulse-like, weak): Sa to 1e-3, the friction energy to 1 %, the peak
    force on the deck to 2 % (quakejoint integrates a run of links in
    steps of at most 0.05 sqrt(m/k), and its slider creeps at most at 1e-5
    m/s where OpenSees' ElasticPP sticks: docs/link.md)."""
    _openseespy()
    import link_sdof

    ours = qj.simulate(deck(link, mass, period, "link", record), history=False)
    theirs = link_sdof.run(link["dir"] / "link_opensees.py", mass, period, 0.05, GM / record)
    assert abs(theirs["sa"] / ours.sa - 1) < 1e-3, (theirs["sa"], ours.sa)
    assert abs(theirs["friction_energy"] / ours.friction_energy - 1) < 0.01
    assert abs(theirs["peak_joint_force"] / ours.peak_joint_force - 1) < 0.02


@pytest.mark.parametrize(
    "mass, period, record",
    [(1e6, 1.0, "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"), (2e7, 1.5, "RSN77_SFERN_PUL254-hor2.AT2")],
)
def test_the_link_against_the_detailed_joint(link, mass, period, record):
    """Where the joint matters and the link holds (docs/link.md, "Where it
    holds"), under records outside the calibration suite: El Centro 180 on
    a 1e6 kg deck at 1 s (the joint takes 27 % off Sa) and the pulse of
    Pacoima Dam 254 on a 2e7 kg deck at 1.5 s (where the link calibrated
    under one record gave a peak force 17 % low). The peak force on the
    deck, what the abutment is designed for, never more than 5 % below the
    detailed joint's and at most 15 % above (strong motion: +0.8 to +14.4 %
    in the study)."""
    detailed = qj.simulate(deck(link, mass, period, "detailed", record), history=False)
    linked = qj.simulate(deck(link, mass, period, "link", record), history=False)
    alone = qj.simulate(deck(link, mass, period, "detailed", record), joint=False, history=False)
    assert abs(linked.sa / detailed.sa - 1) < 0.03
    assert abs(linked.friction_energy / detailed.friction_energy - 1) < 0.10
    assert -0.05 < linked.peak_joint_force / detailed.peak_joint_force - 1 < 0.15
    # the joint's effect on Sa, in sign and within a third of its size
    effect_detailed, effect_link = detailed.sa - alone.sa, linked.sa - alone.sa
    assert effect_detailed * effect_link > 0
    assert abs(effect_link - effect_detailed) < abs(effect_detailed) / 3

TWO_ENDS = """
[bridge]
damping = 0.05
[bridge.modal]
modes = "{modes}"
modes_used = 20
[record]
file = "{record}"
scale = 2.0
[joint]
model = "link"
center_beams = 3            # 4 cells of 40 mm: the deck closes each joint in turn
[joint.link]
{link}
""" + TWO_ABUTMENTS  # (no braces: format leaves it as it is)


def test_the_link_at_both_abutments_in_opensees(link, tmp_path):
    """Both abutments (docs/link.md): the three-span bridge with the link
    at its left end (the deck toward +X, `side=1`) and its right end
    (toward -X, `side=-1`), under Pacoima Dam 164 x 2 for 12 s, in which
    the deck closes the left joint (0.96 MN through it) and the right one
    (2.5 MN). quakejoint's modal bridge (20 modes and the static
    correction) against OpenSees' frame with modalDamping of every mode
    and the exported element (scripts/opensees/link_two_ends.py): the deck
    ends' displacement to 1e-3 of its peak, each joint's peak force on the
    deck to 2 %. A slider on the deck instead (the nodes swapped) caps the
    right joint's force near F."""
    _openseespy()
    import link_two_ends

    keys = ("stiffness", "friction", "mass", "damping", "gap_stiffness")
    text = TWO_ENDS.format(
        modes=ROOT / "tests" / "data" / "three_span" / "modes.toml",
        record=GM / "RSN77_SFERN_PUL164-hor1.AT2",
        link="\n".join(f"{k} = {link[k]!r}" for k in keys),
    )
    (tmp_path / "two_ends.toml").write_text(text)
    ours = qj.simulate(qj.Config.from_file(tmp_path / "two_ends.toml"))
    t, u, force = link_two_ends.run(link["dir"] / "link_opensees.py", GM / "RSN77_SFERN_PUL164-hor1.AT2",
                                    scale=2.0, duration=12.0, gap=4 * 0.04)
    h = ours.history
    window = h["t"] <= t[-1] + 1e-9
    forces = (h["joint_force"], ours.joints[1]["history"]["joint_force"])
    for j in range(2):
        mine = h["points_u"][j][window]
        theirs = np.interp(h["t"][window], t, u[:, j])
        assert np.max(np.abs(mine - theirs)) < 1e-3 * np.max(np.abs(mine)), j
        peak = np.max(np.abs(forces[j][window]))
        assert abs(force[:, j].max() / peak - 1) < 0.02, (j, force[:, j].max(), peak)
        # the gap closed at this end, on the right side
        assert peak > 2 * link["friction"], (j, peak)


def test_the_link_releases_as_the_rigid_plastic_element(link):
    """The link's slider letting go, against the element without
    regularisation integrated event to event (scripts/link_exact.py): the
    reference joint's link, undamped, on a 1e7 kg deck at 1 s under El
    Centro 180. The step control does not see the release's error, and at
    every tolerance from 1e-10 to 1e-12 the peak force was 3 % high; with
    the steps the model sets for a run of links (docs/link.md) the force on
    the deck follows the event-driven one to 0.2 % of its peak at every
    record step."""
    sys.path.insert(0, str(ROOT / "scripts"))
    import link_exact

    record = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    cfg = deck(link, 1e7, 1.0, "link", record).replace({"joint.link.damping": 0.0})
    ours = qj.simulate(cfg)
    exact = link_exact.forces(link["stiffness"], link["friction"], link["mass"], 1e7, 1.0, GM / record)
    n = min(len(exact), len(ours.history["joint_force"]))
    # (the link's force on the deck resists the opening: the opposite sign)
    difference = np.abs(ours.history["joint_force"][:n] + exact[:n])
    assert difference.max() < 2e-3 * np.abs(exact).max(), difference.max()
    assert abs(ours.peak_joint_force / np.abs(exact).max() - 1) < 1e-3


@pytest.fixture(scope="module")
def fused(tmp_path_factory):
    """The medium joint with a 300 kN fuse box of 1 m stroke on the paper's
    deck at 2.5 s under Corralitos 090 x 3 (the fuse breaks at 4.42 s, its
    freed edge beam travels 0.78 m and stops short of its stop), its link
    calibrated from the service loops, and the exports."""
    cfg = qj.Config.from_file(ROOT / "configs" / "medium.toml").replace(
        {
            "joint.fuse.kind": "box",
            "joint.fuse.break_force": 3e5,
            "joint.fuse.stroke": 1.0,
            "bridge.mass": 1e8,
            "bridge.period": 2.5,
            "record.file": str(GM / "RSN753_LOMAP_CLS090-hor2.AT2"),
            "record.scale": 3.0,
        }
    )
    c = qj.calibrate(cfg, earthquake=False)
    out = tmp_path_factory.mktemp("fused")
    for name, text in c["exports"].items():
        (out / name).write_text(text)
    keys = ("stiffness", "friction", "mass", "damping", "gap_stiffness")
    # (the exports' linear gap: the same law in both engines)
    linked = cfg.replace({"joint.model": "link", **{f"joint.link.{k}": c[k] for k in keys}})
    return {"config": cfg, "link": linked, "dir": out, "calibration": c}


def test_the_exported_fuse_in_opensees_is_quakejoints_link(fused):
    """The link with its fuse box in two engines, the same laws in both
    (the exports' linear gap, seat and stop): OpenSees breaks the weld
    within 0.5 ms of quakejoint's located break, the freed beam travels as
    far (3 %) and dissipates as much (1 %), Sa to 1e-3. The peak force on
    the deck, just after the break, is 2.3 % higher in OpenSees: its weld
    node rings on the weld's stiffness and breaks with the gap at 305 kN
    rather than 300 kN. Against the detailed joint with the same fuse, the
    break is within 1 ms."""
    _openseespy()
    import link_sdof

    ours = qj.simulate(fused["link"], history=False)
    detailed = qj.simulate(fused["config"], history=False)
    theirs = link_sdof.run(fused["dir"] / "link_opensees.py", 1e8, 2.5, 0.05, GM / "RSN753_LOMAP_CLS090-hor2.AT2", 3.0)
    print({k: theirs[k] for k in theirs if k.startswith("fuse_")}, ours.fuse_break_time, ours.fuse_stroke_used)
    assert ours.fuse_broken == 1 and theirs["fuse_broke"] and not theirs["fuse_exhausted"]
    assert ours.fuse_stroke_exhausted == 0
    assert abs(theirs["fuse_break_time"] - ours.fuse_break_time) < 5e-4
    assert abs(theirs["sa"] / ours.sa - 1) < 1e-3
    assert abs(theirs["fuse_stroke_used"] / ours.fuse_stroke_used - 1) < 0.05
    assert abs(theirs["fuse_energy"] / ours.fuse_energy - 1) < 0.02
    # (quakejoint watches a closed gap's force inside its steps: OpenSees' at every step)
    assert abs(theirs["peak_joint_force_steps"] / ours.peak_joint_force - 1) < 0.03
    assert abs(theirs["friction_energy"] / ours.friction_energy - 1) < 0.01
    assert detailed.fuse_broken == 1 and abs(detailed.fuse_break_time - ours.fuse_break_time) < 1e-3


def test_the_exported_fuse_element_in_opensees_is_quakejoints_link(tmp_path):
    """The link with a fuse element (the medium joint's middle beam, 300
    kN) in two engines, on the deck and record of the fuse box above: the
    exported gap lets go (its MinMax) where quakejoint's link releases its
    beam, and the second gap, a beam's width later, pushes the deck as
    quakejoint's does; Sa to 1e-3. Against the detailed joint with the same
    element, the release is within 5 ms."""
    _openseespy()
    import link_sdof

    record = GM / "RSN753_LOMAP_CLS090-hor2.AT2"
    cfg = qj.Config.from_file(ROOT / "configs" / "medium.toml").replace(
        {
            "joint.fuse.kind": "element",
            "joint.fuse.break_force": 3e5,
            "joint.fuse.beam": 5,
            "bridge.mass": 1e8,
            "bridge.period": 2.5,
            "record.file": str(record),
            "record.scale": 3.0,
        }
    )
    c = qj.calibrate(cfg, earthquake=False)
    for name, text in c["exports"].items():
        (tmp_path / name).write_text(text)
    keys = ("stiffness", "friction", "mass", "damping", "gap_stiffness")
    linked = cfg.replace({"joint.model": "link", **{f"joint.link.{k}": c[k] for k in keys}})
    ours = qj.simulate(linked, history=False)
    detailed = qj.simulate(cfg, history=False)
    theirs = link_sdof.run(tmp_path / "link_opensees.py", 1e8, 2.5, 0.05, record, 3.0)
    print({k: theirs[k] for k in theirs if k.startswith("fuse_") or k.startswith("peak") or k == "sa"},
          ours.fuse_break_time, ours.peak_joint_force, ours.sa, detailed.fuse_break_time, detailed.peak_joint_force)
    assert ours.fuse_broken == 1 and theirs["fuse_broke"] and detailed.fuse_broken == 1
    assert abs(theirs["fuse_break_time"] - ours.fuse_break_time) < 5e-4
    assert abs(theirs["sa"] / ours.sa - 1) < 1e-3
    assert abs(theirs["peak_joint_force_steps"] / ours.peak_joint_force - 1) < 0.03
    assert abs(theirs["friction_energy"] / ours.friction_energy - 1) < 0.01
    assert abs(detailed.fuse_break_time - ours.fuse_break_time) < 5e-3


TCL_MOCK = """
proc record {args} { puts $args }
foreach c {node fix uniaxialMaterial element remove timeSeries load} {
    proc $c {args} "record $c {*}\\$args"
}
proc pattern {kind tag series body} { record pattern $kind $tag $series; uplevel 1 $body }
proc nodeDisp {node} { return {0.0 0.0 0.0} }
proc nodeCoord {node} { return {0.0 0.0} }
proc getNodeTags {} { return {1 2} }
"""


class _Recorder:
    """openseespy's commands, recorded as the Tcl mock prints them."""

    def __init__(self):
        self.calls = []

    def __getattr__(self, name):
        if name in ("nodeDisp",):
            return lambda *a: [0.0, 0.0, 0.0]
        if name == "nodeCoord":
            return lambda *a: [0.0, 0.0]
        if name == "getNodeTags":
            return lambda *a: [1, 2]
        return lambda *a: self.calls.append(" ".join([name, *(_tcl_word(x) for x in a)]))


def _tcl_word(x):
    return repr(float(x)) if isinstance(x, float) else str(x)


@pytest.mark.parametrize("side", [1, -1])
@pytest.mark.parametrize("fuse", ["none", "level", "ramp", "element"])
def test_the_tcl_export_issues_the_python_exports_commands(fused, fuse, side, tmp_path):
    """link.tcl's procedure and link_opensees.py's function, each run
    against a recorder of OpenSees' commands (tclsh with every command a
    procedure that prints it): the same commands on the same nodes with
    the same numbers at either abutment, for a joint without a fuse, with a
    fuse box on a level floor and on a 10 degree ramp (its lift a load), and
    with a fuse element (its gap's MinMax and a second gap)."""
    import importlib.util
    import shutil
    import subprocess

    tclsh = shutil.which("tclsh")
    if tclsh is None:
        pytest.fail("tclsh is not installed (Debian: apt install tcl; the README's test command installs it)")
    cfg = fused["config"]
    if fuse == "none":
        cfg = qj.Config.from_file(ROOT / "configs" / "medium.toml")
    elif fuse == "ramp":
        cfg = cfg.replace({"joint.fuse.ramp_deg": 10.0})
    elif fuse == "element":
        cfg = qj.Config.from_file(ROOT / "configs" / "medium.toml").replace(
            {"joint.fuse.kind": "element", "joint.fuse.break_force": 3e5, "joint.fuse.beam": 5}
        )
    for name, text in qj.calibrate(cfg, earthquake=False)["exports"].items():
        (tmp_path / name).write_text(text)
    script = tmp_path / "run.tcl"
    script.write_text(TCL_MOCK + f"source {{{tmp_path / 'link.tcl'}}}\nquakejointLink 1 2 3 100 {side}\n")
    out = subprocess.run([tclsh, str(script)], capture_output=True, text=True, check=True).stdout
    tcl = [_normalised(line) for line in out.splitlines()]

    spec = importlib.util.spec_from_file_location("exported", tmp_path / "link_opensees.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    ops = _Recorder()
    module.add_link(ops, 1, 2, 3, 100, side)
    py = [_normalised(line) for line in ops.calls]
    assert any(line.startswith("uniaxialMaterial MinMax") for line in py) == (fuse != "none")
    assert any(line.startswith("load 4") for line in py) == (fuse == "ramp")
    # (a fuse element: a second gap element, 103, on the gap's nodes)
    assert any(line.startswith("element zeroLength 103 1 2") or line.startswith("element zeroLength 103 2 1")
               for line in py) == (fuse == "element")
    assert tcl == py


def _normalised(line):
    """A command with its numbers as floats to 12 digits."""
    words = []
    for w in line.split():
        try:
            words.append(f"{float(w):.12g}")
        except ValueError:
            words.append(w)
    return " ".join(words)
