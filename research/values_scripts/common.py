"""Shared by the issue-13 value scripts: where things are, the NRRD reader, meshenc's
voxel selection and the compressors' sizes.

Every script takes one optional argument, the work folder that run.sh fills with the
encoded streams and their decoded levels and where extract.py leaves its arrays
(default: build/research/values under the repository root)."""
import gzip, pathlib, subprocess, os, sys, numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]                    # the repository
DATA = ROOT / 'data'
WORK = pathlib.Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else ROOT / 'build' / 'research' / 'values'

def work(name):
    """A file of the work folder."""
    return str(WORK / name)

def levels(name):
    """How many levels run.sh decoded for NAME (files NAME_L0.node, NAME_L1.node, ...)."""
    n = 0
    while (WORK / f'{name}_L{n}.node').exists(): n += 1
    if n == 0: raise SystemExit(f'{WORK}: no {name}_L0.node; run research/values_scripts/run.sh first')
    return n

def read_nrrd(path):
    raw = open(path, 'rb').read()
    pos = 0; hdr = {}
    while True:
        nl = raw.index(b'\n', pos); line = raw[pos:nl].decode(); pos = nl + 1
        if line == '': break
        if line.startswith('#') or line.startswith('NRRD'): continue
        k, v = line.split(': ', 1); hdr[k] = v.strip()
    assert hdr['encoding'] == 'gzip' and hdr['endian'] == 'little'
    dt = {'short': '<i2', 'uint16': '<u2'}[hdr['type']]
    sx, sy, sz = map(int, hdr['sizes'].split())
    a = np.frombuffer(gzip.decompress(raw[pos:]), dtype=dt)
    assert a.size == sx * sy * sz
    return hdr, a.reshape(sz, sy, sx)   # vol[k, j, i], raster = x fastest

def select(vol, thr, step):
    """voxel_points.cpp: solid = v >= thr; keep boundary (a 6-neighbour not solid / outside) + interior with i,j,k % step == 0.
    Returns boolean mask (k,j,i)."""
    s = vol >= thr
    p = np.pad(s, 1, constant_values=False)
    inner = s.copy()
    for ax in range(3):
        for d in (-1, 1):
            inner &= np.roll(p, d, axis=ax)[1:-1, 1:-1, 1:-1]
    K, J, I = np.indices(vol.shape)
    return s & (~inner | ((I % step == 0) & (J % step == 0) & (K % step == 0)))

def csize(data: bytes, cmd):
    r = subprocess.run(cmd, input=data, stdout=subprocess.PIPE, check=True)
    return len(r.stdout)

def sizes(data: bytes):
    return {'raw': len(data), 'zstd19': csize(data, ['zstd', '-19', '-c', '-q']),
            'xz9': csize(data, ['xz', '-9', '-c']),
            'xz9raw': csize(data, ['xz', '-9', '--format=raw', '-c'])}
