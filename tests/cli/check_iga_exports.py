#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# An independent reader of the analysis exports of `volspline mesh2spline` (G+Smo XML --gismo,
# MFEM NURBS mesh --mfem, Bézier extraction JSON --bezier): it parses each file with its own
# code (no volspline code, plain Python), evaluates the B-spline patches / NURBS patches /
# Bézier cells at random points and compares them with `volspline eval` to 1e-12 of the bbox
# diagonal, and checks the topology the readers rely on:
#   - G+Smo: every patch side is in exactly one interface or boundary entry; across every
#     interface the two patches agree at random points of the side mapped by the direction map
#     and orientation flags;
#   - MFEM: corners with one vertex id coincide; every element edge is listed once, and the knot
#     vector of its class, oriented along the edge, equals the patch's knot vector there;
#   - Bézier: Σ w_f B_f = 1 on every sampled cell (semi-standard, Eq. 4.3).
# usage: check_iga_exports.py VOLSPLINE SPLINE.json [--gismo X.xml] [--mfem M.mesh]
#                             [--bezier B.json] [--samples N]
import json
import math
import random
import subprocess
import sys
import xml.etree.ElementTree as ET

TOL = 1e-12


def fail(message):
    print("check_iga_exports: FAIL: " + message)
    sys.exit(1)


def basis(knots, t):
    """Index of the first non-zero cubic basis function at t and the four values (NURBS Book A2.2)."""
    n = len(knots) - 4
    if t >= knots[n]:
        span = n - 1
        while knots[span] == knots[span + 1]:
            span -= 1
    else:
        lo, hi = 3, n
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if knots[mid] <= t:
                lo = mid
            else:
                hi = mid
        span = lo
    left, right, N = [0.0] * 4, [0.0] * 4, [1.0, 0.0, 0.0, 0.0]
    for j in range(1, 4):
        left[j] = t - knots[span + 1 - j]
        right[j] = knots[span + j] - t
        saved = 0.0
        for r in range(j):
            temp = N[r] / (right[r + 1] + left[j - r])
            N[r] = saved + right[r + 1] * temp
            saved = left[j - r] * temp
        N[j] = saved
    return span - 3, N


def eval_tensor(knots, points, uvw, weights=None):
    """Tensor cubic B-spline (or NURBS with weights) at uvw; points u fastest."""
    n0, n1 = len(knots[0]) - 4, len(knots[1]) - 4
    f = [basis(knots[a], uvw[a]) for a in range(3)]
    dim = len(points[0])
    value, wsum = [0.0] * dim, 0.0
    for k in range(4):
        for j in range(4):
            for i in range(4):
                row = (f[0][0] + i) + n0 * ((f[1][0] + j) + n1 * (f[2][0] + k))
                b = f[0][1][i] * f[1][1][j] * f[2][1][k]
                w = weights[row] if weights else 1.0
                wsum += b * w
                for d in range(dim):
                    value[d] += b * w * points[row][d]
    return [v / wsum for v in value] if weights else value


def run_eval(binary, spline_path, queries, cuboids):
    """volspline eval at (cuboid, uvw) queries; one call per cuboid."""
    results = [None] * len(queries)
    by_cuboid = {}
    for q, (c, uvw) in enumerate(queries):
        by_cuboid.setdefault(c, []).append((q, uvw))
    for c, items in sorted(by_cuboid.items()):
        command = [binary, "eval", spline_path]
        if cuboids:
            command += ["--cuboid", str(c)]
        for _, uvw in items:
            command += ["--uvw", "%.17g,%.17g,%.17g" % tuple(uvw)]
        lines = subprocess.run(command, check=True, capture_output=True, text=True).stdout.split("\n")
        for (q, _), line in zip(items, lines):
            results[q] = [float(x) for x in line.split()]
    return results


def spline_info(path):
    doc = json.load(open(path))
    if doc.get("format") == "volspline-gpc-spline":
        return doc, True
    return doc, False


def compare(name, values, expected, diagonal):
    worst = 0.0
    for v, e in zip(values, expected):
        worst = max(worst, max(abs(v[d] - e[d]) for d in range(3)) / diagonal)
    print("check_iga_exports: %s: %d random points, max |file - eval| / diagonal = %.3g" % (name, len(values), worst))
    if not worst <= TOL:
        fail("%s differs from volspline eval by %.3g of the diagonal" % (name, worst))


