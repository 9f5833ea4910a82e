#!/usr/bin/env python3
"""Whether each engine's field is a fixed point of the scheme (docs/scheme.md, "Local update"),
evaluated again here in double: 2D, a uniform metric (alpha = 1), voxels more than 3 voxels from
every seed's voxel (outside the frozen blocks, where the offset weight beta is 1).

Usage: python3 docs/measurements/fixed_point_check.py DIR m11,m12,m22
  DIR holds pocl/ and cpu/, the outputs of `rvor voronoi ... --vtu --device pocl|cpu --out DIR/...`
  on a rect: domain under that uniform metric.
Prints, per engine, how many voxels one more update would give another label, and the largest
relative change of the others' values (float rounding for the OpenCL field): 0 and ~1e-7 mean
the field is a fixed point.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "two_label_prototype")]
from engine_agreement import load_engine_fields, uniform_tensor  # noqa: E402
from voronoi import selling, solve  # noqa: E402 (the prototype's Selling terms and sorted solve)


def main():
    pocl, cpu, origin, h, _, seeds = load_engine_fields(sys.argv[1])
    G = uniform_tensor(sys.argv[2], 2)
    det = G[0][0] * G[1][1] - G[0][1] * G[0][1]
    terms, _ = selling([[G[1][1] / det, -G[0][1] / det], [-G[0][1] / det, G[0][0] / det]])
    stencil = [(r, e) for r, e in terms if r > 0]
    position = lambda k: (origin[0] + k[0] * h, origin[1] + k[1] * h)

    def seed_terms(label, p):
        dx, dy = p[0] - seeds[label][0], p[1] - seeds[label][1]
        gq = (G[0][0] * dx + G[0][1] * dy, G[1][0] * dx + G[1][1] * dy)
        return math.sqrt(max(0.0, dx * gq[0] + dy * gq[1])), gq

    def update(field, k):
        p = position(k)
        labels = sorted({field[y][1] for r, e in stencil for s in (1, -1)
                         for y in [(k[0] + s * e[0], k[1] + s * e[1], k[2])]
                         if y in field and field[y][1] >= 0})
        best = (math.inf, -1)
        for label in labels:
            ux, gq = seed_terms(label, p)
            ws, floor = [], math.inf
            for r, e in stencil:
                w = math.inf
                for s in (1, -1):
                    y = (k[0] + s * e[0], k[1] + s * e[1], k[2])
                    if y not in field or field[y][1] != label:
                        continue
                    v = field[y][0]
                    floor = min(floor, v)
                    uy = seed_terms(label, position(y))[0]
                    slope = s * h * (e[0] * gq[0] + e[1] * gq[1]) / ux if ux > 0 else 0.0
                    w = min(w, v + (ux - uy + slope if ux > 0 else 0.0))
                if w < math.inf:
                    ws.append((w, r))
            if ws:
                best = min(best, (max(solve(ws, h * h), floor), label))
        return best

    seed_voxels = [min(cpu, key=lambda k: (position(k)[0] - s[0]) ** 2 + (position(k)[1] - s[1]) ** 2)
                   for s in seeds]
    for name, field in (("pocl", pocl), ("cpu", cpu)):
        checked = relabelled = 0
        worst = 0.0
        for k, (u, label) in field.items():
            if any(max(abs(k[0] - s[0]), abs(k[1] - s[1])) <= 3 for s in seed_voxels):
                continue
            t, new_label = update(field, k)
            checked += 1
            if new_label != label:
                relabelled += 1
            elif math.isfinite(u):
                worst = max(worst, abs(t - u) / u)
        print("%s: %d voxels checked, %d would take another label, values within %.2g relative"
              % (name, checked, relabelled, worst))


if __name__ == "__main__":
    main()
