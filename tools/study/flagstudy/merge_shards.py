"""Joins the CSVs of study shards (cloth_study --shard K/N) into the CSVs a serial run writes.

    tools/study/study.py merge-shards OUT SHARD_DIR...

Every row carries its serial number (column `row`); the merge sorts by it and refuses a set of
shards that misses a row or holds one twice (shard.json gives each file's row count). Writes
OUT/error_vs_runtime.csv and OUT/front.csv (each only if the shards have it), through a temporary
file and a rename. extreme_cases.csv (the paths' pin motion) is the same in every shard: copied once,
refused if the shards differ.
"""
import csv
import json
import os
import sys

FILES = ["error_vs_runtime.csv", "front.csv"]
QUOTED = {"solver", "constraints"}  # the columns a serial run quotes (solver and constraint specs)
WHOLE = ["extreme_cases.csv"]  # every shard writes all of it


def shard_info(shard_dirs):
    """The shards' shard.json: they must be parts 1..N of one N-way split of the same run."""
    infos = []
    for d in shard_dirs:
        try:
            with open(os.path.join(d, "shard.json")) as f:
                infos.append(json.load(f))
        except (OSError, ValueError) as e:
            sys.exit(f"{d}/shard.json: cannot read it ({e}); is {d} a cloth_study --shard output?")
    n = infos[0]["of"]
    parts = sorted(i["shard"] for i in infos)
    if any(i["of"] != n or i["rows"] != infos[0]["rows"] for i in infos) or parts != list(range(1, n + 1)):
        sys.exit(f"shards {parts} of {[i['of'] for i in infos]}: not the parts 1..{n} of one run")
    return infos[0]["rows"]


def merge(name, shard_dirs, out, expected):
    """One CSV's rows from every shard, sorted by `row`; exits unless they are rows 0..expected-1,
    each once. Returns the row count, or None if no shard has the file."""
    header, rows = None, []
    present = [d for d in shard_dirs if os.path.isfile(os.path.join(d, name))]
    if not present:
        return None
    for d in present:
        with open(os.path.join(d, name), newline="") as f:
            reader = csv.reader(f)
            h = next(reader)
            if header is not None and h != header:
                sys.exit(f"{d}/{name}: columns {h} differ from {header}")
            header = h
            rows += [r for r in reader if r]
    numbers = sorted(int(r[0]) for r in rows)
    if numbers != list(range(expected)):
        seen, dupes = set(), set()
        for n in numbers:
            (dupes if n in seen else seen).add(n)
        missing = sorted(set(range(expected)) - seen)
        sys.exit(f"{name}: the shards do not make one run (missing rows {missing[:10]}, twice {sorted(dupes)[:10]})")
    rows.sort(key=lambda r: int(r[0]))
    tmp = os.path.join(out, name + ".tmp")
    with open(tmp, "w", newline="") as f:
        # The serial run's quoting: the spec columns are quoted, nothing else.
        quoted = {i for i, c in enumerate(header) if c in QUOTED}
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(f'"{v}"' if i in quoted else v for i, v in enumerate(r)) + "\n")
    os.replace(tmp, os.path.join(out, name))
    return len(rows)


def copy_whole(name, shard_dirs, out):
    """A file every shard writes whole: copied once; exits if the shards' copies differ."""
    texts = []
    for d in shard_dirs:
        if os.path.isfile(os.path.join(d, name)):
            with open(os.path.join(d, name)) as f:
                texts.append(f.read())
    if not texts:
        return False
    if len(texts) != len(shard_dirs) or any(t != texts[0] for t in texts):
        sys.exit(f"{name}: the shards' copies differ or some shards lack it")
    tmp = os.path.join(out, name + ".tmp")
    with open(tmp, "w") as f:
        f.write(texts[0])
    os.replace(tmp, os.path.join(out, name))
    return True


def main(argv):
    """Runs on argv, the command line's arguments without the program's name."""
    if len(argv) < 2:
        sys.exit(__doc__)
    out, shard_dirs = argv[0], argv[1:]
    expected = shard_info(shard_dirs)
    os.makedirs(out, exist_ok=True)
    for name in FILES:
        if name not in expected:
            continue  # shards of a run that did not write it
        n = merge(name, shard_dirs, out, expected[name])
        if n is not None:
            print(f"{out}/{name}: {n} rows from {len(shard_dirs)} shards")
    for name in WHOLE:
        if copy_whole(name, shard_dirs, out):
            print(f"{out}/{name}: the same in all {len(shard_dirs)} shards")
