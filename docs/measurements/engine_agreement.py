#!/usr/bin/env python3
"""Randomized differential campaign: the OpenCL engine (--device pocl) against the CPU reference
(--device cpu), voxel by voxel through canvas.vtu (README, "Where the two engines differ").

Usage: python3 docs/measurements/engine_agreement.py MASTER_SEED CASES [SECONDS]
  case i draws its configuration from random.Random(MASTER_SEED * 100000 + i) and prints one line;
  python3 docs/measurements/engine_agreement.py --case CASE_SEED reruns one case and keeps its runs.
  python3 docs/measurements/engine_agreement.py --summary RESULTS [OTHER] counts a campaign's cases
  by outcome (refused alike, agree, distances, labels, other); with OTHER, a run of the same draws
  on another build, it then lists the cases whose outcome or beyond_tie_chains changed.
  python3 docs/measurements/engine_agreement.py --compare DIR compares DIR/pocl and DIR/cpu, the
  outputs of `rvor voronoi ... --vtu --device pocl|cpu --out DIR/...`, and prints the stats.
Environment: RVOR (default build/bin/rvor), CAMPAIGN_DIR (default /tmp/rvor-campaign), which holds
results.jsonl (one JSON object per case, with its command) and cases/<case seed>/{pocl,cpu}.
Each case's stats count, among others, the voxels beyond the campaign's rule (dist_unexplained,
label_unexplained: no tie within 3 voxels) and beyond the engine tests' rule (beyond_tie_chains:
no chain of differing voxels from a tie). A case's runs are kept when it has a problem.
The 2026-12-05 campaign ran master seeds 1, 2, 3 and 4 with 3, 393, 2206 and 1068 cases (3370
compared on the kernels of 60c27f9, 3402 on those of e6a5340 and again on those of the
session-41 commit that writes rises within the rounding without news).
"""
import collections
import json
import math
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import time

RVOR = os.path.abspath(os.environ.get("RVOR", "build/bin/rvor"))
WORK = os.environ.get("CAMPAIGN_DIR", "/tmp/rvor-campaign")
BASE = os.path.join(WORK, "cases")
os.environ.setdefault("POCL_CACHE_DIR", os.path.join(WORK, "pocl-cache"))


