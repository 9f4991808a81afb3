#!/usr/bin/env python3
"""What 23.0's exact cell symbols would cost, from 14.0's (research/exact_closing.md).

Input: the lines a temporary dump in the exact cell coder printed while
`meshenc --exact` (14.0) coded a mesh, one file per mesh:
  F x b1 b2 filled     a filled decision: 13.0's context x, how many of the
                       face's edges have one face made boundary (b1) and two
                       or more (b2), the bit
  C x n b1 b2          a face given a cell: its context, its candidates
  K q fits closes      each candidate in the Delaunay order: whether its cell
                       fits (12.0's test), how many open faces it would close
  R rank nfit cand apex  the apex: its 14.0 rank, how many candidates fit,
                       whether it is one, its vertex
Costs are those of the coder's adaptive bits (bitstream/range_coder.h's
AdaptiveBit, replayed), in bits.
"""
import math
import sys
from collections import defaultdict


class Bit:
    __slots__ = ("p0", "seen")

    def __init__(self):
        self.p0, self.seen = 32768, 0

    def cost(self, bit):
        p = self.p0 / 65536.0
        c = -math.log2(1 - p if bit else p)
        rate = min(7, (self.seen + 2).bit_length())
        self.p0 = self.p0 - (self.p0 >> rate) if bit else self.p0 + ((65536 - self.p0) >> rate)
        self.seen = min(255, self.seen + 1)
        return c


def bits(events, context):
    models = defaultdict(Bit)
    return sum(models[context(e)].cost(e[-1]) for e in events)


def rank_bits(ranks, context):
    """Unary over 6 adaptive bits, then Exp-Golomb with adaptive prefixes."""
    models, total = defaultdict(Bit), 0.0
    for r in ranks:
        k, rank = context(r), r["rank"]
        for i in range(6):
            total += models[(k, "u", i)].cost(rank > i)
            if rank == i:
                break
        else:
            e = (rank - 6 + 1).bit_length() - 1
            total += sum(models[("p", min(i, 15))].cost(1) for i in range(e))
            total += models[("p", min(e, 15))].cost(0) + e
    return total


def read(path):
    filled, ranks, face = [], [], None
    for line in open(path):
        p = line.split()
        if p[0] == "F":
            filled.append(tuple(int(v) for v in p[1:]))
        elif p[0] == "C":
            face = dict(x=int(p[1]), K=[])
        elif p[0] == "K":
            face["K"].append(tuple(int(v) for v in p[1:]))
        elif p[0] == "R":
            face.update(cand=int(p[3]), apex=int(p[4]))
            ranks.append(face)
    return filled, ranks


def ranked(faces, key):
    """Each face's apex rank among the candidates that fit, in `key`'s order."""
    out = []
    for f in faces:
        fit = [k for k in f["K"] if k[1]]
        order = sorted(range(len(fit)), key=lambda i: key(fit[i], i))
        ids = [fit[i][0] for i in order]
        out.append(dict(f, rank=ids.index(f["apex"]) if f["cand"] and f["apex"] in ids else len(ids),
                        first=fit[order[0]][2] if fit else -1,
                        most=max([k[2] for k in f["K"]] or [-1])))
    return out


kind = lambda f: f["x"] >= 13  # a kept cell's face or a fill cell's (13.0's contexts)
for path in sys.argv[1:]:
    filled, faces = read(path)
    delaunay = ranked(faces, lambda k, i: i)
    closing = ranked(faces, lambda k, i: (-k[2], i))
    first_then_closing = ranked(faces, lambda k, i: (i > 0, -k[2], i))
    print(path, "filled: 14.0 %.0f, x edges (23.0) %.0f, x any boundary edge %.0f;" % (
        bits(filled, lambda e: e[0]), bits(filled, lambda e: (e[0], min(e[1], 2), e[2] > 0)),
        bits(filled, lambda e: (e[0], 2 if e[2] else 1 if e[1] else 0))),
        "ranks: 14.0 %.0f, all closing first %.0f, first then closing (23.0) %.0f, "
        "with the most any closes %.0f" % (
            rank_bits(delaunay, kind), rank_bits(closing, lambda f: (kind(f), f["first"])),
            rank_bits(first_then_closing, lambda f: f["first"]),
            rank_bits(first_then_closing, lambda f: (f["first"], f["most"]))))