def diagonal_of(points):
    lo = [min(p[d] for p in points) for d in range(3)]
    hi = [max(p[d] for p in points) for d in range(3)]
    return math.sqrt(sum((hi[d] - lo[d]) ** 2 for d in range(3)))


def check_gismo(binary, spline_path, path, gpc, samples, rng):
    root = ET.parse(path).getroot()
    patches = {}
    for g in root.findall("Geometry"):
        if g.get("type") != "TensorBSpline3":
            fail("G+Smo geometry type %s" % g.get("type"))
        basis_node = g.find("Basis")
        if basis_node.get("type") != "TensorBSplineBasis3":
            fail("G+Smo basis type %s" % basis_node.get("type"))
        knots = [None] * 3
        for b in basis_node.findall("Basis"):
            kv = b.find("KnotVector")
            if kv.get("degree") != "3":
                fail("G+Smo degree %s" % kv.get("degree"))
            knots[int(b.get("index"))] = [float(x) for x in kv.text.split()]
        coefs = g.find("coefs")
        dim = int(coefs.get("geoDim"))
        values = [float(x) for x in coefs.text.split()]
        points = [values[i:i + dim] for i in range(0, len(values), dim)]
        if len(points) != math.prod(len(k) - 4 for k in knots):
            fail("G+Smo patch %s: %d coefs for knot vectors of %s" % (g.get("id"), len(points), [len(k) for k in knots]))
        patches[int(g.get("id"))] = (knots, points)
    mp = root.find("MultiPatch")
    first, last = [int(x) for x in mp.find("patches").text.split()]
    if sorted(patches) != list(range(first, last + 1)):
        fail("G+Smo patch ids %s, MultiPatch range %d..%d" % (sorted(patches), first, last))
    numbers = [int(x) for x in (mp.find("interfaces").text or "").split()]
    interfaces = [numbers[i:i + 10] for i in range(0, len(numbers), 10)]
    numbers = [int(x) for x in (mp.find("boundary").text or "").split()]
    boundary = [numbers[i:i + 2] for i in range(0, len(numbers), 2)]
    sides = {}
    for it in interfaces:
        for p, s in ((it[0], it[1]), (it[2], it[3])):
            sides[(p, s)] = sides.get((p, s), 0) + 1
    for p, s in boundary:
        sides[(p, s)] = sides.get((p, s), 0) + 1
    if sorted(sides) != [(p, s) for p in sorted(patches) for s in range(1, 7)] or set(sides.values()) != {1}:
        fail("G+Smo: the patch sides are not each in exactly one interface or boundary entry")
    diagonal = diagonal_of([p for _, pts in patches.values() for p in pts])
    ids = sorted(patches)
    queries, values = [], []
    for _ in range(samples):
        p = rng.choice(ids)
        knots, points = patches[p]
        uvw = [knots[a][0] + rng.random() * (knots[a][-1] - knots[a][0]) for a in range(3)]
        queries.append((p, uvw))
        values.append(eval_tensor(knots, points, uvw))
    compare("G+Smo (%d patches)" % len(ids), values, run_eval(binary, spline_path, queries, gpc), diagonal)
    # Interfaces: side s of patch p (direction (s-1)//2 at its lower/upper end) meets patch q.
    worst = 0.0
    for it in interfaces:
        p, s, q, r = it[:4]
        dmap, orient = it[4:7], it[7:10]
        kp, pp = patches[p]
        kq, pq = patches[q]
        for _ in range(10):
            h = [kp[a][0] + rng.random() * (kp[a][-1] - kp[a][0]) for a in range(3)]
            h[(s - 1) // 2] = kp[(s - 1) // 2][-1 if (s - 1) % 2 else 0]
            g = [0.0] * 3
            for a in range(3):
                b = dmap[a]
                t = (h[a] - kp[a][0]) / (kp[a][-1] - kp[a][0])
                if a == (s - 1) // 2:
                    t = 1.0 if (r - 1) % 2 else 0.0
                elif not orient[a]:
                    t = 1.0 - t
                g[b] = kq[b][0] + t * (kq[b][-1] - kq[b][0])
            x, y = eval_tensor(kp, pp, h), eval_tensor(kq, pq, g)
            worst = max(worst, max(abs(x[d] - y[d]) for d in range(3)) / diagonal)
    print("check_iga_exports: G+Smo: %d interfaces, %d boundary sides, max gap across an interface / diagonal = %.3g"
          % (len(interfaces), len(boundary), worst))
    if not worst <= 1e-11:
        fail("G+Smo: the two sides of an interface differ by %.3g of the diagonal" % worst)


def mfem_tokens(path):
    lines = [l.split("#")[0] for l in open(path).read().split("\n")]
    if not lines[0].startswith("MFEM NURBS mesh v1.0"):
        fail("MFEM header: %r" % lines[0])
    return " ".join(lines[1:]).split()


def check_mfem(binary, spline_path, path, gpc, samples, rng):
    tok = mfem_tokens(path)
    pos = [0]

    def word():
        pos[0] += 1
        return tok[pos[0] - 1]

    def expect(name):
        w = word()
        if w != name:
            fail("MFEM: expected '%s', read '%s'" % (name, w))

    expect("dimension")
    if word() != "3":
        fail("MFEM dimension is not 3")
    expect("elements")
    elements = []
    for _ in range(int(word())):
        attr, geom = word(), word()
        if geom != "5":
            fail("MFEM element geometry %s (5 = cube)" % geom)
        elements.append([int(word()) for _ in range(8)])
    expect("boundary")
    boundary = []
    for _ in range(int(word())):
        word()
        if word() != "3":
            fail("MFEM boundary geometry is not 3 (square)")
        boundary.append([int(word()) for _ in range(4)])
    expect("edges")
    edges = {}
    for _ in range(int(word())):
        kv, v0, v1 = int(word()), int(word()), int(word())
        key = (min(v0, v1), max(v0, v1))
        if key in edges:
            fail("MFEM edge %s listed twice" % (key,))
        edges[key] = (kv, v0, v1)
    expect("vertices")
    num_vertices = int(word())
    expect("patches")
    patches = []
    for _ in elements:
        expect("knotvectors")
        if word() != "3":
            fail("MFEM patch without 3 knot vectors")
        knots = []
        for _ in range(3):
            order, ncp = int(word()), int(word())
            kv = [float(word()) for _ in range(ncp + order + 1)]
            if order != 3:
                fail("MFEM knot vector of order %d" % order)
            knots.append(kv)
        expect("dimension")
        dim = int(word())
        expect("controlpoints")
        count = math.prod(len(k) - 4 for k in knots)
        rows = [[float(word()) for _ in range(dim + 1)] for _ in range(count)]
        # Homogeneous form: (x w, y w, z w, w).
        patches.append((knots, [[r[d] / r[dim] for d in range(dim)] for r in rows], [r[dim] for r in rows]))
    if pos[0] != len(tok):
        fail("MFEM: %d words left after the patches" % (len(tok) - pos[0]))
    # Cuboid of each patch and the boxes, from the '# patch p: cuboid c' comments.
    cuboid_of = {}
    for line in open(path):
        if line.startswith("# patch "):
            p, c = line[len("# patch "):].split(": cuboid ")
            cuboid_of[int(p)] = int(c)
    if len(cuboid_of) != len(patches):
        fail("MFEM: %d '# patch p: cuboid c' comments for %d patches" % (len(cuboid_of), len(patches)))
    diagonal = diagonal_of([p for _, pts, _ in patches for p in pts])
    # Corners: MFEM's hex corner k at (0,0,0) (1,0,0) (1,1,0) (0,1,0), then w = 1.
    corner_bits = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    at_vertex = {}
    edge_knots = {}
    worst = 0.0
    for (knots, points, weights), verts in zip(patches, elements):
        if len(set(verts)) != 8 or max(verts) >= num_vertices:
            fail("MFEM element with repeated or out-of-range vertices %s" % verts)
        for k, v in enumerate(verts):
            uvw = [knots[a][-1] if corner_bits[k][a] else knots[a][0] for a in range(3)]
            x = eval_tensor(knots, points, uvw, weights)
            if v in at_vertex:
                worst = max(worst, max(abs(x[d] - at_vertex[v][d]) for d in range(3)) / diagonal)
            else:
                at_vertex[v] = x
        # MFEM's hex edges and the patch direction each runs along.
        for (a, b), direction in zip([(0, 1), (3, 2), (4, 5), (7, 6), (0, 3), (1, 2), (4, 7), (5, 6),
                                      (0, 4), (1, 5), (2, 6), (3, 7)], [0] * 4 + [1] * 4 + [2] * 4):
            key = (min(verts[a], verts[b]), max(verts[a], verts[b]))
            if key not in edges:
                fail("MFEM: element edge %s not in the edge list" % (key,))
            kv, v0, _ = edges[key]
            forward = v0 == verts[a]
            # Compared on [0, 1]: MFEM keeps one knot vector per class and maps every element to
            # its reference cube, so only the relative knot spacing must agree.
            own = [(t - knots[direction][0]) / (knots[direction][-1] - knots[direction][0]) for t in knots[direction]]
            oriented = own if forward else [1.0 - t for t in reversed(own)]
            seen = edge_knots.setdefault(kv, oriented)
            if len(seen) != len(oriented) or max(abs(s - t) for s, t in zip(seen, oriented)) > 1e-12:
                fail("MFEM: knot vector class %d differs between two edges" % kv)
    print("check_iga_exports: MFEM: %d patches, %d vertices, %d edges, %d boundary faces; max corner gap / diagonal = %.3g"
          % (len(patches), num_vertices, len(edges), len(boundary), worst))
    if not worst <= 1e-11:
        fail("MFEM: corners with one vertex id lie %.3g of the diagonal apart" % worst)
    queries, values = [], []
    for _ in range(samples):
        p = rng.randrange(len(patches))
        knots, points, weights = patches[p]
        uvw = [knots[a][0] + rng.random() * (knots[a][-1] - knots[a][0]) for a in range(3)]
        queries.append((cuboid_of[p], uvw))
        values.append(eval_tensor(knots, points, uvw, weights))
    compare("MFEM", values, run_eval(binary, spline_path, queries, gpc), diagonal)



def bernstein(t):
    s = 1.0 - t
    return [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]


def check_bezier(binary, spline_path, path, gpc, samples, rng):
    doc = json.load(open(path))
    if doc.get("format") != "volspline-bezier-extraction" or doc.get("degree") != [3, 3, 3]:
        fail("Bézier JSON: format/degree")
    points, weights, rows, cells = doc["control_points"], doc["weights"], doc["univariate"], doc["cells"]
    diagonal = diagonal_of(points)
    queries, values, worst_unity = [], [], 0.0
    for _ in range(samples):
        cell = rng.choice(cells)
        s = [rng.random() for _ in range(3)]
        B = [bernstein(t) for t in s]
        value, unity = [0.0, 0.0, 0.0], 0.0
        for f, (iu, iv, iw) in zip(cell["functions"], cell["extraction"]):
            # B_f(s) = Σ_m C[f][m] Bernstein_m(s), C[f][i + 4j + 16k] = U[iu][i] U[iv][j] U[iw][k].
            bf = (sum(rows[iu][i] * B[0][i] for i in range(4)) * sum(rows[iv][j] * B[1][j] for j in range(4)) *
                  sum(rows[iw][k] * B[2][k] for k in range(4)))
            unity += weights[f] * bf
            for d in range(3):
                value[d] += weights[f] * bf * points[f][d]
        worst_unity = max(worst_unity, abs(unity - 1.0))
        uvw = [cell["uvw_min"][a] + s[a] * (cell["uvw_max"][a] - cell["uvw_min"][a]) for a in range(3)]
        queries.append((cell["cuboid"], uvw))
        values.append(value)
    print("check_iga_exports: Bézier: %d cells, %d univariate rows, max |Σ w B - 1| = %.3g" % (len(cells), len(rows), worst_unity))
    if not worst_unity <= 1e-12:
        fail("Bézier: Σ w_f B_f differs from 1 by %.3g" % worst_unity)
    compare("Bézier", values, run_eval(binary, spline_path, queries, gpc), diagonal)


def main():
    args = sys.argv[1:]
    if len(args) < 2:
        print("usage: check_iga_exports.py VOLSPLINE SPLINE.json [--gismo X.xml] [--mfem M.mesh] [--bezier B.json] [--samples N]")
        sys.exit(2)
    binary, spline_path = args[:2]
    samples = int(args[args.index("--samples") + 1]) if "--samples" in args else 200
    _, gpc = spline_info(spline_path)
    rng = random.Random(7)
    if "--gismo" in args:
        check_gismo(binary, spline_path, args[args.index("--gismo") + 1], gpc, samples, rng)
    if "--mfem" in args:
        check_mfem(binary, spline_path, args[args.index("--mfem") + 1], gpc, samples, rng)
    if "--bezier" in args:
        check_bezier(binary, spline_path, args[args.index("--bezier") + 1], gpc, samples, rng)
    print("check_iga_exports: ok")


if __name__ == "__main__":
    main()
