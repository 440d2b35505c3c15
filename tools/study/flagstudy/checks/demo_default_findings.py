"""The findings of docs/study.md's "The demo default and why": each choice of the demo's default
configuration against the CSVs that show it."""
from flagstudy.checks.common import CASES, DEMO_DEFAULT, ext, need, num, one, stable


def c_paper_step_alone_fails_extremes(docs):
    bad = [f"{c} {n}" for n in (33, 65) for c in CASES if stable(ext(docs, "kangcho_1", c, n))]
    need(not bad, f"extreme.csv: the paper's step alone is stable in {bad} (docs: in none)")
    return "the paper's step alone (kangcho_1) is unstable in all six cases at 33x33 and 65x65"


def c_tight_tethers_hold(docs):
    rows = docs.rows("default_candidates_extreme.csv")
    configs = {r["config"] for r in rows}
    for c in configs:
        bad = sum(not stable(r) for r in rows if r["config"] == c)
        if "tether=0.1" in c:
            need(bad >= 1, f"{c} holds all its runs (docs: no pass count holds all six cases with tethers at 10%)")
    full = sorted((int(c.split("strain_passes=")[1].split(",")[0]), c) for c in configs
                  if sum(r["config"] == c for r in rows) == 72 and all(stable(r) for r in rows if r["config"] == c))
    need(full and full[0][0] == 3, f"the fewest passes stable in all 72 runs: {full[:1]} (docs: 3)")
    two = [c for c in configs if "strain_passes=2" in c and sum(r["config"] == c for r in rows) == 72]
    need(two and all(sum(not stable(r) for r in rows if r["config"] == c) == 1 for c in two),
         "two passes do not lose exactly one run of 72")
    t = docs.rows("tethers_extreme.csv")
    for n in ("33", "65"):
        r = one(t, "tethers_extreme.csv", variant="kc_s4", case="spin_5radps", size=n)
        need(not stable(r), f"tethers_extreme.csv kc_s4 spin {n}: stable (docs: 4 passes without tethers lose the spin)")
    return "tethers at 10% never hold all six cases; 3 passes are the fewest stable in 72 runs, 2 lose one; without tethers 4 passes lose the spin"


def c_float_as_stable_as_double(docs):
    rows = docs.rows("default_candidates_extreme.csv")
    out = []
    for tail in ("strain_passes=3,tether=0.03", "strain_passes=4,tether=0.03"):
        for prec in ("precision=float,", ""):
            c = f"kangcho:iterations=1,{prec}strain_limit=0.1,{tail}"
            mine = [r for r in rows if r["config"] == c]
            need(len(mine) == 72 and all(stable(r) for r in mine), f"{c}: {sum(stable(r) for r in mine)} of {len(mine)} runs stable (docs: 72 of 72)")
        out.append(tail.replace("strain_passes=", "").replace(",tether=0.03", " passes"))
    return "float and double with tethers at 3% hold all 72 runs alike with " + " and ".join(out)


def c_default_stays_below_pole_top(docs):
    rows = docs.rows("rest_climb.csv")
    solver = DEMO_DEFAULT.replace("iterations=1,", "")
    mine = [r for r in rows if r["solver"] == solver and r["centroid_5s_m"]]
    need(len(mine) == 6 and all(num(r["highest_particle_m"]) <= 0.02 for r in mine),
         f"the demo default rises over the pole top at rest: {[r['highest_particle_m'] for r in mine]}")
    scan = [r for r in rows if not r["centroid_5s_m"]]
    rise = sum(num(r["highest_particle_m"]) > 0.02 for r in scan)
    need(len(scan) == 32 and rise == 16, f"{rise} of {len(scan)} configurations rise > 2 cm (docs: 16 of 32)")
    return "at rest the demo default never rises over the pole top (6 densities); 16 of 32 configurations do"


