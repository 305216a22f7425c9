#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# Reads a Bézier .vtu that `volspline mesh2spline --vtk` (or vol2spline --vtk) wrote with VTK
# (Debian python3-vtk9) and checks it against the spline JSON:
#   - every cell is VTK_BEZIER_HEXAHEDRON (79) with 64 points and HigherOrderDegrees (3, 3, 3);
#   - VTK's own evaluation (vtkBezierHexahedron.EvaluateLocation) at random parametric points of
#     random cells agrees with `volspline eval` at the matching uvw to 1e-12 relative to the bbox;
#   - optionally, the scaled Jacobian from VTK's shape-function derivatives (InterpolateDerivs)
#     at 4×4×4 Gauss points of every cell is positive wherever scaled_jacobian_min (the
#     certificate) is ≥ 0, and the count of cells with a negative Gauss value is printed.
# usage: check_bezier_vtu.py VOLSPLINE SPLINE.json OUT.vtu [--samples N] [--gauss]
import json
import random
import subprocess
import sys

import vtk

# 4-point Gauss–Legendre nodes on [0, 1].
GAUSS4 = [0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
          0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526]


def array_values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
            m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def fail(message):
    print("check_bezier_vtu: FAIL: " + message)
    sys.exit(1)


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        print(__doc__ if __doc__ else "usage: check_bezier_vtu.py VOLSPLINE SPLINE.json OUT.vtu [--samples N] [--gauss]")
        sys.exit(2)
    binary, spline_path, vtu_path = args[:3]
    samples = int(args[args.index("--samples") + 1]) if "--samples" in args else 200
    gauss = "--gauss" in args

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu_path)
    reader.Update()
    grid = reader.GetOutput()
    cells = grid.GetNumberOfCells()
    if cells == 0:
        fail("no cells read from " + vtu_path)
    types = set(grid.GetCellType(c) for c in range(cells))
    if types != {79}:
        fail("cell types %s, expected all 79" % sorted(types))
    if any(grid.GetCell(c).GetNumberOfPoints() != 64 for c in range(0, cells, max(1, cells // 50))):
        fail("a cell has not 64 points")
    degrees = grid.GetCellData().GetArray("HigherOrderDegrees")
    if degrees is None or set(array_values(degrees)) != {3}:
        fail("HigherOrderDegrees missing or not (3, 3, 3)")
    for name in ("cuboid", "uvw_min", "uvw_max"):
        if grid.GetCellData().GetArray(name) is None:
            fail("cell data '%s' missing" % name)

    spline = json.load(open(spline_path))
    gpc = spline.get("format") == "volspline-gpc-spline"
    # Every cell's parameter box (cell data uvw_min, uvw_max) and cuboid.
    box_lo = array_values(grid.GetCellData().GetArray("uvw_min"))
    box_hi = array_values(grid.GetCellData().GetArray("uvw_max"))
    cuboid_of = array_values(grid.GetCellData().GetArray("cuboid"))
    if not gpc:
        # The knot-line grid of the spline: cell c of the VTU is TSpline cell c (u fastest).
        lines = []
        for a in range(3):
            values = sorted({k for f in spline["functions"] for k in f["knots"][a]})
            lines.append(values)
        nc = [len(l) - 1 for l in lines]
        if nc[0] * nc[1] * nc[2] != cells:
            fail("%d cells, the spline's knot-line grid has %d" % (cells, nc[0] * nc[1] * nc[2]))
        for c in range(0, cells, max(1, cells // 50)):
            k = [c % nc[0], (c // nc[0]) % nc[1], c // (nc[0] * nc[1])]
            if any(box_lo[3 * c + a] != lines[a][k[a]] or box_hi[3 * c + a] != lines[a][k[a] + 1] for a in range(3)):
                fail("cell %d: uvw_min/uvw_max are not its knot-line box" % c)
    bounds = grid.GetBounds()
    diagonal = ((bounds[1] - bounds[0]) ** 2 + (bounds[3] - bounds[2]) ** 2 + (bounds[5] - bounds[4]) ** 2) ** 0.5

    rng = random.Random(1)
    queries = []
    for _ in range(samples):
        c = rng.randrange(cells)
        p = [rng.random(), rng.random(), rng.random()]
        uvw = [box_lo[3 * c + a] + p[a] * (box_hi[3 * c + a] - box_lo[3 * c + a]) for a in range(3)]
        queries.append((c, p, uvw))
    out = [None] * len(queries)
    for cuboid in sorted({cuboid_of[c] for c, _, _ in queries}):
        picked = [q for q, (c, _, _) in enumerate(queries) if cuboid_of[c] == cuboid]
        command = [binary, "eval", spline_path] + (["--cuboid", str(cuboid)] if gpc else [])
        for q in picked:
            command += ["--uvw", "%.17g,%.17g,%.17g" % tuple(queries[q][2])]
        lines_out = subprocess.run(command, check=True, capture_output=True, text=True).stdout.split("\n")
        for q, line in zip(picked, lines_out):
            out[q] = line
    # D = 4 (vol2spline): the density is point data on the same Bézier net, interpolated by VTK
    # with the cell's own weights (Bernstein basis).
    density = grid.GetPointData().GetArray("density")
    if spline.get("dimension", 3) == 4 and density is None:
        fail("point data 'density' missing for a 4-dimensional spline")
    density_range = None
    worst = 0.0
    worst_density = 0.0
    for (c, p, _), line in zip(queries, out):
        expected = [float(x) for x in line.split()]
        cell = grid.GetCell(c)
        x = [0.0, 0.0, 0.0]
        weights = [0.0] * cell.GetNumberOfPoints()
        cell.EvaluateLocation(vtk.mutable(0), p, x, weights)
        worst = max(worst, max(abs(x[d] - expected[d]) for d in range(3)) / diagonal)
        if spline.get("dimension", 3) == 4:
            if density_range is None:
                density_range = max(density.GetRange()[1] - density.GetRange()[0], 1e-300)
            value = sum(weights[n] * density.GetValue(cell.GetPointId(n)) for n in range(len(weights)))
            worst_density = max(worst_density, abs(value - expected[3]) / density_range)
    print("check_bezier_vtu: %d cells, %d random points, max |VTK - eval| / diagonal = %.3g" % (cells, samples, worst))
    if worst > 1e-12:
        fail("VTK's evaluation differs from volspline eval by %.3g of the diagonal" % worst)
    if spline.get("dimension", 3) == 4:
        print("check_bezier_vtu: density: max |VTK - eval| / range of the net = %.3g" % worst_density)
        if worst_density > 1e-12:
            fail("VTK's density differs from volspline eval by %.3g of the range" % worst_density)

    if gauss:
        bound = grid.GetCellData().GetArray("scaled_jacobian_min")
        if bound is None:
            fail("cell data 'scaled_jacobian_min' missing")
        bound = array_values(bound)
        negative_cells = 0
        contradictions = 0
        lowest = 1.0
        derivs = [0.0] * (64 * 3)
        for c in range(cells):
            cell = grid.GetCell(c)
            points = cell.GetPoints()
            pts = [points.GetPoint(i) for i in range(64)]
            cell_min = 1.0
            for a in GAUSS4:
                for b in GAUSS4:
                    for g in GAUSS4:
                        cell.InterpolateDerivs([a, b, g], derivs)
                        # rows: d/dr, d/ds, d/dt of x (a Bézier cell's derivs: 3 per point)
                        jac = [[sum(derivs[n * 3 + r] * pts[n][d] for n in range(64)) for d in range(3)]
                               for r in range(3)]
                        norms = 1.0
                        for r in range(3):
                            norms *= sum(x * x for x in jac[r]) ** 0.5
                        q = det3(jac) / norms if norms > 0 else -1.0
                        cell_min = min(cell_min, q)
            lowest = min(lowest, cell_min)
            if cell_min <= 0:
                negative_cells += 1
                if bound[c] >= 0:
                    contradictions += 1
            if bound[c] > cell_min + 1e-9:
                fail("cell %d: certified bound %.6g above VTK's Gauss-point scaled Jacobian %.6g" % (c, bound[c], cell_min))
        print("check_bezier_vtu: VTK Gauss points (4x4x4 per cell): %d cells with scaled Jacobian <= 0, min %.4g; "
              "certified cells: %d, min bound %.4g" % (negative_cells, lowest, sum(1 for b in bound if b >= 0),
                                                      min(bound)))
        if contradictions:
            fail("%d certified cells have a non-positive scaled Jacobian at VTK's Gauss points" % contradictions)
    print("check_bezier_vtu: ok")


main()
