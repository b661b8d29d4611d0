"""pvbatch test of the plugin's OpenVDB reader and writer proxies.

Run as ``pvbatch --force-offscreen-rendering test_plugin_vdb_reader.py`` with ``PTV_PLUGIN`` (the
plugin .so), ``PYTHONPATH`` (<build>/python, for the wrapped ``pathtracedvolume`` package) and
``PTV_TEST_TEMP`` (a writable folder) set, as ctest does.

1. writes a small .vdb with ``pathtracedvolume.vtkPTVOpenVDBWriter`` (no ParaView involved);
2. opens it through the ``PTVOpenVDBReader`` proxy (``OpenVDBReaderPathTracedVolume`` in
   paraview.simple, which names constructors after the proxy label) and checks the grid list,
   the selected grid, extent, bounds, array name/range and every value of the fetched image;
3. saves the reader's output through the ``PTVOpenVDBWriter`` proxy (writer factory, by the .vdb
   extension) and reads that file back with the VTK reader.
Exits non-zero on any mismatch; prints PASS at the end.
"""
import os
import sys

from paraview.simple import *  # noqa: F401,F403 (pvbatch convention)
from paraview import servermanager

LoadPlugin(os.environ["PTV_PLUGIN"], remote=False, ns=globals())

import pathtracedvolume  # noqa: E402
from vtkmodules.vtkCommonCore import vtkFloatArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

DIMS = (9, 7, 5)
SPACING = 0.25
ORIGIN = (1.0, -2.0, 0.5)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAILED:", what)


def value(i, j, k):
    # All non-zero (the whole box is active), exactly representable as float.
    return 1.0 + i + 10.0 * j + 100.0 * k


def near(a, b, tol=1e-6):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


temp = os.environ.get("PTV_TEST_TEMP", ".")
os.makedirs(temp, exist_ok=True)
source_file = os.path.join(temp, "pv_plugin_vdb_reader.vdb")
saved_file = os.path.join(temp, "pv_plugin_vdb_writer.vdb")
for path in (source_file, saved_file):
    if os.path.exists(path):
        os.remove(path)

# 1. Write the input file with the wrapped VTK writer.
image = vtkImageData()
image.SetDimensions(*DIMS)
image.SetSpacing(SPACING, SPACING, SPACING)
image.SetOrigin(*ORIGIN)
values = vtkFloatArray()
values.SetName("field")
values.SetNumberOfTuples(DIMS[0] * DIMS[1] * DIMS[2])
n = 0
for k in range(DIMS[2]):
    for j in range(DIMS[1]):
        for i in range(DIMS[0]):
            values.SetValue(n, value(i, j, k))
            n += 1
image.GetPointData().SetScalars(values)
writer = pathtracedvolume.vtkPTVOpenVDBWriter()
writer.SetInputData(image)
writer.SetFileName(source_file)
writer.SetGridName("density")
if writer.Write() != 1 or not os.path.exists(source_file):
    print("FAILED: vtkPTVOpenVDBWriter could not write", source_file)
    sys.exit(1)

# 2. Read it through the proxy. paraview.simple names proxy constructors after the XML *label*
# ("OpenVDB Reader (PathTracedVolume)"), not the proxy name (PTVOpenVDBReader).
reader = OpenVDBReaderPathTracedVolume(FileName=source_file)
reader.UpdatePipeline()
reader.UpdatePropertyInformation()
grid_names = list(reader.GetProperty("GridNamesInfo"))
check(grid_names == ["density"], "GridNamesInfo must be ['density'], got %s" % grid_names)
check(reader.GridName == "density", "GridName must default to 'density', got %r" % reader.GridName)

info = reader.GetDataInformation()
extent = info.GetExtent()
bounds = info.GetBounds()
expected_extent = (0, DIMS[0] - 1, 0, DIMS[1] - 1, 0, DIMS[2] - 1)
expected_bounds = []
for axis in range(3):
    expected_bounds += [ORIGIN[axis], ORIGIN[axis] + (DIMS[axis] - 1) * SPACING]
check(tuple(extent) == expected_extent, "extent %s != %s" % (tuple(extent), expected_extent))
check(near(bounds, expected_bounds), "bounds %s != %s" % (tuple(bounds), expected_bounds))
check(info.GetNumberOfPoints() == DIMS[0] * DIMS[1] * DIMS[2],
      "number of points %d" % info.GetNumberOfPoints())
array_info = reader.PointData["density"] if "density" in reader.PointData.keys() else None
check(array_info is not None, "point array 'density' missing: %s" % list(reader.PointData.keys()))
if array_info is not None:
    expected_range = (value(0, 0, 0), value(DIMS[0] - 1, DIMS[1] - 1, DIMS[2] - 1))
    check(near(array_info.GetRange(), expected_range),
          "range %s != %s" % (array_info.GetRange(), expected_range))

data = servermanager.Fetch(reader)
check(data is not None and data.IsA("vtkImageData"), "Fetch must give a vtkImageData")
if data is not None:
    check(tuple(data.GetDimensions()) == DIMS, "fetched dims %s" % (data.GetDimensions(),))
    check(near(data.GetOrigin(), ORIGIN), "fetched origin %s" % (data.GetOrigin(),))
    check(near(data.GetSpacing(), (SPACING,) * 3), "fetched spacing %s" % (data.GetSpacing(),))
    scalars = data.GetPointData().GetArray("density")
    check(scalars is not None and scalars.GetDataTypeAsString() == "float",
          "fetched 'density' must be a float array")
    if scalars is not None:
        bad = 0
        for k in range(DIMS[2]):
            for j in range(DIMS[1]):
                for i in range(DIMS[0]):
                    pid = data.ComputePointId([i, j, k])
                    if scalars.GetValue(pid) != value(i, j, k):
                        bad += 1
        check(bad == 0, "%d fetched values differ" % bad)

# 3. Save through the writer proxy (chosen by the .vdb extension) and read back with VTK.
SaveData(saved_file, proxy=reader, GridName="copy")
check(os.path.exists(saved_file), "SaveData must write " + saved_file)
if os.path.exists(saved_file):
    vtk_reader = pathtracedvolume.vtkPTVOpenVDBReader()
    vtk_reader.SetFileName(saved_file)
    vtk_reader.Update()
    out = vtk_reader.GetOutput()
    check(vtk_reader.GetNumberOfGrids() == 1 and vtk_reader.GetGridName(0) == "copy",
          "saved file must hold one grid 'copy'")
    check(tuple(out.GetDimensions()) == DIMS, "saved dims %s" % (out.GetDimensions(),))
    check(near(out.GetOrigin(), ORIGIN), "saved origin %s" % (out.GetOrigin(),))
    copy = out.GetPointData().GetArray("copy")
    check(copy is not None and copy.GetRange() == (value(0, 0, 0),
                                                  value(DIMS[0] - 1, DIMS[1] - 1, DIMS[2] - 1)),
          "saved values must keep their range")

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("PASS")
