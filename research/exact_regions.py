#!/usr/bin/env python3
"""Where a tetrahedral mesh departs from the Delaunay tetrahedralization of
its points, as regions (issue 42, research/exact_regions.md).

Usage: research/exact_regions.py MODEL.node [BUILD_DIR] [-- MESHENC OPTIONS]

Encodes MODEL (.node + .ele) twice with the built meshenc, `--exact
--keep-order` (level 0 = the input's cells, in the input's numbering) and
without (level 0 = the Delaunay cells carved to the solid), decodes both
with meshdec, and matches their vertices by their decoded coordinates (the
same grid). The cells only one side has make regions: two such cells are in
one region when they share a face. A region that trades 3 Delaunay cells for
2 input cells is one 3-2 flip, 2 for 3 a 2-3 flip. Prints the regions' sizes
how many of their input cells have a corner on the input's boundary, and
how many 2 -> 2 regions are ties (four coplanar corners). Needs python3 alone.
"""
import collections
import itertools
import os
import subprocess
import sys
import tempfile


def read_mesh(base):
    """The decoded points' coordinates (as text) by id, and the cells."""
    with open(base + ".node") as f:
        lines = f.read().split("\n")
    n = int(lines[0].split()[0])
    coords = {}
    for line in lines[1 : 1 + n]:
        t = line.split()
        coords[int(t[0])] = tuple(t[1:4])
    with open(base + ".ele") as f:
        lines = f.read().split("\n")
    m = int(lines[0].split()[0])
    cells = [tuple(int(x) for x in line.split()[1:5]) for line in lines[1 : 1 + m]]
    return coords, cells


def faces_of(cell):
    return [tuple(x for i, x in enumerate(cell) if i != j) for j in range(4)]


def orientation(points, a, b, c, d):
    u, v, w = ([points[q][i] - points[a][i] for i in range(3)] for q in (b, c, d))
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0]))


def split_arguments(argv):
    """MODEL.node [BUILD_DIR] [-- MESHENC OPTIONS]"""
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1 :]
        argv = argv[: argv.index("--")]
    return argv[0], (argv[1] if len(argv) > 1 else "build"), extra


class Comparison:
    """The input's cells and the default stream's Delaunay cells of one model,
    in the input's numbering, and the regions of the cells only one side has."""

    def __init__(self, model, build, extra):
        enc, dec = os.path.join(build, "tools/meshenc"), os.path.join(build, "tools/meshdec")
        with tempfile.TemporaryDirectory() as work:
            for kind, options in (("exact", ["--exact", "--keep-order"]), ("delaunay", [])):
                stream = os.path.join(work, kind + ".dtm")
                subprocess.run([enc, model, "-q", "-o", stream] + options + extra, check=True)
                subprocess.run([dec, stream, "-q", "-o", os.path.join(work, kind + ".node")], check=True)
            exact_coords, exact_cells = read_mesh(os.path.join(work, "exact"))
            delaunay_coords, delaunay_cells = read_mesh(os.path.join(work, "delaunay"))
        by_coords = {c: v for v, c in exact_coords.items()}
        to_exact = {v: by_coords[c] for v, c in delaunay_coords.items()}
        self.coords = exact_coords  # as text, by vertex (the input's numbering)
        self.points = {v: tuple(float(x) for x in c) for v, c in exact_coords.items()}
        self.inputs = {tuple(sorted(c)) for c in exact_cells}
        self.delaunay = {tuple(sorted(to_exact[v] for v in c)) for c in delaunay_cells}
        self.only_input, self.only_delaunay = self.inputs - self.delaunay, self.delaunay - self.inputs

        cells = [(c, "input") for c in sorted(self.only_input)] + [(c, "delaunay") for c in sorted(self.only_delaunay)]
        parent = list(range(len(cells)))

        def find(x):
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        by_face = collections.defaultdict(list)
        for i, (c, _) in enumerate(cells):
            for f in faces_of(c):
                by_face[f].append(i)
        for members in by_face.values():
            for i in members[1:]:
                parent[find(i)] = find(members[0])
        regions = collections.defaultdict(lambda: {"delaunay": [], "input": []})
        for i, (c, side) in enumerate(cells):
            regions[find(i)][side].append(c)
        self.regions = list(regions.values())

    def flatness(self, cells):
        """The smallest |orientation| of four corners of `cells` over the cube
        of their longest edge: below 1e-12 (the decoded coordinates are
        rounded), four coplanar corners."""
        p = self.points
        corners = sorted(set(v for c in cells for v in c))
        longest = max(sum((p[a][i] - p[b][i]) ** 2 for i in range(3)) for a in corners for b in corners)
        return min(abs(orientation(p, *q)) for q in itertools.combinations(corners, 4)) / longest ** 1.5

    def one_flips(self):
        """The regions of one 3-2 flip: 3 Delaunay cells for 2 input cells."""
        return [r for r in self.regions if len(r["delaunay"]) == 3 and len(r["input"]) == 2]

    def ties(self):
        """The 2 -> 2 regions whose four corners are coplanar."""
        return [r for r in self.regions if len(r["delaunay"]) == 2 and len(r["input"]) == 2 and
                self.flatness(r["delaunay"]) < 1e-12]


def main():
    model, build, extra = split_arguments(sys.argv[1:])
    m = Comparison(model, build, extra)
    inputs, regions = m.inputs, m.regions
    only_input = m.only_input
    print(f"{os.path.basename(model)}: {len(inputs)} input cells, {len(m.delaunay)} Delaunay cells kept; "
          f"{len(only_input)} input cells not Delaunay, {len(m.only_delaunay)} Delaunay cells not the input's")

    face_count = collections.Counter(f for c in inputs for f in faces_of(c))
    boundary = {v for f, n in face_count.items() if n == 1 for v in f}
    total = len(only_input)
    kinds = collections.Counter((len(r["delaunay"]), len(r["input"])) for r in regions)
    print(f"  {len(regions)} regions; the commonest, Delaunay cells -> input cells:")
    for (d, i), n in kinds.most_common(6):
        print(f"    {d} -> {i}: {n} regions, {n * i} input cells ({100 * n * i / max(1, total):.1f}%)")
    print("  input cells by the size of their region (input cells), and the share with a corner on the boundary:")
    buckets = [(1, 2, "1-2"), (3, 10, "3-10"), (11, 100, "11-100"), (101, 10**9, ">100")]
    for low, high, name in buckets:
        members = [c for r in regions if low <= len(r["input"]) <= high for c in r["input"]]
        on_boundary = sum(1 for c in members if any(v in boundary for v in c))
        print(f"    {name:>7}: {len(members):6d} cells ({100 * len(members) / max(1, total):5.1f}%), "
              f"{100 * on_boundary / max(1, len(members)):5.1f}% at the boundary")
    everywhere = sum(1 for c in inputs if any(v in boundary for v in c))
    print(f"    (of all input cells, {100 * everywhere / len(inputs):.1f}% have a corner on the boundary)")

    # The 2 -> 2 regions: how many are ties, both diagonals of a coplanar
    # quad being Delaunay.
    two = [r for r in regions if len(r["delaunay"]) == 2 and len(r["input"]) == 2]
    if two:
        flatness = sorted(m.flatness(r["delaunay"]) for r in two)
        print(f"  2 -> 2 regions: {sum(1 for f in flatness if f < 1e-12)} of {len(flatness)} have four coplanar "
              f"corners; median flatness {flatness[len(flatness) // 2]:.3g}")


if __name__ == "__main__":
    main()
