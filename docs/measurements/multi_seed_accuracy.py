#!/usr/bin/env python3
"""Accuracy of a solved field with several seeds under a uniform metric G, against the exact
nearest-seed distance min_s |x - s|_G at every voxel centre (README, "How accurate, how fast").

Usage: python3 docs/measurements/multi_seed_accuracy.py [RVOR_BINARY [RESOLUTION [SEEDS [METRIC
[DEVICE]]]]] (defaults: build/bin/rvor, 48, 20, euclidean, pocl). METRIC is a 3D rvor metric
spec, euclidean or uniform:m11,m12,m22,m13,m23,m33. Prints the share of voxels whose distance is
off by more than 1e-4 relative, the worst relative error, how many are labelled with another seed
than the nearest (and by how much farther that seed is, in voxel lengths), split by the voxels'
distance to the nearest label boundary or the canvas's boundary.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

rvor = sys.argv[1] if len(sys.argv) > 1 else "build/bin/rvor"
n = int(sys.argv[2]) if len(sys.argv) > 2 else 48
count = int(sys.argv[3]) if len(sys.argv) > 3 else 20
metric = sys.argv[4] if len(sys.argv) > 4 else "euclidean"
device = sys.argv[5] if len(sys.argv) > 5 else "pocl"
h = 2 / n
if metric == "euclidean":
    G = np.eye(3)
else:
    m = [float(v) for v in metric.split(":")[1].split(",")]
    G = np.array([[m[0], m[1], m[3]], [m[1], m[2], m[4]], [m[3], m[4], m[5]]])

with tempfile.TemporaryDirectory() as work:
    c = -1 + (np.arange(n) + 0.5) * h
    X = np.stack(np.meshgrid(c, c, c, indexing="ij"), -1).reshape(-1, 3)
    points = os.path.join(work, "all.xyz")
    np.savetxt(points, X, fmt="%.9f")
    out = os.path.join(work, "out")
    subprocess.run([rvor, "voronoi", "--domain", "box:-1,-1,-1,1,1,1", "--resolution", str(n),
                    "--metric", metric, "--random-seeds", str(count), "--rng-seed", "5",
                    "--device", device, "--probe", points, "--out", out, "--quiet"], check=True)
    seeds = np.loadtxt(os.path.join(out, "seeds.xyz")).reshape(-1, 3)
    probe = np.loadtxt(os.path.join(out, "probe.csv"), delimiter=",", skiprows=1)

distance, label = probe[:, 3], probe[:, 4].astype(int)
diff = X[:, None, :] - seeds[None, :, :]
exact_all = np.sqrt(np.einsum("psi,ij,psj->ps", diff, G, diff))
exact = exact_all.min(1)
nearest = exact_all.argmin(1)
own = exact_all[np.arange(len(X)), label]
step = h * np.sqrt(np.linalg.eigvalsh(G).max())
error = np.abs(distance - exact) / np.maximum(exact, step)
lab = label.reshape(n, n, n)
# Chebyshev distance (capped at 5) to a voxel of another label or outside the canvas (label -1):
# the scheme's one-sided updates at both kinds of boundary are where its errors are.
padded = np.pad(lab, 4, constant_values=-1)
boundary = np.full(lab.shape, 99)
for r in range(4, 0, -1):
    near = np.zeros(lab.shape, bool)
    for d in np.ndindex(2 * r + 1, 2 * r + 1, 2 * r + 1):
        o = 4 + np.array(d) - r
        near |= padded[o[0]:o[0] + n, o[1]:o[1] + n, o[2]:o[2] + n] != lab
    boundary[near] = r
boundary = boundary.reshape(-1)
print(f"{metric} {n}^3, {count} seeds, {device}: {len(X)} voxels")
for name, mask in [("all", np.ones(len(X), bool)),
                   ("within 1 voxel of a label boundary or the domain's", boundary <= 1),
                   ("2-4 voxels from one", (boundary >= 2) & (boundary <= 4)),
                   ("farther", boundary > 4)]:
    e = error[mask]
    wrong = mask & (label != nearest)
    print(f"  {name}: {mask.sum()} voxels, {100 * (e > 1e-4).mean():.2f}% beyond 1e-4, worst "
          f"{e.max():.3g}; {wrong.sum()} ({100 * wrong.sum() / len(X):.1f}% of all voxels) "
          f"labelled by another seed than the nearest, up to "
          f"{((own - exact)[wrong].max() / step if wrong.any() else 0):.2f} voxel lengths farther")
