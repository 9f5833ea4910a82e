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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from engine_agreement import load_engine_fields, uniform_tensor  # noqa: E402


def selling_2d(D):
    """Terms (rho, e) of D = sum rho e e^T from an obtuse superbase (Selling's algorithm)."""
    dot = lambda u, v: u[0] * (D[0][0] * v[0] + D[0][1] * v[1]) + u[1] * (D[0][1] * v[0] + D[1][1] * v[1])
    b = [(1, 0), (0, 1), (-1, -1)]
    changed = True
    while changed:
        changed = False
        for i, j in ((0, 1), (0, 2), (1, 2)):
            if dot(b[i], b[j]) > 0:
                k = 3 - i - j
                b[k] = (b[i][0] - b[j][0], b[i][1] - b[j][1])
                b[i] = (-b[i][0], -b[i][1])
                changed = True
                break
    terms = []
    for i, j in ((0, 1), (0, 2), (1, 2)):
        k = 3 - i - j
        terms.append((-dot(b[i], b[j]), (-b[k][1], b[k][0])))
    return [(r, e) for r, e in terms if r > 0]


def solve_sorted(ws, h2):
    ws.sort()
    a = b = c = 0.0
    for m, (w, r) in enumerate(ws):
        a += r
        b += r * w
        c += r * w * w
        t = (b + math.sqrt(max(0.0, b * b - a * (c - h2)))) / a
        if m + 1 == len(ws) or t <= ws[m + 1][0]:
            return t
    return math.inf


def main():
    pocl, cpu, origin, h, _, seeds = load_engine_fields(sys.argv[1])
    G = uniform_tensor(sys.argv[2], 2)
    det = G[0][0] * G[1][1] - G[0][1] * G[0][1]
    stencil = selling_2d([[G[1][1] / det, -G[0][1] / det], [-G[0][1] / det, G[0][0] / det]])
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
                best = min(best, (max(solve_sorted(ws, h * h), floor), label))
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
