"""Fits of bench/scaling/run.sh output (docs/parallel.md, "Scaling"): python3 fit.py scale.txt"""
import sys
import re, math
def lstsq(A, y):  # normal equations, small
    n=len(A[0]); M=[[sum(a[i]*a[j] for a in A) for j in range(n)] for i in range(n)]; b=[sum(a[i]*v for a,v in zip(A,y)) for i in range(n)]
    for i in range(n):  # Gauss-Jordan
        p=max(range(i,n),key=lambda r:abs(M[r][i])); M[i],M[p]=M[p],M[i]; b[i],b[p]=b[p],b[i]
        for r in range(n):
            if r!=i:
                f=M[r][i]/M[i][i]; M[r]=[x-f*z for x,z in zip(M[r],M[i])]; b[r]-=f*b[i]
    return [b[i]/M[i][i] for i in range(n)]
rows=[]
for l in open(sys.argv[1]):
    m=re.match(r'm(\d+)k_np(\d+) (\d+) (\d+) [\d.]+ coll/step ([\d.]+) rss_mb \[([^\]]*)\] tets \[([^\]]*)\] B/step \[([^\]]*)\] msg/step \[([^\]]*)\]', l)
    if not m: continue
    f=lambda g:[float(x) for x in m.group(g).split(',')]
    rows.append(dict(N=int(m.group(3)),P=int(m.group(2)),steps=int(m.group(4)),coll=float(m.group(5)),rss=f(6),tets=f(7),B=f(8),msg=f(9)))
A=[];y=[]
for r in rows:
    for k in range(1,r['P']): A.append([1,r['tets'][k],r['N']]); y.append(r['rss'][k])
c=lstsq(A,y); print('ranks>0: RSS = %.1f MB + %.0f B x part tets + %.1f B x whole tets'%(c[0],c[1]*1e6,c[2]*1e6), 'max rel err %.3f'%max(abs(sum(a*b for a,b in zip(x,c))-v)/v for x,v in zip(A,y)))
A=[];y=[]
for r in rows: A.append([1,r['tets'][0],r['N']]); y.append(r['rss'][0])
c0=lstsq(A,y); print('rank 0:  RSS = %.1f MB + %.0f B x part tets + %.1f B x whole tets'%(c0[0],c0[1]*1e6,c0[2]*1e6), 'max rel err %.3f'%max(abs(sum(a*b for a,b in zip(x,c0))-v)/v for x,v in zip(A,y)))
S=[[1,r['steps']] for r in rows if r['P']==2]; t=[r['coll']*r['steps'] for r in rows if r['P']==2]
k=lstsq(S,t); print('collectives = %.1f + %.2f per step'%(k[0],k[1]))
X=[];Y=[]
for r in rows:
    if r['P']>1: X.append(math.log(r['N']/r['P'])); Y.append(math.log(max(r['B'])))
n=len(X); mx=sum(X)/n; my=sum(Y)/n; s=sum((x-mx)*(y-my) for x,y in zip(X,Y))/sum((x-mx)**2 for x in X); print('max ghost B/step = %.1f (N/P)^%.2f'%(math.exp(my-s*mx),s))
g=math.exp(sum(y-2/3*x for x,y in zip(X,Y))/n); print('with exponent 2/3: %.1f (N/P)^(2/3)'%g)
print('N P | rss rank0 | rss others max | max B/step | max msg/step')
for r in rows: print(r['N'],r['P'],r['rss'][0],max(r['rss'][1:]) if r['P']>1 else '-',max(r['B']),max(r['msg']))
