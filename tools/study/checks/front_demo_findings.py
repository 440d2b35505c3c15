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


def c_demo_true_motion_costs(docs):
    fine = [c for c in ("newton_bdf2_960", "newton_bdf2_960_2", "newton_bdf2_1920", "newton_bdf2_1920_2")
            if not demo_misses(docs, c)]
    need(len(fine) == 4, f"front.csv: of BDF2 in small steps only {fine} within every bound on the demo's flag (docs: all four)")
    cost = [num(front(docs, "demo", "drive", c)["ms_per_frame"]) / num(front(docs, "demo", "drive", "shipped")["ms_per_frame"])
            for c in fine]
    small = demo_misses(docs, "small_steps")
    need(sorted(small) == ["gale_40mps", "speed_50mps", "teleport_1m"],
         f"front.csv: small_steps on the demo's flag misses on {small} (docs: 50 m/s, the teleport, the gale)")
    explicit = demo_misses(docs, "explicit_32")
    need(list(explicit) == ["light_particles"], f"front.csv: explicit_32 on the demo's flag misses on {explicit} (docs: light particles alone)")
    kept = [num(front(docs, "demo", p, c)["energy_ratio"]) for p in ("speed_50mps", "gale_40mps") for c in ("small_steps", "explicit_32")]
    need(max(kept[0], kept[2]) < 0.5 <= min(kept[1], kept[3]),
         f"front.csv: 50 m/s and gale flutter kept by small_steps / explicit_32: {kept} (docs: under 0.5x / within the band)")
    return (f"within every bound on all seven paths: BDF2 in steps of 1/960 s and less, {min(cost):.0f}-{max(cost):.0f}x the shipped "
            f"step's cost on the drive; explicit in 32 substeps misses light particles alone; small_steps, the constraints once per "
            f"tick, misses {', '.join(f'{p} ({m})' for p, m in small.items())}, its flutter {kept[0]:.2f}x and {kept[2]:.2f}x "
            f"where explicit_32's is {kept[1]:.2f}x and {kept[3]:.2f}x")


def c_demo_teleport_reference_unconverged(docs):
    p99 = {c: {d: num(r["p99_stretch"]) for d, r in teleport_rows(docs, "teleports_demo.csv", "demo", c).items()}
           for c in ("reference", "reference_half_step", "reference_quarter_step", "newton_bdf2_960")}
    jumps = sorted(p99["reference"])
    need(len(jumps) >= 9 and 1.0 in jumps and all(sorted(v) == jumps for v in p99.values()),
         f"teleports_demo.csv: jumps {[sorted(v) for v in p99.values()]} (docs: the same eleven for each)")
    span = {c: (min(v.values()), max(v.values())) for c, v in p99.items()}
    need(span["reference"][1] > 3 * span["reference_quarter_step"][1] and span["reference_quarter_step"][1] < 0.12
         and span["reference_half_step"][1] < 0.16,
         f"teleports_demo.csv: the demo reference's p99 after a teleport {span} (docs: up to 59% at its step, 15% at half, 11% at a quarter)")
    stiff = {c: {d: num(r["p99_stretch"]) for d, r in teleport_rows(docs, "teleports_stiff.csv", "stiff", c).items()}
             for c in ("reference", "reference_half_step")}
    gap = max(abs(v - stiff["reference_half_step"][p]) for p, v in stiff["reference"].items())
    need(gap <= 0.012, f"teleports_stiff.csv: the stiff reference's p99 moves {gap:.1%} under halving (docs: 1.2 points at most)")
    one = front(docs, "demo", "teleport_1m", "reference")
    need(num(one["p99_stretch"]) == p99["reference"][1.0], "teleports_demo.csv and front.csv disagree on the reference's 1 m teleport")
    bdf2 = front(docs, "demo", "teleport_1m", "newton_bdf2_960")
    need(not bdf2["misses"] and p99["newton_bdf2_960"][1.0] > 2 * p99["reference_quarter_step"][1.0],
         f"front.csv: newton_bdf2_960 on the demo's 1 m teleport misses {bdf2['misses']!r}, p99 {p99['newton_bdf2_960'][1.0]:.3f} "
         "(docs: within, at over twice the quarter-step reference's p99)")
    f = lambda c: f"{span[c][0]:.1%}-{span[c][1]:.1%}"
    return (f"after teleports of {jumps[0]}-{jumps[-1]} m the demo flag's reference has a p99 stretch of {f('reference')} at its "
            f"step, {f('reference_half_step')} at half, {f('reference_quarter_step')} at a quarter; at 1 m newton_bdf2_960 is "
            f"within its bounds at {p99['newton_bdf2_960'][1.0]:.1%}; the stiff reference's p99 moves at most {gap:.1%} under halving")


FRONT_DEMO_FINDINGS = [
    ("demo_flag_far_from_its_reference", c_demo_flag_far_from_its_reference),
    ("constraints_are_part_of_the_model", c_constraints_are_part_of_the_model),
    ("demo_true_motion_costs", c_demo_true_motion_costs),
    ("demo_teleport_reference_unconverged", c_demo_teleport_reference_unconverged),
]
