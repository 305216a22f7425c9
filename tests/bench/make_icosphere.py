#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes a unit icosphere as OFF: 20 * 4^K triangles (K = 8: 1,310,720), for the large-mesh timings
of gpc / mesh2spline.  Usage: make_icosphere.py K OUT.off"""
import sys, math
k = int(sys.argv[1]); out = sys.argv[2]
t = (1 + 5 ** 0.5) / 2
V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
V = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in V]
F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
for _ in range(k):
    cache = {}
    def mid(a, b):
        key = (a, b) if a < b else (b, a)
        if key in cache: return cache[key]
        p = [(V[a][i] + V[b][i]) / 2 for i in range(3)]; n = math.sqrt(sum(x * x for x in p))
        V.append(tuple(x / n for x in p)); cache[key] = len(V) - 1; return cache[key]
    G = []
    for a, b, c in F:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        G += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    F = G
with open(out, 'w') as f:
    f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
    f.write("".join("%.9f %.9f %.9f\n" % v for v in V))
    f.write("".join("3 %d %d %d\n" % tri for tri in F))
