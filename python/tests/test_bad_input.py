"""Python values the engine cannot take are refused with an InputError that
names where they are: dicts that contain themselves or are nested absurdly
deep (in a subprocess, so that a crash fails the test instead of ending
pytest), whole numbers beyond a field's range, complex numbers."""
import subprocess
import sys
import textwrap
from fractions import Fraction

import numpy as np
import pytest

import quakejoint as qj

from conftest import RECORD


def python(code):
    """Runs `code` in a fresh interpreter; returns its stdout, failing on a crash."""
    p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, f"the interpreter exited with {p.returncode}: {p.stderr[-3000:]}"
    return p.stdout.strip()


REFUSE = """
import quakejoint as qj
def refused(f):
    try:
        f()
    except qj.InputError as e:
        print(str(e).replace(chr(10), " | "))
    else:
        print("accepted")
"""


def test_a_dict_that_contains_itself_is_refused_naming_where():
    out = python(
        REFUSE
        + """
d = {"bridge": {"mass": 2e8}}
d["bridge"]["loop"] = d
refused(lambda: qj.Config(d))
inner = {"mu": 0.1}
inner["again"] = inner
refused(lambda: qj.Config().replace({"joint.friction": inner}))
l = [1.0]
l.append(l)
refused(lambda: qj.Config({"sweep": {"periods": l}}))
"""
    )
    lines = out.splitlines()
    assert lines[0] == (
        "config (dict): bridge.loop: refers back to the whole config (a dict or list that contains itself); "
        "a config is a tree of dicts and lists"
    )
    assert lines[1].endswith("joint.friction.again: refers back to joint.friction (a dict or list that contains "
                             "itself); a config is a tree of dicts and lists")
    assert lines[2].startswith("config (dict): sweep.periods[1]: refers back to sweep.periods ")


def test_a_dict_nested_100000_deep_is_refused_naming_where():
    out = python(
        REFUSE
        + """
deep = x = {}
for _ in range(100_000):
    x["a"] = {}
    x = x["a"]
refused(lambda: qj.Config({"bridge": deep}))
refused(lambda: qj.Config().replace({"bridge": deep}))
l = []
for _ in range(100_000):
    l = [l]
refused(lambda: qj.Config({"sweep": {"periods": l}}))
refused(lambda: qj.Config().replace({".".join(["a"] * 100_000): 1.0}))
refused(lambda: qj.Config.from_toml("a = " + "{b = " * 100_000 + "1" + "}" * 100_000))
"""
    )
    lines = out.splitlines()
    assert len(lines) == 5, out
    assert lines[0].startswith("config (dict): bridge.a.a.a.a.a.a.a.a") and lines[0].endswith(
        ": nested deeper than 32 levels (no config key is nested that deep)"
    )
    assert "bridge.a.a.a" in lines[1] and "nested deeper than 32 levels" in lines[1]
    assert lines[2].startswith("config (dict): sweep.periods[0][0][0]") and "nested deeper than 32" in lines[2]
    assert lines[3].startswith("replace: a.a.a.a") and "nested deeper than 32 levels" in lines[3]
    assert lines[4].startswith("config (text): TOML parse error")


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("simulation.max_steps", 10**30, "simulation.max_steps = 1e30: must be within 1 <= x <= 1e12"),
        ("simulation.max_steps", -1, "simulation.max_steps = -1: must be within 1 <= x <= 1e12"),
        ("simulation.max_steps", 2**63, "simulation.max_steps = 9.223372036854776e18: must be within 1 <= x <= 1e12"),
        ("joint.center_beams", 10**30, "joint.center_beams = 1e30: must be within 1 <= x <= 1000"),
        ("joint.center_beams", -3, "joint.center_beams = -3: must be within 1 <= x <= 1000"),
        ("service.cycles", 2**40, "service.cycles = 1.099511627776e12: must be within 1 <= x <= 1000"),
        ("service.cycles", -(10**30), "service.cycles = -1e30: must be within 1 <= x <= 1000"),
        ("bridge.mass", 10**400, "bridge.mass = 1000000000000000000000... (401 digits): must be within 10000 <= x <= 1e10 kg"),
        (
            "record.column",
            10**30,
            "record.column = 1e30: out of range (a config holds whole numbers from -9223372036854775808 to "
            "9223372036854775807)",
        ),
        ("record.column", -1, "record.column = -1: must be a whole number >= 0"),
        ("simulation.max_steps", 1e5, "simulation.max_steps = 100000.0: must be a whole number"),
    ],
)
def test_a_whole_number_out_of_range_names_the_field(key, value, message):
    table, _, name = key.rpartition(".")
    tables = {table: {name: value}}
    if table == "record":
        tables["record"]["file"] = str(RECORD)
    with pytest.raises(qj.InputError) as e:
        qj.Config(tables)
    assert str(e.value) == f"config (dict): {message}"
    with pytest.raises(qj.InputError) as e:
        qj.Config().replace({key: value} if table != "record" else tables)
    assert str(e.value).endswith(message)


def test_numpy_whole_numbers_are_whole_numbers_in_a_config():
    c = qj.Config({"joint": {"center_beams": np.int64(9)}, "simulation": {"max_steps": np.uint32(100_000)}})
    assert c.to_dict()["joint"]["center_beams"] == 9 and c.to_dict()["simulation"]["max_steps"] == 100_000
    assert c.replace({"service.cycles": np.int16(3)}).to_dict()["service"]["cycles"] == 3
    with pytest.raises(qj.InputError, match=r"^config \(dict\): simulation.max_steps = 1.8446744073709552e19: must be"):
        qj.Config({"simulation": {"max_steps": np.uint64(2**64 - 1)}})


