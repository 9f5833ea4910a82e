#!/usr/bin/env python3
"""Both engines' fields of one uniform-metric case against the exact distances: how many voxels each
labels by a seed farther than the exact nearest, and at the voxels where their labels differ, the
worst relative error of each against the exact nearest distance.

Usage: python3 docs/measurements/engine_agreement_exact.py DIR M
  DIR holds pocl/ and cpu/, the outputs of `rvor voronoi ... --vtu --device pocl|cpu --out DIR/...`;
  M the tensor as given to uniform: (m11,m12,m22 or m11,m12,m22,m13,m23,m33).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from engine_agreement import load_engine_fields, metric_distance, uniform_tensor  # noqa: E402

pocl, cpu, origin, h, report, seeds = load_engine_fields(sys.argv[1])
G = uniform_tensor(sys.argv[2], report["dimension"])
wrong = {"pocl": 0, "cpu": 0}
error = {"pocl": 0.0, "cpu": 0.0}
differing = 0
for k in cpu:
    p = [origin[i] + k[i] * h for i in range(3)]
    nearest = min((metric_distance(G, p, s), i) for i, s in enumerate(seeds))
    for name, field in (("pocl", pocl), ("cpu", cpu)):
        label = field[k][1]
        if label != nearest[1] and metric_distance(G, p, seeds[label]) > nearest[0] * (1 + 1e-6):
            wrong[name] += 1
    if pocl[k][1] != cpu[k][1]:
        differing += 1
        for name, field in (("pocl", pocl), ("cpu", cpu)):
            error[name] = max(error[name], abs(field[k][0] - nearest[0]) / nearest[0])
print("voxels", len(cpu), "labelled differently", differing,
      "labelled by a farther seed than the exact nearest:", wrong,
      "worst relative error against the exact distance where the labels differ:", error)
