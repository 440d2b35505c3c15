"""The front at 65x65 on all seven paths (docs/study.md): each flag's reference, its paper's step and
its true motion as the scenes ship them (front.csv, size=65), the other configurations on the drive
alone."""
from flagstudy.checks.common import PATHS, front, misses_on, need, num

# Each flag's true motion and paper's step as its scenes ship them.
TRUE_MOTION = {"demo": "small_steps_paced", "stiff": "shipped"}
PAPER_STEP = {"demo": "shipped", "stiff": "kangcho_float"}


def cost_range(docs, flag, config):
    """The lowest and highest cloth ms per frame of config over the seven paths at 65x65."""
    ms = [num(front(docs, flag, p, config, 65)["ms_per_frame"]) for p in PATHS]
    return min(ms), max(ms)


def c_front_at_65_all_paths(docs):
    out = []
    for flag in ("demo", "stiff"):
        true, paper = TRUE_MOTION[flag], PAPER_STEP[flag]
        missed = misses_on(docs, flag, true, 65)
        need(not missed, f"front.csv: at 65x65 the {flag} flag's true motion ({true}) misses {missed} (docs: none)")
        paper_missed = misses_on(docs, flag, paper, 65)
        short = [p for p in PATHS if not {"p99", "peak"} <= set(paper_missed.get(p, "").split(";"))]
        need(not short, f"front.csv: at 65x65 the {flag} flag's paper's step ({paper}) misses p99 and peak "
                        f"on every path but {short} (docs: on every path)")
        lo, hi = cost_range(docs, flag, true)
        out.append(f"{flag}: {true} within every bound on all seven paths at {lo:.0f}-{hi:.0f} ms per frame, "
                   f"{paper} misses p99 and peak on all seven")
    return "at 65x65: " + "; ".join(out)


FRONT_65_FINDINGS = [
    ("front_at_65_all_paths", c_front_at_65_all_paths),
]
