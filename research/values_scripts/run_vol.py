import sys, numpy as np
from ent import *; from vol_pred import *; from common import work, levels
def node_pts(path, org, sp):
    a = np.loadtxt(path, skiprows=1, comments='#')[:, 1:4]
    ijk = np.rint((a - org) / sp).astype(np.int64); return ijk[:, ::-1]   # (k,j,i)
def ele(path):
    return np.loadtxt(path, skiprows=1, dtype=np.int64)[:, 1:5]
def row(name, r, spread, g):
    rep = report(r // g, None if spread is None else np.asarray(spread) / g)
    print(f"  {name:55s} " + "  ".join(f"{k}={v:.3f}" for k, v in rep.items()), flush=True)

for vname, org, sp, nlev in (('ct', np.array([-12, -12, -12.]), 0.5, levels('ct')), ('mri', np.zeros(3), 2.0, levels('mri'))):
    vol = np.load(work(f'{vname}_vol.npy')).astype(np.int64); mask = np.load(work(f'{vname}_mask.npy'))
    g = int(np.gcd.reduce(np.abs(vol).ravel()))
    for which in ('all', 'sel'):
        P = np.argwhere(mask if which == 'sel' else np.ones_like(mask))    # raster order (k,j,i)
        v = vol[P[:, 0], P[:, 1], P[:, 2]]
        print(f"== {vname} {which}: {len(v)} values, gcd {g}", flush=True)
        preds, ras = causal_pred(vol.shape, P, v)
        for name, (p, s) in preds.items():
            if name == 'raster predecessor':
                r = v - p; s = np.zeros(len(v)); o = ras; s[o[1:]] = np.abs(r[o[:-1]])   # ctx: previous |residual|
            row(name, v - p, s, g)
        Lmax = int(np.log2(max(vol.shape))) - 1 if which == 'all' else 3
        for L in sorted({1, 2, Lmax}):
            p, s, nf, npass = dyadic_pred(vol.shape, P, v, L)
            row(f"dyadic L={L} 26-mean ({npass} passes, {nf} kNN fallbacks)", v - p, s, g)
        if which == 'sel':
            # the codec's own levels: .node order is coarse-to-fine (level L = first n_L points)
            Pn = node_pts(work(f'{vname}_L0.node'), org, sp)
            vn = vol[Pn[:, 0], Pn[:, 1], Pn[:, 2]]
            ns = [len(np.loadtxt(work(f'{vname}_L{L}.node'), skiprows=1, max_rows=0) if False else open(work(f'{vname}_L{L}.node')).readline().split()[0]) for L in range(nlev)]
            ns = [int(open(work(f'{vname}_L{L}.node')).readline().split()[0]) for L in range(nlev)]
            print("   codec levels (coarse->fine sizes):", ns[::-1])
            # order of the values as meshenc codes the points
            import subprocess
            data = vn.astype(vol.dtype).tobytes()
            from common import sizes
            sz = sizes(data); print("   zstd/xz in codec (.node) order bits/value:", {k: round(8 * x / len(vn), 3) for k, x in sz.items()})
            bounds = [0] + ns[::-1]
            for k, mode in ((4, 'mean'), (8, 'mean'), (8, 'idw'), (6, 'median')):
                pred = np.zeros(len(vn)); spread = np.zeros(len(vn))
                base = np.arange(bounds[1]); o = np.lexsort(Pn[base].T[::-1])
                pred[o[1:]] = vn[o[:-1]]; pred[o[0]] = vn[o[0]]
                for L in range(1, len(bounds) - 1):
                    q = np.arange(bounds[L], bounds[L + 1])
                    pp, ss = knn_pred(Pn, vn, np.arange(bounds[L]), q, k, mode); pred[q] = pp; spread[q] = ss
                row(f"codec levels, kNN k={k} {mode} of coarser", vn - np.rint(pred).astype(np.int64), spread, g)
            # mesh neighbours: level L's new vertices from their level-L mesh neighbours in coarser levels
            pred = np.zeros(len(vn)); spread = np.zeros(len(vn))
            base = np.arange(bounds[1]); o = np.lexsort(Pn[base].T[::-1]); pred[o[1:]] = vn[o[:-1]]; pred[o[0]] = vn[o[0]]
            nfb = 0
            for L in range(1, len(bounds) - 1):
                T = ele(work(f'{vname}_L{nlev - 1 - L}.ele'))
                E = np.concatenate([T[:, [a, b]] for a in range(4) for b in range(4) if a != b])
                E = E[(E[:, 0] >= bounds[L]) & (E[:, 1] < bounds[L])]
                E = np.unique(E, axis=0)
                sm = np.bincount(E[:, 0], vn[E[:, 1]], len(vn)); cnt = np.bincount(E[:, 0], None, len(vn))
                mx = np.full(len(vn), -1e18); mn = np.full(len(vn), 1e18)
                np.maximum.at(mx, E[:, 0], vn[E[:, 1]]); np.minimum.at(mn, E[:, 0], vn[E[:, 1]])
                q = np.arange(bounds[L], bounds[L + 1]); have = cnt[q] > 0
                pred[q[have]] = sm[q[have]] / cnt[q[have]]; spread[q[have]] = (mx - mn)[q[have]]
                if (~have).any():
                    nfb += (~have).sum(); pp, ss = knn_pred(Pn, vn, np.arange(bounds[L]), q[~have], 4); pred[q[~have]] = pp; spread[q[~have]] = ss
            row(f"codec levels, mean of mesh neighbours in coarser ({nfb} fb)", vn - np.rint(pred).astype(np.int64), spread, g)
            # random halving (stand-in for levels)
            rng = np.random.default_rng(1); perm = rng.permutation(len(v)); sizes_ = []
            n = len(v)
            while n > 64: sizes_.append(n); n //= 2
            bnd = [0, n] + sizes_[::-1]
            pred = np.zeros(len(v)); spread = np.zeros(len(v))
            Pp = P[perm]; vp = v[perm]
            pred[1:bnd[1]] = vp[:bnd[1] - 1]; pred[0] = vp[0]
            for L in range(1, len(bnd) - 1):
                q = np.arange(bnd[L], bnd[L + 1]); pp, ss = knn_pred(Pp, vp, np.arange(bnd[L]), q, 4); pred[q] = pp; spread[q] = ss
            row(f"random halving ({len(bnd)-1} levels), kNN k=4 mean", vp - np.rint(pred).astype(np.int64), spread, g)
