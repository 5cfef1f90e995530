"""The examples run as a user runs them, and say what they found."""
import re
import subprocess
import sys

import pytest

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

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


@pytest.mark.parametrize("example", ["figure12.py", "mass_study.py"])
def test_an_example_without_matplotlib_names_the_extra(example, tmp_path):
    path = str(ROOT / "examples" / example)
    code = (
        "import runpy, sys; sys.modules['matplotlib'] = None; "
        f"sys.argv = [{path!r}]; runpy.run_path({path!r}, run_name='__main__')"
    )
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert p.returncode == 1
    assert 'pip install "quakejoint[plot]"' in p.stderr and 'pip install ".[plot]"' in p.stderr, p.stderr
    assert "Traceback" not in p.stderr


def test_the_extras_are_documented():
    """Every extra of pyproject.toml is named, with what it brings, in the
    README's Python section and in docs/python.md."""
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert {"plot", "xarray", "pandas"} <= set(extras)
    readme = (ROOT / "README.md").read_text()
    python_section = readme[readme.index("## Python") : readme.index("## Examples and scripts")]
    for text in (python_section, (ROOT / "docs" / "python.md").read_text()):
        for name, requirements in extras.items():
            assert f'".[{name}]"' in text or f'"quakejoint[{name}]"' in text, name
            for requirement in requirements:
                package = re.split(r"[<>=!~ ;\[]", requirement)[0]
                assert package in text, (name, package)
