"""What the checks of the docs' findings share: the committed CSVs, each read once (Docs); a finding
that does not hold (Finding, need); a row by the values of its columns (one, ext); and what a
configuration ranked by reference_table misses (misses, stretch_misses, rows_repeat)."""
import csv
import os

import reference_table

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")  # this file is in tools/study/checks/

# The demo default as the CSVs label it: the solver's keys and the constraints in one spec, with
# the stretch limit's keys under their CSV names (strain_limit, strain_passes).
DEMO_DEFAULT = "kangcho:iterations=1,precision=float,strain_limit=0.1,strain_passes=4,tether=0.02"
CASES = ["speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]


def num(v):
    try:
        return float(v)
    except ValueError:
        return float("nan")


class Finding(Exception):
    pass


class Docs:
    """The committed CSVs of one folder, read once each."""

    def __init__(self, d):
        self.d = d
        self.cache = {}

    def rows(self, name):
        if name not in self.cache:
            path = os.path.join(self.d, name)
            try:
                with open(path, newline="") as f:
                    self.cache[name] = list(csv.DictReader(f))
            except OSError as e:
                raise Finding(f"cannot read {path}: {e}")
        return self.cache[name]

    def merged(self, *names):
        """The rows of the named CSVs as one, a later file's row replacing an earlier one's
        (reference_table.merge): a configuration beside the reference rows of older runs."""
        return reference_table.merge([self.rows(n) for n in names])


def need(ok, what):
    if not ok:
        raise Finding(what)


def one(rows, what, **match):
    """The single row whose columns equal `match`."""
    hits = [r for r in rows if all(r[k] == v for k, v in match.items())]
    need(len(hits) == 1, f"{what}: {len(hits)} rows with {match}, expected 1")
    return hits[0]


def ext(docs, config, case, size, name="extreme.csv"):
    return one(docs.rows(name), name, config=config, case=case, size=str(size))


def stable(r):
    return r["stable"] == "1"


def pct(v):
    return f"{num(v):.0%}"


def stretch_misses(entry):
    """The cases a reference_table.ranking entry misses the stretch bounds in (or is unstable)."""
    return sorted(x for x, m in entry["judged"].items() if {"unstable", "p99", "peak"} & set(m))


def misses(entry):
    """The cases a reference_table.ranking entry misses any bound in, with the bounds it misses."""
    return {x: m for x, m in entry["judged"].items() if m}


def rows_repeat(docs, name, source, size, config="stiff_reference", cases=reference_table.CASES):
    """The runs are deterministic: `config`'s rows in `name` repeat those in `source`."""
    for x in cases:
        a, b = (one(docs.rows(f), f, config=config, case=x, size=size) for f in (name, source))
        need(all(a[k] == b[k] for k in ("stable", "p99_stretch", "peak_stretch", "ke_late", "ke_windows")),
             f"{name}: {config}'s {x} row differs from {source}'s")


def reference_repeats(docs, name, source, size, cases=reference_table.CASES):
    """The stiff reference's rows in `name` repeat those in `source`."""
    rows_repeat(docs, name, source, size, "stiff_reference", cases)
