"""The examples run as a user runs them, and say what they found."""
import subprocess
import sys

from conftest import ROOT


def run(args, cwd):
    p = subprocess.run([sys.executable, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_figure12(tmp_path):
    out = run([ROOT / "examples" / "figure12.py", tmp_path / "f12.png"], tmp_path)
    assert "Sa with the joint" in out and "validity: ok" in out
    assert (tmp_path / "f12.png").stat().st_size > 20_000


def test_mass_study(tmp_path):
    out = run([ROOT / "examples" / "mass_study.py", "--periods", "3", "--duration", "8", "--output", "m.png"], tmp_path)
    assert out.count("reduction of Sa") == 3
    assert (tmp_path / "m.png").stat().st_size > 20_000
