# exact_carving_sim.py DUMP [VARIANTS]: level 0's carving bits of an exact stream
# under other contexts, replayed with the coder's adaptive bits
# (research/exact_carving_models.md; DUMP from research/exact_carving_dump.patch).
import sys, math
from collections import defaultdict
STEPS=[0.29730177875068026,0.3535533905932738,0.42044820762685725,0.5,0.5946035575013605,0.7071067811865476,0.8408964152537145,1.0,1.189207115002721,1.4142135623730951,1.681792830507429,2.0,2.378414230005442,2.8284271247461903,3.363585661014858]
LOG=[0.0]*65537
for i in range(1,65536): LOG[i]=-math.log2(i/65536.0)
class Bit:
    __slots__=('p0','seen')
    def __init__(s): s.p0=32768; s.seen=0
def cost_update(m,b):
    r=min(7,(m.seen+2).bit_length())
    if b: c=LOG[65536-m.p0]; m.p0-=m.p0>>r
    else: c=LOG[m.p0]; m.p0+=(65536-m.p0)>>r
    if m.seen<255: m.seen+=1
    return c
def load(path):
    cells=[]
    for line in open(path):
        t=line.split()
        i=int(t[0]); nb=[int(x) for x in t[1:5]]
        cells.append(dict(nb=nb,alpha=int(t[5]),truth=int(t[6]),s=[float(x) for x in t[7:11]],q=float(t[11])/18**0.5,ratio=float(t[12]),nvb=int(t[13]),nvf=int(t[14]),fb=int(t[15])))
    return cells
def run(cells, ctxfn):
    models=defaultdict(Bit)
    n=len(cells)
    kept=[c['alpha'] for c in cells]
    wrong=[0]*n; decoded=[False]*n; wrongrem=[0]*n
    total=0.0
    for i,c in enumerate(cells):
        st=dict(kept=kept,wrong=wrong,decoded=decoded,i=i)
        key=ctxfn(c,st)
        b= c['alpha']!=c['truth']
        total+=cost_update(models[key],b)
        decoded[i]=True
        if b:
            kept[i]^=1
            for nb in c['nb']:
                if nb>=0: wrong[nb]+=1
    return total
def bucket(r): return sum(1 for t in STEPS if r>t*1.0)
def mb(s,steps=(0.06,0.17,0.39)):
    m=min(s); return sum(1 for t in steps if m>t)
def sb(q): return (q>0.05)+(q>0.2)
def keptn(c,st): return sum(1 for nb in c['nb'] if nb>=0 and st['kept'][nb])
def base(c,st): return (bucket(c['ratio'])//2, keptn(c,st), min(st['wrong'][st['i']],2))
V={}
V['cur']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']))
V['+nvb']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),min(c['nvb'],4))
V['+nvb3']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),min(c['nvb'],2))
V['+nlow']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),min(sum(1 for x in c['s'] if x<0.17),2))
V['margin6']=lambda c,st: base(c,st)+(mb(c['s'],(0.02,0.06,0.11,0.17,0.39)),sb(c['q']))
V['shape4']=lambda c,st: base(c,st)+(mb(c['s']),sum(1 for t in (0.05,0.2,0.4) if c['q']>t))
V['nobucket']=lambda c,st: (min(bucket(c['ratio'])//2,4),keptn(c,st), min(st['wrong'][st['i']],2),mb(c['s']),sb(c['q']))
V['+nvf']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),min(c['nvf'],1))
V['+fb']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),c['fb'])
V['+alpha']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),c['alpha'])
def ndec(c,st): return sum(1 for nb in c['nb'] if nb>=0 and st['decoded'][nb])
V['+ndec']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),min(ndec(c,st),3))
V['+ndec2']=lambda c,st: base(c,st)+(mb(c['s']),sb(c['q']),ndec(c,st)>=2)
V['nob+ndec']=lambda c,st: (min(bucket(c['ratio'])//2,4),keptn(c,st), min(st['wrong'][st['i']],2),mb(c['s']),sb(c['q']),min(ndec(c,st),3))
if __name__=='__main__':
    names=sys.argv[2].split(',') if len(sys.argv)>2 else list(V)
    cells=load(sys.argv[1])
    ones=sum(1 for c in cells if c['alpha']!=c['truth'])
    print(sys.argv[1].split('/')[-1], 'cells',len(cells),'wrong',ones, ' '.join('%s=%.0f'%(k,run(cells,V[k])) for k in names))
