#!/usr/bin/env python3
"""Both engines' fields of one uniform-metric case against the exact distances: how many voxels each
labels by a seed farther than the exact nearest, and at the voxels where their labels differ, the
worst relative error of each against the exact nearest distance.

Usage: python3 docs/measurements/engine_agreement_exact.py DIR M
  DIR holds pocl/ and cpu/, the outputs of `rvor voronoi ... --vtu --device pocl|cpu --out DIR/...`;
  M the metric's tensor as given to uniform: (m11,m12,m22 or m11,m12,m22,m13,m23,m33).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import engine_agreement as difftest  # noqa: E402
d = sys.argv[1]; m = [float(x) for x in sys.argv[2].split(",")]
rep = json.load(open(d + "/cpu/report.json")); h = rep["voxel_size"]; dim = rep["dimension"]
G = [[m[0], m[1], 0], [m[1], m[2], 0], [0, 0, 1]] if dim == 2 else [[m[0], m[1], m[3]], [m[1], m[2], m[4]], [m[3], m[4], m[5]]]
def dist(p, s):
    v = [p[i] - s[i] for i in range(3)]
    return math.sqrt(max(0, sum(v[i] * G[i][j] * v[j] for i in range(3) for j in range(3))))
a, o = difftest.parse_vtu(d + "/pocl/canvas.vtu", h); b, _ = difftest.parse_vtu(d + "/cpu/canvas.vtu", h, o)
S = [tuple(list(map(float, l.split())) + [0.0] * (3 - len(l.split()))) for l in open(d + "/cpu/seeds.xyz") if l.strip()]
wrong = {"pocl": 0, "cpu": 0}; err = {"pocl": 0.0, "cpu": 0.0}; n = 0
for k in b:
    p = [o[i] + k[i] * h for i in range(3)]
    ex = min((dist(p, s), i) for i, s in enumerate(S))
    for name, f in (("pocl", a), ("cpu", b)):
        if f[k][1] != ex[1] and dist(p, S[f[k][1]]) > ex[0] * (1 + 1e-6): wrong[name] += 1
    if a[k][1] != b[k][1]:
        n += 1
        for name, f in (("pocl", a), ("cpu", b)):
            err[name] = max(err[name], abs(f[k][0] - ex[0]) / ex[0])
print("voxels", len(b), "label mismatches", n, "voxels not labelled by an exactly nearest seed:", wrong, "worst error vs exact at mismatches:", err)
