"""Writes ct_torus.nrrd: a CT-like scan of a torus (a 48^3 int16 volume in
Hounsfield-like units, 0.5 mm isotropic voxels, gzip-encoded NRRD). Air is
about -1000, the solid about +400, with a one-voxel partial-volume edge and
deterministic noise. Threshold at 0 to take the solid.  usage: make_ct_torus.py OUT.nrrd"""
import gzip
import math
import random
import struct
import sys

n, spacing = 48, 0.5
rng = random.Random(7)
values = []
for k in range(n):
    for j in range(n):
        for i in range(n):
            x, y, z = i - 23.5, j - 23.5, (k - 23.5) * 1.0
            depth = 6.0 - math.hypot(math.hypot(x, y) - 14.0, z)  # voxels inside the tube
            frac = min(1.0, max(0.0, depth + 0.5))                 # partial volume at the edge
            v = -1000 + 1400 * frac + rng.gauss(0, 20)
            values.append(int(round(v / 10)) * 10)
data = gzip.compress(struct.pack("<%dh" % len(values), *values), compresslevel=9, mtime=0)
header = (
    "NRRD0004\n# CT-like torus written by data/make_ct_torus.py\n"
    "type: short\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n"
    "space directions: (%g,0,0) (0,%g,0) (0,0,%g)\nkinds: domain domain domain\n"
    "endian: little\nencoding: gzip\nspace origin: (-12,-12,-12)\n\n" % (n, n, n, spacing, spacing, spacing)
)
with open(sys.argv[1], "wb") as f:
    f.write(header.encode() + data)
