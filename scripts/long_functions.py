"""Functions longer than a limit in the crates' sources (crates/*/src), longest first.

    python3 scripts/long_functions.py [LIMIT]     # default 120 lines, from `fn` to its closing brace

Exits 1 when a function is longer than LIMIT (scripts/test.sh checks the default).

A rough reader of Rust (strings, characters and line comments blanked before the braces are counted):
what issue 36 counts, not a parser.
"""

import glob
import re
import sys

FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?fn\s+(\w+)")


def code(line):
    """The line without its strings, characters and line comment."""
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"//.*", "", line)
    return re.sub(r"'(\\.|[^'\\])'", "''", line)


def length(lines, start):
    """Lines from the `fn` at `start` to its closing brace; None for a declaration without a body."""
    depth, opened = 0, False
    for j in range(start, len(lines)):
        text = code(lines[j])
        for ch in text:
            if ch == "{":
                depth, opened = depth + 1, True
            elif ch == "}":
                depth -= 1
        if opened and depth == 0:
            return j - start + 1
        if not opened and text.rstrip().endswith(";"):
            return None
    return None


def functions():
    """(lines, file, line number, name) of every function with a body."""
    for path in sorted(glob.glob("crates/*/src/**/*.rs", recursive=True)):
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        for i, line in enumerate(lines):
            m = FN.match(line)
            if m:
                n = length(lines, i)
                if n is not None:
                    yield n, path, i + 1, m.group(6)


def main():
    limit = int(sys.argv[1]) if len(sys.argv) > 1 else 120
    long = sorted((f for f in functions() if f[0] > limit), reverse=True)
    for n, path, line, name in long:
        print(f"{n:5} {path}:{line} {name}")
    print(f"{len(long)} functions over {limit} lines")
    return 1 if long else 0


if __name__ == "__main__":
    sys.exit(main())
