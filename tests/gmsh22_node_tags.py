#!/usr/bin/python3
"""Give an ASCII gmsh 2.2 file's nodes other tags, as files that do not
number their nodes 1 to n have them (gmsh after removing entities, an
Abaqus deck's parts from their own offsets, a solver's random ids).

    gmsh22_node_tags.py SRC DST MAP [--reverse] [--ids IDS]

MAP names each node tag t's new tag:
    3t+100     every third id from 103
    offsets    parts of 5,000 nodes from their own offsets: t + 100000 (t // 5000)
    stride     every tenth id: 10t
    random     distinct random ids below 10^9 (seeded: the same every run)
--reverse lists the $Nodes rows last first (the ids then out of order);
--ids writes the new tags in the file's node order, blank-separated.
$Elements rows name their nodes by the new tags. The file must be gmsh 2.2
ASCII (meshio.write(..., file_format="gmsh22", binary=False) gives one).
Used by tests/golden/make.sh, tests/mesher_outputs.sh and bench/node_order.sh.
"""
import argparse
import random


def tag_map(name):
    if name == "3t+100":
        return lambda t: 3 * t + 100
    if name == "offsets":
        return lambda t: t + 100000 * (t // 5000)
    if name == "stride":
        return lambda t: 10 * t
    if name == "random":
        rnd, given, used = random.Random(3), {}, set()

        def random_id(t):
            while t not in given:
                v = rnd.randrange(1, 10**9)
                if v not in used:
                    used.add(v)
                    given[t] = v
            return given[t]

        return random_id
    raise SystemExit(f"gmsh22_node_tags.py: no map {name!r} (3t+100, offsets, stride, random)")


def main():
    args = argparse.ArgumentParser(description="new node tags for a gmsh 2.2 ASCII file")
    args.add_argument("src")
    args.add_argument("dst")
    args.add_argument("map")
    args.add_argument("--reverse", action="store_true", help="list the nodes last first")
    args.add_argument("--ids", help="write the new tags here, in the file's node order")
    a = args.parse_args()
    tag = tag_map(a.map)
    lines = open(a.src).read().split("\n")
    if "$MeshFormat" not in lines or not lines[lines.index("$MeshFormat") + 1].startswith("2.2 0"):
        raise SystemExit(f"{a.src}: not an ASCII gmsh 2.2 file")
    out, ids, i = [], [], 0
    while i < len(lines):
        out.append(lines[i])
        if lines[i] in ("$Nodes", "$Elements"):
            n = int(lines[i + 1])
            out.append(lines[i + 1])
            rows = []
            for line in lines[i + 2:i + 2 + n]:
                f = line.split()
                if lines[i] == "$Nodes":
                    f[0] = str(tag(int(f[0])))
                else:  # number, type, tag count, the tags, then the nodes
                    f = f[:3 + int(f[2])] + [str(tag(int(v))) for v in f[3 + int(f[2]):]]
                rows.append(" ".join(f))
            if lines[i] == "$Nodes":
                if a.reverse:
                    rows.reverse()
                ids = [int(r.split()[0]) for r in rows]
            out += rows
            i += 2 + n
            continue
        i += 1
    open(a.dst, "w").write("\n".join(out))
    if a.ids:
        open(a.ids, "w").write(" ".join(map(str, ids)))


if __name__ == "__main__":
    main()
