"""Shared fixtures: the checkout, the `quakejoint` command built from it
(the Python package is checked against it) and small real outputs."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "ground_motions" / "RSN753_LOMAP_CLS090-hor2.AT2"


@pytest.fixture(scope="session")
def cli():
    """Path of the command-line program (QUAKEJOINT_BIN, else built with cargo)."""
    path = os.environ.get("QUAKEJOINT_BIN")
    if path:
        return Path(path)
    subprocess.run(["cargo", "build", "-q", "-p", "quakejoint"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "quakejoint"


def run_cli(cli, *args, check=True):
    """Runs the command; returns (exit code, stdout, stderr)."""
    p = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, cwd=ROOT)
    if check and p.returncode not in (0, 4):
        raise AssertionError(f"quakejoint {' '.join(map(str, args))} exited {p.returncode}: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


def cli_json(cli, *args):
    return json.loads(run_cli(cli, *args, "--json")[1])


#: the small joint of configs/small.toml (3 center beams)
SMALL_JOINT = """
[joint]
center_beams = 3
[[joint.support_beams]]
kind = "guide"
y = -7.2
[[joint.support_beams]]
kind = "joist"
y = -1.0
angle_deg = 13.0
[[joint.support_beams]]
kind = "joist"
y = 5.0
angle_deg = 17.0
"""

SHORT_SMALL = SMALL_JOINT + f"""[record]
file = "{RECORD}"
scale = 0.3
[simulation]
duration = 4.0
"""


@pytest.fixture(scope="session")
def short_config(tmp_path_factory):
    """The small (3-beam) joint under 4 s of Corralitos at 0.3 times its strength."""
    path = tmp_path_factory.mktemp("configs") / "short.toml"
    path.write_text(SHORT_SMALL)
    return path


@pytest.fixture(scope="session")
def quick_sweep(cli, tmp_path_factory):
    """configs/quick.toml swept by the command line (16 jobs, histories at one period)."""
    out = tmp_path_factory.mktemp("sweep") / "quick.h5"
    run_cli(cli, "sweep", ROOT / "configs" / "quick.toml", "--output", out, "--progress", "none")
    return out


STUDY = SMALL_JOINT + f"""[record]
file = "{RECORD}"
scale = 0.15
[simulation]
duration = 3.0
[sweep]
periods = [0.6, 1.2]
damping = [0.05]
[[sweep.cases]]
name = "mu 0.02"
joint.friction.mu = 0.02
[[sweep.cases]]
name = "mu 0.05"
[[sweep.cases]]
name = "mu 0.2"
joint.friction.mu = 0.2
[[sweep.cases]]
name = "mu 0.5"
joint.friction.mu = 0.5
"""


@pytest.fixture(scope="session")
def study_sweep(cli, tmp_path_factory):
    """A friction study of the small joint: 4 values of mu at 2 periods."""
    d = tmp_path_factory.mktemp("study")
    (d / "study.toml").write_text(STUDY)
    run_cli(cli, "sweep", d / "study.toml", "--output", d / "study.h5", "--progress", "none")
    return d / "study.h5"


@pytest.fixture(scope="session")
def run_h5(cli, short_config, tmp_path_factory):
    """`simulate --output` of the short small-joint run, with and without the joint."""
    d = tmp_path_factory.mktemp("run")
    run_cli(cli, "simulate", short_config, "--period", "1.2", "--output", d / "run.h5")
    run_cli(cli, "simulate", short_config, "--period", "1.2", "--no-joint", "--output", d / "alone.h5")
    return d / "run.h5", d / "alone.h5"


@pytest.fixture(scope="session")
def service_h5(cli, tmp_path_factory):
    """`service --output` of the small joint opened and closed by 50 mm."""
    out = tmp_path_factory.mktemp("service") / "loop.h5"
    run_cli(cli, "service", ROOT / "configs" / "small.toml", "--amplitude", "0.05", "--cycles", "2", "--output", out)
    return out


def suite_config():
    gm = ROOT / "ground_motions"
    return SMALL_JOINT + f"""[simulation]
