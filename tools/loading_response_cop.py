#!/usr/bin/env python3
"""Where the ground force acts at each stance's loading response, as loaded and after residual
reduction (docs/residual-reduction.md, "The knee moments reduction moves, and why").

Per stance (not within 10 frames of the take's ends), the frame of the knee extensor peak in
its first 40 %; there the centre of pressure ahead of the ankle along the foot's heading (ankle
to toe joint, horizontal) and the anterior-posterior ground force, in body weights; medians.

Inputs, all written by articula (PREFIX is any path prefix):
  articula anatomy TAKE --mass M --consistent off -o PREFIXa_off.csv   (and on: PREFIXa_on.csv)
  articula id TAKE --mass M --joints ball --contact feet --consistent off -o PREFIXi_off.csv  (and on)
  articula export positions TAKE -o PREFIXp.csv
Usage: loading_response_cop.py PREFIX ANKLE_L ANKLE_R TOE_L TOE_R MASS_KG UP_AXIS
  e.g. loading_response_cop.py /tmp/bw Foot_L Foot_R Toes_L Toes_R 75 y   (the Bandai walk)
The ankle is the unadjusted motion's: the pelvis offset moves it by a few centimetres.
"""
import csv,sys,statistics as st
pre=sys.argv[1]; ankle={'left':sys.argv[2],'right':sys.argv[3]}; toe={'left':sys.argv[4],'right':sys.argv[5]}; mass=float(sys.argv[6])
off=list(csv.DictReader(open(pre+'a_off.csv'))); on=list(csv.DictReader(open(pre+'a_on.csv')))
gi=list(csv.DictReader(open(pre+'i_off.csv'))); go=list(csv.DictReader(open(pre+'i_on.csv')))
p=list(csv.DictReader(open(pre+'p.csv')))
up=sys.argv[7]; hz=[a for a in 'xyz' if a!=up]
res={}
for side,s in (('left','l'),('right','r')):
    ko=[float(r[f'moment:knee_{s}:flexion']) for r in off]; kn=[float(r[f'moment:knee_{s}:flexion']) for r in on]
    c=[float(r[f'contact:{side}']) for r in off]; n=len(c); i=0
    while i<n:
        if c[i]>0 and (i==0 or c[i-1]==0):
            j=i
            while j<n and c[j]>0: j+=1
            if i>10 and j<n-10:
                w=range(i,i+max(1,int(.4*(j-i))))
                for tag,k_,g in (('off',max(w,key=lambda k:ko[k]),gi),('on',max(w,key=lambda k:kn[k]),go)):
                    k=k_
                    A=[float(p[k][f'pos:{ankle[side]}:{x}']) for x in hz]; T=[float(p[k][f'pos:{toe[side]}:{x}']) for x in hz]
                    d=[T[0]-A[0],T[1]-A[1]]; L=(d[0]**2+d[1]**2)**.5; d=[d[0]/L,d[1]/L]
                    C=[float(g[k][f'cop:{side}:{x}']) for x in hz]
                    F=[float(g[k][f'grf:{side}:{x}']) for x in hz]
                    along=(C[0]-A[0])*d[0]+(C[1]-A[1])*d[1]; fa=F[0]*d[0]+F[1]*d[1]
                    kk=(ko if tag=='off' else kn)[k]
                    res.setdefault(tag,[]).append((kk/mass, along*100, fa/(mass*9.81)))
            i=j
        else: i+=1
for tag in ('off','on'):
    r=res[tag]
    print(tag, 'stances',len(r),'knee %.2f N·m/kg'%st.median(x[0] for x in r), 'COP %.1f cm ahead of ankle'%st.median(x[1] for x in r), 'AP force %.2f BW'%st.median(x[2] for x in r))
