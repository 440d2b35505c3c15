"""What the checks of the docs' findings share: the committed CSVs, each read once (Docs); a finding
that does not hold (Finding, need); a row by the values of its columns (one, ext); a row of the
front (front, PATHS)."""
import csv
import json
import os

from flagstudy import stale

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..")  # in tools/study/flagstudy/checks/

# The demo default as the CSVs label it: the solver's keys and the constraints in one spec, with
# the stretch limit's keys under their CSV names (strain_limit, strain_passes).
DEMO_DEFAULT = "kangcho:iterations=1,precision=float,strain_limit=0.1,strain_passes=4,tether=0.02"
CASES = ["speed_50mps", "stop_10g", "spin_5radps", "teleport_1m", "light_particles", "gale_40mps"]
PATHS = ["drive"] + CASES  # the front's carrier paths


def scene(name):
    """A scene file of assets/scenes/, parsed."""
    with open(os.path.join(ROOT, "assets", "scenes", name)) as f:
        return json.load(f)


def wrapped_stretch(rest):
    """The stretch of a spring of rest length `rest` wrapped halfway round the demo's pole: both
    ends on the pole's collision shell (the pole's radius, the engine's default of 3 cm unless the
    scene sets it, and the cloth's thickness from its axis), on opposite sides at one height."""
    demo = scene("flag_vehicle.json")
    shell = demo["vehicle"].get("pole_radius", 0.03) + demo["flag"]["thickness"]
    return 2 * shell / rest - 1


def num(v):
    try:
        return float(v)
    except ValueError:
        return float("nan")


class Finding(Exception):
    pass


class StaleRow(dict):
    """A committed row that stale.csv marks: a finding may find it by its key, and fails when it
    reads anything else (the row is not what today's code computes)."""

    def __init__(self, row, name, mark):
        super().__init__(row)
        self.name, self.mark = name, mark

    def __getitem__(self, column):
        if column not in stale.KEYS.get(self.name, ()) and column not in self.mark.match:
            raise Finding(f"cites {self.name} {stale.key_of(self.name, self)}, which {stale.NAME} marks stale "
                          f"({self.mark.why}): re-run the row")
        return super().__getitem__(column)

    def get(self, column, default=None):
        return self[column] if column in self else default


class Docs:
    """The committed CSVs of one folder, read once each; the rows stale.csv marks as StaleRow."""

    def __init__(self, d):
        self.d = d
        self.cache = {}
        try:
            self.marks = stale.read_marks(d)
        except ValueError as e:
            raise Finding(str(e))

    def rows(self, name):
        if name not in self.cache:
            path = os.path.join(self.d, name)
            try:
                with open(path, newline="") as f:
                    rows = list(csv.DictReader(f))
            except OSError as e:
                raise Finding(f"cannot read {path}: {e}")
            marked = ((r, stale.mark_of(self.marks, name, r)) for r in rows)
            self.cache[name] = [StaleRow(r, name, m) if m else r for r, m in marked]
        return self.cache[name]


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


def front(docs, flag, path, config, size="33"):
    """front.csv's row of one flag, path, configuration and size."""
    return one(docs.rows("front.csv"), "front.csv", flag=flag, path=path, config=config, size=str(size))


def is_stale(r):
    """Whether stale.csv marks the row (a StaleRow: only its key may be read)."""
    return isinstance(r, StaleRow)


def stale_paths(docs, flag, config, size="33"):
    """The front's paths whose row of config stale.csv marks."""
    return [p for p in PATHS if is_stale(front(docs, flag, p, config, size))]


def misses_on(docs, flag, config, size="33", skip_stale=False):
    """The front's paths where config misses a bound (or is unstable): {path: "unstable" or the
    misses as front.csv writes them, ';'-separated}; empty when it is within every bound. With
    skip_stale, the paths whose row stale.csv marks are left out (else reading one fails)."""
    out = {}
    for p in PATHS:
        r = front(docs, flag, p, config, size)
        if skip_stale and is_stale(r):
            continue
        if not stable(r) or r["misses"]:
            out[p] = "unstable" if not stable(r) else r["misses"]
    return out


def teleport_rows(docs, name, flag, config):
    """A teleport ensemble's rows (teleports_stiff.csv, teleports_demo.csv) of one flag and
    configuration at 33x33, by jump length in m (path teleport_<d>m)."""
    rows = [r for r in docs.rows(name) if r["flag"] == flag and r["size"] == "33" and r["config"] == config]
    return {float(r["path"][len("teleport_"):-1]): r for r in rows}
