"""The findings of docs/multigrid.md: the default's accuracy and its design choices (multigrid_*.csv)."""
from flagstudy.checks.common import need, num, one, stable


def mg(docs, name, size, solver):
    """A row of one of the multigrid CSVs."""
    return one(docs.rows(name), name, size=str(size), solver=solver)


def c_multigrid_default_accuracy(docs):
    out = []
    for n in (17, 33, 65, 129):
        m, e = mg(docs, "multigrid_start.csv", n, "multigrid"), mg(docs, "multigrid_start.csv", n, "exact:method=multigrid")
        a, b = num(m["max_stretch"]) / num(e["max_stretch"]), num(m["p99_stretch"]) / num(e["p99_stretch"])
        need(stable(m) and num(m["solve_error"]) <= 0.02 and a <= 1.5 and b <= 1.25,
             f"multigrid_start.csv {n}: error {m['solve_error']}, max {a:.2f}x, p99 {b:.2f}x exact (goal 0.02, 1.5x, 1.25x)")
        out.append(m["solve_error"])
    return "the multigrid default on the vehicle path: solve error " + " / ".join(out) + ", stretch within 1.5x / 1.25x of exact"


def c_galerkin_beats_rediscretized(docs):
    g = mg(docs, "multigrid_vehicle_path.csv", 129, "multigrid")
    r = mg(docs, "multigrid_vehicle_path.csv", 129, "multigrid:coarse=rediscretize")
    ratio = num(r["solve_error"]) / num(g["solve_error"])
    need(ratio > 2, f"re-discretized coarse levels leave {ratio:.1f}x Galerkin's error at 129x129 (docs: > 2x)")
    return f"re-discretized coarse levels leave {ratio:.1f}x the Galerkin error at 129x129"


def c_bend_collapse_as_accurate(docs):
    out = []
    for n in (17, 33, 65, 129):
        k = mg(docs, "multigrid_bend_collapse.csv", n, "multigrid:bend=keep")
        c = mg(docs, "multigrid_bend_collapse.csv", n, "multigrid:bend=collapse")
        need(stable(c) and num(c["solve_error"]) <= 0.02 and num(c["solve_error"]) <= 1.2 * num(k["solve_error"]),
             f"multigrid_bend_collapse.csv {n}: collapsed {c['solve_error']} against kept {k['solve_error']}")
        out.append(f"{k['solve_error']} / {c['solve_error']}")
    return "bend springs collapsed on the coarse levels: solve error kept / collapsed " + ", ".join(out)


def c_cg_beats_stationary_cycles(docs):
    out = []
    for n in (17, 33, 65, 129):
        a, s = mg(docs, "multigrid_vehicle_path.csv", n, "multigrid"), mg(docs, "multigrid_vehicle_path.csv", n, "multigrid:krylov=none")
        ratio = num(s["solve_error"]) / num(a["solve_error"])
        need(ratio >= 3.5, f"multigrid_vehicle_path.csv {n}: stationary cycles leave {ratio:.1f}x CG's error (docs: >= 4x)")
        out.append(f"{ratio:.0f}x")
    v22 = [num(mg(docs, "multigrid_vehicle_path.csv", n, "multigrid:pre_sweeps=2,post_sweeps=2")["solve_error"]) >=
           0.9 * num(mg(docs, "multigrid_vehicle_path.csv", n, "multigrid")["solve_error"]) for n in (17, 33, 65, 129)]
    need(all(v22), "V(2,2) is clearly more accurate than V(1,1) at the same tolerance")
    return "stationary cycles leave " + ", ".join(out) + " CG's error (17-129); V(2,2) is no more accurate than V(1,1)"


def c_kcycle_tolerance(docs):
    k = mg(docs, "multigrid_kcycle.csv", 129, "multigrid:kcycle=1,tolerance=2e-3")
    e = mg(docs, "multigrid_kcycle.csv", 129, "exact:method=multigrid")
    d = mg(docs, "multigrid_kcycle.csv", 129, "multigrid")
    v = mg(docs, "multigrid_kcycle.csv", 129, "multigrid:kcycle=0,tolerance=1e-3")
    p = num(k["p99_stretch"]) / num(e["p99_stretch"])
    need(p > 1.25, f"the K-cycle at 2e-3 keeps p99 within 1.25x at 129x129 ({p:.2f}x): the tolerance could rise")
    need(num(d["solve_error"]) < 0.6 * num(v["solve_error"]), "the K-cycle at 1.5e-3 does not beat the V-cycle at 1e-3 at 129x129")
    return f"K-cycle: at 1.5e-3 {d['solve_error']} against the V-cycle's {v['solve_error']} (1e-3) at 129x129; 2e-3 puts p99 at {p:.2f}x exact"


