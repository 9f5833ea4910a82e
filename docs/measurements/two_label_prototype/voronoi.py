"""Prototype: per-label discrete Voronoi eikonal scheme (1 label vs 2 labels per point),
two schedules (value-ordered worklist, Gauss-Seidel sweeps). Pure Python.
"""
import heapq, math, time, sys

INF = math.inf
RTOL = 1e-12


# ---------------------------------------------------------------- Selling
def selling(D):
    a, b, c = D[0][0], D[0][1], D[1][1]
    dot = lambda u, v: u[0] * (a * v[0] + b * v[1]) + u[1] * (b * v[0] + c * v[1])
    B = [(1, 0), (0, 1), (-1, -1)]
    for _ in range(1000):
        done = True
        for i, j in ((0, 1), (0, 2), (1, 2)):
            if dot(B[i], B[j]) > 0:
                k = 3 - i - j
                bi, bj = B[i], B[j]
                B[i] = (-bi[0], -bi[1])
                B[k] = (bi[0] - bj[0], bi[1] - bj[1])
                done = False
                break
        if done:
            break
    out = []
    for i, j in ((0, 1), (0, 2), (1, 2)):
        k = 3 - i - j
        rho = -dot(B[i], B[j])
        e = (-B[k][1], B[k][0])
        out.append((rho, e))
    # verify
    R = [[0.0, 0.0], [0.0, 0.0]]
    for rho, e in out:
        assert rho >= -1e-14, rho
        for p in range(2):
            for q in range(2):
                R[p][q] += rho * e[p] * e[q]
    err = max(abs(R[p][q] - D[p][q]) for p in range(2) for q in range(2))
    assert err < 1e-12 * max(1.0, abs(a) + abs(c)), err
    return out, err


def inv2(G):
    a, b, c = G[0][0], G[0][1], G[1][1]
    det = a * c - b * b
    return [[c / det, -b / det], [-b / det, a / det]]


def lam_max(G):
    a, b, c = G[0][0], G[0][1], G[1][1]
    m = 0.5 * (a + c)
    return m + math.sqrt(0.25 * (a - c) ** 2 + b * b)


