#!/usr/bin/env python3
"""Can chains of flips turn the Delaunay cells into a TetGen mesh's large
boundary regions, and what would a decoder pay to be told which flips?
(issue 42, research/exact_flip_chains.md)

Usage: research/exact_flip_chains.py [--dihedral] MODEL.node [BUILD_DIR] [-- MESHENC OPTIONS]

With the regions of exact_regions.py (the input's cells against the default
stream's carved Delaunay cells, in the input's numbering):
* The cells to rework are the Delaunay cells of the regions that hold input
  cells (the other regions lie outside the input's solid: the carving's
  business). A decoder would be told them by the carving.
* Region by region (connected by faces), flips are made while one makes
  progress towards the input: its cells out are all cells to rework (never
  an input cell), it removes no input edge, and it makes an input cell or
  an input edge. The flips are 2-3 (a face), and the removal of an edge
  with 3 to 6 cells around it into any triangulation of its ring (3-2,
  4-4, 5-6, 6-8). A flip must be valid: every new cell of positive volume,
  their volumes summing to the removed cells'.
* Its cost: the decoder would list the same candidates (every valid flip
  of the region's cells to rework, and of the cells flips made) and rank
  them by how much the flip raises the least quality (volume over the cube
  of the mean squared edge length; with --dihedral, the least dihedral
  angle) of its cells; the encoder picks, among
  the flips that make progress, the one ranked first. The ranks' histogram
  and their cost are printed.
Needs python3 alone; slow (a minute at 10k vertices).
"""
import collections
import itertools
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exact_regions import Comparison, split_arguments  # noqa: E402


def sorted_cell(*v):
    return tuple(sorted(v))


def ring_triangulations(polygon):
    """Every triangulation of a convex polygon's vertex cycle."""
    if len(polygon) < 3:
        yield []
        return
    a, b = polygon[0], polygon[-1]
    for k in range(1, len(polygon) - 1):
        for left in ring_triangulations(polygon[: k + 1]):
            for right in ring_triangulations(polygon[k:]):
                yield [(a, polygon[k], b)] + left + right