def c_local_test_bounds_peak(docs):
    rows = docs.rows("multigrid_local_ensemble.csv")
    exact = num(one(rows, "multigrid_local_ensemble.csv", solver="exact:method=multigrid")["max_stretch"])
    with_ = [num(r["max_stretch"]) / exact for r in rows if r["family"] == "multigrid" and "local_tolerance=0" not in r["solver"]]
    without = [num(r["max_stretch"]) / exact for r in rows if "local_tolerance=0" in r["solver"]]
    need(len(with_) == 20 and max(with_) <= 1.15, f"with the local test the peak reaches {max(with_):.2f}x exact (docs: <= 1.14x)")
    need(len(without) == 20 and max(without) > 1.5, f"without it the peak stays at {max(without):.2f}x (docs: over 1.5x)")
    return f"129x129 ensemble: peak stretch up to {max(with_):.2f}x exact with the local test, {max(without):.2f}x without"


def c_warm_start_helps(docs):
    out = []
    for n in (33, 65):
        w, z = mg(docs, "multigrid_warm_start.csv", n, "multigrid"), mg(docs, "multigrid_warm_start.csv", n, "multigrid:start=zero")
        need(num(w["solve_error"]) <= num(z["solve_error"]), f"multigrid_warm_start.csv {n}: the warm start is less accurate")
        out.append(f"{w['solve_error']} / {z['solve_error']}")
    h1 = [num(mg(docs, "multigrid_start.csv", n, "multigrid:start_history=1")["solve_error"]) for n in (17, 33, 65, 129)]
    h2 = [num(mg(docs, "multigrid_start.csv", n, "multigrid")["solve_error"]) for n in (17, 33, 65, 129)]
    need(h2[3] < h1[3], "two start vectors are not more accurate than one at 129x129")
    h3 = [num(mg(docs, "multigrid_start.csv", n, "multigrid:start_history=3")["solve_error"]) for n in (17, 33, 65, 129)]
    need(all(c >= b for b, c in zip(h2, h3)), f"three start vectors beat two somewhere: {h3} against {h2}")
    return "warm start / zero start solve error " + ", ".join(out) + f" (33, 65); two vectors {h2[3]} against one {h1[3]} at 129x129"


def c_float_cycles_stretch_more(docs):
    out = []
    for name, dbl, flt in (("multigrid_extreme_precision.csv", "cycle_precision=same", "cycle_precision=float"),
                           ("multigrid_start_extreme_precision.csv", None, "cycle_precision=float")):
        rows = [r for r in docs.rows(name) if r["case"] == "stop_10g" and r["size"] == "65" and "kcycle=0" not in r["config"]
                and "local_tolerance=0" not in r["config"]]
        def tol(c):
            for kv in c.split(":")[1].split(","):
                if kv.startswith("tolerance="):
                    return float(kv.split("=")[1])
            return 1.5e-3
        pairs = {}
        for r in rows:
            pairs.setdefault(tol(r["config"]), {})["f" if flt in r["config"] else "d"] = num(r["peak_stretch"])
        pairs = [p for p in pairs.values() if len(p) == 2]
        higher = sum(p["f"] > p["d"] for p in pairs)
        need(len(pairs) == 5 and higher >= 3 and max(p["f"] for p in pairs) > max(p["d"] for p in pairs),
             f"{name}: float cycles peak higher in {higher} of {len(pairs)} tolerances in the 10 g stop at 65x65")
        out.append(f"{name}: higher in {higher} of 5, worst {max(p['f'] for p in pairs):.2f} against {max(p['d'] for p in pairs):.2f}")
    return "float cycles stretch the stiff flag more in the 10 g stop at 65x65 (peak; " + "; ".join(out) + ")"


def c_one_cycle_not_accurate(docs):
    errs = [num(mg(docs, "multigrid_start.csv", n, "multigrid:cycles=1,krylov=none")["solve_error"]) for n in (17, 33, 65, 129)]
    need(min(errs) > 0.4 and all(stable(mg(docs, "multigrid_start.csv", n, "multigrid:cycles=1,krylov=none")) for n in (17, 33, 65, 129)),
         f"one cycle alone leaves {errs}")
    return f"one fixed cycle: stable, solve error {min(errs)}-{max(errs)}"


MULTIGRID_FINDINGS = [
    ("multigrid_default_accuracy", c_multigrid_default_accuracy),
    ("galerkin_beats_rediscretized", c_galerkin_beats_rediscretized),
    ("bend_collapse_as_accurate", c_bend_collapse_as_accurate),
    ("cg_beats_stationary_cycles", c_cg_beats_stationary_cycles),
    ("kcycle_tolerance", c_kcycle_tolerance),
    ("local_test_bounds_peak", c_local_test_bounds_peak),
    ("warm_start_helps", c_warm_start_helps),
    ("float_cycles_stretch_more", c_float_cycles_stretch_more),
    ("one_cycle_not_accurate", c_one_cycle_not_accurate),
]