duration = 3.0
[sweep]
periods = [0.5, 1.0]
damping = [0.05]
records = [
  {{ file = "{gm / 'RSN753_LOMAP_CLS090-hor2.AT2'}" }},
  {{ file = "{gm / 'RSN6_IMPVALL.I_I-ELC180-hor1.AT2'}" }},
  {{ file = "{gm / 'RSN77_SFERN_PUL164-hor1.AT2'}" }},
]
[sweep.suite]
target = {{ code = "ec8", type = 1, ground = "C", ag_g = 0.3 }}
range = [0.2, 2.0]
"""


@pytest.fixture(scope="session")
def suite_sweep(cli, tmp_path_factory):
    """Three records scaled to Eurocode 8 type 1, ground C, 0.3 g; the small joint at 2 periods."""
    d = tmp_path_factory.mktemp("suite")
    (d / "suite.toml").write_text(suite_config())
    run_cli(cli, "sweep", d / "suite.toml", "--output", d / "suite.h5", "--progress", "none")
    return d / "suite.h5"


ONE_RECORD = SMALL_JOINT + f"""[record]
file = "{RECORD}"
scale = 0.15
[simulation]
duration = 2.0
[sweep]
periods = [0.5, 1.0, 2.0]
damping = [0.02, 0.05]
[[sweep.cases]]
name = "base"
[[sweep.cases]]
name = "few steps"
simulation.max_steps = 5
"""


@pytest.fixture(scope="session")
def one_record_sweep(cli, tmp_path_factory):
    """One record, two cases at 3 periods and 2 damping ratios: the small
    joint under 2 s of Corralitos at 0.15, and the same stopped after 5
    steps (its jobs fail: exit code 3)."""
    d = tmp_path_factory.mktemp("one_record")
    (d / "one.toml").write_text(ONE_RECORD)
    code, _, err = run_cli(cli, "sweep", d / "one.toml", "--output", d / "one.h5", "--progress", "none", check=False)
    assert code == 3, err
    return d / "one.h5"


#: a joint at each abutment of the three-span bridge of tests/data/three_span
TWO_ABUTMENTS = """[[joints]]
name = "left abutment"
deck_point = "left end"
deck_side = "+x"
[[joints]]
name = "right abutment"
deck_point = "right end"
deck_side = "-x"
"""

#: the small joint at both ends of the three-span bridge of
#: tests/data/three_span (OpenSees' modes), under 6 s of Corralitos at 0.6
#: times its strength: the joints pound
TWO_JOINTS = SMALL_JOINT + f"""[record]
file = "{RECORD}"
scale = 0.6
[simulation]
duration = 6.0
[bridge.modal]
modes = "{ROOT / 'tests' / 'data' / 'three_span' / 'modes.toml'}"
modes_used = 20
""" + TWO_ABUTMENTS


@pytest.fixture(scope="session")
def two_joints(cli, tmp_path_factory):
    """`simulate --output` of the two joints on the modal bridge: (config, run file)."""
    d = tmp_path_factory.mktemp("modal")
    config = d / "two_joints.toml"
    config.write_text(TWO_JOINTS)
    run_cli(cli, "simulate", config, "--output", d / "two.h5")
    return config, d / "two.h5"


#: the small joint at both ends of the three-span bridge (all its modes)
#: under 3 s of Corralitos at 0.15, swept by two period scales in two
#: cases, one keeping 3 modes
MODAL_SWEEP = SMALL_JOINT + f"""[record]
file = "{RECORD}"
scale = 0.15
[simulation]
duration = 3.0
[bridge.modal]
modes = "{ROOT / 'tests' / 'data' / 'three_span' / 'modes.toml'}"
[[joints]]
name = "left"
deck_point = "left end"
deck_side = "+x"
[[joints]]
name = "right"
deck_point = "right end"
deck_side = "-x"
[sweep]
period_scales = [0.8, 1.25]
[[sweep.cases]]
name = "all modes"
[[sweep.cases]]
name = "3 modes"
bridge.modal.modes_used = 3
"""


@pytest.fixture(scope="session")
def modal_sweep(cli, tmp_path_factory):
    """A sweep over a bridge given by its modes (2 cases x 2 period scales)."""
    d = tmp_path_factory.mktemp("modal_sweep")
    (d / "modal.toml").write_text(MODAL_SWEEP)
    run_cli(cli, "sweep", d / "modal.toml", "--output", d / "modal.h5", "--progress", "none")
    return d / "modal.h5"


STRIPES = """
[sweep]
periods = [1.0]
records = [{{ file = "{a}" }}, {{ file = "{b}" }}, {{ file = "{c}" }}, {{ file = "{d}" }}]
[sweep.stripes]
measure = "pga"
levels = [0.05, 0.1, 0.15, 0.2, 0.3, 0.4]
[sweep.fragility]
bootstrap = 100
hazard = {{ intensity = [0.01, 0.1, 1.0, 10.0], frequency = [1.0, 1e-2, 1e-4, 1e-6] }}
[[sweep.fragility.limit_states]]
kind = "capacity"
[[sweep.fragility.limit_states]]
kind = "pounding"
speed = 0.1
[[sweep.fragility.limit_states]]
kind = "abutment_force"
force = 1.0e5
[[sweep.fragility.limit_states]]
kind = "field"
field = "max_subgap"
above = 0.07
[[sweep.fragility.limit_states]]
kind = "deck"
measure = "sd"
above = 0.05
"""


DESIGN = """
[sweep]
periods = [1.0]
records = [{{ file = "{a}" }}, {{ file = "{b}" }}, {{ file = "{c}" }}, {{ file = "{d}" }}]
[sweep.stripes]
measure = "pga"
levels = [0.2, 0.4, 0.6, 0.8, 1.0, 1.3]
[sweep.fragility]
bootstrap = 100
hazard = {{ intensity = [0.1, 1.0], frequency = [1e-2, 3e-5] }}
[[sweep.fragility.limit_states]]
kind = "abutment_force"
force = 1.0e6
target = 2e-4
[[sweep.fragility.limit_states]]
kind = "fuse_broken"
target = 1e-2
[[sweep.cases]]
name = "3 beams"
[[sweep.cases]]
name = "3 beams, fuse"
joint.fuse = {{ kind = "box", break_force = 2e5, stroke = 0.3 }}
"""


def stripes_of_four_records(cli, tmp_path_factory, name, sweep, duration):
    """Runs the small joint for `duration` [s] under `sweep` (a `[sweep]`
    text with the four records as `{a}` .. `{d}`: Corralitos 090 and 000,
    El Centro 180 and 270); the output file."""
    gm = ROOT / "ground_motions"
    names = ["RSN753_LOMAP_CLS090-hor2", "RSN753_LOMAP_CLS000-hor1", "RSN6_IMPVALL.I_I-ELC180-hor1", "RSN6_IMPVALL.I_I-ELC270-hor2"]
    files = dict(zip("abcd", (gm / f"{n}.AT2" for n in names)))
    d = tmp_path_factory.mktemp(name)
    cfg = d / f"{name}.toml"
    cfg.write_text(SMALL_JOINT + f"[simulation]\nduration = {duration}\n" + sweep.format(**files))
    out = d / f"{name}.h5"
    run_cli(cli, "sweep", cfg, "--output", out)
    return out


@pytest.fixture(scope="session")
def design_sweep(cli, tmp_path_factory):
    """A design study (docs/design.md): the small joint with and without a
    fuse box as candidates, four records at six stripes of PGA, targets on
    the abutment force and the fuse's break."""
    return stripes_of_four_records(cli, tmp_path_factory, "design", DESIGN, 8.0)


@pytest.fixture(scope="session")
def stripes_sweep(cli, tmp_path_factory):
    """A multiple-stripe sweep: four records at six stripes of PGA on the
    small joint, with a hazard curve and six limit states."""
    return stripes_of_four_records(cli, tmp_path_factory, "stripes", STRIPES, 4.0)
