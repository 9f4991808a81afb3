"""Writes ellipsoid_793.node and .ele: a small quality tetrahedral mesh made
as the corpus's are (TetGen refining by Steiner points at circumcentres), for
the golden stream whose layers use format 7.0's candidates. The surface is an
icosphere (2 subdivisions, 162 vertices) scaled to an ellipsoid of semi-axes
1, 0.8, 0.6; TetGen 1.6 (Debian's tetgen) meshes it with -pq1.3a0.02.
usage: make_ellipsoid.py OUT_DIR"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

t = (1 + 5 ** 0.5) / 2
vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
            (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]


def unit(p):
    length = math.sqrt(sum(c * c for c in p))
    return tuple(c / length for c in p)


vertices = [unit(p) for p in vertices]
for _ in range(2):
    middle = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in middle:
            vertices.append(unit(tuple((vertices[a][i] + vertices[b][i]) / 2 for i in range(3))))
            middle[key] = len(vertices) - 1
        return middle[key]

    finer = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    faces = finer

out = sys.argv[1]
with tempfile.TemporaryDirectory() as work:
    off = os.path.join(work, "ellipsoid.off")
    with open(off, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(vertices), len(faces)))
        for x, y, z in vertices:
            f.write("%.9f %.9f %.9f\n" % (x, 0.8 * y, 0.6 * z))
        for a, b, c in faces:
            f.write("3 %d %d %d\n" % (a, b, c))
    subprocess.run(["tetgen", "-pq1.3a0.02", "-Q", off], check=True)
    for ext in ("node", "ele"):
        shutil.copy(os.path.join(work, "ellipsoid.1." + ext), os.path.join(out, "ellipsoid_793." + ext))