class FlipChains:
    def __init__(self, m, by_dihedral=False):
        self.m, self.points, self.inputs = m, m.points, m.inputs
        self.by_dihedral = by_dihedral
        self.input_edges = {e for c in self.inputs for e in itertools.combinations(c, 2)}
        self.edges, self.faces = collections.defaultdict(set), collections.defaultdict(set)
        self.current = set()
        for c in m.delaunay:
            self.add(c)
        # The cells to rework: those of regions with input cells.
        self.rework = {c for r in m.regions if r["input"] for c in r["delaunay"]}

    def add(self, c):
        self.current.add(c)
        for e in itertools.combinations(c, 2):
            self.edges[e].add(c)
        for f in itertools.combinations(c, 3):
            self.faces[f].add(c)

    def remove(self, c):
        self.current.discard(c)
        for e in itertools.combinations(c, 2):
            self.edges[e].discard(c)
        for f in itertools.combinations(c, 3):
            self.faces[f].discard(c)

    def volume(self, c):
        a, b, d, e = (self.points[v] for v in c)
        u, v, w = ([q[i] - a[i] for i in range(3)] for q in (b, d, e))
        return abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                   u[2] * (v[0] * w[1] - v[1] * w[0]))

    def quality(self, c):
        p = self.points
        s = sum(sum((p[a][i] - p[b][i]) ** 2 for i in range(3)) for a, b in itertools.combinations(c, 2)) / 6
        return self.volume(c) / s ** 1.5 if s > 0 else 0

    def flips_at(self, c):
        """The valid flips of cells to rework that remove c: (removed, made)."""
        out = []
        for f in itertools.combinations(c, 3):
            cs = self.faces.get(f, ())
            if len(cs) != 2 or not all(x in self.rework for x in cs):
                continue
            a, b = sorted(cs)
            p, q = [v for v in a if v not in f][0], [v for v in b if v not in f][0]
            out.append(((a, b), [sorted_cell(p, q, f[0], f[1]), sorted_cell(p, q, f[1], f[2]),
                                 sorted_cell(p, q, f[0], f[2])]))
        for e in itertools.combinations(c, 2):
            cs = sorted(self.edges.get(e, ()))
            n = len(cs)
            if n < 3 or n > 6 or not all(x in self.rework for x in cs):
                continue
            ring = {v for x in cs for v in x} - set(e)
            if len(ring) != n:
                continue
            beside = collections.defaultdict(list)
            for x in cs:
                r = [v for v in x if v not in e]
                beside[r[0]].append(r[1])
                beside[r[1]].append(r[0])
            if any(len(v) != 2 for v in beside.values()):
                continue
            cycle, previous = [min(ring)], None
            while len(cycle) < n:
                step = [v for v in beside[cycle[-1]] if v != previous][0]
                previous = cycle[-1]
                cycle.append(step)
            for triangles in ring_triangulations(cycle):
                out.append((tuple(cs), [sorted_cell(*t, e[0]) for t in triangles] +
                            [sorted_cell(*t, e[1]) for t in triangles]))
        valid = []
        for removed, made in out:
            if any(x in self.current for x in made):
                continue
            before = sum(self.volume(x) for x in removed)
            after = [self.volume(x) for x in made]
            if min(after) > 1e-9 * before and abs(sum(after) - before) <= 1e-7 * before:
                valid.append((removed, made))
        return valid

    def progress(self, removed, made):
        if any(x in self.inputs for x in removed):
            return False
        kept = {e for x in made for e in itertools.combinations(x, 2)}
        lost = {e for x in removed for e in itertools.combinations(x, 2)} - kept
        if lost & self.input_edges:
            return False
        new = {e for e in kept if not self.edges.get(e)}
        return any(x in self.inputs for x in made) or bool(new & self.input_edges)

    def least_dihedral(self, c):
        """The cell's least dihedral angle (radians)."""
        p = [self.points[v] for v in c]

        def sub(a, b):
            return [a[i] - b[i] for i in range(3)]

        def cross(a, b):
            return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

        least = math.pi
        for i, j in itertools.combinations(range(4), 2):
            k, l = [x for x in range(4) if x not in (i, j)]
            e = sub(p[j], p[i])
            n1, n2 = cross(e, sub(p[k], p[i])), cross(e, sub(p[l], p[i]))
            d1, d2 = math.sqrt(sum(x * x for x in n1)), math.sqrt(sum(x * x for x in n2))
            if d1 == 0 or d2 == 0:
                return 0.0
            cosine = max(-1.0, min(1.0, sum(a * b for a, b in zip(n1, n2)) / (d1 * d2)))
            least = min(least, math.acos(cosine))
        return least

    def gain(self, removed, made):
        measure = self.least_dihedral if self.by_dihedral else self.quality
        return min(measure(x) for x in made) - min(measure(x) for x in removed)

    def run(self):
        ranks, regions, seen = [], 0, set()
        while True:
            left = sorted(self.rework - seen)
            if not left:
                return ranks, regions
            region, stack = {left[0]}, [left[0]]
            while stack:
                c = stack.pop()
                for f in itertools.combinations(c, 3):
                    for x in self.faces.get(f, ()):
                        if x in self.rework and x not in region:
                            region.add(x)
                            stack.append(x)
            regions += 1
            while True:
                candidates = {}
                for c in region:
                    for removed, made in self.flips_at(c):
                        candidates[(removed, tuple(made))] = (removed, made)
                ranked = sorted(candidates.values(), key=lambda f: -self.gain(*f))
                first = next((i for i, f in enumerate(ranked) if self.progress(*f)), None)
                if first is None:
                    break
                removed, made = ranked[first]
                ranks.append((first, len(ranked)))
                for x in removed:
                    self.remove(x)
                    self.rework.discard(x)
                    region.discard(x)
                for x in made:
                    self.add(x)
                    self.rework.add(x)
                    region.add(x)
            seen |= region


def exp_golomb_bits(r):
    return 2 * int(math.log2(r + 1)) + 1


def main():
    argv = sys.argv[1:]
    by_dihedral = "--dihedral" in argv
    argv = [a for a in argv if a != "--dihedral"]
    model, build, extra = split_arguments(argv)
    m = Comparison(model, build, extra)
    chains = FlipChains(m, by_dihedral)
    missing_before = len(m.inputs - chains.current)
    ranks, regions = chains.run()
    missing_after = len(m.inputs - chains.current)
    name = os.path.basename(model)
    print(f"{name}: {missing_before} input cells not Delaunay; {len(ranks)} flips in {regions} regions "
          f"leave {missing_after} ({100 * (missing_before - missing_after) / max(1, missing_before):.0f}% made)")
    histogram = collections.Counter(min(r, 10) for r, _ in ranks)
    print("  rank of the first flip that makes progress (10: 10 or more): " +
          ", ".join(f"{r}: {n}" for r, n in sorted(histogram.items())))
    total = max(1, len(ranks))
    entropy = -sum(n / total * math.log2(n / total) for n in histogram.values())
    print(f"  candidates a flip (mean) {sum(n for _, n in ranks) / total:.1f}; rank bits a flip: "
          f"{entropy:.2f} (entropy, ranks of 10+ one symbol), "
          f"{sum(exp_golomb_bits(r) for r, _ in ranks) / total:.2f} (Exp-Golomb)")


if __name__ == "__main__":
    main()
