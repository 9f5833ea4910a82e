#!/usr/bin/env python3
"""Accuracy at the seeds' initialisation blocks under a varying metric, against a finer solve
(docs/scheme.md, "Initialisation": claims).

Usage: python3 docs/measurements/block_accuracy.py [RVOR_BINARY [RESOLUTION [SEEDS [METRIC]]]]
(defaults: build/bin/rvor, 128, 400, swirl). Solves rect:-1,-1,1,1 at RESOLUTION with SEEDS random
seeds (--rng-seed 2, the CPU reference), then the same seeds at 3 x RESOLUTION, whose voxel centres
include the coarse ones, and compares the distances and labels at the coarse voxel centres: over
the voxels of the seeds' 5 x 5 blocks and over the whole field.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

rvor = sys.argv[1] if len(sys.argv) > 1 else "build/bin/rvor"
n = int(sys.argv[2]) if len(sys.argv) > 2 else 128
count = sys.argv[3] if len(sys.argv) > 3 else "400"
metric = sys.argv[4] if len(sys.argv) > 4 else "swirl"
h = 2 / n


def solve(resolution, seeds_args, probes, out):
    subprocess.run([rvor, "voronoi", "--domain", "rect:-1,-1,1,1", "--metric", metric,
                    "--resolution", str(resolution), "--device", "cpu", "--probe", probes,
                    "--out", out, "--quiet"] + seeds_args, check=True)
    return np.loadtxt(os.path.join(out, "probe.csv"), delimiter=",", skiprows=1)


with tempfile.TemporaryDirectory() as work:
    c = -1 + (np.arange(n) + 0.5) * h
    X = np.stack(np.meshgrid(c, c, indexing="ij"), -1).reshape(-1, 2)
    probes = os.path.join(work, "probes.xyz")
    np.savetxt(probes, X, fmt="%.9f")
    coarse = solve(n, ["--random-seeds", count, "--rng-seed", "2"], probes,
                   os.path.join(work, "coarse"))
    seeds_file = os.path.join(work, "coarse", "seeds.xyz")
    fine = solve(3 * n, ["--seeds", seeds_file], probes, os.path.join(work, "fine"))
    seeds = np.loadtxt(seeds_file).reshape(-1, 2)

voxel = np.floor((X + 1) / h).astype(int)
in_block = np.zeros(len(X), bool)
for s in np.floor((seeds + 1) / h).astype(int):
    in_block |= np.abs(voxel - s).max(1) <= 2
error = np.abs(coarse[:, 3] - fine[:, 3]) / np.maximum(fine[:, 3], 1e-12)
relabelled = coarse[:, 4] != fine[:, 4]
print(f"{metric} {n}^2 against {3 * n}^2, {len(seeds)} seeds")
for name, mask in [("block voxels", in_block), ("whole field", np.ones(len(X), bool))]:
    print(f"  {name}: {mask.sum()} voxels, mean relative error {error[mask].mean():.3f}, worst "
          f"{error[mask].max():.3f}, {relabelled[mask].sum()} labelled differently")
