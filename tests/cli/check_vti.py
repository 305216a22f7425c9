#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# Reads a .vti that `volspline vol2spline --vti` wrote with VTK (Debian python3-vtk9) and checks
# its dimensions, that it has the arrays sample, density and error, and that error = density −
# sample at every voxel.
# usage: check_vti.py OUT.vti NX NY NZ
import sys

import vtk


def main():
    path, dims = sys.argv[1], [int(x) for x in sys.argv[2:5]]
    reader = vtk.vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    if list(image.GetDimensions()) != dims:
        print("check_vti: FAIL: dimensions %s, expected %s" % (image.GetDimensions(), dims))
        sys.exit(1)
    data = image.GetPointData()
    arrays = {name: data.GetArray(name) for name in ("sample", "density", "error")}
    for name, array in arrays.items():
        if array is None or array.GetNumberOfTuples() != dims[0] * dims[1] * dims[2]:
            print("check_vti: FAIL: array %s missing or of the wrong size" % name)
            sys.exit(1)
    worst = max(abs(arrays["density"].GetValue(i) - arrays["sample"].GetValue(i) - arrays["error"].GetValue(i))
                for i in range(arrays["sample"].GetNumberOfTuples()))
    if worst > 1e-9:
        print("check_vti: FAIL: error != density - sample (%.3g)" % worst)
        sys.exit(1)
    print("check_vti: ok, %d voxels, sample range %s" % (arrays["sample"].GetNumberOfTuples(), arrays["sample"].GetRange()))


main()
