#!/usr/bin/env python3
"""The repository's rules that lizard does not check, each a line per offence (exit 1 on any):

- the cloth library's private headers (cloth/src) are included only inside cloth/ and by the
  white-box tests in tests/cloth/whitebox/ (the one place that may read them);
- no test file is over 500 lines (split it by topic);
- docs/ names no commit: a reference says what is true now, history goes to commit messages and
  CHANGELOG.md (a 7-12 digit hexadecimal word with both a digit and a letter; a golden hash says
  "golden" or "hash" on its line).

    tools/lint_rules.py [ROOT]
"""
import os
import re
import subprocess
import sys

WHITEBOX = "tests/cloth/whitebox/"
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
HEX = re.compile(r"\b[0-9a-f]{7,12}\b")


def tracked(root, *patterns):
    """The files git tracks under root matching the patterns (and the new ones not ignored)."""
    out = subprocess.run(["git", "-C", root, "ls-files", "--cached", "--others", "--exclude-standard", *patterns],
                         capture_output=True, text=True, check=True).stdout
    return [p for p in out.splitlines() if os.path.isfile(os.path.join(root, p))]


def private_headers(root):
    """The paths an include may name for a header of cloth/src (relative to cloth/src)."""
    return {p[len("cloth/src/"):] for p in tracked(root, "cloth/src") if p.endswith(".h")}


def private_includes(root):
    private = private_headers(root)
    for path in tracked(root, "*.cpp", "*.h"):
        if path.startswith("cloth/") or path.startswith(WHITEBOX):
            continue
        with open(os.path.join(root, path), errors="replace") as f:
            for n, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if m and (m.group(1) in private or "cloth/src/" in m.group(1)):
                    yield f"{path}:{n}: includes the cloth library's private header \"{m.group(1)}\" " \
                          f"(only cloth/ and {WHITEBOX} may)"
    for path in tracked(root, "CMakeLists.txt", "*/CMakeLists.txt"):
        if path in ("cloth/CMakeLists.txt", "tests/CMakeLists.txt"):
            continue
        with open(os.path.join(root, path)) as f:
            for n, line in enumerate(f, 1):
                if "cloth/src" in line and not line.lstrip().startswith("#"):
                    yield f"{path}:{n}: puts cloth/src on an include path (only cloth/ and the white-box tests may)"


def long_tests(root):
    for path in tracked(root, "tests/*.cpp", "tests/*.h"):
        with open(os.path.join(root, path), errors="replace") as f:
            lines = sum(1 for _ in f)
        if lines > 500:
            yield f"{path}: {lines} lines (a test file is at most 500: split it by topic)"


def commit_hashes(root):
    for path in tracked(root, "docs/*.md"):
        with open(os.path.join(root, path), errors="replace") as f:
            for n, line in enumerate(f, 1):
                if re.search(r"golden|\bhash\b", line, re.I):
                    continue
                for word in HEX.findall(line):
                    if re.search(r"[a-f]", word) and re.search(r"[0-9]", word):
                        yield f"{path}:{n}: names a commit ({word}): say what is true now; history goes to " \
                              "commit messages and CHANGELOG.md"


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    problems = [*private_includes(root), *long_tests(root), *commit_hashes(root)]
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
