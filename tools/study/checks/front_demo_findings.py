"""The findings of docs/study.md's front on the demo's flag: the flag as `flag_vehicle` ships it
against its reference (its whole model: springs, air, collisions, tethers and stretch limit), the
constraints' own effect, and the cheapest configuration close to the true motion (front.csv,
flag=demo, 33x33)."""
from checks.common import PATHS, front, misses_on, need, num, stable, teleport_rows


def demo_misses(docs, config):
    """The paths where config misses a bound on the demo's flag, the misses comma-separated."""
    return {p: m.replace(";", ", ") for p, m in misses_on(docs, "demo", config).items()}


def c_demo_flag_far_from_its_reference(docs):
    missed = demo_misses(docs, "shipped")
    traj = {p: num(front(docs, "demo", p, "shipped")["traj_error"]) for p in PATHS}
    need(len(missed) >= 5, f"front.csv: the demo's flag as shipped misses a bound on {sorted(missed)} (docs: five or more paths)")
    need(min(traj.values()) >= 0.05, f"front.csv: the shipped demo flag's trajectory error is {traj} (docs: 5% of the width or more)")
    worst = max(traj, key=traj.get)
    return (f"the demo's flag as shipped misses a bound on {len(missed)} of 7 paths ({'; '.join(f'{p}: {m}' for p, m in missed.items())}); "
            f"it is {min(traj.values()):.0%}-{traj[worst]:.0%} of the width from its reference ({worst} the worst)")


def c_constraints_are_part_of_the_model(docs):
    springs = demo_misses(docs, "reference_springs")
    bare = demo_misses(docs, "kangcho_no_constraints")
    need(len(springs) >= 3, f"front.csv: the springs-only reference misses the full one's bounds on {sorted(springs)} (docs: 3 or more paths)")
    need(len(bare) == 7, f"front.csv: the paper's step without constraints misses on {sorted(bare)} (docs: all seven)")
    return (f"the springs-only reference misses the constrained reference's bounds on {len(springs)} of 7 paths "
            f"({', '.join(sorted(springs))}); the paper's step without constraints on all seven")


BDF2_SMALL_STEPS = ("newton_bdf2_960", "newton_bdf2_960_2", "newton_bdf2_1920", "newton_bdf2_1920_2")


def c_demo_true_motion_costs(docs):
    configs = sorted({r["config"] for r in docs.rows("front.csv") if r["flag"] == "demo" and r["size"] == "33"})
    right = [c for c in configs if not c.startswith("reference") and not demo_misses(docs, c)]
    need(not right, f"front.csv: {right} within every bound on the demo's flag on all seven paths (docs: no configuration but the references)")
    for c in BDF2_SMALL_STEPS:
        need(demo_misses(docs, c) == {"teleport_1m": "p99"}, f"front.csv: {c} on the demo's flag misses {demo_misses(docs, c)} (docs: the teleport's p99 alone)")
    tele = [num(front(docs, "demo", "teleport_1m", c)["p99_stretch"]) for c in BDF2_SMALL_STEPS]
    ref = front(docs, "demo", "teleport_1m", "reference")
    allowed = 1.25 * num(ref["p99_stretch"]) + 0.01
    cost = [num(front(docs, "demo", "drive", c)["ms_per_frame"]) / num(front(docs, "demo", "drive", "shipped")["ms_per_frame"])
            for c in BDF2_SMALL_STEPS]
    small = demo_misses(docs, "small_steps")
    need(sorted(small) == ["gale_40mps", "speed_50mps", "teleport_1m"],
         f"front.csv: small_steps on the demo's flag misses on {small} (docs: 50 m/s, the teleport, the gale)")
    explicit = {c: demo_misses(docs, c) for c in ("explicit_32", "explicit_64", "explicit_96", "explicit_128")}
    need(all(list(m) == ["light_particles"] for m in explicit.values()),
         f"front.csv: explicit in 32-128 substeps on the demo's flag misses on {explicit} (docs: light particles alone)")
    kept = [num(front(docs, "demo", p, c)["energy_ratio"]) for p in ("speed_50mps", "gale_40mps") for c in ("small_steps", "explicit_32")]
    need(max(kept[0], kept[2]) < 0.5 <= min(kept[1], kept[3]),
         f"front.csv: 50 m/s and gale flutter kept by small_steps / explicit_32: {kept} (docs: under 0.5x / within the band)")
    return (f"no configuration but the references is within every bound on all seven paths; BDF2 in steps of 1/960 s and less "
            f"({min(cost):.0f}-{max(cost):.0f}x the shipped step's cost on the drive) misses the teleport's p99 alone "
            f"({min(tele):.1%}-{max(tele):.1%}, {allowed:.1%} allowed); explicit in 32-128 substeps misses light particles alone; "
            f"small_steps, the constraints once per tick, misses {', '.join(f'{p} ({m})' for p, m in small.items())}, its flutter "
            f"{kept[0]:.2f}x and {kept[2]:.2f}x where explicit_32's is {kept[1]:.2f}x and {kept[3]:.2f}x")