def run(args, timeout=120):
    t = time.time()
    p = subprocess.run(["nice", "-n", "10", "timeout", str(timeout), RVOR] + args,
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr, time.time() - t


def parse_vtu(path, h, origin=None):
    data = open(path, "rb").read()
    head_end = data.index(b"<AppendedData")
    head = data[:head_end].decode()
    start = data.index(b"_", head_end) + 1
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)"(?: Name="(\w+)")? NumberOfComponents="(\d+)" '
                         r'format="appended" offset="(\d+)"', head):
        typ, name, off = m.group(1), m.group(2) or "points", int(m.group(4))
        p = start + off
        nbytes = struct.unpack_from("<Q", data, p)[0]
        code = {"Float32": "f", "Int32": "i", "UInt8": "B", "Int64": "q", "Float64": "d"}[typ]
        size = struct.calcsize(code)
        arrays[name] = struct.unpack_from("<%d%s" % (nbytes // size, code), data, p + 8)
    pts = arrays["points"]
    conn = arrays["connectivity"]
    offs = arrays["offsets"]
    lab = arrays["label"]
    dist = arrays["distance"]
    cells = {}
    prev = 0
    for c, o in enumerate(offs):
        ids = conn[prev:o]
        prev = o
        n = len(ids)
        cx = sum(pts[3 * i] for i in ids) / n
        cy = sum(pts[3 * i + 1] for i in ids) / n
        cz = sum(pts[3 * i + 2] for i in ids) / n
        if origin is None:
            origin = (cx, cy, cz)
        key = (round((cx - origin[0]) / h), round((cy - origin[1]) / h), round((cz - origin[2]) / h))
        cells[key] = (dist[c], lab[c])
    return cells, origin


def read_seeds(path):
    """The points of a seeds.xyz that rvor wrote, each with 3 coordinates (z = 0 in 2D)."""
    points = [[float(v) for v in line.split()] for line in open(path) if line.strip()]
    return [tuple(p + [0.0] * (3 - len(p))) for p in points]


def load_engine_fields(folder):
    """The fields of `rvor voronoi ... --vtu --device pocl|cpu` written to FOLDER/pocl and
    FOLDER/cpu: (pocl cells, cpu cells, origin, voxel size, cpu report, seeds), cells keyed by
    voxel offsets from one origin."""
    report = json.load(open(os.path.join(folder, "cpu", "report.json")))
    h = report["voxel_size"]
    pocl, origin = parse_vtu(os.path.join(folder, "pocl", "canvas.vtu"), h)
    cpu, _ = parse_vtu(os.path.join(folder, "cpu", "canvas.vtu"), h, origin)
    return pocl, cpu, origin, h, report, read_seeds(os.path.join(folder, "cpu", "seeds.xyz"))


def uniform_tensor(text, dimension):
    """The 3x3 tensor of uniform:'s numbers (m11,m12,m22 or m11,m12,m22,m13,m23,m33)."""
    m = [float(v) for v in text.split(",")]
    if dimension == 2:
        return [[m[0], m[1], 0.0], [m[1], m[2], 0.0], [0.0, 0.0, 1.0]]
    return [[m[0], m[1], m[3]], [m[1], m[2], m[4]], [m[3], m[4], m[5]]]


def metric_distance(G, p, s):
    """|p - s| in the uniform metric G."""
    v = [p[i] - s[i] for i in range(3)]
    return math.sqrt(max(0.0, sum(v[i] * G[i][j] * v[j] for i in range(3) for j in range(3))))


# ---------------------------------------------------------------- random case generation

def rand_spd(rng, dim, aniso):
    """Random SPD tensor with eigenvalue ratio aniso^2 (length anisotropy aniso), rotated."""
    lam = [1.0] + [rng.uniform(1, aniso ** 2) for _ in range(dim - 2)] + [aniso ** 2]
    rng.shuffle(lam)
    s = rng.choice([1.0, rng.uniform(0.01, 100)])
    lam = [l * s for l in lam]
    if dim == 2:
        a = rng.uniform(0, math.pi) if rng.random() < 0.8 else 0.0
        c, si = math.cos(a), math.sin(a)
        R = [[c, -si], [si, c]]
    else:
        if rng.random() < 0.2:
            R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
        else:
            q = [rng.gauss(0, 1) for _ in range(4)]
            n = math.sqrt(sum(x * x for x in q))
            w, x, y, z = (v / n for v in q)
            R = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    M = [[sum(R[i][k] * lam[k] * R[j][k] for k in range(dim)) for j in range(dim)] for i in range(dim)]
    if dim == 2:
        vals = [M[0][0], M[0][1], M[1][1]]
    else:
        vals = [M[0][0], M[0][1], M[1][1], M[0][2], M[1][2], M[2][2]]
    return "uniform:" + ",".join("%.10g" % v for v in vals), max(lam)


def gen_domain(rng, dim):
    """Returns (domain string, sampler(rng)->point inside, bbox lo, hi, kind)."""
    kind = rng.choice(["plain", "plain", "thin", "offset", "far", "implicit", "implicit"])
    if kind == "implicit":
        if dim == 2:
            cx, cy = rng.uniform(-3, 3), rng.uniform(-3, 3)
            r = rng.uniform(0.3, 2)
            dom = "implicit:disk:center=%g,%g,r=%g" % (cx, cy, r)

            def samp(g, m=0.0):
                rr = max(r - m, r * 0.3)
                while True:
                    x, y = g.uniform(-rr, rr), g.uniform(-rr, rr)
                    if x * x + y * y < rr * rr:
                        return (cx + x, cy + y)
            return dom, samp, (cx - r, cy - r), (cx + r, cy + r), "disk"
        shape = rng.choice(["sphere", "torus", "ellipsoid"])
        c = [rng.uniform(-3, 3) for _ in range(3)]
        cs = "center=%g,%g,%g" % tuple(c)
        if shape == "sphere":
            r = rng.uniform(0.3, 2)
            dom = "implicit:sphere:%s,r=%g" % (cs, r)
            inside = lambda p, m: sum(v * v for v in p) < max(r - m, 0.3 * r) ** 2
            ext = (r, r, r)
        elif shape == "torus":
            R, r = rng.uniform(0.5, 2), 0
            r = rng.uniform(0.1, 0.5) * R
            dom = "implicit:torus:%s,R=%g,r=%g" % (cs, R, r)
            inside = lambda p, m: (math.hypot(p[0], p[1]) - R) ** 2 + p[2] ** 2 < max(r - m, 0.3 * r) ** 2
            ext = (R + r, R + r, r)
        else:
            a, b, cc = rng.uniform(0.2, 2), rng.uniform(0.2, 2), rng.uniform(0.1, 2)
            dom = "implicit:ellipsoid:%s,a=%g,b=%g,c=%g" % (cs, a, b, cc)
            inside = lambda p, m: (p[0] / max(a - m, .3 * a)) ** 2 + (p[1] / max(b - m, .3 * b)) ** 2 + (p[2] / max(cc - m, .3 * cc)) ** 2 < 1
            ext = (a, b, cc)

        def samp(g, m=0.0):
            while True:
                p = [g.uniform(-e, e) for e in ext]
                if inside(p, m):
                    return tuple(c[i] + p[i] for i in range(3))
        return dom, samp, tuple(c[i] - ext[i] for i in range(3)), tuple(c[i] + ext[i] for i in range(3)), shape
    if kind == "thin":
        if dim == 2:
            size = [rng.uniform(3, 10), rng.uniform(0.05, 0.5)]
        else:
            size = [1, rng.uniform(0.3, 1), rng.uniform(0.03, 0.1)]
        rng.shuffle(size)
        lo = [rng.uniform(-1, 1) for _ in range(dim)]
    elif kind == "far":
        lo = [rng.choice([1000, -5000, 12345.5, 1e5]) + rng.uniform(0, 10) for _ in range(dim)]
        size = [rng.uniform(0.5, 2) for _ in range(dim)]
    elif kind == "offset":
        lo = [rng.uniform(-20, 20) for _ in range(dim)]
        size = [rng.uniform(0.2, 5) for _ in range(dim)]
    else:
        lo = [-1.0] * dim
        size = [2.0] * dim
        if rng.random() < 0.5:
            size = [rng.uniform(0.5, 3) for _ in range(dim)]
            lo = [rng.uniform(-2, 0) for _ in range(dim)]
    lo = [float("%.6g" % v) for v in lo]
    hi = [float("%.6g" % (lo[i] + size[i])) for i in range(dim)]
    dom = ("rect:" if dim == 2 else "box:") + ",".join("%.10g" % v for v in lo + hi)

    def samp(g, m=0.0):
        return tuple(g.uniform(lo[i], hi[i]) for i in range(dim))
    return dom, samp, tuple(lo), tuple(hi), kind


def fmt_seeds(rng, pts, dim):
    sep = rng.choice([" ", "  ", "\t", ",", ";", ", ", "; "])
    eol = rng.choice(["\n", "\n", "\r\n"])
    three = dim == 2 and rng.random() < 0.3
    fmt = rng.choice(["%.17g", "%.8f", "%g", "%.6e"])
    lines = [sep.join(fmt % v for v in (list(p) + ([0.0] if three else []))) for p in pts]
    text = eol.join(lines) + eol
    if rng.random() < 0.3:
        text += eol * rng.randint(1, 3)  # trailing blank lines
    return text, repr((sep, eol, fmt, three))


def gen_case(case_seed):
    rng = random.Random(case_seed)
    dim = rng.choice([2, 3])
    dom, samp, lo, hi, dkind = gen_domain(rng, dim)
    ext = max(hi[i] - lo[i] for i in range(dim))
    if dim == 3:
        res = rng.choice([8, 13, 17, 23, 29, 31, 37, 45, 53, 61, 64])
    else:
        res = rng.choice([13, 37, 61, 97, 127, 131, 200, 256])
    h = ext / res
    # metric
    mk = rng.choice(["euclidean", "uniform", "uniform", "uniform", "field", "field"])
    aniso = 1.0
    if mk == "uniform":
        aniso = rng.choice([1, 1.5, 3, 10, rng.uniform(1, 50), 50])
        metric, _ = rand_spd(rng, dim, aniso)
    elif mk == "field":
        names = ["hyperbolic_shock"] + (["swirl", "starred", "unidimensional_shock"] if dim == 2 else ["radial_shock_3d"])
        metric = rng.choice(names)
    else:
        metric = "euclidean"
    if rng.random() < 0.25:
        metric += (":" if ":" not in metric else ",") + "scale=%g" % rng.choice([0.01, 0.5, 2, 100, rng.uniform(0.1, 10)])
    # fields on their natural domains half the time (replace domain)
    if mk == "field" and rng.random() < 0.5 and dkind in ("plain", "offset"):
        if "radial_shock_3d" in metric:
            lo, hi = (1.0, 1.0, 1.0), (11.0, 11.0, 11.0)
        else:
            lo, hi = (-1.0,) * dim, (1.0,) * dim
        dom = ("rect:" if dim == 2 else "box:") + ",".join("%g" % v for v in lo + hi)
        ext = 2.0 if "radial" not in metric else 10.0
        h = ext / res
        samp = lambda g, m=0.0, lo=lo, hi=hi: tuple(g.uniform(lo[i], hi[i]) for i in range(dim))
    if dkind not in ("sphere", "torus", "ellipsoid", "disk"):
        nvox = [max(1, math.floor((hi[i] - lo[i]) / h + 0.5)) for i in range(dim)]
        hi = tuple(lo[i] + nvox[i] * h * (1 - 1e-12) for i in range(dim))
        samp = lambda g, m=0.0, lo=lo, hi=hi: tuple(g.uniform(lo[i], hi[i]) for i in range(dim))
    else:
        samp0 = samp
        samp = lambda g, m=0.0: samp0(g, 1.0 * h)
    # seeds
    skind = rng.choice(["random", "random", "file", "file", "file"])
    case = dict(case_seed=case_seed, dim=dim, domain=dom, dkind=dkind, resolution=res, metric=metric,
                aniso=aniso, h=h)
    if skind == "random":
        n = rng.choice([1, 2, 5, 20, 100, 300])
        case["seed_args"] = ["--random-seeds", str(n), "--rng-seed", str(rng.randint(0, 10 ** 6))]
        case["seedkind"] = "random%d" % n
    else:
        sub = rng.choice(["one", "two", "few", "many", "boundary", "corner", "samevoxel", "symmetric"])
        if dkind in ("sphere", "torus", "ellipsoid", "disk") and sub in ("boundary", "corner", "symmetric"):
            sub = "few"
        pts = []
        if sub == "one":
            pts = [samp(rng)]
        elif sub == "two":
            pts = [samp(rng), samp(rng)]
        elif sub == "few":
            pts = [samp(rng) for _ in range(rng.randint(3, 8))]
        elif sub == "many":
            pts = [samp(rng) for _ in range(rng.randint(100, 400))]
        elif sub == "boundary":
            for _ in range(rng.randint(1, 6)):
                p = list(samp(rng))
                ax = rng.randrange(dim)
                p[ax] = rng.choice([lo[ax], hi[ax]])
                pts.append(tuple(p))
        elif sub == "corner":
            for _ in range(rng.randint(1, 4)):
                pts.append(tuple(rng.choice([lo[i], hi[i]]) for i in range(dim)))
            pts = list(dict.fromkeys(pts))
        elif sub == "samevoxel":
            p = samp(rng)
            pts = [p, tuple(v + rng.uniform(-0.2, 0.2) * h for v in p)] + [samp(rng) for _ in range(rng.randint(0, 3))]
        elif sub == "symmetric":
            c = [(lo[i] + hi[i]) / 2 for i in range(dim)]
            for _ in range(rng.randint(1, 3)):
                p = samp(rng)
                pts.append(p)
                pts.append(tuple(2 * c[i] - p[i] for i in range(dim)))
        text, style = fmt_seeds(rng, pts, dim)
        case["seed_text"] = text
        case["seedkind"] = "file-%s(%d)" % (sub, len(pts))
        case["seed_style"] = style
    return case


# ---------------------------------------------------------------- comparison

def compare(dirs):
    """The problems and stats of the pocl and cpu outputs in dirs (README, the campaign's rule)."""
    reps = [json.load(open(os.path.join(d, "report.json"))) for d in dirs]
    problems = []
    for key in ("active_voxels", "seeds", "index_box", "voxel_size", "dimension", "max_anisotropy",
                "longest_stencil_offset"):
        if reps[0].get(key) != reps[1].get(key):
            problems.append("report.%s differs: pocl %r vs cpu %r" % (key, reps[0].get(key), reps[1].get(key)))
    for key in ("empty_cells", "non_empty_cells", "reached_voxels", "unreached_voxels"):
        if reps[0]["field"].get(key) != reps[1]["field"].get(key):
            problems.append("report.field.%s differs: pocl %r vs cpu %r" % (key, reps[0]["field"].get(key), reps[1]["field"].get(key)))
    s0 = open(os.path.join(dirs[0], "seeds.xyz")).read()
    s1 = open(os.path.join(dirs[1], "seeds.xyz")).read()
    if s0 != s1:
        problems.append("seeds.xyz differ")
    h = reps[1]["voxel_size"]
    a, origin = parse_vtu(os.path.join(dirs[0], "canvas.vtu"), h)
    b, _ = parse_vtu(os.path.join(dirs[1], "canvas.vtu"), h, origin)
    if len(a) != reps[0]["active_voxels"] or len(b) != reps[1]["active_voxels"]:
        problems.append("vtu cells %d/%d vs active %d/%d" % (len(a), len(b), reps[0]["active_voxels"], reps[1]["active_voxels"]))
    if set(a) != set(b):
        problems.append("voxel sets differ: %d only pocl, %d only cpu" % (len(set(a) - set(b)), len(set(b) - set(a))))
    # floor: per label, largest reference distance within Chebyshev 1 of its seed's voxel
    seeds = read_seeds(os.path.join(dirs[1], "seeds.xyz"))
    dim = reps[1]["dimension"]
    floor = {}
    for li, s in enumerate(seeds):
        sv = [round((s[i] - origin[i]) / h) for i in range(dim)] + [0] * (3 - dim)
        best = 0.0
        rng3 = range(-1, 2)
        for dx in rng3:
            for dy in rng3:
                for dz in (rng3 if dim == 3 else [0]):
                    k = (sv[0] + dx, sv[1] + dy, sv[2] + dz)
                    if k in b and b[k][1] == li and math.isfinite(b[k][0]):
                        best = max(best, b[k][0])
        floor[li] = best
    gfloor = max([f for f in floor.values() if f > 0] or [0])
    common = set(a) & set(b)
    ties = []
    dist_bad = []
    label_bad = []
    maxrel = 0.0
    worst = None
    nonfinite = 0
    for k in common:
        da, la = a[k]
        db, lb = b[k]
        if not (math.isfinite(da) and math.isfinite(db)):
            if math.isfinite(da) != math.isfinite(db) or la != lb:
                nonfinite += 1
                dist_bad.append(k)
            continue
        f = floor.get(lb, 0) or gfloor
        den = max(abs(db), f, 1e-300)
        rel = abs(da - db) / den
        ok = rel <= 1e-4
        if la != lb:
            if ok:
                ties.append(k)
            else:
                label_bad.append(k)
        elif not ok:
            dist_bad.append(k)
        if rel > maxrel and la == lb:
            maxrel, worst = rel, (k, da, db, la, lb)

    # The voxels within 3 (Chebyshev) of a voxel whose labels differ with distances within 1e-4.
    near_ties = set()
    for t in ties:
        for dx in range(-3, 4):
            for dy in range(-3, 4):
                for dz in (range(-3, 4) if dim == 3 else [0]):
                    near_ties.add((t[0] + dx, t[1] + dy, t[2] + dz))
    near_tie = near_ties.__contains__
    dist_unexpl = [k for k in dist_bad if not near_tie(k)]
    label_unexpl = [k for k in label_bad if not near_tie(k)]
    # The engine tests' rule (expect_same_field, tests/opencl): a difference is a tie's when a chain
    # of differing voxels, steps of at most 3 voxels, leads to it from a tie.
    in_chain = set(ties)
    front = list(ties)
    differing = set(dist_bad) | set(label_bad)
    while front:
        t = front.pop()
        for dx in range(-3, 4):
            for dy in range(-3, 4):
                for dz in (range(-3, 4) if dim == 3 else [0]):
                    k = (t[0] + dx, t[1] + dy, t[2] + dz)
                    if k in differing and k not in in_chain:
                        in_chain.add(k)
                        front.append(k)
    maxrel_unexpl = 0.0
    worst_unexpl = None
    for k in dist_unexpl + label_unexpl:
        da, la = a[k]
        db, lb = b[k]
        if math.isfinite(da) and math.isfinite(db):
            f = floor.get(lb, 0) or gfloor
            rel = abs(da - db) / max(abs(db), f, 1e-300)
        else:
            rel = float("inf")
        if rel > maxrel_unexpl:
            maxrel_unexpl, worst_unexpl = rel, (k, da, db, la, lb)
    stats = dict(voxels=len(common), ties=len(ties), dist_bad=len(dist_bad), label_bad=len(label_bad),
                 dist_unexplained=len(dist_unexpl), label_unexplained=len(label_unexpl),
                 maxrel_same_label=maxrel, worst_same_label=worst, maxrel_unexplained=maxrel_unexpl,
                 worst_unexplained=worst_unexpl, beyond_tie_chains=len(differing - in_chain),
                 nonfinite_mismatch=nonfinite, floor=gfloor,
                 unreached=reps[1]["field"]["unreached_voxels"])
    if dist_unexpl or label_unexpl:
        problems.append("unexplained: %d distance, %d label mismatches (max rel %.3g)" % (
            len(dist_unexpl), len(label_unexpl), maxrel_unexpl))
    return problems, stats


def do_case(case_seed, keep=False):
    case = gen_case(case_seed)
    d = os.path.join(BASE, str(case_seed))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    args = ["voronoi", "--domain", case["domain"], "--resolution", str(case["resolution"]),
            "--metric", case["metric"], "--vtu", "--quiet", "--overwrite"]
    if "seed_text" in case:
        sf = os.path.join(d, "seeds_in.xyz")
        open(sf, "w", newline="").write(case["seed_text"])
        args += ["--seeds", sf]
    else:
        args += case["seed_args"]
    outs = [os.path.join(d, "pocl"), os.path.join(d, "cpu")]
    rcs = []
    for dev, out in zip(["pocl", "cpu"], outs):
        rc, so, se, t = run(args + ["--device", dev, "--out", out])
        rcs.append((rc, se.strip()[-500:], round(t, 2)))
    case["cmd"] = " ".join("'%s'" % x if any(c in x for c in ",;: ") else x for x in [RVOR] + args)
    case["runs"] = rcs
    case.pop("seed_text", None)
    problems = []
    stats = {}
    if rcs[0][0] != rcs[1][0]:
        problems.append("exit codes differ: pocl %d (%s) vs cpu %d (%s)" % (rcs[0][0], rcs[0][1], rcs[1][0], rcs[1][1]))
    elif rcs[0][0] in (124, 137) or rcs[0][0] < 0 or rcs[0][0] > 1:
        problems.append("both abnormal rc %d" % rcs[0][0])
    if rcs[0][0] == 0 and rcs[1][0] == 0:
        try:
            problems2, stats = compare(outs)
            problems += problems2
        except Exception:  # noqa: BLE001 (a crash of the comparison is a finding)
            import traceback
            problems.append("compare crashed: %r" % traceback.format_exc()[-600:])
    case["problems"] = problems
    case["stats"] = stats
    if not problems and not keep:
        for out in outs:
            shutil.rmtree(out, ignore_errors=True)
    os.makedirs(WORK, exist_ok=True)
    with open(os.path.join(WORK, "results.jsonl"), "a") as f:
        f.write(json.dumps(case) + "\n")
    return case


# ---------------------------------------------------------------- campaign summaries

def outcome(case):
    """refused (both engines refused alike), agree, distances (beyond the rule in distances only),
    labels (in labels too) or other (another problem: exit codes, reports, voxel sets)."""
    stats = case.get("stats")
    if not stats:
        refused = all(run[0] != 0 for run in case["runs"]) and not case["problems"]
        return "refused" if refused else "other"
    if not case["problems"]:
        return "agree"
    if stats["label_unexplained"] > 0:
        return "labels"
    if stats["dist_unexplained"] > 0 and len(case["problems"]) == 1:
        return "distances"
    return "other"


def load_results(path):
    with open(path) as f:
        return {case["case_seed"]: case for case in map(json.loads, f)}


def beyond_tie_chains(case):
    return (case.get("stats") or {}).get("beyond_tie_chains", 0)


def summarize(path):
    cases = load_results(path)
    counts = collections.Counter(outcome(case) for case in cases.values())
    beyond = sum(1 for case in cases.values() if beyond_tie_chains(case) > 0)
    unexplained = sum((case.get("stats") or {}).get("dist_unexplained", 0) for case in cases.values())
    print("%s: %d cases, %s; %d beyond the tests' rule; %d voxels beyond 1e-4 with no tie within 3"
          % (path, len(cases), ", ".join("%s %d" % kv for kv in sorted(counts.items())), beyond,
             unexplained))
    return cases


def print_changes(before, after):
    for seed in sorted(set(before) & set(after)):
        a, b = before[seed], after[seed]
        if outcome(a) != outcome(b) or beyond_tie_chains(a) != beyond_tie_chains(b):
            print("%d %s %s: %s (beyond_tie_chains %d) -> %s (%d)" % (
                seed, a["metric"][:40], a["seedkind"], outcome(a), beyond_tie_chains(a),
                outcome(b), beyond_tie_chains(b)))


if __name__ == "__main__":
    if sys.argv[1] == "--summary":
        runs = [summarize(path) for path in sys.argv[2:4]]
        if len(runs) == 2:
            print_changes(*runs)
        sys.exit(0)
    if sys.argv[1] == "--compare":
        folders = [os.path.join(sys.argv[2], engine) for engine in ("pocl", "cpu")]
        problems, stats = compare(folders)
        print(json.dumps({"problems": problems, "stats": stats}, indent=1))
        sys.exit(0)
    if sys.argv[1] == "--case":
        c = do_case(int(sys.argv[2]), keep=True)
        print(json.dumps(c, indent=1))
        sys.exit(0)
    master, n = int(sys.argv[1]), int(sys.argv[2])
    deadline = time.time() + float(sys.argv[3]) if len(sys.argv) > 3 else 1e20
    for i in range(n):
        if time.time() > deadline:
            break
        cs = master * 100000 + i
        c = do_case(cs)
        st = c["stats"]
        print("%d %dD %s res=%d %s %s rc=%s t=%s | %s | ties=%s maxrel=%.2g %s" % (
            cs, c["dim"], c["domain"], c["resolution"], c["metric"][:40], c["seedkind"],
            [r[0] for r in c["runs"]], [r[2] for r in c["runs"]],
            "; ".join(c["problems"]) or "OK", st.get("ties"), st.get("maxrel_same_label", 0) or 0,
            (c["runs"][0][1][:150] if c["runs"][0][0] else "")), flush=True)
