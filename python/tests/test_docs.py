"""The documentation's code runs as a user runs it, and the repository paths
it names exist.

Every ```python block of README.md, python/README.md and docs/*.md runs:
the blocks of one file in order, in one namespace, in a working directory
that holds the repository's folders (configs/, ground_motions/, tests/,
...) and the files a user makes with the command before reading them in
Python (`paper.h5`, `run.h5`, `fragility.h5`, `suite_ec8.h5`: the
`doc_outputs` fixture says how each is made). A block that cannot run in CI
is marked in the doc, on the line before its fence, with
`<!-- not run: the reason -->`; nothing else is skipped. Blocks in other
languages (sh, toml, rust, text) are not run here.
"""
import glob
import itertools
import linecache
import re
import subprocess
import sys
import warnings

import pytest

from conftest import ROOT

#: the documents whose Python is run and whose paths are checked
DOCS = [ROOT / "README.md", ROOT / "python" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
#: ... and the documents whose paths are checked only
PATH_DOCS = DOCS + sorted((ROOT / "tests").glob("*/README.md"))
#: the repository's top-level folders: a path the docs name that starts with
#: one of them is a path of the repository
TOP = ("crates", "configs", "docs", "scripts", "tests", "python", "ground_motions", "examples")

FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)")
NOT_RUN = re.compile(r"<!--\s*not run:\s*(.*?)\s*-->")


def rel(path):
    return path.relative_to(ROOT).as_posix()


def code_blocks(path):
    """The fenced blocks of a Markdown file: (language, first line number of
    the code, code, the `not run` reason or None)."""
    lines = path.read_text(encoding="utf-8").splitlines()
    blocks, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, lang = m.groups()
        prev = next((lines[j] for j in range(i - 1, -1, -1) if lines[j].strip()), "")
        marker = NOT_RUN.search(prev)
        j = i + 1
        while j < len(lines) and not (lines[j].strip().startswith(fence[0] * len(fence)) and not lines[j].strip().strip(fence[0])):
            j += 1
        body = [line[len(indent):] if line.startswith(indent) else line.lstrip() for line in lines[i + 1 : j]]
        blocks.append((lang.lower(), i + 2, "\n".join(body) + "\n", marker.group(1) if marker else None))
        i = j + 1
    return blocks


def python_blocks(path):
    return [b for b in code_blocks(path) if b[0] in ("python", "py", "python3")]