def c_demo_teleport_reference_paced(docs):
    rows = {c: teleport_rows(docs, "teleports_demo.csv", "demo", c)
            for c in ("reference", "reference_half_step", "reference_unpaced", "newton_bdf2_960")}
    p99 = {c: {d: num(r["p99_stretch"]) for d, r in v.items()} for c, v in rows.items()}
    jumps = sorted(p99["reference"])
    need(len(jumps) >= 9 and 1.0 in jumps and all(sorted(v) == jumps for v in p99.values()),
         f"teleports_demo.csv: jumps {[sorted(v) for v in p99.values()]} (docs: the same eleven for each)")
    paced = {d: int(r["substeps"]) for d, r in rows["reference"].items()}
    need(all(n == round(d / 0.01) for d, n in paced.items()), f"teleports_demo.csv: the reference's substeps {paced} (docs: one per cm of the jump)")
    need(all(int(r["substeps"]) == 24 for r in rows["reference_unpaced"].values()), "teleports_demo.csv: the unpaced reference runs 24 substeps (docs)")
    span = {c: (min(v.values()), max(v.values())) for c, v in p99.items()}
    gap = max(abs(v - p99["reference_half_step"][d]) for d, v in p99["reference"].items())
    need(span["reference_unpaced"][1] > 3 * span["reference"][1] and span["reference"][1] < 0.12 and gap <= 0.01,
         f"teleports_demo.csv: the demo reference's p99 after a teleport {span}, {gap:.1%} under halving "
         "(docs: up to 59% unpaced, under 12% paced, within a point under halving)")
    stiff = {c: {d: num(r["p99_stretch"]) for d, r in teleport_rows(docs, "teleports_stiff.csv", "stiff", c).items()}
             for c in ("reference", "reference_half_step")}
    stiff_gap = max(abs(v - stiff["reference_half_step"][p]) for p, v in stiff["reference"].items())
    need(stiff_gap <= 0.012, f"teleports_stiff.csv: the stiff reference's p99 moves {stiff_gap:.1%} under halving (docs: 1.2 points at most)")
    for c in ("reference", "newton_bdf2_960"):
        need(num(front(docs, "demo", "teleport_1m", c)["p99_stretch"]) == p99[c][1.0],
             f"teleports_demo.csv and front.csv disagree on {c}'s 1 m teleport")
    bdf2 = [d for d, r in rows["newton_bdf2_960"].items() if "p99" not in r["misses"]]
    need(not bdf2, f"teleports_demo.csv: newton_bdf2_960 within the p99 bound after the jumps {bdf2} (docs: none)")
    explicit = sorted(d for d, r in teleport_rows(docs, "teleports_demo.csv", "demo", "explicit_32").items() if r["misses"])
    need(explicit == [d for d in jumps if d >= 1.1], f"teleports_demo.csv: explicit_32 misses after the jumps {explicit} (docs: 1.1 m and longer)")
    unpaced = front(docs, "demo", "teleport_1m", "reference_unpaced")
    need("p99" in unpaced["misses"], f"front.csv: the unpaced reference on the 1 m teleport misses {unpaced['misses']!r} (docs: p99)")
    f = lambda c: f"{span[c][0]:.1%}-{span[c][1]:.1%}"
    return (f"after teleports of {jumps[0]}-{jumps[-1]} m the demo flag's reference has a p99 stretch of {f('reference_unpaced')} "
            f"unpaced (24 substeps), {f('reference')} paced (a substep per cm), moving at most {gap:.1%} under halving; "
            f"newton_bdf2_960 misses p99 after every jump ({f('newton_bdf2_960')}), explicit_32 after {explicit[0]} m and longer; "
            f"the stiff reference's p99 moves at most {stiff_gap:.1%} under halving")


FRONT_DEMO_FINDINGS = [
    ("demo_flag_far_from_its_reference", c_demo_flag_far_from_its_reference),
    ("constraints_are_part_of_the_model", c_constraints_are_part_of_the_model),
    ("demo_true_motion_costs", c_demo_true_motion_costs),
    ("demo_teleport_reference_paced", c_demo_teleport_reference_paced),
]
