"""The finding on NVIDIA Newton's solvers in the front (docs/study.md): VBD, XPBD and Style3D as
cloth_study's solver kind nvidia_newton (--nvidia-newton), on both flags and all seven paths at
33x33, judged against the flags' references like every configuration, every row from front.csv."""
from flagstudy.checks.common import PATHS, front, misses_on, need, num, stable

PEERS = {"demo": ["nvidia_newton_vbd", "nvidia_newton_xpbd_7200", "nvidia_newton_style3d"],
         "stiff": ["nvidia_newton_vbd", "nvidia_newton_xpbd_22800", "nvidia_newton_style3d"]}
# Where each is within every bound, as docs/study.md says.
WITHIN = {("demo", "nvidia_newton_vbd"): [],
          ("demo", "nvidia_newton_xpbd_7200"): ["drive", "speed_50mps", "stop_10g", "spin_5radps", "gale_40mps"],
          ("demo", "nvidia_newton_style3d"): ["speed_50mps", "spin_5radps", "light_particles"],
          ("stiff", "nvidia_newton_vbd"): [],
          ("stiff", "nvidia_newton_xpbd_22800"): ["spin_5radps", "teleport_1m", "gale_40mps"],
          ("stiff", "nvidia_newton_style3d"): ["speed_50mps", "spin_5radps"]}


def within(docs, flag, config):
    missed = misses_on(docs, flag, config)
    return [p for p in PATHS if p not in missed]


def cheapest_within(docs, flag, path):
    """The cheapest configuration within every bound on one flag and path at 33x33 (references aside)."""
    rows = [r for r in docs.rows("front.csv") if r["flag"] == flag and r["path"] == path and r["size"] == "33"
            and stable(r) and r["misses"] == "" and not r["config"].startswith("reference")]
    return min(rows, key=lambda r: num(r["ms_per_frame"]))["config"] if rows else None


def c_nvidia_newton_on_the_judge(docs):
    found = {(f, c): within(docs, f, c) for f in PEERS for c in PEERS[f]}
    need(found == WITHIN, f"front.csv: NVIDIA Newton's solvers within every bound on {found} (docs: {WITHIN})")
    torn = [num(front(docs, "demo", p, "nvidia_newton_vbd")["p99_stretch"]) for p in PATHS]
    need(min(torn) > 3, f"front.csv: the demo flag's nvidia_newton_vbd p99 stretch {torn} (docs: over 300% on every path)")
    diverged = [p for p in PATHS if not stable(front(docs, "stiff", p, "nvidia_newton_vbd"))]
    need(diverged == PATHS, f"front.csv: the stiff flag's nvidia_newton_vbd unstable on {diverged} (docs: all seven)")
    failed = [int(front(docs, "stiff", p, "nvidia_newton_vbd")["failures"]) for p in PATHS]
    need(min(failed) == 4 and max(failed) == 480, f"front.csv: its failed ticks {failed} (docs: 4-480)")
    xpbd = [num(front(docs, "demo", p, "nvidia_newton_xpbd_7200")["traj_error"]) for p in WITHIN[("demo", "nvidia_newton_xpbd_7200")]]
    need(max(xpbd) < 0.04, f"front.csv: nvidia_newton_xpbd_7200's trajectory errors where within bounds {xpbd} (docs: under 4%)")
    damped = num(front(docs, "demo", "drive", "nvidia_newton_style3d")["energy_ratio"])
    need(0.1 < damped < 0.2, f"front.csv: Style3D's flutter on the demo drive {damped}x the reference's (docs: 0.14x)")
    peer_ms = [num(front(docs, f, p, c)["ms_per_frame"]) for f in PEERS for c in PEERS[f] for p in PATHS]
    need(69 <= min(peer_ms) < 70 and 356 < max(peer_ms) <= 357, f"front.csv: the peers' costs {min(peer_ms)}-{max(peer_ms)} ms "
         f"per frame (docs: 69-357)")
    ours = num(front(docs, "demo", "drive", "small_steps_paced")["ms_per_frame"])
    need(min(peer_ms) > 20 * ours, f"front.csv: the peers' costs from {min(peer_ms)} ms per frame against small_steps_paced's "
         f"{ours} on the demo drive (docs: over 20 times)")
    crossed = sum(int(front(docs, f, p, c)["crossings"]) > 0 for f in PEERS for c in PEERS[f] for p in PATHS)
    ref = front(docs, "demo", "drive", "reference")
    need(crossed == 36 and (ref["crossings"], ref["crossing_ticks"]) == ("333", "245"),
         f"front.csv: {crossed} peer rows cross, the demo drive's reference {ref['crossings']} in {ref['crossing_ticks']} "
         f"ticks (docs: 36 of 42; 333 in 245)")
    peers = {c for cs in PEERS.values() for c in cs}
    cheapest = {(f, p): cheapest_within(docs, f, p) for f in PEERS for p in PATHS}
    need(not peers & set(cheapest.values()), f"front.csv: the cheapest within every bound {cheapest} (docs: never a peer)")
    return (f"within every bound: the demo flag's XPBD (30 substeps a tick) on {len(found[('demo', 'nvidia_newton_xpbd_7200')])} "
            f"paths at {min(xpbd):.1%}-{max(xpbd):.1%} of the width, Style3D on {found[('demo', 'nvidia_newton_style3d')]}, "
            f"the stiff flag's Style3D on {found[('stiff', 'nvidia_newton_style3d')]} and XPBD (95 substeps) on "
            f"{found[('stiff', 'nvidia_newton_xpbd_22800')]}; VBD tears the demo flag "
            f"(p99 {min(torn):.0%}-{max(torn):.0%}) and diverges on the stiff flag's seven paths; the peers cost "
            f"{min(peer_ms):.0f}-{max(peer_ms):.0f} ms per frame on Warp's CPU device, small_steps_paced {ours} on the drive; "
            f"none is the cheapest within every bound anywhere")


NVIDIA_NEWTON_FRONT_FINDINGS = [("nvidia_newton_on_the_judge", c_nvidia_newton_on_the_judge)]
