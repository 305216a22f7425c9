#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# Scaled Jacobian of every cell of a Bézier-hexahedron .vtu at N×N×N Gauss–Legendre points, from
# VTK's own shape-function derivatives (vtkBezierHexahedron.InterpolateDerivs, Debian
# python3-vtk9), against the file's certified `scaled_jacobian_min`: prints the cells with a
# non-positive value, the minimum, and any certified cell whose bound exceeds VTK's value (there
# must be none). A measurement (needs python3-numpy), not part of ctest.
# usage: vtk_gauss_quality.py OUT.vtu [--points N]   (default N = 4)
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def main():
    path = sys.argv[1]
    n = int(sys.argv[sys.argv.index("--points") + 1]) if "--points" in sys.argv else 4
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    cells = grid.GetNumberOfCells()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    connectivity = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(cells, 64)
    bound = vtk_to_numpy(grid.GetCellData().GetArray("scaled_jacobian_min"))
    nodes, _ = np.polynomial.legendre.leggauss(n)
    nodes = 0.5 * (nodes + 1.0)
    cell = grid.GetCell(0)
    derivs = []
    buffer = [0.0] * 192
    for a in nodes:
        for b in nodes:
            for g in nodes:
                cell.InterpolateDerivs([a, b, g], buffer)
                derivs.append(np.array(buffer).reshape(64, 3).T)  # (3, 64): d/dr, d/ds, d/dt
    derivs = np.array(derivs)  # (G, 3, 64)
    lowest = np.empty(cells)
    for start in range(0, cells, 2048):
        x = points[connectivity[start:start + 2048]]  # (C, 64, 3)
        jac = np.einsum("gan,cnd->cgad", derivs, x)  # rows: parametric directions
        det = np.linalg.det(jac)
        norms = np.prod(np.linalg.norm(jac, axis=3), axis=2)
        q = np.where(norms > 0, det / np.where(norms > 0, norms, 1), -1.0)
        lowest[start:start + 2048] = q.min(axis=1)
    bad = int((lowest <= 0).sum())
    contradictions = int(((bound >= 0) & (lowest <= 0)).sum())
    above = int(((bound >= 0) & (bound > lowest + 1e-9)).sum())  # a bound only where certified
    print('{"file": "%s", "cells": %d, "gauss_points_per_cell": %d, "cells_scaled_jacobian_le_0": %d, '
          '"min_scaled_jacobian": %.6g, "certified_cells": %d, "certified_with_nonpositive_gauss": %d, '
          '"certified_bound_above_gauss_value": %d}' % (path, cells, n ** 3, bad, lowest.min(), int((bound >= 0).sum()),
                                              contradictions, above))


main()
