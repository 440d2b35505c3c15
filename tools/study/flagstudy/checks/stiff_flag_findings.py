"""The findings of docs/stiff_flag.md: the stiff flag against its fine-step reference, every row from
front.csv (flag=stiff), each judged by the bounds front_checks.py recomputes."""
import statistics

from flagstudy.checks.common import PATHS, front, misses_on, need, num, scene, stable, teleport_rows

FLUTTER = ["speed_50mps", "gale_40mps"]
# The implicit configurations whose step is a whole 240 Hz tick or longer.
LONG_STEPS = ["kangcho", "kangcho_3", "kangcho_16", "desbrun", "multigrid", "multigrid_1_cycle", "newton_1",
              "newton_be_60", "newton_be_240", "newton_be_240_2", "newton_bdf2_60", "newton_bdf2_60_2",
              "newton_bdf2_240", "newton_bdf2_240_2"]
XPBD = ["xpbd_960", "xpbd_960_16", "xpbd_1920", "xpbd_chains_1920", "xpbd_3840"]


def c_stiff_flag_ships_the_true_motion(docs):
    stiff = scene("flag_vehicle_stiff.json")
    need(stiff["flag"]["solver"] == {"name": "small_steps", "max_move": 0.01} and stiff["timing"]["physics_hz"] == 240,
         f"flag_vehicle_stiff.json ships {stiff['flag']['solver']} at {stiff['timing']['physics_hz']} Hz (docs: small_steps paced at 1 cm, 240 Hz)")
    missed = misses_on(docs, "stiff", "shipped")
    need(not missed, f"front.csv: the shipped stiff flag misses {missed} (docs: nothing)")
    traj = [num(front(docs, "stiff", p, "shipped")["traj_error"]) for p in PATHS]
    need(max(traj) <= 0.04, f"front.csv: the shipped stiff flag's trajectory error up to {max(traj):.2%} (docs: under 4%)")
    cost = [num(front(docs, "stiff", p, "shipped")["ms_per_frame"]) for p in PATHS if p != "light_particles"]
    tp = front(docs, "stiff", "teleport_1m", "shipped")
    allowed = 1.5 * num(tp["ref_peak_stretch"]) + 0.02
    unpaced = front(docs, "stiff", "teleport_1m", "small_steps")
    need(misses_on(docs, "stiff", "small_steps") == {"teleport_1m": "peak"} and num(unpaced["peak_stretch"]) - allowed < 0.03,
         f"front.csv: unpaced small_steps misses {misses_on(docs, 'stiff', 'small_steps')}, its teleport peak {unpaced['peak_stretch']} "
         f"(docs: the teleport's peak alone, by under 3 points)")
    same = [p for p in PATHS if p != "teleport_1m" and all(front(docs, "stiff", p, "small_steps")[k] == front(docs, "stiff", p, "shipped")[k]
                                                            for k in ("p99_stretch", "peak_stretch", "ke_patch_late"))]
    need(len(same) == 6, f"front.csv: unpaced small_steps moves like the shipped step on {same} (docs: the six paths without a jump)")
    peaks = {c: num(front(docs, "stiff", "teleport_1m", c)["peak_stretch"])
             for c in ("reference_half_step", "small_steps_f12", "small_steps_64", "small_steps_96")}
    need(all(v <= allowed for v in peaks.values()), f"front.csv: the teleport's peaks {peaks}, allowed {allowed:.3f}")
    need(not misses_on(docs, "stiff", "small_steps_f12"), "front.csv: small_steps_f12 misses a bound (docs: within all)")
    for c in LONG_STEPS:
        need(misses_on(docs, "stiff", c), f"front.csv: {c} within every bound on all seven paths (docs: none in long steps)")
    return (f"small_steps paced at 1 cm at 240 Hz: within every bound on all seven paths, {min(traj):.2%}-{max(traj):.2%} of the "
            f"width from the reference, {min(cost):.1f}-{max(cost):.1f} ms per frame (light particles "
            f"{num(front(docs, 'stiff', 'light_particles', 'shipped')['ms_per_frame']):.0f}); the teleport's peak "
            f"{num(tp['peak_stretch']):.1%} against {allowed:.1%} allowed, where unpaced small_steps (the same stretch and flutter on "
            f"the six other paths) peaks at {num(unpaced['peak_stretch']):.1%}, "
            f"{', '.join(f'{c} at {v:.1%}' for c, v in peaks.items())}; no step of 1/240 s or longer is within all")


