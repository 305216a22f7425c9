# SPDX-License-Identifier: MIT
"""Reads a hex-mesh VTU with VTK (python3-vtk9) and checks its least scaled Jacobian as VTK
computes it (vtkMeshQuality, HexScaledJacobian) against a floor, and against the file's own
cell data `scaled_jacobian`. usage: check_hex_quality.py GRID.vtu FLOOR"""
import sys

import vtk

reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(sys.argv[1])
reader.Update()
grid = reader.GetOutput()
floor = float(sys.argv[2])
quality = vtk.vtkMeshQuality()
quality.SetInputData(grid)
quality.SetHexQualityMeasureToScaledJacobian()
quality.Update()
values = quality.GetOutput().GetCellData().GetArray("Quality")
ours = grid.GetCellData().GetArray("scaled_jacobian")
n = grid.GetNumberOfCells()
if n == 0 or values is None or ours is None:
    sys.exit("no hexes or no quality arrays in " + sys.argv[1])
vtk_min = min(values.GetValue(c) for c in range(n))
our_min = min(ours.GetValue(c) for c in range(n))
print("cells %d, VTK least scaled Jacobian %.6f, file's %.6f" % (n, vtk_min, our_min))
if vtk_min < floor:
    sys.exit("VTK's least scaled Jacobian %.6f is below %.3f" % (vtk_min, floor))
if abs(vtk_min - our_min) > 1e-6:
    sys.exit("VTK's least scaled Jacobian %.6f differs from the file's %.6f" % (vtk_min, our_min))