def c_pass_in_spring_order(docs):
    rows = docs.rows("pass_order_extreme.csv")
    def r(v, case, n):
        return one(rows, "pass_order_extreme.csv", variant=v, case=case, size=str(n))
    sp, co = "spring order (kept), 33 and 65", "colour order (not kept), 33 and 65"
    need(num(r(co, "light_particles", 33)["p99_stretch"]) > 2 * num(r(sp, "light_particles", 33)["p99_stretch"]),
         "colour order does not stretch light particles twice as much as spring order")
    need(stable(r(sp, "teleport_1m", 65)) and not stable(r(co, "teleport_1m", 65)), "the teleport at 65x65 does not separate the orders")
    dens = [x for x in rows if x["variant"] == "spring order (kept)" and x["case"] == "stop_10g"]
    held = sum(stable(x) for x in dens)
    need(len(dens) == 6 and held == 3, f"the previous default holds the 10 g stop in {held} of {len(dens)} densities (docs: 3 of 6)")
    return "the pass in spring order beats colour order (light particles, teleport at 65); the previous default's 10 g stop: 3 of 6 densities"


def c_default_cheaper_than_previous(docs):
    rows = docs.rows("default_cost_extreme.csv")
    out = []
    for n in ("33", "65"):
        for rnd in ("1", "2"):
            med = {}
            for r in rows:
                if r["size"] == n and r["round"] == rnd and r["case"] != "spin_5radps":  # the old spin: not counted
                    med.setdefault(r["default"].split(" ")[0], []).append(num(r["ms_per_tick"]))
            old, new = sorted(med["previous"])[2], sorted(med["candidate"])[2]
            need(len(med["previous"]) == len(med["candidate"]) == 5 and new < old,
                 f"default_cost_extreme.csv {n} round {rnd}: the candidate's median {new} against {old} ms per tick (docs: cheaper)")
        out.append(n)
    need(all(not stable(r) for r in rows if r["default"].startswith("previous") and r["case"] == "stop_10g"),
         "the previous default holds the 10 g stop in default_cost_extreme.csv")
    return "float with 4 passes: a lower median ms per tick than the previous default over the five cases, both rounds, 33 and 65"


def c_implicit_air_no_gain_for_demo(docs):
    a, b = "kangcho_1_strain_10pct", "kangcho_1_strain_10pct_implicit_air"
    runs = [(case, n) for n in (33, 65) for case in CASES]
    held = [sum(stable(ext(docs, cfg, c, n)) for c, n in runs) for cfg in (a, b)]
    gains = [f"{c} {n}" for c, n in runs if stable(ext(docs, b, c, n)) and not stable(ext(docs, a, c, n))]
    losses = [f"{c} {n}" for c, n in runs if stable(ext(docs, a, c, n)) and not stable(ext(docs, b, c, n))]
    need(held[0] == held[1] == 9, f"extreme.csv: explicit air stable in {held[0]}, implicit in {held[1]} of 12 runs (docs: 9 each)")
    need(gains == ["stop_10g 33"] and losses == ["spin_5radps 65"],
         f"extreme.csv: implicit air holds {gains} and loses {losses} (docs: holds the 10 g stop at 33, loses the spin at 65)")
    ma = sorted(num(ext(docs, a, c, 33)["ms_per_tick"]) for c in CASES)
    mb = sorted(num(ext(docs, b, c, 33)["ms_per_tick"]) for c in CASES)
    need(sum(mb[2:4]) > 1.3 * sum(ma[2:4]), "implicit air is not dearer per tick at 33x33")
    return (f"implicit air with the pass: 9 of 12 runs stable either way (holds {gains[0]}, loses {losses[0]}), "
            f"{sum(mb[2:4]) / sum(ma[2:4]):.1f}x the ms per tick at 33x33")


DEMO_DEFAULT_FINDINGS = [
    ("paper_step_alone_fails_extremes", c_paper_step_alone_fails_extremes),
    ("tight_tethers_hold", c_tight_tethers_hold),
    ("float_as_stable_as_double", c_float_as_stable_as_double),
    ("default_stays_below_pole_top", c_default_stays_below_pole_top),
    ("pass_in_spring_order", c_pass_in_spring_order),
    ("default_cheaper_than_previous", c_default_cheaper_than_previous),
    ("implicit_air_no_gain_for_demo", c_implicit_air_no_gain_for_demo),
]
