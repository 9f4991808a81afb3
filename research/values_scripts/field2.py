import os, sys, numpy as np
# field.py's set-up (the bunny's points and the quantized field q), without its measurements.
exec(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'field.py')).read().split('for tag, data')[0])
from field_helpers import lsq_pred
D = np.loadtxt(work('bunny_L0.node'), skiprows=1, comments='#')[:, 1:4]
ns = [int(open(work(f'bunny_L{L}.node')).readline().split()[0]) for L in range(levels('bunny'))][::-1]
ids = np.empty(len(D), dtype=np.int64)
for s in range(0, len(D), 512): ids[s:s + 512] = np.argmin(((D[s:s + 512, None] - X[None]) ** 2).sum(-1), 1)
Po = X[ids]; vo = q[ids].astype(np.int64); bounds = [0] + ns
def idw(known, query, k, p=1):
    Kp = Po[known]; out = np.empty(len(query))
    for s in range(0, len(query), 512):
        Q = Po[query[s:s+512]]; d2 = ((Q[:, None] - Kp[None]) ** 2).sum(-1); kk = min(k, len(known))
        nn = np.argpartition(d2, kk - 1, 1)[:, :kk]; w = 1 / np.maximum(np.sqrt(np.take_along_axis(d2, nn, 1)), 1e-9) ** p
        out[s:s+512] = (w * vo[known][nn]).sum(1) / w.sum(1)
    return out
# base level coded sequentially: each base point from kNN among earlier base points (greedy nearest order not needed)
nb = bounds[1]; base_pred = np.zeros(nb); base_pred[0] = 0
for i in range(1, nb): base_pred[i] = idw(np.arange(i), np.array([i]), 3)[0]
rb = vo[:nb] - np.rint(base_pred).astype(np.int64)
print(f"base level ({nb} pts) sequential kNN3 IDW: AC2 {adaptive_bits2(rb):.3f} (vs previous-value delta {adaptive_bits2(np.diff(vo[:nb], prepend=0)):.3f})")
for label, fn in (('kNN3 IDW 1/d (G-PCC-like)', lambda k, qq: idw(k, qq, 3, 1)),
                  ('kNN8 IDW 1/d^2', lambda k, qq: idw(k, qq, 8, 2)),
                  ('kNN8 plane fit', lambda k, qq: lsq_pred(Po, vo, k, qq, 8)[0])):
    r = [rb]
    for L in range(1, len(bounds) - 1):
        qi = np.arange(bounds[L], bounds[L + 1]); r.append(vo[qi] - np.rint(fn(np.arange(bounds[L]), qi)).astype(np.int64))
    r = np.concatenate(r)
    print(f"codec levels, {label:26s}: H0 {H0(r):.3f} AC2 {adaptive_bits2(r):.3f}  per level AC2 " + " ".join(f"{adaptive_bits2(x):.2f}" for x in np.split(r, bounds[1:-1])))
