"""Entropy measures of integer residuals (already divided by the GCD)."""
import numpy as np, math

def H0(r):
    _, c = np.unique(r, return_counts=True); p = c / c.sum()
    return float(-(p * np.log2(p)).sum())

def Hcond(r, ctx):
    tot = 0.0
    for b in np.unique(ctx):
        s = r[ctx == b]; tot += len(s) * H0(s)
    return tot / len(r)

def bucket(spread, nb=8):
    s = np.abs(np.asarray(spread, dtype=np.int64))
    b = np.zeros(len(s), dtype=np.int64)
    nz = s > 0
    b[nz] = np.floor(np.log2(s[nz])).astype(np.int64) + 1   # 0 | 1 | 2-3 | 4-7 | ...
    return np.minimum(b, nb - 1)

class Bit:
    """dtm::AdaptiveBit (bitstream/range_coder.h): p0 in 1/65536, rate min(7, bit_width(seen+2))."""
    __slots__ = ('p0', 'seen')
    def __init__(self): self.p0 = 32768; self.seen = 0
    def cost(self, bit):
        p = self.p0 / 65536.0
        c = -math.log2(1 - p if bit else p)
        rate = min(7, (self.seen + 2).bit_length())
        if bit: self.p0 -= self.p0 >> rate
        else: self.p0 += (65536 - self.p0) >> rate
        if self.seen < 255: self.seen += 1
        return c

def adaptive_bits(r, ctx=None, nctx=1):
    """Cost in bits/value of coding r with the project's binary adaptive models:
    zero flag[ctx], sign[ctx], Exp-Golomb class of |r| in unary (models[ctx][pos]),
    first mantissa bit adaptive [ctx][class], rest raw."""
    if ctx is None: ctx = np.zeros(len(r), dtype=np.int64)
    Z = [Bit() for _ in range(nctx)]; S = [Bit() for _ in range(nctx)]
    U = [[Bit() for _ in range(24)] for _ in range(nctx)]
    M = [[Bit() for _ in range(24)] for _ in range(nctx)]
    tot = 0.0
    for x, c in zip(r.tolist(), ctx.tolist()):
        tot += Z[c].cost(x != 0)
        if x == 0: continue
        tot += S[c].cost(x < 0)
        m = abs(x)                    # >= 1
        k = m.bit_length() - 1        # class: m in [2^k, 2^(k+1))
        for i in range(k): tot += U[c][i].cost(1)
        tot += U[c][k].cost(0)
        if k >= 1:
            tot += M[c][k].cost((m >> (k - 1)) & 1)
            tot += k - 1
    return tot / len(r)

def report(r, spread=None, nb=8):
    out = {'H0': H0(r), 'AC': adaptive_bits(r)}
    if spread is not None:
        b = bucket(spread, nb)
        out['H|ctx'] = Hcond(r, b); out['AC|ctx'] = adaptive_bits(r, b, nb)
    return out

def adaptive_bits2(r, ctx=None, nctx=1, tree_bits=2):
    """As adaptive_bits, but the top `tree_bits` mantissa bits are coded with adaptive models
    in a binary tree per (ctx, class); the sign model is per (ctx, class)."""
    if ctx is None: ctx = np.zeros(len(r), dtype=np.int64)
    Z = [Bit() for _ in range(nctx)]; S = {}
    U = [[Bit() for _ in range(24)] for _ in range(nctx)]
    T = {}
    tot = 0.0
    for x, c in zip(r.tolist(), ctx.tolist()):
        tot += Z[c].cost(x != 0)
        if x == 0: continue
        m = abs(x); k = m.bit_length() - 1
        for i in range(k): tot += U[c][i].cost(1)
        tot += U[c][k].cost(0)
        tot += S.setdefault((c, k), Bit()).cost(x < 0)
        node = 1
        for i in range(min(k, tree_bits)):
            b = (m >> (k - 1 - i)) & 1
            tot += T.setdefault((c, k, node), Bit()).cost(b); node = 2 * node + b
        tot += max(0, k - tree_bits)
    return tot / len(r)
