import sys
from voronoi import *
from run_cases import CASES
for name in sys.argv[1].split(","):
    P = CASES[name]()
    for nlab in (1, 2):
        a = run_worklist(P, nlab, minonly=True); b = run_gs(P, nlab, minonly=True)
        dl, md = compare(P, a, b)
        print(name, nlab, "MIN-ONLY: labdiff", dl, "maxreldiff %.3g" % md, "wrong WL/GS", stats(P, a)["wrong"], stats(P, b)["wrong"],
              "counts", label_counts(a, len(P.seeds))[:2], label_counts(b, len(P.seeds))[:2], "updates", a.updates, b.updates, flush=True)
