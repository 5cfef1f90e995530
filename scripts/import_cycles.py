"""Import circles between the modules of a crate (its top-level files and folders under src/).

    python3 scripts/import_cycles.py [CRATE] [MODULE ...]

Module A uses module B when a file of A names `crate::B` (in a `use` or a path; doc links
and other comments do not count). Prints each circle (a strongly connected set
of more than one module) and exits 1 if one passes through a MODULE given (default: the model
crate's core, which issue 36 asks to keep free of circles: config, generator, run, modal,
placement, validity), else 0. A rough reader of Rust, not a parser.
"""

import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
CORE = ["config", "generator", "run", "modal", "placement", "validity"]
USE = re.compile(r"\bcrate::(\w+)")
# `use crate::{a, b::c}`: the names inside the braces
GROUP = re.compile(r"\bcrate::\{([^}]*)\}")


def code(line):
    """The line without strings and its line comment (doc comments included)."""
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    return re.sub(r"//.*", "", line)


def graph(crate):
    """{module: set of modules it uses} for the crate's top-level modules."""
    src = ROOT / "crates" / crate / "src"
    modules = {p.stem for p in src.glob("*.rs")} | {p.name for p in src.iterdir() if p.is_dir()}
    modules -= {"lib", "main"}
    uses = {m: set() for m in modules}
    for m in modules:
        files = [src / f"{m}.rs"] if (src / f"{m}.rs").exists() else []
        files += sorted((src / m).rglob("*.rs")) if (src / m).is_dir() else []
        # a statement over several lines read as one
        text = " ".join(code(l) for f in files for l in f.read_text().splitlines())
        names = set(USE.findall(text))
        for group in GROUP.findall(text):
            names |= {n.strip().split("::")[0] for n in group.split(",") if n.strip()}
        uses[m] = {n for n in names if n in modules and n != m}
    return uses


def circles(uses):
    """Strongly connected sets of more than one module (Tarjan's algorithm)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(uses[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1:
                out.append(sorted(part))

    for v in sorted(uses):
        if v not in index:
            visit(v)
    return out


def main(argv):
    crate = argv[1] if len(argv) > 1 else "model"
    watched = set(argv[2:]) or set(CORE)
    uses = graph(crate)
    bad = False
    for part in circles(uses):
        inside = sorted(set(part) & watched)
        edges = [f"{a} -> {b}" for a in part for b in sorted(uses[a]) if b in part]
        mark = "CIRCLE through " + ", ".join(inside) if inside else "circle"
        print(f"{mark}: {', '.join(part)} ({'; '.join(edges)})")
        bad |= bool(inside)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