@pytest.fixture(scope="session")
def doc_outputs(cli, tmp_path_factory):
    """The files the docs read that a user makes with the command, each the
    smallest faithful one: the shipped config it comes from, with its
    bridge, records, cases, damping, histories and tables, cut to fewer
    periods, records or stripes and a shorter window. The debug command
    runs the reference joint at about 2 CPU-seconds per simulated second,
    so only `paper.h5` and `run.h5` keep it; the stripes and the suite run the
    joint of configs/small.toml (3 center beams) at levels where it does
    not pound, on records whose Sa(T) is reached in their first 4 s (the
    scaling uses the run's window):

    - `paper.h5`: `quakejoint sweep configs/paper.toml --output paper.h5`
      (what scripts/main_job.sh runs) at 2 periods (0.5 and 1 s: the
      histories at 1 s are kept) over the first 1 s of Corralitos;
    - `run.h5`: `quakejoint simulate configs/paper.toml --output run.h5`
      over the first 1 s;
    - `fragility.h5`: `quakejoint sweep configs/fragility.toml --output
      fragility.h5`: 2 of its records (El Centro 270, Pacoima Dam 164) at 2
      stripes of Sa(2.5 s) (0.05 and 0.1 g), 50 bootstrap resamples, over
      the first 4 s; every limit state and the hazard curve kept;
    - `suite_ec8.h5`: `quakejoint sweep configs/suite_ec8.toml --output
      suite_ec8.h5`: 3 of its records at 1 period (0.5 s) over the first
      4 s; its target, range and rule kept.

    Returns the folder that holds them."""
    import quakejoint as qj

    gen = tmp_path_factory.mktemp("doc_configs")
    (gen / "configs").mkdir()
    # the shipped configs name their records as ../ground_motions/...
    (gen / "ground_motions").symlink_to(ROOT / "ground_motions")
    out = tmp_path_factory.mktemp("doc_outputs")
    records = lambda *names: [{"file": f"../ground_motions/{n}.AT2"} for n in names]  # noqa: E731
    small_joint = qj.Config.from_file(ROOT / "configs" / "small.toml").to_dict()["joint"]
    derived = {
        "paper": {"simulation.duration": 1.0, "sweep.periods": [0.5, 1.0]},
        "fragility": {
            "joint": small_joint,
            "simulation.duration": 4.0,
            "sweep.records": records("RSN6_IMPVALL.I_I-ELC270-hor2", "RSN77_SFERN_PUL164-hor1"),
            "sweep.stripes.levels": [0.05, 0.1],
            "sweep.fragility.bootstrap": 50,
        },
        "design": {
            "joint": small_joint,
            "simulation.duration": 4.0,
            "sweep.records": records("RSN6_IMPVALL.I_I-ELC270-hor2", "RSN77_SFERN_PUL164-hor1"),
            "sweep.stripes.levels": [0.05, 0.1],
            "sweep.fragility.bootstrap": 50,
        },
        "suite_ec8": {
            "joint": small_joint,
            "simulation.duration": 4.0,
            "sweep.periods": [0.5],
            "sweep.records": records(
                "RSN753_LOMAP_CLS090-hor2", "RSN6_IMPVALL.I_I-ELC270-hor2", "RSN77_SFERN_PUL164-hor1"
            ),
        },
    }
    for name, changes in derived.items():
        cfg = qj.Config.from_file(ROOT / "configs" / f"{name}.toml").replace(changes)
        (gen / "configs" / f"{name}.toml").write_text(cfg.to_toml())
    commands = [
        [cli, "sweep", gen / "configs" / f"{name}.toml", "--output", out / f"{name}.h5", "--progress", "none"]
        for name in derived
    ]
    commands.append([cli, "simulate", gen / "configs" / "paper.toml", "--output", out / "run.h5"])
    procs = [subprocess.Popen(list(map(str, c)), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for c in commands]
    for c, p in zip(commands, procs):
        _, stderr = p.communicate(timeout=600)
        # 4: finished, some runs outside the model's validity (a file all the same)
        assert p.returncode in (0, 4), f"{' '.join(map(str, c))} exited {p.returncode}: {stderr}"
    return out


@pytest.fixture
def user_dir(doc_outputs, tmp_path, monkeypatch):
    """A working directory as a user's checkout after the main job: the
    repository's folders and the files of `doc_outputs`."""
    for name in TOP:
        (tmp_path / name).symlink_to(ROOT / name)
    for f in doc_outputs.iterdir():
        (tmp_path / f.name).symlink_to(f)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", list(sys.path))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


def run_blocks(doc, blocks):
    """Runs the blocks in order in one namespace; a failure names the doc and
    its line (the code is compiled with the doc's line numbers)."""
    namespace = {"__name__": "__main__"}
    filename = str(doc)
    linecache.cache[filename] = (0, None, doc.read_text(encoding="utf-8").splitlines(True), filename)
    for _, line, code, _ in blocks:
        exec(compile("\n" * (line - 1) + code, filename, "exec"), namespace)


DOCS_WITH_PYTHON = [d for d in DOCS if python_blocks(d)]


@pytest.mark.parametrize("doc", [pytest.param(d, id=rel(d)) for d in DOCS_WITH_PYTHON])
def test_python_blocks_run(doc, user_dir):
    """The doc's ```python blocks, in order in one namespace, from a user's
    checkout (a failure names the doc's line)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
    except ImportError:
        pass
    blocks = python_blocks(doc)
    run = [b for b in blocks if b[3] is None]
    with warnings.catch_warnings():
        # a warning the docs' code causes is the user's to see, not an error here
        warnings.simplefilter("default")
        run_blocks(doc, run)
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")


def test_the_docs_have_python_to_run():
    names = [rel(d) for d in DOCS_WITH_PYTHON]
    assert {"README.md", "python/README.md", "docs/python.md"} <= set(names), names


def test_not_run_markers_name_a_reason_and_a_python_block():
    """`<!-- not run: reason -->` stands right before a ```python block and
    says why."""
    for doc in DOCS:
        text = doc.read_text(encoding="utf-8")
        marked = [b for b in python_blocks(doc) if b[3] is not None]
        for _, line, _, why in marked:
            assert why, f"{rel(doc)}:{line - 1}: `<!-- not run: -->` without a reason"
        assert len(marked) == len(NOT_RUN.findall(text)), (
            f"{rel(doc)}: a `<!-- not run: ... -->` marker that is not right before a ```python block"
        )


#: a path of the repository: one of its top-level folders, a slash and path
#: characters (`<name>` a placeholder, `*` a wildcard), not preceded by a
#: path character (so not `../configs/x`, `crates/motion/tests/...` as
#: `tests/...`, or a URL)
PATH = re.compile(r"(?<![\w./<>{}$~-])((?:%s)/[\w.<>*{},/@+-]*)" % "|".join(TOP))


def named_paths(text):
    """(line, path) of every repository path named in a doc's text."""
    for n, line in enumerate(text.splitlines(), 1):
        for m in PATH.finditer(line):
            yield n, m.group(1).rstrip(".,:;")


def exists(path):
    """Whether a named path exists; `<name>` and `*` match any name, `{a,b}`
    either (at least one file must match)."""
    pattern = re.sub(r"<[^<>/]*>", "*", path)
    alternatives = [
        "".join(parts)
        for parts in itertools.product(
            *[p.split(",") if i % 2 else [p] for i, p in enumerate(re.split(r"[{}]", pattern))]
        )
    ]
    return any(glob.glob(str(ROOT / p)) if "*" in p else (ROOT / p).exists() for p in alternatives)


def test_named_paths_exist():
    missing = [
        f"{rel(doc)}:{n}: {p}"
        for doc in PATH_DOCS
        for n, p in named_paths(doc.read_text(encoding="utf-8"))
        if not exists(p)
    ]
    assert not missing, "paths the docs name that are not in the repository:\n" + "\n".join(missing)


def test_the_path_pattern():
    found = lambda text: [p for _, p in named_paths(text)]  # noqa: E731
    assert found("see `crates/model/src/run/coupled.rs`.") == ["crates/model/src/run/coupled.rs"]
    assert found("(scripts/plot_spectrum.py out.h5), configs/x.toml,") == ["scripts/plot_spectrum.py", "configs/x.toml"]
    assert found('file = "../ground_motions/a.AT2", crates/motion/tests/limits.rs') == ["crates/motion/tests/limits.rs"]
    assert found("https://github.com/o/r/tree/main/docs/x paper.h5 src/lib.rs") == []
    assert exists("tests/bad_inputs/<name>.toml") and exists("docs/figures/*.png")
    assert exists("crates/{model,motion}/Cargo.toml") and not exists("configs/<name>.json")