# ---------------------------------------------------------------- problem
class Problem:
    def __init__(self, nx, ny, h, ox, oy, G, seeds, init_mode="radius"):
        self.init_mode = init_mode
        self.nx, self.ny, self.h = nx, ny, h
        self.G = G
        self.seeds = seeds
        self.D = inv2(G)
        self.stencil, self.selling_err = selling(self.D)
        self.stencil = [(r, e) for r, e in self.stencil if r > 0]
        N = nx * ny
        self.N = N
        self.px = [ox + h * (idx // ny) for idx in range(N)]
        self.py = [oy + h * (idx % ny) for idx in range(N)]
        # neighbours: per point list of (rho, plus, minus, ex*h, ey*h)
        nbs = []
        for idx in range(N):
            i, j = divmod(idx, ny)
            lst = []
            for rho, (ex, ey) in self.stencil:
                ip, jp, im, jm = i + ex, j + ey, i - ex, j - ey
                p = ip * ny + jp if 0 <= ip < nx and 0 <= jp < ny else -1
                m = im * ny + jm if 0 <= im < nx and 0 <= jm < ny else -1
                lst.append((rho, p, m, ex * h, ey * h))
            nbs.append(lst)
        self.nbs = nbs
        # readers = set of stencil neighbours (symmetric stencil)
        self.readers = [[q for _, p, m, _, _ in nbs[idx] for q in (p, m) if q >= 0] for idx in range(N)]
        g00, g01, g11 = G[0][0], G[0][1], G[1][1]
        # u0 per label per point (precomputed: cheap at these sizes)
        self.u0 = []
        for (sx, sy) in seeds:
            row = []
            for idx in range(N):
                dx, dy = self.px[idx] - sx, self.py[idx] - sy
                row.append(math.sqrt(max(0.0, g00 * dx * dx + 2 * g01 * dx * dy + g11 * dy * dy)))
            self.u0.append(row)
        # exact
        self.exact = [INF] * N
        self.exact_lab = [-1] * N
        for L, row in enumerate(self.u0):
            for idx in range(N):
                if row[idx] < self.exact[idx]:
                    self.exact[idx] = row[idx]
                    self.exact_lab[idx] = L
        # frozen seed points: within 1.5 grid steps (Euclidean) of the seed
        self.init = {}  # idx -> sorted list of (u0, L)
        for L, (sx, sy) in enumerate(seeds):
            for idx in range(N):
                if math.hypot(self.px[idx] - sx, self.py[idx] - sy) <= 1.5 * h:
                    self.init.setdefault(idx, []).append((self.u0[L][idx], L))
        if init_mode == "exact":
            # frozen points carry the exact metric-nearest labels over ALL seeds
            for idx in self.init:
                self.init[idx] = [(self.u0[L][idx], L) for L in range(len(seeds))]
        for v in self.init.values():
            v.sort()

    def grad(self, L, idx):
        sx, sy = self.seeds[L]
        u = self.u0[L][idx]
        if u == 0.0:
            return None
        dx, dy = self.px[idx] - sx, self.py[idx] - sy
        G = self.G
        return ((G[0][0] * dx + G[0][1] * dy) / u, (G[1][0] * dx + G[1][1] * dy) / u)


def solve(ws, h2):
    """ws: list of (w, rho), finite w. Solve sum rho max(0,t-w)^2 = h^2."""
    ws.sort()
    A = B = C = 0.0
    n = len(ws)
    t = INF
    for m in range(n):
        w, r = ws[m]
        A += r
        B += r * w
        C += r * w * w
        disc = B * B - A * (C - h2)
        if disc < 0:
            disc = 0.0
        t = (B + math.sqrt(disc)) / A
        if m + 1 == n or t <= ws[m + 1][0]:
            break
    return t


def candidate(P, idx, M, getval):
    """candidate_M(idx); getval(q, M) returns the label-M value carried by q or INF."""
    u0M = P.u0[M]
    u0x = u0M[idx]
    g = P.grad(M, idx)
    ws = []
    for rho, p, m, ehx, ehy in P.nbs[idx]:
        best = INF
        if p >= 0:
            v = getval(p, M)
            if v < INF:
                if g is not None:
                    v = v + u0x - u0M[p] + (g[0] * ehx + g[1] * ehy)
                best = v
        if m >= 0:
            v = getval(m, M)
            if v < INF:
                if g is not None:
                    v = v + u0x - u0M[m] - (g[0] * ehx + g[1] * ehy)
                if v < best:
                    best = v
        if best < INF:
            ws.append((best, rho))
    if not ws:
        return INF
    return solve(ws, P.h * P.h)


def changed(a, b):
    if a == b:
        return False
    if a == INF or b == INF:
        return True
    return abs(a - b) > RTOL * max(abs(a), abs(b))


# ---------------------------------------------------------------- state
class State:
    """nlab = 1 or 2 pairs per point."""

    def __init__(self, P, nlab, band=INF, start="inf"):
        self.P, self.nlab, self.band = P, nlab, band
        N = P.N
        self.u1 = [INF] * N
        self.L1 = [-1] * N
        self.u2 = [INF] * N
        self.L2 = [-1] * N
        if isinstance(start, tuple) and start[0] in ("random", "second"):
            # adversarial valid starts: each point carries a random / the second-nearest seed with its exact u0
            import random as _r
            rng = _r.Random(start[1])
            for idx in range(N):
                l = sorted((P.u0[L][idx], L) for L in range(len(P.seeds)))
                if start[0] == "second":
                    a = l[1]; b = l[2] if len(l) > 2 else (INF, -1)
                else:
                    a, b = rng.sample(l, 2)
                    if b < a: a, b = b, a
                self.u1[idx], self.L1[idx] = a
                if nlab == 2:
                    self.u2[idx], self.L2[idx] = b
        if start == "exact":  # exact nearest (and second nearest) pairs everywhere
            for idx in range(N):
                l = sorted((P.u0[L][idx], L) for L in range(len(P.seeds)))
                self.u1[idx], self.L1[idx] = l[0]
                if nlab == 2 and len(l) > 1 and l[1][0] <= l[0][0] + band:
                    self.u2[idx], self.L2[idx] = l[1]
        self.frozen = [False] * N
        for idx, lst in P.init.items():
            self.frozen[idx] = True
            self.u2[idx], self.L2[idx] = INF, -1
            self.u1[idx], self.L1[idx] = lst[0]
            if nlab == 2 and len(lst) > 1 and lst[1][0] <= lst[0][0] + band:
                self.u2[idx], self.L2[idx] = lst[1]
        self.updates = 0

    def getval(self, q, M):
        if self.L1[q] == M:
            return self.u1[q]
        if self.L2[q] == M:
            return self.u2[q]
        return INF

    def recompute(self, idx):
        """Recompute idx; return (changed?, key)."""
        P = self.P
        self.updates += 1
        labs = set()
        L1, L2 = self.L1, self.L2
        for q in P.readers[idx]:
            if L1[q] >= 0:
                labs.add(L1[q])
            if L2[q] >= 0:
                labs.add(L2[q])
        cands = []
        gv = self.getval
        for M in labs:
            t = candidate(P, idx, M, gv)
            if t < INF:
                cands.append((t, M))
        if getattr(self, "minonly", False):  # variant: never increase (keep old pairs in the pool)
            cands.append((self.u1[idx], self.L1[idx]))
            cands.append((self.u2[idx], self.L2[idx]))
            best = {}
            for t, M in cands:
                if M >= 0 and t < best.get(M, INF):
                    best[M] = t
            cands = [(t, M) for M, t in best.items()]
        cands.sort()
        n1 = cands[0] if cands else (INF, -1)
        n2 = (INF, -1)
        if self.nlab == 2 and len(cands) > 1 and cands[1][0] <= n1[0] + self.band:
            n2 = cands[1]
        ch1 = changed(self.u1[idx], n1[0]) or self.L1[idx] != n1[1]
        ch2 = changed(self.u2[idx], n2[0]) or self.L2[idx] != n2[1]
        if not (ch1 or ch2):
            return False, None
        key = min(n1[0], self.u1[idx]) if ch1 else min(n2[0], self.u2[idx])
        self.u1[idx], self.L1[idx] = n1
        self.u2[idx], self.L2[idx] = n2
        return True, key


def run_worklist(P, nlab, band=INF, max_updates=50_000_000, minonly=False):
    S = State(P, nlab, band)
    S.minonly = minonly
    ver = [0] * P.N
    heap = [(S.u1[idx], 0, idx) for idx in P.init]
    heapq.heapify(heap)
    frozen = S.frozen
    while heap:
        key, v, idx = heapq.heappop(heap)
        if v != ver[idx]:
            continue
        for r in P.readers[idx]:
            if frozen[r]:
                continue
            ch, k = S.recompute(r)
            if ch:
                ver[r] += 1
                heapq.heappush(heap, (k, ver[r], r))
        if S.updates > max_updates:
            raise RuntimeError("worklist did not converge")
    return S


def run_gs(P, nlab, band=INF, max_sets=10000, start="inf", minonly=False):
    S = State(P, nlab, band, start)
    S.minonly = minonly
    nx, ny = P.nx, P.ny
    orders = []
    for di, dj in ((1, 1), (-1, 1), (1, -1), (-1, -1)):
        I = range(nx) if di > 0 else range(nx - 1, -1, -1)
        J = range(ny) if dj > 0 else range(ny - 1, -1, -1)
        orders.append([i * ny + j for j in J for i in I if not S.frozen[i * ny + j]])
    sets = 0
    while True:
        sets += 1
        any_ch = False
        for od in orders:
            for idx in od:
                ch, _ = S.recompute(idx)
                any_ch = any_ch or ch
        if not any_ch or sets >= max_sets:
            break
    S.sets = sets
    return S


# ---------------------------------------------------------------- metrics
def stats(P, S):
    wrong = 0
    maxrel = 0.0
    unreached = 0
    for idx in range(P.N):
        if S.L1[idx] < 0:
            unreached += 1
            continue
        if S.L1[idx] != P.exact_lab[idx] and P.u0[S.L1[idx]][idx] > P.exact[idx]:
            wrong += 1
        ex = P.exact[idx]
        if ex > 0:
            maxrel = max(maxrel, abs(S.u1[idx] - ex) / ex)
    maxrel_far = 0.0
    for idx in range(P.N):
        if S.L1[idx] < 0 or P.exact[idx] == 0:
            continue
        if min(math.hypot(P.px[idx] - sx, P.py[idx] - sy) for sx, sy in P.seeds) > 3 * P.h:
            maxrel_far = max(maxrel_far, abs(S.u1[idx] - P.exact[idx]) / P.exact[idx])
    return dict(wrong=wrong, maxrel=maxrel, maxrel_far=maxrel_far, unreached=unreached, updates=S.updates)


def compare(P, Sa, Sb):
    dl = sum(1 for idx in range(P.N) if Sa.L1[idx] != Sb.L1[idx])
    md = 0.0
    for idx in range(P.N):
        a, b = Sa.u1[idx], Sb.u1[idx]
        if a == b:
            continue
        if a == INF or b == INF:
            md = INF
            continue
        md = max(md, abs(a - b) / max(abs(a), abs(b)))
    return dl, md


def label_counts(S, nl):
    c = [0] * nl
    for L in S.L1:
        if L >= 0:
            c[L] += 1
    return c
