"""Runs the two-label prototype (voronoi.py) on named cases: python3 run_cases.py A,A-exactinit,B128-GR-x
(docs/scheme.md, "Convergence", session 39). Prints one JSON line per case, scheme and schedule:
labels differing between the schedules, points labelled by a farther seed than the exact nearest,
the worst relative error, updates and seconds. Pure Python: case A takes about a minute."""
import math, random, time, json, sys
from voronoi import *

GA = [[5.655093547, 3.945991947], [3.945991947, 4.344906453]]
c, s = math.cos(math.pi/6), math.sin(math.pi/6)
GR = [[100*c*c+s*s, 99*c*s], [99*c*s, 100*s*s+c*c]]

def caseA(init_mode="radius"):
    x0, x1, y0, y1 = -0.128596, 2.15755, -1.89078, 0.752208
    L = max(x1-x0, y1-y0); h = L/131
    nx = int(math.floor((x1-x0)/h - 0.5)) + 1
    ny = int(math.floor((y1-y0)/h - 0.5)) + 1
    return Problem(nx, ny, h, x0+h/2, y0+h/2, GA, [(0.7961052, -0.158253), (0.8163789, -0.1665257)], init_mode)

def caseB(n, G, nseeds=30, rs=12345, init_mode="radius"):
    rng = random.Random(rs)
    seeds = [(rng.uniform(-1, 1), rng.uniform(-1, 1)) for _ in range(nseeds)]
    h = 2/n
    return Problem(n, n, h, -1+h/2, -1+h/2, G, seeds, init_mode)

CASES = {
    "A": caseA,
    "A-exactinit": lambda: caseA("exact"),
    "B64-GA": lambda: caseB(64, GA),
    "B64-GR": lambda: caseB(64, GR),
    "B128-GA": lambda: caseB(128, GA),
    "B128-GR": lambda: caseB(128, GR),
    "B64-GA-x": lambda: caseB(64, GA, init_mode="exact"),
    "B64-GR-x": lambda: caseB(64, GR, init_mode="exact"),
    "B128-GA-x": lambda: caseB(128, GA, init_mode="exact"),
    "B128-GR-x": lambda: caseB(128, GR, init_mode="exact"),
}

def run_case(name, schemes):
    P = CASES[name]()
    lm = math.sqrt(lam_max(P.G))
    out = []
    print(f"# case {name}: grid {P.nx}x{P.ny} N={P.N} h={P.h:.6g} seeds={len(P.seeds)} stencil={P.stencil} frozen={len(P.init)}", flush=True)
    print(f"#   exact label counts {label_counts(type('S',(object,),{'L1':P.exact_lab})(), len(P.seeds))[:4]}...", flush=True)
    for sch in schemes:
        nlab, bandf = sch
        band = INF if bandf is None else bandf * P.h * lm
        res = {}
        for nm, f in (("WL", run_worklist), ("GS", run_gs), ("GSx", lambda P, n, b: run_gs(P, n, b, start="exact"))):
            t0 = time.time()
            S = f(P, nlab, band)
            dt = time.time() - t0
            st = stats(P, S); st["time"] = dt
            st["counts"] = label_counts(S, len(P.seeds))[:4]
            if nm != "WL": st["sets"] = S.sets
            if nlab == 2:
                st["with2"] = sum(1 for L in S.L2 if L >= 0)
            res[nm] = (S, st)
        dl, md = compare(P, res["WL"][0], res["GS"][0])
        dlx, mdx = compare(P, res["WL"][0], res["GSx"][0])
        tag = f"{nlab}lab" + ("" if nlab == 1 else (" noband" if bandf is None else f" band={bandf}h*sqrt(lmax)"))
        for nm in ("WL", "GS", "GSx"):
            st = res[nm][1]
            row = dict(case=name, scheme=tag, sched=nm, labdiff=dl if nm != "GSx" else dlx, maxreldiff=md if nm != "GSx" else mdx, **st)
            print(json.dumps(row), flush=True)
            out.append(row)
    return out

if __name__ == "__main__":
    names = sys.argv[1].split(",")
    schemes = [(1, None), (2, None), (2, 3.0)]
    if len(sys.argv) > 2:
        schemes = eval(sys.argv[2])
    for nm in names:
        run_case(nm, schemes)
