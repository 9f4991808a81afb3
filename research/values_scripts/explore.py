import sys, numpy as np
from ent import *; from vol_pred import *; from common import select, work
for vname, thr, org, sp in (('ct', 0, np.array([-12, -12, -12.]), 0.5), ('mri', 150, np.zeros(3), 2.0)):
    vol = np.load(work(f'{vname}_vol.npy')).astype(np.int64); mask = np.load(work(f'{vname}_mask.npy'))
    g = int(np.gcd.reduce(np.abs(vol).ravel()))
    solid = vol >= thr; interior = select(vol, thr, 1) & ~select(vol, thr, 10**6)   # solid & not boundary
    P = np.argwhere(mask); v = vol[mask]; isb = ~interior[mask]
    print(f"== {vname}: {len(v)} sel, boundary {isb.sum()} interior {(~isb).sum()}")
    print("   H0(values)", round(H0(v // g), 3), " boundary", round(H0(v[isb] // g), 3), " interior", round(H0(v[~isb] // g), 3))
    # mesh boundary vertices (faces used once in level-0 .ele)
    T = np.loadtxt(work(f'{vname}_L0.ele'), skiprows=1, dtype=np.int64)[:, 1:5]
    F = np.sort(np.concatenate([T[:, [0, 1, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 3]], T[:, [1, 2, 3]]]), 1)
    u, c = np.unique(F, axis=0, return_counts=True); mb = np.unique(u[c == 1])
    a = np.loadtxt(work(f'{vname}_L0.node'), skiprows=1)[:, 1:4]; ijk = np.rint((a - org) / sp).astype(int)[:, ::-1]
    meshb = np.zeros(vol.shape, bool); meshb[tuple(ijk[mb].T)] = True; mbs = meshb[mask]
    print("   mesh-boundary vertices", mbs.sum(), " agree with voxel boundary:", (mbs == isb).mean().round(3))
    preds, ras = causal_pred(vol.shape, P, v)
    for name in ('causal 26-mean', 'MED 3D (median of MED2D, d, MED2D+d-MED2Dprev)'):
        p, s = preds[name]; r = (v - p) // g
        print(f"   {name[:14]}: H0 all {H0(r):.3f}  boundary {H0(r[isb]):.3f}  interior {H0(r[~isb]):.3f}  H|isb {Hcond(r, isb.astype(int)):.3f} AC|isb {adaptive_bits(r, isb.astype(int), 2):.3f}  AC|isb x spread4 {adaptive_bits(r, isb.astype(int)*4 + bucket(s/g, 4), 8):.3f}")
    p, s, _, _ = dyadic_pred(vol.shape, P, v, 3); r = (v - p) // g
    print(f"   dyadic L=3   : H0 all {H0(r):.3f}  boundary {H0(r[isb]):.3f}  interior {H0(r[~isb]):.3f}  H|isb {Hcond(r, isb.astype(int)):.3f} AC|isb {adaptive_bits(r, isb.astype(int), 2):.3f}  AC|isb x spread4 {adaptive_bits(r, isb.astype(int)*4 + bucket(s/g, 4), 8):.3f}")
    # value coded directly, context = bucket of the prediction (conditional entropy; optimistic)
    pb = np.clip((p - thr) // (g * 8), 0, 63)
    print(f"   H(value | dyadic-pred/8 class) {Hcond(v // g, pb):.3f}  (#ctx {len(np.unique(pb))})")
