#!/usr/bin/env python3
"""What a mesh's one-flip regions cost `--exact` today, and what a flag per
candidate edge would cost instead (issue 42, research/exact_regions.md).

Usage: research/exact_flips.py MODEL.node [BUILD_DIR] [-- MESHENC OPTIONS]

With the regions of exact_regions.py:
* Today's cost. The input is written again with each one-flip region (3
  Delaunay cells traded for 2 input cells) given back its 3 Delaunay cells,
  and with each coplanar 2 -> 2 tie given the Delaunay diagonal; each
  variant is encoded with --exact, and the difference in stream bytes over
  the regions is what they cost. The variants have the same solid.
* A flag per edge. The candidates are the edges of the kept Delaunay cells
  that have exactly 3 cells around them, and whose ring triangle the edge
  crosses, so that the 3-2 flip is valid. The flag's ideal code length is
  the entropy over the candidates: in one context, and in contexts from
  the flip's effect on the least solid angle (the least of the 3 cells
  before, as a power of two; how many times larger the least of the 2
  cells after is, as a power of two; or not larger). The counts are
  static; the last figure codes the flags in edge order with a counting
  (Krichevsky-Trofimov) model per context, as an adaptive coder would.
Needs python3 alone. It writes the variants beside MODEL.
"""
import collections
import itertools
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from exact_regions import Comparison, orientation, split_arguments  # noqa: E402


def entropy(p):
    return 0.0 if p <= 0 or p >= 1 else -(p * math.log2(p) + (1 - p) * math.log2(1 - p))


def solid_angle(points, apex, a, b, c):
    """The solid angle at `apex` of the tetrahedron (Van Oosterom and Strackee)."""
    u, v, w = ([points[q][i] - points[apex][i] for i in range(3)] for q in (a, b, c))
    lu, lv, lw = (math.sqrt(sum(x * x for x in t)) for t in (u, v, w))
    det = abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
              u[2] * (v[0] * w[1] - v[1] * w[0]))

    def dot(s, t):
        return sum(x * y for x, y in zip(s, t))

    return 2 * math.atan2(det, lu * lv * lw + dot(u, v) * lw + dot(u, w) * lv + dot(v, w) * lu)


def least_solid_angle(points, cell):
    a, b, c, d = cell
    return min(solid_angle(points, a, b, c, d), solid_angle(points, b, a, c, d),
               solid_angle(points, c, a, b, d), solid_angle(points, d, a, b, c))


def flag_bits(m, flips):
    """The candidates, the input's among them, and the flag's ideal bits in one
    context and in the solid-angle contexts."""
    p = m.points
    flipped = set()
    for r in flips:
        common = set(r["delaunay"][0]).intersection(*r["delaunay"][1:])
        flipped.add(tuple(sorted(common)))
    around = collections.defaultdict(list)
    for c in m.delaunay:
        for a, b in itertools.combinations(c, 2):
            around[(a, b)].append(c)
    contexts = collections.defaultdict(lambda: [0, 0])
    adaptive = 0.0  # the same flags coded in edge order by a counting (KT) model per context
    for (a, b), cells in sorted(around.items()):
        if len(cells) != 3:
            continue
        ring = sorted(set(cells[0] + cells[1] + cells[2]) - {a, b})
        if len(ring) != 3 or orientation(p, *ring, a) * orientation(p, *ring, b) >= 0:
            continue
        before = min(least_solid_angle(p, c) for c in cells)
        after = min(least_solid_angle(p, (*ring, a)), least_solid_angle(p, (*ring, b)))
        key = (min(5, int(-math.log2(max(before, 1e-9)))),
               min(4, int(math.log2(after / max(before, 1e-12)) + 1)) if after > before else -1)
        n, k = contexts[key]
        hit = (a, b) in flipped
        p_hit = (k + 0.5) / (n + 1)
        adaptive -= math.log2(p_hit if hit else 1 - p_hit)
        contexts[key][0] += 1
        contexts[key][1] += hit
    candidates = sum(n for n, _ in contexts.values())
    hits = sum(k for _, k in contexts.values())
    one = candidates * entropy(hits / max(1, candidates))
    split = sum(n * entropy(k / n) for n, k in contexts.values())
    return candidates, hits, one, split, adaptive


def stream_bytes(model, extra, build):
    report = model[: -len(".node")] + ".exact.json"
    stream = model[: -len(".node")] + ".exact.dtm"
    subprocess.run([os.path.join(build, "tools/meshenc"), model, "--exact", "-q", "-o", stream, "--report", report] +
                   extra, check=True)
    r = json.load(open(report))
    return os.path.getsize(stream), r["exact"]["bytes"], r["levels"][0]["carving_bytes"]


def write_variant(m, model, name, regions):
    """MODEL's .node beside `name`.node, and its cells with `regions` given
    back their Delaunay cells, every cell positively oriented."""
    drop = {c for r in regions for c in r["input"]}
    cells = [c for c in m.inputs if c not in drop] + [c for r in regions for c in r["delaunay"]]
    for k, c in enumerate(cells):
        if orientation(m.points, *c) < 0:
            cells[k] = (c[1], c[0], c[2], c[3])
    base = model[: -len(".node")]
    if not os.path.exists(name + ".node"):
        os.symlink(os.path.abspath(model), name + ".node")
    # The input's numbering (the decoded one starts at 0, the .node at its first index).
    lines = [line for line in open(base + ".node") if line.strip() and not line.startswith("#")]
    first = int(lines[1].split()[0])
    shift = first - min(m.points)
    with open(name + ".ele", "w") as f:
        f.write(f"{len(cells)} 4 0\n")
        for i, c in enumerate(cells):
            f.write(f"{i + first} {' '.join(str(v + shift) for v in c)}\n")
    return name + ".node"


def main():
    model, build, extra = split_arguments(sys.argv[1:])
    m = Comparison(model, build, extra)
    flips, ties = m.one_flips(), m.ties()
    candidates, hits, one, split, adaptive = flag_bits(m, flips)
    name = os.path.basename(model)
    print(f"{name}: {len(flips)} one-flip regions, {len(ties)} coplanar 2 -> 2 ties")
    print(f"  valid 3-2 flips in the kept Delaunay cells: {candidates}, the input's {hits}; a flag each: "
          f"{one:.0f} bits in one context ({one / max(1, hits):.2f} a flip), {split:.0f} in the solid-angle "
          f"contexts ({split / max(1, hits):.2f} a flip; {adaptive / max(1, hits):.2f} a flip coded adaptively)")
    now = stream_bytes(model, extra, build)
    print(f"  --exact: stream, exact section, level-0 carving: {now[0]}, {now[1]}, {now[2]} bytes")
    base = model[: -len(".node")]
    for label, regions, suffix in (("one-flip regions", flips, "_no_flips"), ("ties", ties, "_no_ties")):
        if not regions:
            continue
        variant = write_variant(m, model, base + suffix, regions)
        then = stream_bytes(variant, extra, build)
        print(f"  its {label} made Delaunay: {then[0]}, {then[1]}, {then[2]} bytes; they cost "
              f"{8 * (now[0] - then[0]) / len(regions):.2f} bits each today")


if __name__ == "__main__":
    main()
