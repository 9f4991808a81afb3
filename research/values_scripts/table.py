"""Consolidated bits/value table for the two volumes (selected points, codec order = .node order)."""
import sys, numpy as np
from ent import *; from vol_pred import *; from common import sizes, work, levels; from field_helpers import lsq_pred
for vname, thr, org, sp, nlev in (('ct', 0, np.array([-12, -12, -12.]), 0.5, levels('ct')), ('mri', 150, np.zeros(3), 2.0, levels('mri'))):
    vol0 = np.load(work(f'{vname}_vol.npy')); vol = vol0.astype(np.int64); mask = np.load(work(f'{vname}_mask.npy'))
    g = int(np.gcd.reduce(np.abs(vol).ravel()))
    a = np.loadtxt(work(f'{vname}_L0.node'), skiprows=1)[:, 1:4]; P = np.rint((a - org) / sp).astype(int)[:, ::-1]
    v = vol[tuple(P.T)]; N = len(v)
    ns = [int(open(work(f'{vname}_L{L}.node')).readline().split()[0]) for L in range(nlev)][::-1]; bounds = [0] + ns
    sz = sizes(v.astype(vol0.dtype).tobytes())
    print(f"== {vname}: codec (.node) order zstd19 {8*sz['zstd19']/N:.3f} xz9 {8*sz['xz9']/N:.3f}")
    T = np.loadtxt(work(f'{vname}_L0.ele'), skiprows=1, dtype=np.int64)[:, 1:5]
    F = np.sort(np.concatenate([T[:, [0, 1, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 3]], T[:, [1, 2, 3]]]), 1)
    u, c = np.unique(F, axis=0, return_counts=True); mb = np.zeros(N, int); mb[np.unique(u[c == 1])] = 1
    for label, fn in (('kNN8 IDW', lambda k, q: knn_pred(P, v, k, q, 8, 'idw')),
                      ('kNN8 plane fit', lambda k, q: lsq_pred(P.astype(float), v, k, q, 8))):
        pred = np.zeros(N); spr = np.zeros(N)
        base = np.arange(bounds[1]); o = np.lexsort(P[base].T[::-1]); pred[o[1:]] = v[o[:-1]]; pred[o[0]] = v[o[0]]
        for L in range(1, len(bounds) - 1):
            qi = np.arange(bounds[L], bounds[L + 1]); pp, ss = fn(np.arange(bounds[L]), qi); pred[qi] = pp; spr[qi] = ss
        cm = np.zeros(N)
        for L in range(len(bounds) - 1):
            qi = np.arange(bounds[L], bounds[L + 1]); cm[qi] = v[:bounds[L]].mean() if L else v[qi].mean()
        for al in (0.0, 0.5, 1.0):
            r = (v - np.rint(cm + al * (pred - cm)).astype(np.int64)) // g
            print(f"  codec levels {label:15s} alpha {al:.1f}: H0 {H0(r):.3f} H|spread {Hcond(r, bucket(spr/g)):.3f} AC2 {adaptive_bits2(r):.3f} AC2|spread8 {adaptive_bits2(r, bucket(spr/g), 8):.3f} AC2|meshbnd {adaptive_bits2(r, mb, 2):.3f} AC2|meshbnd x spread4 {adaptive_bits2(r, mb*4 + bucket(spr/g, 4), 8):.3f}", flush=True)
    # raster-order predictors on the selected set and on all voxels, AC2
    for which in ('sel', 'all'):
        Pr = np.argwhere(mask if which == 'sel' else np.ones_like(mask)); vr = vol[tuple(Pr.T)]
        preds, ras = causal_pred(vol.shape, Pr, vr)
        out = []
        for name in ('raster predecessor', 'causal 26-mean', 'MED 3D (median of MED2D, d, MED2D+d-MED2Dprev)'):
            p, s = preds[name]; r = (vr - p) // g
            if name == 'raster predecessor': s = np.zeros(len(r)); s[ras[1:]] = np.abs(r[ras[:-1]]) * g
            out.append(f"{name[:14]}: AC2 {adaptive_bits2(r):.3f} AC2|spr {adaptive_bits2(r, bucket(s/g), 8):.3f}")
        p, s, _, _ = dyadic_pred(vol.shape, Pr, vr, 3 if which == 'sel' else 4); r = (vr - p) // g
        out.append(f"dyadic: AC2 {adaptive_bits2(r):.3f} AC2|spr {adaptive_bits2(r, bucket(s/g), 8):.3f}")
        out.append(f"values/gcd order-0: H0 {H0(vr // g):.3f} AC2(v-mean) {adaptive_bits2((vr - int(round(vr.mean()))) // g):.3f}")
        print(f"  raster {which}: " + " | ".join(out), flush=True)
