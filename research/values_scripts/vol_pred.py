import itertools, numpy as np
from ent import *

OFFS = np.array([o for o in itertools.product((-1, 0, 1), repeat=3) if o != (0, 0, 0)])  # (dk,dj,di)

def knn_pred(P, v, known_idx, query_idx, k=4, mode='mean'):
    """Predict v[query] from the k nearest points of known (Euclidean on lattice coords)."""
    Kp = P[known_idx].astype(np.float64); Kv = v[known_idx].astype(np.float64)
    pred = np.empty(len(query_idx)); spread = np.empty(len(query_idx))
    kk = min(k, len(known_idx))
    for s in range(0, len(query_idx), 512):
        q = P[query_idx[s:s + 512]].astype(np.float64)
        d2 = ((q[:, None, :] - Kp[None, :, :]) ** 2).sum(-1)
        nn = np.argpartition(d2, kk - 1, axis=1)[:, :kk] if kk < len(known_idx) else np.tile(np.arange(kk), (len(q), 1))
        vals = Kv[nn]; dd = np.take_along_axis(d2, nn, 1)
        if mode == 'idw':
            w = 1.0 / np.maximum(dd, 1e-12); pred[s:s + 512] = (w * vals).sum(1) / w.sum(1)
        elif mode == 'median':
            pred[s:s + 512] = np.median(vals, 1)
        else:
            pred[s:s + 512] = vals.mean(1)
        spread[s:s + 512] = vals.max(1) - vals.min(1)
    return pred, spread

def dyadic_passes(P, Lmax):
    """Passes coarsest first: level l = largest l with all coords % 2^l == 0 (capped Lmax);
    within a level, sub-passes by number of odd coords at that scale: 3 (body), 2 (face), 1 (edge)."""
    lev = np.full(len(P), Lmax)
    for l in range(Lmax - 1, -1, -1):
        lev[np.any(P % (1 << (l + 1)) != 0, axis=1)] = l
    passes = [(Lmax, np.nonzero(lev == Lmax)[0])]
    for l in range(Lmax - 1, -1, -1):
        odd = ((P >> l) & 1).sum(1)
        for n in (3, 2, 1):
            idx = np.nonzero((lev == l) & (odd == n))[0]
            if len(idx): passes.append((l, idx))
    return passes

def dyadic_pred(shape, P, v, Lmax, knn_fallback=True):
    """Each pass predicted from the mean of its known 26-neighbours at scale 2^l;
    coarsest pass: raster predecessor; no known lattice neighbour: mean of 4 nearest known."""
    idmap = -np.ones(shape, dtype=np.int64); idmap[P[:, 0], P[:, 1], P[:, 2]] = np.arange(len(P))
    passno = np.full(len(P), 1 << 30)
    passes = dyadic_passes(P, Lmax)
    pred = np.zeros(len(P)); spread = np.zeros(len(P)); nfall = 0
    for pi, (l, idx) in enumerate(passes):
        if pi == 0:
            o = idx[np.lexsort(P[idx].T[::-1])]
            pred[o[1:]] = v[o[:-1]]; pred[o[0]] = v[o[0]]; spread[o] = 0
        else:
            s = 1 << l; sm = np.zeros(len(idx)); cnt = np.zeros(len(idx)); mx = np.full(len(idx), -1e18); mn = np.full(len(idx), 1e18)
            for off in OFFS:
                q = P[idx] + off * s
                ok = np.all((q >= 0) & (q < np.array(shape)), axis=1)
                nb = np.full(len(idx), -1); nb[ok] = idmap[q[ok, 0], q[ok, 1], q[ok, 2]]
                ok &= nb >= 0
                ok[ok] = passno[nb[ok]] < pi
                val = v[nb[ok]]
                sm[ok] += val; cnt[ok] += 1; mx[ok] = np.maximum(mx[ok], val); mn[ok] = np.minimum(mn[ok], val)
            have = cnt > 0
            pred[idx[have]] = sm[have] / cnt[have]; spread[idx[have]] = mx[have] - mn[have]
            if (~have).any():
                nfall += (~have).sum()
                known = np.nonzero(passno < pi)[0]
                pp, ss = knn_pred(P, v, known, idx[~have], 4)
                pred[idx[~have]] = pp; spread[idx[~have]] = ss
        passno[idx] = pi
    return np.rint(pred).astype(np.int64), spread, nfall, len(passes)

