#!/usr/bin/env python3
"""Distinct neighbour labels per voxel of a solved euclidean field, and the label passes a vector
visit needs when its 8 lanes are 8 bricks in lockstep (brick_lanes) or 8 voxels of one brick's
diagonal plane (docs/scheme.md, "Lanes from one brick instead of eight").

Usage: python3 docs/measurements/label_groups.py [RVOR_BINARY [RESOLUTION [SEEDS]]]
(defaults: build/bin/rvor, 128, 125). Solves with `rvor voronoi --probe` at every voxel centre.
"""
import os
import random
import subprocess
import sys
import tempfile

rvor = sys.argv[1] if len(sys.argv) > 1 else "build/bin/rvor"
n = int(sys.argv[2]) if len(sys.argv) > 2 else 128
seeds = int(sys.argv[3]) if len(sys.argv) > 3 else 125
h = 2 / n


def idx(i, j, k):
    return (i * n + j) * n + k


with tempfile.TemporaryDirectory() as work:
    points = os.path.join(work, "all.xyz")
    centre = ["%.6f" % (-1 + (i + 0.5) * h) for i in range(n)]
    with open(points, "w") as f:
        for i in range(n):
            for j in range(n):
                f.write("".join(f"{centre[i]} {centre[j]} {centre[k]}\n" for k in range(n)))
    out = os.path.join(work, "out")
    subprocess.run([rvor, "voronoi", "--domain", "box:-1,-1,-1,1,1,1", "--resolution", str(n),
                    "--random-seeds", str(seeds), "--probe", points, "--out", out, "--quiet"],
                   check=True)
    label = [0] * (n * n * n)
    with open(os.path.join(out, "probe.csv")) as f:
        next(f)
        for line in f:
            x, y, z, _, l = line.split(",")
            i, j, k = (int(round((float(v) + 1) / h - 0.5)) for v in (x, y, z))
            label[idx(i, j, k)] = int(l)


def distinct_neighbour_labels(i, j, k):
    found = set()
    for di, dj, dk in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)):
        a, b, c = i + di, j + dj, k + dk
        if 0 <= a < n and 0 <= b < n and 0 <= c < n:
            found.add(label[idx(a, b, c)])
    return len(found)


count = [distinct_neighbour_labels(i, j, k) for i in range(n) for j in range(n) for k in range(n)]
bricks = [(bi, bj, bk) for bi in range(n // 8) for bj in range(n // 8) for bk in range(n // 8)]
random.seed(1)
lockstep = []  # 8 random bricks visited at the same local position
for _ in range(2000):
    group = random.sample(bricks, 8)
    for _ in range(8):
        x, y, z = random.randrange(8), random.randrange(8), random.randrange(8)
        lockstep.append(max(count[idx(bi * 8 + x, bj * 8 + y, bk * 8 + z)] for bi, bj, bk in group))
plane_passes = plane_vectors = plane_voxels = 0  # consecutive groups of 8 in a diagonal plane
for bi, bj, bk in bricks:
    for s in range(22):
        members = [(x, y, s - x - y) for x in range(8) for y in range(8) if 0 <= s - x - y < 8]
        for g in range(0, len(members), 8):
            group = members[g:g + 8]
            plane_passes += max(count[idx(bi * 8 + x, bj * 8 + y, bk * 8 + z)] for x, y, z in group)
            plane_vectors += 1
            plane_voxels += len(group)
lock = sum(lockstep) / len(lockstep)
print("distinct neighbour labels per voxel: %.3f" % (sum(count) / len(count)))
print("8 bricks in lockstep: %.3f passes per vector of 8 voxels (%.3f per voxel)" % (lock, lock / 8))
print("one brick's diagonal planes: %.3f passes per vector of %.2f voxels (%.3f per voxel)"
      % (plane_passes / plane_vectors, plane_voxels / plane_vectors, plane_passes / plane_voxels))
