import numpy as np
from common import *
vols = {'ct': (DATA / 'ct_torus.nrrd', 0, 2), 'mri': (DATA / 'fields' / 'mri_s0.nrrd', 150, 2)}
for name, (path, thr, step) in vols.items():
    hdr, vol = read_nrrd(path)
    m = select(vol, thr, step)
    K, J, I = np.nonzero(m)          # C order of (k,j,i) = raster order, x fastest
    vals = vol[m]
    np.save(work(f'{name}_vol.npy'), vol); np.save(work(f'{name}_mask.npy'), m)
    vals.astype(vol.dtype).tofile(work(f'{name}_sel.raw'))
    vol.tofile(work(f'{name}_all.raw'))
    # check against meshdec's .node (physical coords)
    if 'space directions' in hdr:
        sp = 0.5; org = np.array([-12, -12, -12.])
    else:
        sp = 2.0; org = np.zeros(3)
    node = np.loadtxt(work(f'{name}_L0.node'), skiprows=1, comments='#')[:, 1:4]   # meshdec's finest level
    idx = np.rint((node - org) / sp).astype(int)
    a = set(map(tuple, idx)); b = set(zip(I, J, K))
    print(name, vol.shape, vol.dtype, 'range', vol.min(), vol.max(), 'selected', m.sum(), 'node pts', len(node), 'same set', a == b)
    gv = np.gcd.reduce(np.abs(vals.astype(np.int64))); ga = np.gcd.reduce(np.abs(vol.astype(np.int64)).ravel())
    print('  sel range', vals.min(), vals.max(), 'gcd sel', gv, 'gcd all', ga, 'distinct sel', len(np.unique(vals)))
    for tag, data in (('sel', vals.tobytes()), ('all', vol.tobytes())):
        s = sizes(data); n = len(data) // 2
        print('  ', tag, n, {k: (v, round(8 * v / n, 3)) for k, v in s.items()})
