# exact_carving_mix.py DUMP: the same symbols coded by a logistic mix of
# the 23.0 contexts' model and two small ones (research/exact_carving_models.md).
import sys, math
from exact_carving_sim import *
from collections import defaultdict
cells=load(sys.argv[1])
def st(p): p=min(max(p,1e-4),1-1e-4); return math.log(p/(1-p))
def sq(x): return 1/(1+math.exp(-x))
class M:  # adaptive prob of 1, like AdaptiveBit
    __slots__=('p','n')
    def __init__(s): s.p=0.5; s.n=0
    def upd(s,b):
        r=min(7,(s.n+2).bit_length()); s.p+= ((1 if b else 0)-s.p)/(1<<r); s.n=min(s.n+1,255)
def run_mix(ctxfns, lr=0.02, sel=None):
    n=len(cells)
    models=[defaultdict(M) for _ in ctxfns]
    W=defaultdict(lambda: [0.3]*len(ctxfns))
    kept=[c['alpha'] for c in cells]; wrong=[0]*n; decoded=[False]*n
    total=0.0; single=0.0
    for i,c in enumerate(cells):
        s=dict(kept=kept,wrong=wrong,decoded=decoded,i=i)
        ms=[models[k][f(c,s)] for k,f in enumerate(ctxfns)]
        xs=[st(m.p) for m in ms]
        w=W[sel(c,s) if sel else 0]
        p=sq(sum(a*b for a,b in zip(w,xs)))
        p=min(max(p,1/4096),1-1/4096)
        b=c['alpha']!=c['truth']
        total+=-math.log2(p if b else 1-p)
        pm=min(max(ms[0].p,1/65536),1-1/65536); single+=-math.log2(pm if b else 1-pm)
        err=(1 if b else 0)-p
        for k in range(len(w)): w[k]+=lr*err*xs[k]
        for m in ms: m.upd(b)
        decoded[i]=True
        if b:
            kept[i]^=1
            for nb in c['nb']:
                if nb>=0: wrong[nb]+=1
    return total, single
cur=V['cur']
small1=lambda c,s:(c['alpha'],keptn(c,s),min(s['wrong'][s['i']],2),min(c['nvb'],4))
small2=lambda c,s:(mb(c['s']),sb(c['q']),bucket(c['ratio'])//2)
small3=lambda c,s:(c['alpha'],min(sum(1 for x in c['s'] if x<0.17),3),sb(c['q']),min(s['wrong'][s['i']],2))
for name,fns in [('cur alone',[cur]),('cur+s1',[cur,small1]),('cur+s1+s2',[cur,small1,small2]),('cur+s1+s2+s3',[cur,small1,small2,small3])]:
    t,sg=run_mix(fns)
    print(sys.argv[1].split('/')[-1], name, 'mixed %.0f'%t, 'cur %.0f'%sg)
