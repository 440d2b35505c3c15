"""The findings on contact (docs/study.md, the front with contact): both flags at 33x33 on all
seven paths with contact (cloth_study --contact) in the references and in three configurations
each, every row from front_contact.csv."""
from flagstudy.checks.common import PATHS, need, one

NAME = "front_contact.csv"
# The configurations run with contact per flag: its reference, the paper's step and the true motion.
PAPER = {"demo": "shipped", "stiff": "kangcho_float"}
TRUE_MOTION = {"demo": "small_steps_paced", "stiff": "shipped"}


def row(docs, flag, path, config):
    return one(docs.rows(NAME), NAME, flag=flag, path=path, config=config, size="33")


def crossing_paths(docs, flag, config):
    return [p for p in PATHS if row(docs, flag, p, config)["crossings"] != "0"]


def missed(docs, flag, config):
    misses = {p: row(docs, flag, p, config)["misses"] for p in PATHS}
    return {p: m for p, m in misses.items() if m}


def c_contact_no_crossing(docs):
    for flag in ("demo", "stiff"):
        for config in ("reference", TRUE_MOTION[flag], PAPER[flag]):
            bad = crossing_paths(docs, flag, config)
            need(not bad, f"{NAME}: {flag} {config} crosses on {bad} (docs: on no path)")
    jump = row(docs, "demo", "teleport_1m", "shipped")
    return (f"no crossing in any tick for both references, both true motions and both flags' paper's step on all "
            f"seven paths, the demo flag's 1 m teleport included (the paper's step peaks at "
            f"{float(jump['peak_stretch']):.0%} stretch there)")


def c_contact_true_motion_within_bounds(docs):
    demo, stiff = missed(docs, "demo", "small_steps_paced"), missed(docs, "stiff", "shipped")
    need(demo == {"stop_10g": "peak"}, f"{NAME}: the demo flag's small_steps_paced misses {demo} (docs: the 10 g stop's peak alone)")
    need(stiff == STIFF_TRUE_MOTION_MISSES, f"{NAME}: the stiff flag's shipped step misses {stiff} (docs: {STIFF_TRUE_MOTION_MISSES})")
    stop = row(docs, "demo", "stop_10g", "small_steps_paced")
    bound = 1.5 * float(stop["ref_peak_stretch"]) + 0.02
    return (f"the demo flag's small_steps_paced within every bound of the reference with contact but the 10 g stop's "
            f"peak ({float(stop['peak_stretch']):.1%} against {bound:.1%} allowed); the stiff flag's shipped step misses {stiff or 'none'}")


STIFF_TRUE_MOTION_MISSES = {}


def c_contact_costs(docs):
    def ms(name, flag, config):
        return float(one(docs.rows(name), name, flag=flag, path="drive", config=config, size="33")["ms_per_frame"])
    demo = ms(NAME, "demo", "small_steps_paced") / ms("front.csv", "demo", "small_steps_paced")
    stiff = ms(NAME, "stiff", "shipped") / ms("front.csv", "stiff", "shipped")
    paper = ms(NAME, "demo", "shipped") / ms("front.csv", "demo", "shipped")
    need(demo > 4 and stiff > 8 and paper > 4,
         f"{NAME} against front.csv on the drive: contact multiplies the cost by {demo:.1f} (demo small_steps_paced), "
         f"{stiff:.1f} (stiff shipped), {paper:.1f} (demo shipped) (docs: over 4, 8 and 4)")
    return (f"on the drive contact multiplies the cloth's cost per frame by {demo:.1f} (the demo flag's true motion), "
            f"{stiff:.1f} (the stiff flag's) and {paper:.1f} (the paper's step), both runs beside other work")

CONTACT_FINDINGS = [("contact_no_crossing", c_contact_no_crossing),
                    ("contact_true_motion_within_bounds", c_contact_true_motion_within_bounds),
                    ("contact_costs", c_contact_costs)]