def c_reference_converges_under_halving(docs):
    worst, teleport = 0, 0
    for flag in ("demo", "stiff"):
        for p in PATHS:
            r = front(docs, flag, p, "reference_half_step")
            need(stable(r) and not r["misses"], f"front.csv: the {flag} reference at half the step misses {r['misses']} on {p}")
            if p == "teleport_1m":
                teleport = max(teleport, num(r["traj_error"]))
            else:
                worst = max(worst, num(r["traj_error"]))
    need(worst <= 0.02 and teleport <= 0.05,
         f"front.csv: halving the references' step moves the flag {worst:.2%} of the width, {teleport:.2%} in the teleport (docs: 2%, 5%)")
    return (f"halving either reference's step stays within every bound of it on all seven paths, at most {worst:.2%} of the "
            f"width away, {teleport:.1%} after the teleport")


def c_implicit_steps_damp_the_flutter(docs):
    damped = [c for c in LONG_STEPS if c.startswith("newton") or c in ("desbrun", "kangcho_16")]
    worst = max(num(front(docs, "stiff", p, c)["energy_ratio"]) for c in damped for p in FLUTTER)
    need(worst < 0.5, f"front.csv: an implicit step of 1/240 s or longer keeps {worst:.2f}x of the patch flutter (docs: under 0.5x)")
    bdf2 = num(front(docs, "stiff", "gale_40mps", "newton_bdf2_240")["energy_ratio"])
    rest = max(num(front(docs, "stiff", p, c)["energy_ratio"]) for c in damped for p in FLUTTER
               if (p, c) != ("gale_40mps", "newton_bdf2_240"))
    need(bdf2 == worst and rest < 0.2, f"front.csv: BDF2 at 1/240 s keeps {bdf2:.2f}x in the gale, the rest at most {rest:.2f}x "
                                       "(docs: it the most, the rest under 0.2x)")
    mg = [front(docs, "stiff", p, "multigrid") for p in FLUTTER]
    need(all(0.5 <= num(r["energy_ratio"]) <= 2 and "p99" in r["misses"] for r in mg),
         "front.csv: multigrid keeps the flutter and misses p99 at 50 m/s and in the gale (docs)")
    kept = ", ".join(f"{num(r['energy_ratio']):.2f}x" for r in mg)
    return (f"the implicit steps of 1/240 s or longer with the air fully coupled (newton, any cap), desbrun and 16 Jacobi "
            f"sweeps keep at most {worst:.2f}x of the "
            f"reference's 8x8 patch flutter at 50 m/s and in the gale (BDF2 at 1/240 s in the gale; the rest at most "
            f"{rest:.2f}x); the linearized multigrid step keeps {kept} and misses p99")


def c_small_implicit_steps_cost_the_most(docs):
    fine = {c: misses_on(docs, "stiff", c) for c in ("newton_bdf2_960", "newton_bdf2_960_2", "newton_bdf2_1920")}
    want = {"newton_bdf2_960": {}, "newton_bdf2_960_2": {}, "newton_bdf2_1920": {"teleport_1m": "peak"}}
    need(fine == want, f"front.csv: BDF2 in steps of 1/960 s or less misses {fine} "
                       "(docs: at 1/960 s within every bound; at 1/1920 s the teleport's peak alone)")
    peak = num(front(docs, "stiff", "teleport_1m", "newton_bdf2_1920")["peak_stretch"])
    shipped = num(front(docs, "stiff", "drive", "shipped")["ms_per_frame"])
    cost = {c: num(front(docs, "stiff", "drive", c)["ms_per_frame"]) for c in fine}
    need(min(cost.values()) > 5 * shipped, f"front.csv: on the drive BDF2 in small steps costs {cost} ms (docs: over 5x the shipped {shipped:.1f})")
    return (f"BDF2 in steps of 1/960 s, converged and capped at two iterations, is within every bound on all seven paths; "
            f"converged at 1/1920 s it misses the 1 m teleport's peak ({peak:.1%}); "
            f"{min(cost.values()) / shipped:.0f}-{max(cost.values()) / shipped:.0f}x the shipped step's cost on the drive")


