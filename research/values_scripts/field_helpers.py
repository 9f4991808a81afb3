import numpy as np
def lsq_pred(P, v, known, query, k=8):
    """local linear (plane) fit over the k nearest known points, evaluated at the query."""
    Kp = P[known]; Kv = v[known].astype(float); out = np.empty(len(query)); spr = np.empty(len(query))
    for s in range(0, len(query), 256):
        Q = P[query[s:s + 256]]
        d2 = ((Q[:, None, :] - Kp[None]) ** 2).sum(-1); nn = np.argpartition(d2, k - 1, 1)[:, :k]
        for t in range(len(Q)):
            A = np.c_[np.ones(k), Kp[nn[t]] - Q[t]]; y = Kv[nn[t]]
            w = np.linalg.lstsq(A, y, rcond=1e-6)[0]
            m = y.mean(); out[s + t] = w[0] if abs(w[0] - m) <= 2 * (y.max() - y.min()) + 1 else m
            spr[s + t] = y.max() - y.min()
    return out, spr

