#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Generated held-out solids: marching tetrahedra (Freudenthal split of a cubic lattice) of an
# implicit solid f < 0, written as a closed, consistently oriented OFF mesh. These shapes are not
# among ../shared/data's meshes and check gpc / mesh2spline on layouts they were not tuned on.
# usage: make_implicit_solid.py NAME CELLS OUT.off   (NAME: dtorus pretzel mug plate2 grid4
#        ring_fin star suitcase trihole frame wheel ladder hand chair ball3 bottle twocup bent; CELLS: lattice cells per side, e.g. 64)
import sys, math
def mt(f, lo, hi, n, out):
    h = [(hi[d]-lo[d])/n for d in range(3)]
    N = n+1
    val = [0.0]*(N*N*N)
    idx = lambda i,j,k: (i*N+j)*N+k
    for i in range(N):
        x = lo[0]+i*h[0]
        for j in range(N):
            y = lo[1]+j*h[1]
            for k in range(N):
                v = f(x, y, lo[2]+k*h[2])
                if abs(v) < 1e-9: v = 1e-9
                val[idx(i,j,k)] = v
    # push values away from 0 relative to neighbours so no crossing lands on a grid vertex
    verts = {}; P = []; T = []
    def vid(a, b):
        key = (a, b) if a < b else (b, a)
        r = verts.get(key)
        if r is not None: return r
        va, vb = val[a], val[b]
        t = va/(va-vb); t = min(max(t, 0.08), 0.92)
        pa = pos(a); pb = pos(b)
        P.append([pa[d]+t*(pb[d]-pa[d]) for d in range(3)]); verts[key] = len(P)-1
        return len(P)-1
    def pos(a):
        k = a % N; j = (a//N) % N; i = a//(N*N)
        return (lo[0]+i*h[0], lo[1]+j*h[1], lo[2]+k*h[2])
    perms = [(0,1,2),(0,2,1),(1,0,2),(1,2,0),(2,0,1),(2,1,0)]
    for i in range(n):
        for j in range(n):
            for k in range(n):
                base = (i,j,k)
                for p in perms:
                    c = list(base); tet = [idx(*c)]
                    for ax in p:
                        c[ax] += 1; tet.append(idx(*c))
                    s = [val[v] < 0 for v in tet]
                    ns = sum(s)
                    if ns == 0 or ns == 4: continue
                    # orientation of tet
                    a,b,cc,d = [pos(v) for v in tet]
                    u=[b[q]-a[q] for q in range(3)]; v=[cc[q]-a[q] for q in range(3)]; w=[d[q]-a[q] for q in range(3)]
                    det = u[0]*(v[1]*w[2]-v[2]*w[1])-u[1]*(v[0]*w[2]-v[2]*w[0])+u[2]*(v[0]*w[1]-v[1]*w[0])
                    ins = [t for t,q in zip(tet,s) if q]; outs = [t for t,q in zip(tet,s) if not q]
                    tris = []
                    if ns == 1:
                        a0 = ins[0]; tris.append([vid(a0,o) for o in outs])
                    elif ns == 3:
                        o0 = outs[0]; tris.append([vid(o0,q) for q in ins])
                    else:
                        i0,i1 = ins; o0,o1 = outs
                        q = [vid(i0,o0), vid(i0,o1), vid(i1,o1), vid(i1,o0)]
                        tris += [[q[0],q[1],q[2]],[q[0],q[2],q[3]]]
                    for t in tris:
                        # orient: normal should point from inside to outside
                        A,B,C = [P[x] for x in t]
                        nx = [(B[1]-A[1])*(C[2]-A[2])-(B[2]-A[2])*(C[1]-A[1]),(B[2]-A[2])*(C[0]-A[0])-(B[0]-A[0])*(C[2]-A[2]),(B[0]-A[0])*(C[1]-A[1])-(B[1]-A[1])*(C[0]-A[0])]
                        ci = [sum(pos(x)[q] for x in ins)/len(ins) for q in range(3)]
                        co = [sum(pos(x)[q] for x in outs)/len(outs) for q in range(3)]
                        dirn = [co[q]-ci[q] for q in range(3)]
                        if sum(nx[q]*dirn[q] for q in range(3)) < 0: t = [t[0],t[2],t[1]]
                        T.append(t)
    with open(out,'w') as fo:
        fo.write('OFF\n%d %d 0\n' % (len(P), len(T)))
        for p in P: fo.write('%.7f %.7f %.7f\n' % tuple(p))
        for t in T: fo.write('3 %d %d %d\n' % tuple(t))
    print(out, len(P), len(T))

def torus(x,y,z,R,r): q = math.sqrt(x*x+y*y)-R; return math.sqrt(q*q+z*z)-r
def smin(a,b,k):
    h = max(k-abs(a-b),0.0)/k; return min(a,b)-h*h*k*0.25
def box(x,y,z,a,b,c):
    qx,qy,qz = abs(x)-a, abs(y)-b, abs(z)-c
    o = math.sqrt(max(qx,0)**2+max(qy,0)**2+max(qz,0)**2); return o+min(max(qx,qy,qz),0)
def capsule(p, a, b, r):
    pa=[p[i]-a[i] for i in range(3)]; ba=[b[i]-a[i] for i in range(3)]
    t=max(0,min(1,sum(pa[i]*ba[i] for i in range(3))/sum(x*x for x in ba)))
    return math.sqrt(sum((pa[i]-t*ba[i])**2 for i in range(3)))-r
def rot(x,y,a): c,s=math.cos(a),math.sin(a); return c*x-s*y, s*x+c*y
def trihole(x,y,z):
    d=1e9
    for k in range(3):
        cx,cy=rot(0.9,0,2*math.pi*k/3); d=smin(d, torus(x-cx,y-cy,z,0.75,0.22),0.25)
    return d
def star(x,y,z):
    d=math.sqrt(x*x+y*y+z*z)-0.6
    for a in ((1,0,0),(-1,0,0),(0,1,0),(0,-1,0),(0,0,1),(0,0,-1)):
        d=smin(d, capsule((x,y,z),(0,0,0),(1.5*a[0],1.5*a[1],1.5*a[2]),0.22),0.2)
    return d
def frame(x,y,z):
    d=1e9
    for a in range(3):
        for s1 in (-1,1):
            for s2 in (-1,1):
                p=[0.0,0.0,0.0]; q=[0.0,0.0,0.0]
                b,c=(a+1)%3,(a+2)%3
                p[a],q[a]=-1.0,1.0; p[b]=q[b]=s1; p[c]=q[c]=s2
                d=smin(d, capsule((x,y,z),p,q,0.2),0.15)
    return d
def wheel(x,y,z):
    d=smin(torus(x,y,z,1.2,0.16), math.sqrt(x*x+y*y+z*z)-0.3, 0.1)
    for k in range(5):
        cx,cy=rot(1.2,0,2*math.pi*k/5+0.3); d=smin(d, capsule((x,y,z),(0,0,0),(cx,cy,0),0.1),0.1)
    return d
def ladder(x,y,z):
    d=smin(capsule((x,y,z),(-0.6,-1.5,0),(-0.6,1.5,0),0.15), capsule((x,y,z),(0.6,-1.5,0),(0.6,1.5,0),0.15),0.1)
    for yy in (-1.1,-0.35,0.35,1.1):
        d=smin(d, capsule((x,y,z),(-0.6,yy,0),(0.6,yy,0),0.12),0.1)
    return d
def hand(x,y,z):
    d=box(x,y,z,0.5,0.12,0.45)-0.08
    d=smin(d, capsule((x,y,z),(0,0,-0.4),(0,0,-1.3),0.22),0.15)
    for fx,L in ((-0.36,0.75),(-0.12,0.9),(0.12,0.85),(0.36,0.7)):
        d=smin(d, capsule((x,y,z),(fx,0,0.4),(fx,0,0.4+L),0.09),0.06)
    return smin(d, capsule((x,y,z),(0.5,0,-0.1),(1.0,0,0.35),0.1),0.08)
def chair(x,y,z):
    d=box(x,y,z,0.6,0.6,0.06)-0.02
    for sx in (-1,1):
        for sy in (-1,1):
            d=smin(d, capsule((x,y,z),(0.5*sx,0.5*sy,0),(0.5*sx,0.5*sy,-0.9),0.06),0.05)
    return smin(d, box(x,y-0.56,z-0.6,0.6,0.05,0.6)-0.02, 0.05)
def ball3(x,y,z):
    d=math.sqrt(x*x+y*y+z*z)-0.9
    for k in range(3):
        c,s=math.cos(2*math.pi*k/3),math.sin(2*math.pi*k/3)
        d=smin(d, torus(x*c+y*s-0.95, z, -x*s+y*c, 0.4, 0.1), 0.08)
    return d
def bottle(x,y,z):
    body=math.sqrt(x*x+y*y)-0.6 if abs(z)<0.7 else math.sqrt(x*x+y*y+(abs(z)-0.7)**2)-0.6
    return smin(body, capsule((x,y,z),(0,0,0.8),(0,0,1.8),0.15), 0.3)
def twocup(x,y,z):
    d=max(math.sqrt(x*x+y*y)-0.7, abs(z)-0.9)-0.05
    return smin(smin(d, torus(x-0.8,z,y,0.45,0.12),0.12), torus(x+0.8,z,y,0.45,0.12),0.12)
def bent(x,y,z):
    th=math.atan2(y,x); return torus(x,y,z,1.0,0.1+0.3*(0.5+0.5*math.cos(th)))
def holecube(x,y,z):
    d=box(x,y,z,0.8,0.8,0.8)-0.12
    for a,b in ((x,y),(y,z),(z,x)):
        d=max(d, -(math.sqrt(a*a+b*b)-0.35))
    return d
def glasses(x,y,z):
    d=1e9
    for sx in (-1,1):
        d=smin(d, torus(x-0.75*sx,z,y,0.55,0.09),0.06)
        d=smin(d, capsule((x,y,z),(1.3*sx,0,0),(1.35*sx,1.6,-0.1),0.07),0.06)
    return smin(d, capsule((x,y,z),(-0.25,0,0.3),(0.25,0,0.3),0.07),0.06)
def gemring(x,y,z):
    return smin(torus(x,y,z,0.9,0.13), math.sqrt((x-1.15)**2+y*y+z*z)-0.35, 0.12)
def tee(x,y,z):
    d=smin(capsule((x,y,z),(-1.4,0,0),(1.4,0,0),0.4), capsule((x,y,z),(0,0,0),(0,0,-1.5),0.35),0.2)
    return max(d, -capsule((x,y,z),(0,-1,0),(0,1,0),0.16))
def fork(x,y,z):
    d=capsule((x,y,z),(0,-2.0,0),(0,0.2,0),0.12)
    d=smin(d, box(x,y-0.35,z,0.3,0.15,0.05)-0.03,0.1)
    for fx in (-0.25,0.0,0.25):
        d=smin(d, capsule((x,y,z),(fx,0.4,0),(fx,1.4,0),0.05),0.05)
    return d
def rings2(x,y,z):
    return smin(torus(x+0.75,y,z,0.8,0.16), torus(x-0.75,z,y,0.8,0.16), 0.1)
def key(x,y,z):
    d=smin(torus(x+1.1,z,y,0.45,0.12), capsule((x,y,z),(-0.6,0,0),(1.6,0,0),0.1),0.08)
    for tx in (0.9,1.2,1.45):
        d=smin(d, box(x-tx,y,z+0.18,0.05,0.06,0.14),0.04)
    return d
def coil(x,y,z):
    d=1e9
    for k in range(96):
        t0,t1=k/96.0,(k+1)/96.0
        p=lambda t:(0.8*math.cos(6*math.pi*t),0.8*math.sin(6*math.pi*t),-1.0+2.0*t)
        d=min(d, capsule((x,y,z),p(t0),p(t1),0.16))
    return d
def smoothcube(x,y,z):
    # the drilled cube with its edges blended (no crease)
    d=box(x,y,z,0.8,0.8,0.8)-0.12
    for a,b in ((x,y),(y,z),(z,x)):
        d=-smin(-d, math.sqrt(a*a+b*b)-0.35, 0.15)
    return d
def cubeframe(x,y,z):
    d=1e9
    for i in range(3):
        for s1 in (-0.8,0.8):
            for s2 in (-0.8,0.8):
                a=[0,0,0]; b=[0,0,0]; a[i]=-0.8; b[i]=0.8
                a[(i+1)%3]=b[(i+1)%3]=s1; a[(i+2)%3]=b[(i+2)%3]=s2
                d=smin(d, capsule((x,y,z),a,b,0.15),0.08)
    return d
shapes = {
 # genus 2: two tori blended
 'dtorus': (lambda x,y,z: smin(torus(x+0.9,y,z,0.9,0.3), torus(x-0.9,y,z,0.9,0.3), 0.3), (-2.2,-1.3,-0.5),(2.2,1.3,0.5)),
 # genus 3: three tori in a row, thinner
 'pretzel': (lambda x,y,z: smin(smin(torus(x+1.5,y,z,0.8,0.25), torus(x,y,z,0.8,0.25),0.25), torus(x-1.5,y,z,0.8,0.25),0.25), (-2.7,-1.2,-0.4),(2.7,1.2,0.4)),
 # genus 1: mug = rounded cylinder body + handle
 'mug': (lambda x,y,z: smin(max(math.sqrt(x*x+y*y)-0.8, abs(z)-1.0)-0.05, torus(x-0.9, z, y, 0.55, 0.15), 0.15), (-1.0,-1.0,-1.2),(1.8,1.0,1.2)),
 # genus 2: plate with two round holes (creases softened by rounding)
 'plate2': (lambda x,y,z: max(box(x,y,z,1.6,0.8,0.2)-0.08, -(math.sqrt((x+0.75)**2+y*y)-0.4), -(math.sqrt((x-0.75)**2+y*y)-0.4)), (-1.9,-1.1,-0.4),(1.9,1.1,0.4)),
 # genus 4: square plate with 2 x 2 round holes
 'grid4': (lambda x,y,z: max(box(x,y,z,1.3,1.3,0.22)-0.08, -(math.sqrt((x+0.6)**2+(y+0.6)**2)-0.33), -(math.sqrt((x-0.6)**2+(y+0.6)**2)-0.33), -(math.sqrt((x+0.6)**2+(y-0.6)**2)-0.33), -(math.sqrt((x-0.6)**2+(y-0.6)**2)-0.33)), (-1.5,-1.5,-0.4),(1.5,1.5,0.4)),
 # genus 1: torus with a thin flat fin
 'ring_fin': (lambda x,y,z: smin(torus(x,y,z,1.0,0.28), box(x-1.6,y,z,0.6,0.5,0.07)-0.02, 0.15), (-1.4,-1.4,-0.4),(2.3,1.4,0.4)),
 # genus 0: ball with 6 capsule limbs along the axes
 'star': (star, (-1.85,-1.85,-1.85),(1.85,1.85,1.85)),
 # genus 1: rounded box with a thin handle on its top
 'suitcase': (lambda x,y,z: smin(box(x,y,z,1.0,0.35,0.7)-0.1, torus(x, z-0.95, y, 0.4, 0.09), 0.08), (-1.25,-0.5,-0.85),(1.25,0.5,1.5)),
 # genus 3: three tori in a triangle
 'trihole': (trihole, (-2.0,-2.0,-0.35),(2.0,2.0,0.35)),
 # genus 5: the 12 edges of a cube as round bars, a 3-way junction at every corner
 'frame': (frame, (-1.3,-1.3,-1.3),(1.3,1.3,1.3)),
 # genus 5: a rim with 5 spokes meeting at a hub (a 5-way junction)
 'wheel': (wheel, (-1.45,-1.45,-0.3),(1.45,1.45,0.3)),
 # genus 3: two rails joined by 4 rungs
 'ladder': (ladder, (-0.85,-1.75,-0.25),(0.85,1.75,0.25)),
 # genus 0: a palm with 4 close fingers, a thumb and a wrist (a many-way junction of thin limbs)
 'hand': (hand, (-0.75,-0.35,-1.6),(1.2,0.35,1.45)),
 # genus 0: a thin seat and back on 4 thin legs
 'chair': (chair, (-0.8,-0.8,-1.05),(0.8,0.8,1.3)),
 # genus 3: a ball with 3 thin handles standing on it
 'ball3': (ball3, (-1.6,-1.6,-1.1),(1.6,1.6,1.1)),
 # genus 0: a round body with a long thin neck
 'bottle': (bottle, (-0.8,-0.8,-1.45),(0.8,0.8,2.0)),
 # genus 2: a cylinder with two handles
 'twocup': (twocup, (-1.5,-0.9,-1.1),(1.5,0.9,1.1)),
 # genus 1: a ring whose thickness varies 4 times around it
 'bent': (bent, (-1.5,-1.5,-0.5),(1.5,1.5,0.5)),
 # genus 3: a rounded cube drilled through along each axis
 'holecube': (holecube, (-1.05,-1.05,-1.05),(1.05,1.05,1.05)),
 # genus 2: two thin rings, a bridge and two temples
 'glasses': (glasses, (-1.6,-0.75,-0.7),(1.6,1.8,0.7)),
 # genus 1: a thin ring with a ball on it
 'gemring': (gemring, (-1.15,-1.15,-0.4),(1.6,1.15,0.4)),
 # genus 1: a T of round bars with a hole through the junction
 'tee': (tee, (-1.9,-0.5,-2.0),(1.9,0.5,0.5)),
 # genus 0: a handle with a flat head and three thin tines
 'fork': (fork, (-0.45,-2.2,-0.2),(0.45,1.55,0.2)),
 # genus 1: a key: a ring, a long shaft and three teeth under it
 'key': (key, (-1.75,-0.3,-0.6),(1.8,0.3,0.6)),
 # genus 0: a helix of three turns, one thin limb wound up
 # genus 5: the drilled cube with blended edges
 'smoothcube': (smoothcube, (-1.05,-1.05,-1.05),(1.05,1.05,1.05)),
 # genus 5: a cube's twelve edges as round bars
 'cubeframe': (cubeframe, (-1.05,-1.05,-1.05),(1.05,1.05,1.05)),
 'coil': (coil, (-1.1,-1.1,-1.3),(1.1,1.1,1.3)),
 # genus 2: two rings in perpendicular planes fused where they cross
 'rings2': (rings2, (-1.8,-1.05,-1.05),(1.8,1.05,1.05)),
}
if len(sys.argv) != 4 or sys.argv[1] not in shapes:
    sys.exit("usage: make_implicit_solid.py NAME CELLS OUT.off; NAME one of " + " ".join(sorted(shapes)))
f, lo, hi = shapes[sys.argv[1]]
mt(f, lo, hi, int(sys.argv[2]), sys.argv[3])