def c_xpbd_keeps_flutter_not_stretch(docs):
    stretch = {c: sum(1 for p in PATHS if {"p99", "peak", "unstable"} & set(misses_on(docs, "stiff", c).get(p, "").split(";")))
               for c in XPBD}
    need(all(n >= 3 for n in stretch.values()), f"front.csv: xpbd misses a stretch bound on {stretch} paths (docs: 3 or more each)")
    need(all(not stable(front(docs, "stiff", "light_particles", c)) for c in XPBD), "front.csv: xpbd stable with light particles")
    return (f"xpbd misses a stretch bound (or is unstable) on {min(stretch.values())}-{max(stretch.values())} of seven paths "
            "at each rate, and blows up with light particles at every rate")


def c_explicit_needs_its_stability_limit(docs):
    unstable = {c: [p for p in PATHS if not stable(front(docs, "stiff", p, c))] for c in ("explicit_16", "explicit_32", "explicit_64", "small_steps_64")}
    need(len(unstable["explicit_16"]) == 7 and len(unstable["explicit_32"]) == 7
         and unstable["explicit_64"] == ["light_particles"] and unstable["small_steps_64"] == ["light_particles"],
         f"front.csv: the stiff flag's fixed substep counts unstable on {unstable} (docs: 16 and 32 everywhere, 64 with light particles)")
    need(stable(front(docs, "stiff", "light_particles", "shipped")), "front.csv: small_steps from its bound unstable with light particles")
    return ("explicit in 16 or 32 substeps per tick blows up on all seven paths, in 64 with light particles only (as does "
            "small_steps at a fixed 64); small_steps from the stability bound holds them all")


# The configurations judged over the teleport ensemble (teleports_stiff.csv): the reference at half its
# step, the shipped step and the same at other fractions of its stability bound, the double explicit
# step, BDF2 in steps of 1/960 s, converged and capped at two Newton iterations.
ENSEMBLE = ["reference_half_step", "shipped", "small_steps", "small_steps_f09", "small_steps_f11", "small_steps_f12",
            "explicit_96", "newton_bdf2_960", "newton_bdf2_960_2"]


def stiff_teleports(docs, config):
    return teleport_rows(docs, "teleports_stiff.csv", "stiff", config)


def ensemble_verdict(docs, config, ref, allowed):
    """(within the ensemble's bounds, median peak, jumps whose own peak bound it misses): stable and
    within p99 on every jump, its median peak within the bound on the reference's median peak."""
    rows = stiff_teleports(docs, config)
    need(sorted(rows) == sorted(ref), f"teleports_stiff.csv: {config} on jumps {sorted(rows)}, the reference on {sorted(ref)}")
    peak = statistics.median(num(r["peak_stretch"]) for r in rows.values())
    held = all(stable(r) and "p99" not in r["misses"] for r in rows.values()) and peak <= allowed
    return held, peak, sorted(d for d, r in rows.items() if "peak" in r["misses"])


