import sys, numpy as np
from ent import *; from vol_pred import *; from common import select, work
for vname, thr in (('ct', 0), ('mri', 150)):
    vol = np.load(work(f'{vname}_vol.npy')).astype(np.int64); mask = np.load(work(f'{vname}_mask.npy'))
    g = int(np.gcd.reduce(np.abs(vol).ravel())); solid = vol >= thr
    interior = select(vol, thr, 1) & ~select(vol, thr, 10**6)
    # (1) ceiling: dense volume, residuals restricted to solid voxels
    P = np.argwhere(np.ones_like(mask)); v = vol.ravel(); sv = solid.ravel()
    preds, _ = causal_pred(vol.shape, P, v)
    p, s = preds['MED 3D (median of MED2D, d, MED2D+d-MED2Dprev)']
    print(f"== {vname}: dense volume, solid voxels only ({sv.sum()}): H0(values) {H0(v[sv]//g):.3f} MED3D H0 {H0((v-p)[sv]//g):.3f} AC {adaptive_bits((v-p)[sv]//g):.3f} AC|spread {adaptive_bits((v-p)[sv]//g, bucket(s[sv]/g), 8):.3f}")
    # LS oracle over 13 causal neighbours (Chebyshev 1) + 1, solid only
    idm = vol.astype(float); pad = np.pad(idm, 1, mode='edge')
    feats = []
    import itertools
    for off in itertools.product((-1, 0, 1), repeat=3):
        if off >= (0, 0, 0): continue
        feats.append(pad[1+off[0]:1+off[0]+vol.shape[0], 1+off[1]:1+off[1]+vol.shape[1], 1+off[2]:1+off[2]+vol.shape[2]].ravel())
    X = np.stack(feats + [np.ones(v.size)], 1)[sv]; y = v[sv].astype(float)
    w, *_ = np.linalg.lstsq(X, y, rcond=None); r = np.rint(y - X @ w).astype(np.int64) // g
    print(f"   dense LS-oracle 13 causal nbrs, solid only: H0 {H0(r):.3f} AC {adaptive_bits(r):.3f}")
    # (2) sparse selected set, dyadic L=3 predictor with shrinkage toward the running mean of known values
    P = np.argwhere(mask); v = vol[mask]; isb = (~interior[mask]).astype(int)
    p, s, _, _ = dyadic_pred(vol.shape, P, v, 3)
    passes = dyadic_passes(P, 3)
    # c = mean of all coarser-pass values (decoder knows them)
    c = np.zeros(len(v)); seen = []
    for pi, (l, idx) in enumerate(passes):
        c[idx] = np.mean(v[np.concatenate(seen)]) if seen else v[idx].mean()
        seen.append(idx)
    for a in (0, 0.25, 0.5, 0.75, 1.0):
        pa = np.rint(c + a * (p - c)).astype(np.int64); r = (v - pa) // g
        pb = bucket((pa - thr) / g, 8)
        print(f"   sparse dyadic, alpha={a:.2f}: H0 {H0(r):.3f} AC {adaptive_bits(r):.3f} AC|spread8 {adaptive_bits(r, bucket(s/g), 8):.3f} AC|isb {adaptive_bits(r, isb, 2):.3f} AC|predmag8 {adaptive_bits(r, pb, 8):.3f} AC|isb x spread4 x predmag4 {adaptive_bits(r, isb*16 + bucket(s/g,4)*4 + bucket((pa-thr)/g/16, 4), 32):.3f}")
