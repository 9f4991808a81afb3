import sys, numpy as np
from ent import *; from vol_pred import knn_pred; from common import sizes, work, levels
X = np.loadtxt(work('bunny_10k.node'), comments='#', skiprows=3)[:, 1:4]   # .node order
N = len(X); lo, hi = X.min(0), X.max(0); ext = (hi - lo).max()
rng = np.random.default_rng(13)
C = lo + rng.random((3, 3)) * (hi - lo); S = np.array([0.15, 0.25, 0.35]) * ext; A = np.array([1.0, -0.7, 0.5])
f = sum(A[i] * np.exp(-((X - C[i]) ** 2).sum(1) / (2 * S[i] ** 2)) for i in range(3)).astype(np.float32)
R = float(f.max() - f.min()); E = 1e-3 * R
q = np.rint(f.astype(np.float64) / (2 * E)).astype(np.int32)
assert np.abs(q * 2 * E - f).max() <= E * 1.0001
print(f"bunny_10k: {N} points, extent {ext:.3f}, field range {R:.4f}, E {E:.3g}, q range {q.min()}..{q.max()} ({len(np.unique(q))} distinct)")
for tag, data in (('float32', f.tobytes()), ('q int32', q.astype('<i4').tobytes())):
    s = sizes(data); print(f"  {tag} .node order:", {k: round(8 * x / N, 3) for k, x in s.items()})
# delta in .node order
d = np.diff(q.astype(np.int64), prepend=0)
print(f"  .node-order delta: H0 {H0(d):.3f} AC2 {adaptive_bits2(d):.3f}")
print(f"  q values H0 {H0(q):.3f}")

def lsq_pred(P, v, known, query, k=8):
    """local linear (plane) fit over the k nearest known points, evaluated at the query."""
    Kp = P[known]; Kv = v[known].astype(float); out = np.empty(len(query)); spr = np.empty(len(query))
    for s in range(0, len(query), 256):
        Q = P[query[s:s + 256]]
        d2 = ((Q[:, None, :] - Kp[None]) ** 2).sum(-1); nn = np.argpartition(d2, k - 1, 1)[:, :k]
        for t in range(len(Q)):
            A = np.c_[np.ones(k), Kp[nn[t]] - Q[t]]; y = Kv[nn[t]]
            w = np.linalg.lstsq(A, y, rcond=1e-6)[0]
            m = y.mean(); out[s + t] = w[0] if abs(w[0] - m) <= 2 * (y.max() - y.min()) + 1 else m
            spr[s + t] = y.max() - y.min()
    return out, spr

def run_levels(name, order, bounds, P, v, modes):
    """order: point ids coarse->fine; bounds: level boundaries in that order."""
    Po = P[order]; vo = v[order].astype(np.int64)
    for label, fn in modes:
        pred = np.zeros(len(vo)); spr = np.zeros(len(vo))
        pred[1:bounds[1]] = vo[:bounds[1] - 1]     # base level: previous value
        for L in range(1, len(bounds) - 1):
            qi = np.arange(bounds[L], bounds[L + 1]); pp, ss = fn(Po, vo, np.arange(bounds[L]), qi); pred[qi] = pp; spr[qi] = ss
        r = vo - np.rint(pred).astype(np.int64)
        fine = slice(bounds[1], None)
        print(f"  {name:28s} {label:22s} H0 {H0(r):.3f}  H|spread {Hcond(r, bucket(spr)):.3f}  AC2 {adaptive_bits2(r):.3f}  AC2|spread8 {adaptive_bits2(r, bucket(spr), 8):.3f}   (finest level only: AC2 {adaptive_bits2(r[bounds[-2]:]):.3f})", flush=True)

modes = [('kNN4 mean', lambda P, v, k, q: knn_pred(P, v, k, q, 4)),
         ('kNN8 mean', lambda P, v, k, q: knn_pred(P, v, k, q, 8)),
         ('kNN8 IDW', lambda P, v, k, q: knn_pred(P, v, k, q, 8, 'idw')),
         ('kNN8 plane fit', lambda P, v, k, q: lsq_pred(P, v, k, q, 8)),
         ('kNN12 plane fit', lambda P, v, k, q: lsq_pred(P, v, k, q, 12))]
# (a) random halving
perm = np.random.default_rng(1).permutation(N); sz = []; n = N
while n > 64: sz.append(n); n //= 2
run_levels('random halving', perm, [0, n] + sz[::-1], X, q, modes)
# (b) the codec's own levels: map decoded (quantized) points back to input ids
D = np.loadtxt(work('bunny_L0.node'), skiprows=1, comments='#')[:, 1:4]
nlev = levels('bunny')
ns = [int(open(work(f'bunny_L{L}.node')).readline().split()[0]) for L in range(nlev)][::-1]
ids = np.empty(len(D), dtype=np.int64)
for s in range(0, len(D), 512):
    ids[s:s + 512] = np.argmin(((D[s:s + 512, None] - X[None]) ** 2).sum(-1), 1)
assert len(np.unique(ids)) == N
run_levels('codec levels ' + str(ns), ids, [0] + ns, X, q, modes)
# codec levels with mesh neighbours of the finer level (mean over coarser neighbours)
def mesh_mode(Lfile_of):
    def fn(P, v, known, query):
        L = fn.L; T = np.loadtxt(Lfile_of(L), skiprows=1, dtype=np.int64)[:, 1:5]
        E = np.unique(np.concatenate([T[:, [a, b]] for a in range(4) for b in range(4) if a != b]), axis=0)
        E = E[(E[:, 0] >= query[0]) & (E[:, 0] <= query[-1]) & (E[:, 1] < query[0])]
        n = len(v); sm = np.bincount(E[:, 0], v[E[:, 1]], n); cnt = np.bincount(E[:, 0], None, n)
        mx = np.full(n, -1e18); mn = np.full(n, 1e18); np.maximum.at(mx, E[:, 0], v[E[:, 1]]); np.minimum.at(mn, E[:, 0], v[E[:, 1]])
        h = cnt[query] > 0; out = np.zeros(len(query)); spr = np.zeros(len(query))
        out[h] = sm[query[h]] / cnt[query[h]]; spr[h] = (mx - mn)[query[h]]
        if (~h).any():
            pp, ss = knn_pred(P, v, known, query[~h], 4); out[~h] = pp; spr[~h] = ss
        fn.L -= 1
        return out, spr
    return fn
mf = mesh_mode(lambda L: work(f'bunny_L{L}.ele')); mf.L = nlev - 2
run_levels('codec levels', ids, [0] + ns, X, q, [('mesh-neighbour mean', mf)])