def c_teleport_peak_is_chaos(docs):
    ref = stiff_teleports(docs, "reference")
    need(len(ref) >= 9 and 1.0 in ref, f"teleports_stiff.csv: {len(ref)} jumps (docs: eleven, 1 m among them)")
    ref_median = statistics.median(num(r["peak_stretch"]) for r in ref.values())
    allowed = 1.5 * ref_median + 0.02
    v = {c: ensemble_verdict(docs, c, ref, allowed) for c in ENSEMBLE}
    held = [c for c in ENSEMBLE if v[c][0]]
    need(held == [c for c in ENSEMBLE if not c.startswith("newton")],
         f"teleports_stiff.csv: within the ensemble's bounds: {held} (docs: all but BDF2)")
    need(v["small_steps"][2] == [1.0] and not v["shipped"][2],
         f"teleports_stiff.csv: unpaced small_steps misses the peak at {v['small_steps'][2]} m, the shipped step at {v['shipped'][2]} m "
         "(docs: 1 m alone, never)")
    need(num(stiff_teleports(docs, "shipped")[1.0]["peak_stretch"]) == num(front(docs, "stiff", "teleport_1m", "shipped")["peak_stretch"]),
         "teleports_stiff.csv and front.csv disagree on the shipped step's 1 m teleport")
    need(not v["small_steps_f12"][2] and v["small_steps_f12"][1] > v["small_steps"][1],
         f"teleports_stiff.csv: small_steps_f12 misses at {v['small_steps_f12'][2]} m, median {v['small_steps_f12'][1]:.3f} "
         f"against small_steps' {v['small_steps'][1]:.3f} (docs: within on every jump, yet a higher median)")
    for c in ("newton_bdf2_960", "newton_bdf2_960_2"):
        need(not misses_on(docs, "stiff", c).get("teleport_1m"), f"front.csv: {c} misses on the 1 m teleport (docs: within there)")
    traj = {c: statistics.median(num(r["traj_error"]) for r in stiff_teleports(docs, c).values())
            for c in ("shipped", "newton_bdf2_960")}
    need(traj["newton_bdf2_960"] > 3 * traj["shipped"], f"teleports_stiff.csv: median trajectory errors {traj} (docs: BDF2 over 3x the shipped)")
    return (f"over {len(ref)} teleports of {min(ref)}-{max(ref)} m the reference's median peak is {ref_median:.1%} ({allowed:.1%} "
            f"allowed); median peaks {', '.join(f'{c} {v[c][1]:.1%}' for c in ENSEMBLE)}; one jump's peak bound missed by "
            f"{'; '.join(f'{c} at {v[c][2]} m' for c in ENSEMBLE if v[c][2])}; all but BDF2 within the ensemble's bounds; median "
            f"trajectory error {traj['shipped']:.1%} shipped, {traj['newton_bdf2_960']:.1%} BDF2 at 1/960 s")


def c_small_steps_stability_margin(docs):
    rows = docs.rows("small_steps_margin.csv")

    def stable_on(config):
        return [r["path"] for r in rows if r["config"] == config and stable(r)]
    need(all(sorted(stable_on(c)) == sorted(PATHS) for c in ("shipped", "small_steps_f12", "small_steps_f14")),
         "small_steps_margin.csv: small_steps at fraction 1, 1.2 or 1.4 unstable on a path (docs: stable on all seven)")
    need(sorted(set(PATHS) - set(stable_on("small_steps_f15"))) == ["teleport_1m"],
         f"small_steps_margin.csv: fraction 1.5 stable on {stable_on('small_steps_f15')} (docs: all but the teleport)")
    need(not stable_on("small_steps_f16"), f"small_steps_margin.csv: fraction 1.6 stable on {stable_on('small_steps_f16')} (docs: none)")
    return ("small_steps is stable on all seven paths at 1, 1.2 and 1.4 times its stability bound's step, blows up in the "
            "teleport at 1.5 and on every path at 1.6")


def c_stiff_flag_at_65(docs):
    r = front(docs, "stiff", "drive", "shipped", "65")
    need(stable(r) and not r["misses"], f"front.csv: the shipped stiff flag at 65x65 on the drive misses {r['misses']}")
    return f"at 65x65 on the drive the shipped step is within every bound, {num(r['ms_per_frame']):.0f} ms per frame"


STIFF_FLAG_FINDINGS = [
    ("stiff_flag_ships_the_true_motion", c_stiff_flag_ships_the_true_motion),
    ("reference_converges_under_halving", c_reference_converges_under_halving),
    ("implicit_steps_damp_the_flutter", c_implicit_steps_damp_the_flutter),
    ("small_implicit_steps_cost_the_most", c_small_implicit_steps_cost_the_most),
    ("xpbd_keeps_flutter_not_stretch", c_xpbd_keeps_flutter_not_stretch),
    ("explicit_needs_its_stability_limit", c_explicit_needs_its_stability_limit),
    ("stiff_flag_at_65", c_stiff_flag_at_65),
    ("teleport_peak_is_chaos", c_teleport_peak_is_chaos),
    ("small_steps_stability_margin", c_small_steps_stability_margin),
]
