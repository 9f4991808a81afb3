#!/usr/bin/env python3
"""Are a mesh's non-Delaunay cells constrained Delaunay with respect to its
boundary triangles? (issue 42, research/exact_flip_chains.md)

Usage: research/exact_constrained.py MODEL.node [BUILD_DIR] [-- MESHENC OPTIONS]

With the cells of exact_regions.py: for each input cell that is not a
Delaunay cell, the vertices strictly inside its circumsphere (found through
a uniform grid), and whether any of them sees the cell's centroid, the
segment crossing no boundary triangle of the input (one that does not have
the vertex as a corner). A vertex that sees the centroid sees the cell's
interior, so the cell is not constrained Delaunay; one that none sees is
counted as constrained Delaunay (visibility from the centroid only: an
upper bound on those). Cells whose sphere spans more than 4000 grid cells
are left out. Needs python3 alone.
"""
import sys, collections, itertools, math, time
sys.path.insert(0, __import__('os').path.dirname(__import__('os').path.abspath(__file__)))
import exact_regions as er
model, build, extra = er.split_arguments(sys.argv[1:])
m = er.Comparison(model, build, extra)
P = m.points
ids = sorted(P)
fc = collections.Counter(f for c in m.inputs for f in itertools.combinations(c, 3))
bnd = [f for f, n in fc.items() if n == 1]
# grids
xs = [P[v] for v in ids]
lo = [min(p[i] for p in xs) for i in range(3)]; hi = [max(p[i] for p in xs) for i in range(3)]
ext = max(hi[i] - lo[i] for i in range(3))
G = 32; h = ext / G
def cell(p): return tuple(min(G - 1, int((p[i] - lo[i]) / h)) for i in range(3))
pgrid = collections.defaultdict(list)
for v in ids: pgrid[cell(P[v])].append(v)
tgrid = collections.defaultdict(list)
for t in bnd:
    a = [min(P[v][i] for v in t) for i in range(3)]; b = [max(P[v][i] for v in t) for i in range(3)]
    ca, cb = cell(a), cell(b)
    for x in range(ca[0], cb[0] + 1):
        for y in range(ca[1], cb[1] + 1):
            for z in range(ca[2], cb[2] + 1): tgrid[(x, y, z)].append(t)
def sub(a, b): return (a[0]-b[0], a[1]-b[1], a[2]-b[2])
def dot(a, b): return a[0]*b[0]+a[1]*b[1]+a[2]*b[2]
def cross(a, b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def circumsphere(c):
    a = P[c[0]]; u, v, w = (sub(P[x], a) for x in c[1:])
    d = 2 * dot(u, cross(v, w))
    if d == 0: return None
    n = tuple(dot(u,u)*cross(v,w)[i] + dot(v,v)*cross(w,u)[i] + dot(w,w)*cross(u,v)[i] for i in range(3))
    ctr = tuple(a[i] + n[i] / d for i in range(3))
    return ctr, dot(sub(ctr, a), sub(ctr, a))
def seg_hits_tri(p, q, t):
    # proper intersection of segment pq with triangle t's interior
    a, b, c = (P[x] for x in t)
    def orient(x, y, z, w): return dot(sub(y, x), cross(sub(z, x), sub(w, x)))
    o1, o2 = orient(a, b, c, p), orient(a, b, c, q)
    if o1 * o2 >= 0: return False
    s1, s2, s3 = orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)
    return (s1 > 0 and s2 > 0 and s3 > 0) or (s1 < 0 and s2 < 0 and s3 < 0)
def tris_near_segment(p, q):
    ca, cb = cell([min(p[i], q[i]) for i in range(3)]), cell([max(p[i], q[i]) for i in range(3)])
    out = set()
    for x in range(ca[0], cb[0] + 1):
        for y in range(ca[1], cb[1] + 1):
            for z in range(ca[2], cb[2] + 1): out.update(tgrid.get((x, y, z), ()))
    return out
stats = collections.Counter(); t0 = time.time()
cells = sorted(m.only_input)
for c in cells:
    cs = circumsphere(c)
    if cs is None: stats['flat'] += 1; continue
    ctr, r2 = cs; r = math.sqrt(r2)
    ca, cb = cell([ctr[i] - r for i in range(3)]), cell([ctr[i] + r for i in range(3)])
    if (cb[0]-ca[0]+1)*(cb[1]-ca[1]+1)*(cb[2]-ca[2]+1) > 4000: stats['huge sphere'] += 1; continue
    inside = []
    for x in range(max(0,ca[0]), min(G,cb[0] + 1)):
        for y in range(max(0,ca[1]), min(G,cb[1] + 1)):
            for z in range(max(0,ca[2]), min(G,cb[2] + 1)):
                for v in pgrid.get((x, y, z), ()):
                    if v in c: continue
                    if dot(sub(P[v], ctr), sub(P[v], ctr)) < r2 * (1 - 1e-9): inside.append(v)
    if not inside: stats['delaunay (empty sphere)'] += 1; continue
    cen = tuple(sum(P[v][i] for v in c) / 4 for i in range(3))
    visible = 0
    for v in inside:
        blocked = any(seg_hits_tri(P[v], cen, t) for t in tris_near_segment(P[v], cen) if v not in t)
        if not blocked: visible += 1; break
    stats['constrained Delaunay' if not visible else 'not CDT'] += 1
print(len(cells), 'non-Delaunay input cells:', dict(stats), '%.0f s' % (time.time() - t0))
