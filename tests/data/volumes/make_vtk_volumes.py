# SPDX-License-Identifier: MIT
# Writes the volumes of tests/data/volumes with VTK 9.1 (Debian python3-vtk9): /usr/bin/python3 make_vtk_volumes.py
# in that folder. Sample i of each 5x4x3 volume is i; spacing 0.5, 0.25, 2; origin 10, -20, 30.
import vtk
def image(dtype, dims=(5,4,3)):
    img = vtk.vtkImageData(); img.SetDimensions(*dims); img.SetSpacing(0.5, 0.25, 2.0); img.SetOrigin(10, -20, 30)
    n = dims[0]*dims[1]*dims[2]
    a = dtype(); a.SetNumberOfTuples(n); a.SetName("density")
    for i in range(n): a.SetValue(i, i % 250)
    img.GetPointData().SetScalars(a); return img
img = image(vtk.vtkUnsignedCharArray)
w = vtk.vtkStructuredPointsWriter(); w.SetInputData(img); w.SetFileName("u8_bin.vtk"); w.SetFileTypeToBinary(); w.Write()
w.SetFileName("u8_ascii.vtk"); w.SetFileTypeToASCII(); w.Write()
m = vtk.vtkMetaImageWriter(); m.SetInputData(img); m.SetFileName("u8.mha"); m.SetCompression(True); m.Write()
m = vtk.vtkMetaImageWriter(); m.SetInputData(img); m.SetFileName("u8.mhd"); m.SetRAWFileName("u8.zraw"); m.SetCompression(True); m.Write()
img2 = image(vtk.vtkUnsignedCharArray); img2.SetDirectionMatrix(-1,0,0, 0,-1,0, 0,0,1)
for mode in ["ascii", "binary", "appended"]:
  for comp in [False, True]:
    x = vtk.vtkXMLImageDataWriter(); x.SetInputData(img2); x.SetFileName(f"d_{mode}_{'z' if comp else 'n'}.vti")
    getattr(x, "SetDataModeTo" + mode.capitalize())()
    if comp: x.SetCompressorTypeToZLib()
    else: x.SetCompressorTypeToNone()
    x.Write()
x = vtk.vtkXMLImageDataWriter(); x.SetInputData(img2); x.SetFileName("d_appended_b64.vti"); x.SetDataModeToAppended(); x.EncodeAppendedDataOff(); x.Write()
x = vtk.vtkXMLImageDataWriter(); x.SetInputData(img2); x.SetFileName("d_appended_enc.vti"); x.SetDataModeToAppended(); x.EncodeAppendedDataOn(); x.SetCompressorTypeToNone(); x.Write()
for name in ["n.nii", "n.nii.gz"]:
  nw = vtk.vtkNIFTIImageWriter(); nw.SetInputData(image(vtk.vtkShortArray)); nw.SetFileName(name); nw.Write()
img3 = image(vtk.vtkFloatArray); img3.SetDirectionMatrix(0,1,0, -1,0,0, 0,0,1)
x = vtk.vtkXMLImageDataWriter(); x.SetInputData(img3); x.SetFileName("f32_u64_raw_z.vti"); x.SetDataModeToAppended(); x.EncodeAppendedDataOff(); x.SetHeaderTypeToUInt64(); x.Write()
img4 = image(vtk.vtkUnsignedShortArray)
nw = vtk.vtkNIFTIImageWriter(); nw.SetInputData(img4); nw.SetFileName("u16_q.nii.gz")
t = vtk.vtkMatrix4x4(); t.SetElement(0,0,-1); t.SetElement(1,1,-1); t.SetElement(0,3,5); t.SetElement(1,3,6); t.SetElement(2,3,7)
nw.SetQFormMatrix(t); nw.SetSFormMatrix(t); nw.Write()