def causal_pred(shape, P, v):
    """Raster-order (x fastest) causal predictors on a (possibly sparse) lattice point set.
    a=(i-1), b=(j-1), c=(j-1,i-1), d=(k-1) and the previous slice's a',b',c'; a missing one
    falls back to the same direction at distance 2, then to the mean of the causal 26-neighbours
    (Chebyshev 1, then 2), then to the raster predecessor."""
    N = len(P)
    idmap = -np.ones(shape, dtype=np.int64); idmap[P[:, 0], P[:, 1], P[:, 2]] = np.arange(N)
    ras = np.lexsort(P.T[::-1]) ; rank = np.empty(N, dtype=np.int64); rank[ras] = np.arange(N)
    vf = v.astype(np.float64)
    def look(off, mult=(1, 2)):
        out = np.full(N, np.nan)
        for m in mult:
            q = P + np.array(off) * m
            ok = np.all((q >= 0) & (q < np.array(shape)), axis=1) & np.isnan(out)
            nb = np.full(N, -1); nb[ok] = idmap[q[ok, 0], q[ok, 1], q[ok, 2]]
            ok &= nb >= 0
            out[ok] = vf[nb[ok]]
        return out
    # causal neighbourhood mean (offsets before in raster order)
    def causal_mean(r):
        sm = np.zeros(N); cnt = np.zeros(N); mx = np.full(N, -1e18); mn = np.full(N, 1e18)
        for off in itertools.product(range(-r, r + 1), repeat=3):
            if off >= (0, 0, 0): continue   # lexicographic (dk,dj,di) < 0 <=> earlier in raster order
            q = P + np.array(off)
            ok = np.all((q >= 0) & (q < np.array(shape)), axis=1)
            nb = np.full(N, -1); nb[ok] = idmap[q[ok, 0], q[ok, 1], q[ok, 2]]; ok &= nb >= 0
            val = vf[nb[ok]]; sm[ok] += val; cnt[ok] += 1
            mx[ok] = np.maximum(mx[ok], val); mn[ok] = np.minimum(mn[ok], val)
        m = np.where(cnt > 0, sm / np.maximum(cnt, 1), np.nan)
        return m, np.where(cnt > 0, mx - mn, 0)
    m1, s1 = causal_mean(1); m2, s2 = causal_mean(2)
    prev = np.full(N, np.nan); prev[ras[1:]] = vf[ras[:-1]]; prev[ras[0]] = 0
    base = np.where(~np.isnan(m1), m1, np.where(~np.isnan(m2), m2, prev))
    bspread = np.where(~np.isnan(m1), s1, np.where(~np.isnan(m2), s2, 0))
    fill = lambda x: np.where(np.isnan(x), base, x)
    a = fill(look((0, 0, -1))); b = fill(look((0, -1, 0))); c = fill(look((0, -1, -1)))
    d = fill(look((-1, 0, 0))); a1 = fill(look((-1, 0, -1))); b1 = fill(look((-1, -1, 0))); c1 = fill(look((-1, -1, -1)))
    med = lambda x, y, z: np.median(np.stack([x, y, z]), 0)
    med2 = med(a, b, a + b - c)
    med2p = med(a1, b1, a1 + b1 - c1)
    med3 = med(med2, d, med2 + d - med2p)
    lorenzo = a + b + d - c - a1 - b1 + c1
    grad = np.abs(a - c) + np.abs(b - c) + np.abs(d - a1) + np.abs(a - b)   # JPEG-LS-like activity
    R = lambda x: np.rint(x).astype(np.int64)
    return {'raster predecessor': (R(prev), np.abs(vf - prev)),   # spread for raster pred: |prev - prevprev| below
            'causal 26-mean': (R(base), bspread),
            'MED 2D (JPEG-LS, in slice)': (R(med2), grad),
            'MED 3D (median of MED2D, d, MED2D+d-MED2Dprev)': (R(med3), grad),
            'Lorenzo 3D': (R(lorenzo), grad)}, ras