def test_arguments_out_of_range_name_the_argument():
    cfg = qj.Config()
    with pytest.raises(qj.InputError, match=r"^simulate: period = 1000000000000000000000\.\.\. \(401 digits\): "):
        qj.simulate(cfg, period=10**400)
    with pytest.raises(qj.InputError, match=r"^simulate: period = \(1\+1j\): must be a real number, not complex"):
        qj.simulate(cfg, period=1 + 1j)
    with pytest.raises(qj.InputError, match=r"^Record.read: column = -1: must be a whole number from 1 to "):
        qj.Record.read(RECORD, column=-1)
    with pytest.raises(qj.InputError, match=r"^Record.read: column = 1180591620717411303424: must be a whole number"):
        qj.Record.read(RECORD, column=2**70)
    with pytest.raises(qj.InputError, match=r"^Record.read: column = 2.5: must be a whole number"):
        qj.Record.read(RECORD, column=2.5)
    with pytest.raises(qj.InputError, match=r"^spectrum: dt = 1000000000000000000000\.\.\. \(401 digits\): "):
        qj.spectrum(np.zeros(10), [1.0], dt=10**400, units="g")
    with pytest.raises(qj.InputError, match=r"^spectrum: subdivisions = -1: must be a whole number from 0 to "):
        qj.spectrum(np.zeros(10), [1.0], dt=0.01, units="g", subdivisions=-1)
    with pytest.raises(qj.InputError, match=r"^Record.spectrum: subdivisions = 4294967296: must be a whole number"):
        qj.Record.read(RECORD).spectrum([1.0], subdivisions=2**32)
    with pytest.raises(qj.InputError, match=r"^Record.from_array: scale = 1000000000000000000000\.\.\. \(401 digits\)"):
        qj.Record.from_array(np.zeros(10), 0.01, units="g", scale=10**400)
    with pytest.raises(qj.InputError, match=r"^Record.from_array: dt = \(0.01\+0j\): must be a real number"):
        qj.Record.from_array(np.zeros(10), 0.01 + 0j, units="g")
    with pytest.raises(qj.InputError, match=r"^spectrum: periods = 1000000000000000000000\.\.\. \(401 digits\)"):
        qj.spectrum(np.zeros(10), 10**400, dt=0.01, units="g")


COMPLEX = "is complex (complex128): the imaginary part would be dropped; pass real numbers (`.real`, if that is meant)"


def test_complex_arrays_are_refused_naming_the_argument():
    a = np.zeros(100) + 0j
    rec = qj.Record.read(RECORD)
    with pytest.raises(qj.InputError) as e:
        qj.Record.from_array(a, 0.01, units="g")
    assert str(e.value) == f"Record.from_array: `acceleration` {COMPLEX}"
    with pytest.raises(qj.InputError) as e:
        qj.spectrum(a, [1.0], dt=0.01, units="g")
    assert str(e.value) == f"spectrum: `record` {COMPLEX}"
    with pytest.raises(qj.InputError) as e:
        qj.spectrum(rec, np.array([0.5, 1.0]) + 0j)
    assert str(e.value) == f"spectrum: `periods` {COMPLEX}"
    with pytest.raises(qj.InputError) as e:
        qj.spectrum(rec, [1.0], np.complex128(0.05))
    assert str(e.value) == f"spectrum: `damping` {COMPLEX}"
    with pytest.raises(qj.InputError) as e:
        rec.spectrum([1.0], [0.02, np.complex128(0.05 + 0.01j)])
    assert str(e.value) == f"Record.spectrum: `damping` {COMPLEX}"
    with pytest.raises(qj.InputError, match=r"^spectrum: `periods` is complex \(complex64\)"):
        qj.spectrum(rec, [np.complex64(1.0)])
    with pytest.raises(qj.InputError, match=r"^spectrum: `periods` is complex \(complex128\)"):
        qj.spectrum(rec, [1.0, 1 + 1j])
    with pytest.raises(qj.InputError, match=r"^spectrum: `periods` is complex \(object\)"):
        qj.spectrum(rec, [Fraction(1, 2), 1 + 1j])
    assert qj.spectrum(rec, [Fraction(1, 2)]).sa.tolist() == qj.spectrum(rec, [0.5]).sa.tolist()
    with pytest.raises(qj.InputError, match=r"^spectrum: `periods` must be real numbers, not an array of <U1"):
        qj.spectrum(rec, np.array(["1"]))
    with pytest.raises(qj.InputError, match=r"^config \(dict\): bridge.mass = \(100000000\+1j\): must be a real"):
        qj.Config({"bridge": {"mass": np.complex128(1e8 + 1j)}})
    with pytest.raises(qj.InputError, match=r"^config \(dict\): sweep.periods\[0\] = \(1\+0j\): must be a real"):
        qj.Config({"sweep": {"periods": np.array([1.0, 2.0]) + 0j}})
    # real numbers of every numpy kind are numbers
    assert qj.spectrum(rec, np.array([1, 2], dtype=np.int32), np.float32(0.05)).sa.shape == (2,)


def test_an_array_that_holds_itself_is_refused_naming_where():
    code = (
        "import numpy as np, quakejoint as qj\n"
        "a = np.empty((), dtype=object)\n"
        "a[()] = a\n"
        "try:\n"
        "    qj.Config({'bridge': {'mass': a}})\n"
        "except qj.InputError as e:\n"
        "    print('InputError', e)\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, f"the interpreter died ({p.returncode}): {p.stderr}"
    assert "InputError" in p.stdout and "bridge.mass" in p.stdout, p.stdout
