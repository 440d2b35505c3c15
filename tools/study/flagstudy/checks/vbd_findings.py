"""The findings on Vertex Block Descent (vbd, docs/study.md): its two configurations of the front,
vbd_10 (10 passes at 240 Hz) and vbd_960_5 (5 passes at 960 Hz), on both flags and all seven paths
at 33x33, against the flags' references and beside xpbd and small_steps, every row from front.csv."""
from flagstudy.checks.common import PATHS, front, misses_on, need, num, one, stable
from flagstudy.checks.run_outputs import VBD_BOUND_M, VBD_CONVERGED, VBD_MOVED_M

VBD = ["vbd_10", "vbd_960_5"]


def c_vbd_on_the_judge(docs):
    within = {(f, c): [p for p in PATHS if p not in misses_on(docs, f, c)] for f in ("demo", "stiff") for c in VBD}
    want = {("demo", "vbd_10"): ["spin_5radps"], ("demo", "vbd_960_5"): ["speed_50mps", "spin_5radps"],
            ("stiff", "vbd_10"): [], ("stiff", "vbd_960_5"): []}
    need(within == want, f"front.csv: vbd within every bound on {within} (docs: {want})")
    unstable = [(f, c) for f in ("demo", "stiff") for c in VBD if not stable(front(docs, f, "light_particles", c))]
    need(len(unstable) == 3 and ("demo", "vbd_10") not in unstable,
         f"front.csv: vbd unstable with light particles for {unstable} (docs: all but the demo flag's vbd_10)")
    traj = {c: num(front(docs, "demo", "drive", c)["traj_error"]) for c in VBD + ["shipped", "xpbd_960", "small_steps_paced"]}
    need(traj["vbd_960_5"] < traj["shipped"] and traj["small_steps_paced"] < traj["vbd_960_5"],
         f"front.csv: the demo drive's trajectory errors {traj} (docs: vbd_960_5 between small_steps_paced and the shipped step)")
    cost = {c: num(front(docs, "demo", "drive", c)["ms_per_frame"]) for c in VBD + ["xpbd_960"]}
    need(min(cost[c] for c in VBD) > 5 * cost["xpbd_960"], f"front.csv: the demo drive's costs {cost} (docs: vbd over 5x xpbd_960)")
    return (f"within every bound only on {within[('demo', 'vbd_10')]} (vbd_10) and {within[('demo', 'vbd_960_5')]} (vbd_960_5) "
            f"for the demo flag, on no path for the stiff flag; unstable with light particles but for the demo flag's vbd_10; "
            f"the demo drive's trajectory error {traj['vbd_10']:.1%} and {traj['vbd_960_5']:.1%} against the shipped step's "
            f"{traj['shipped']:.1%}, xpbd_960's {traj['xpbd_960']:.1%} and small_steps_paced's {traj['small_steps_paced']:.1%}, "
            f"at {cost['vbd_10']:.0f} and {cost['vbd_960_5']:.0f} ms per frame (measured beside other work) against xpbd_960's "
            f"{cost['xpbd_960']:.1f}")


def c_vbd_matches_nvidia_newton(docs):
    """nvidia_newton_vbd_check.csv: our vbd and NVIDIA Newton's VBD on the same 9x9 flag on the drive's first half
    second, within the bound at 100 iterations, far apart at 10."""
    rows = docs.rows("nvidia_newton_vbd_check.csv")
    converged = one(rows, "nvidia_newton_vbd_check.csv", iterations=str(VBD_CONVERGED))
    few = one(rows, "nvidia_newton_vbd_check.csv", iterations="10")
    rms, moved, apart = num(converged["rms_m"]), num(converged["moved_rms_m"]), num(few["rms_m"])
    need(rms <= VBD_BOUND_M and moved > VBD_MOVED_M,
         f"at {VBD_CONVERGED} iterations {rms} m apart, the flag moving {moved} m (docs: within {VBD_BOUND_M:g}, moving)")
    need(apart > 10 * VBD_BOUND_M, f"at 10 iterations {apart} m apart (docs: over ten times the bound)")
    return (f"at {VBD_CONVERGED} iterations {rms * 1e3:.3f} mm apart (rms; bound {VBD_BOUND_M * 1e3:g} mm) while the "
            f"flag moves {moved:.2f} m; at 10 iterations {apart * 1e3:.1f} mm apart")


VBD_FINDINGS = [("vbd_on_the_judge", c_vbd_on_the_judge), ("vbd_matches_nvidia_newton", c_vbd_matches_nvidia_newton)]
