"""vtkPTVEXRPassWriter / vtkPTVEXRPassReader and vtkPathTracedVolumeMapper.GetPasses.

* every pass of a rendered frame goes to one float32 EXR with the conventional channel names
  (checked with the independent ``OpenEXR`` bindings), top row first, and comes back bit-exact
  through the reader;
* arbitrary arrays: ``<name>.Y`` / ``.R/G/B`` / ``.R/G/B/A`` / ``.0, .1``; a file without the
  ``ptv.passes`` attribute (written by another tool, ``alpha.A`` as in
  ``Training/ptv_training/exr_io.py``) is grouped by the convention;
* failures (unwritable or missing folder, a directory as file name, 3D input, a string array,
  two arrays on one channel, no arrays, a missing or non-EXR file) are errors naming the path and
  the reason, leave no file and no temporary file behind, and an existing file untouched.
Needs a display for the render (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

import os
import struct
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np
import pytest

import OpenEXR
import vtkmodules.util.numpy_support as vtk_numpy
import pathtracedvolume.vtkPTVFilters as ptv_filters
import pathtracedvolume.vtkPTVRendering as ptv_rendering

from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand, vtkStringArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction  # noqa: E402
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource  # noqa: E402
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer,  # noqa: E402
                                         vtkRenderWindow, vtkVolume, vtkVolumeProperty)
import vtkmodules.vtkRenderingOpenGL2  # noqa: E402,F401

W, H = 24, 16
CONVENTIONAL = {
    "Radiance": ["R", "G", "B"], "Alpha": ["A"], "Albedo": ["albedo.R", "albedo.G", "albedo.B"],
    "Depth": ["Z"], "Position": ["P.X", "P.Y", "P.Z"], "Normal": ["N.X", "N.Y", "N.Z"],
    "ScatterDepth": ["scatter.Z"], "ScatterPosition": ["scatter.P.X", "scatter.P.Y", "scatter.P.Z"],
    "ScatterNormal": ["scatter.N.X", "scatter.N.Y", "scatter.N.Z"],
    "Coverage": ["coverage.A"], "Footprint": ["footprint.A"],
    "Denoised": ["denoised.R", "denoised.G", "denoised.B"],
    "Guides": ["Guides.R", "Guides.G", "Guides.B"],
    "BlendWeights": ["BlendWeights.0", "BlendWeights.1"],
    "Converged": ["Converged.R", "Converged.G", "Converged.B"],
    "HistoryLength": ["HistoryLength.Y"],
    "DenoisedAlpha": ["DenoisedAlpha.Y"],
    "SampleRatio": ["SampleRatio.Y"],
}


class Errors:
    """Collects the error and warning texts of a VTK object (and keeps them off stderr)."""

    def __init__(self, obj) -> None:
        self.messages: List[str] = []

        @calldata_type(VTK_STRING)
        def on_message(caller, event, text) -> None:
            self.messages.append(str(text))

        self._callback = on_message
        obj.AddObserver(vtkCommand.ErrorEvent, on_message)
        obj.AddObserver(vtkCommand.WarningEvent, on_message)


def render_passes(denoise: bool) -> vtkImageData:
    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-8, 8, -8, 8, -8, 8)
    color = vtkColorTransferFunction()
    color.AddRGBPoint(37, 0.2, 0.4, 1.0)
    color.AddRGBPoint(277, 1.0, 0.9, 0.5)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(37, 0.0)
    opacity.AddPoint(277, 0.6)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    mapper = ptv_rendering.vtkPathTracedVolumeMapper()
    mapper.ConvergeStillRendersOff()  # frame by frame
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.SetDenoise(denoise)
    mapper.GetExpertOptions().SetDenoiserUseNetwork(False)
    mapper.GetExpertOptions().ScatterPassesOn()  # every pass, the Scatter* ones too
    errors = Errors(mapper)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    renderer.ResetCamera()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(W, H)
    window.AddRenderer(renderer)
    before = vtkImageData()
    assert not mapper.GetPasses(before)
    assert errors.messages and "before the first render" in errors.messages[-1]
    window.Render()
    window.Render()
    passes = vtkImageData()
    assert mapper.GetPasses(passes)
    # Each array equals GetPass() of the same name.
    for i in range(mapper.GetNumberOfPasses()):
        name = mapper.GetPassName(i)
        array = passes.GetPointData().GetArray(name)
        if array is None:
            assert not denoise and name in ("Denoised", "Guides", "BlendWeights", "Converged",
                                                 "DenoisedAlpha")
            continue
        single = vtkImageData()
        assert mapper.GetPass(name, single)
        assert np.array_equal(vtk_numpy.vtk_to_numpy(array),
                              vtk_numpy.vtk_to_numpy(single.GetPointData().GetArray(name)))
    window.Finalize()
    return passes


def arrays(image: vtkImageData) -> Dict[str, np.ndarray]:
    pd = image.GetPointData()
    return {pd.GetArrayName(i): vtk_numpy.vtk_to_numpy(pd.GetArray(i)).copy()
            for i in range(pd.GetNumberOfArrays())}


def write(image: vtkImageData, path: Path):
    writer = ptv_filters.vtkPTVEXRPassWriter()
    errors = Errors(writer)
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    return writer.Write(), errors.messages


def read(path: Path):
    reader = ptv_filters.vtkPTVEXRPassReader()
    errors = Errors(reader)
    errors_exec = Errors(reader.GetExecutive())
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput(), errors.messages + errors_exec.messages


def leftovers(folder: Path) -> List[str]:
    return sorted(p.name for p in folder.iterdir() if ".tmp-" in p.name)


@pytest.mark.parametrize("denoise", [True, False])
def test_mapper_passes_round_trip(tmp_path: Path, denoise: bool) -> None:
    passes = render_passes(denoise)
    expected = arrays(passes)
    assert passes.GetPointData().GetScalars().GetName() == "Radiance"
    assert ("Denoised" in expected) == denoise
    path = tmp_path / "frame.exr"
    ok, messages = write(passes, path)
    assert ok == 1 and not messages
    assert leftovers(tmp_path) == []

    with OpenEXR.File(str(path), separate_channels=True) as f:
        header = dict(f.header())
        channels = {k: np.asarray(v.pixels) for k, v in f.channels().items()}
    want = [c for name in expected for c in CONVENTIONAL[name]]
    assert sorted(channels) == sorted(want)
    assert all(c.dtype == np.float32 and c.shape == (H, W) for c in channels.values())
    # Top row first: the file's row 0 is VTK's row H-1.
    radiance = expected["Radiance"].reshape(H, W, 3)
    assert np.array_equal(channels["R"], radiance[::-1, :, 0])
    assert np.array_equal(channels["B"], radiance[::-1, :, 2])
    assert np.array_equal(channels["Z"], expected["Depth"].reshape(H, W)[::-1])
    assert np.array_equal(channels["N.Y"], expected["Normal"].reshape(H, W, 3)[::-1, :, 1])
    assert str(header["ptv.passes"]).startswith("Radiance=R,G,B;Alpha=A;")

    image, messages = read(path)
    assert not messages
    assert image.GetDimensions() == (W, H, 1)
    got = arrays(image)
    assert list(got) == list(expected)  # same names, same order
    for name, values in expected.items():
        assert got[name].dtype == np.float32
        assert np.array_equal(got[name], values), name
    assert image.GetPointData().GetScalars().GetName() == "Radiance"


def test_other_arrays_and_types(tmp_path: Path) -> None:
    image = vtkImageData()
    image.SetDimensions(5, 3, 1)
    rng = np.random.default_rng(1)
    values = {"Mask": rng.random(15), "Flow": rng.random((15, 2)), "Color": rng.random((15, 3)),
              "Rgba": rng.random((15, 4)), "Many": rng.random((15, 5)),
              "Ids": np.arange(15, dtype=np.int32)}
    for name, v in values.items():
        a = vtk_numpy.numpy_to_vtk(v, deep=1)
        a.SetName(name)
        image.GetPointData().AddArray(a)
    path = tmp_path / "other.exr"
    ok, messages = write(image, path)
    assert ok == 1 and not messages
    with OpenEXR.File(str(path), separate_channels=True) as f:
        names = sorted(f.channels())
    assert names == sorted(["Mask.Y", "Flow.0", "Flow.1", "Color.R", "Color.G", "Color.B",
                            "Rgba.R", "Rgba.G", "Rgba.B", "Rgba.A"]
                           + [f"Many.{i}" for i in range(5)] + ["Ids.Y"])
    out, messages = read(path)
    assert not messages
    got = arrays(out)
    for name, v in values.items():
        assert np.array_equal(got[name], v.astype(np.float32).reshape(got[name].shape)), name


def test_foreign_file_is_grouped_by_convention(tmp_path: Path) -> None:
    """A file from another tool (no ptv.passes attribute), named like exr_io.py's."""
    rng = np.random.default_rng(2)
    names = ["R", "G", "B", "alpha.A", "albedo.R", "albedo.G", "albedo.B", "Z", "N.X", "N.Y",
             "N.Z", "scatter.P.X", "scatter.P.Y", "scatter.P.Z", "extra.1", "extra.0", "lonely"]
    data = {n: rng.random((4, 6)).astype(np.float32) for n in names}
    path = tmp_path / "foreign.exr"
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, dict(data)) as f:
        f.write(str(path))
    image, messages = read(path)
    assert not messages
    assert image.GetDimensions() == (6, 4, 1)
    got = arrays(image)
    assert sorted(got) == sorted(["Radiance", "Alpha", "Albedo", "Depth", "Normal",
                                  "ScatterPosition", "extra", "lonely"])
    rad = got["Radiance"].reshape(4, 6, 3)
    assert np.array_equal(rad[::-1, :, 1], data["G"])
    assert np.array_equal(got["Alpha"].reshape(4, 6)[::-1], data["alpha.A"])
    extra = got["extra"].reshape(4, 6, 2)
    assert np.array_equal(extra[::-1, :, 0], data["extra.0"])
    assert np.array_equal(extra[::-1, :, 1], data["extra.1"])


def test_writer_failures_leave_nothing(tmp_path: Path) -> None:
    good = vtkImageData()
    good.SetDimensions(4, 4, 1)
    a = vtk_numpy.numpy_to_vtk(np.ones((16, 3), np.float32), deep=1)
    a.SetName("Radiance")
    good.GetPointData().AddArray(a)

    # Unwritable folder (root ignores permissions: use a missing folder and a file as folder).
    missing = tmp_path / "no" / "such" / "folder" / "x.exr"
    ok, messages = write(good, missing)
    assert ok == 0 and str(missing) in messages[-1] and "No such file or directory" in messages[-1]
    blocker = tmp_path / "blocker"
    blocker.write_text("not a folder")
    ok, messages = write(good, blocker / "x.exr")
    assert ok == 0 and "Not a directory" in messages[-1]
    # A directory as the target: the rename fails, the temporary file is removed.
    target = tmp_path / "target.exr"
    target.mkdir()
    ok, messages = write(good, target)
    assert ok == 0 and str(target) in messages[-1] and "rename" in messages[-1]
    assert leftovers(tmp_path) == []
    if os.geteuid() != 0:
        locked = tmp_path / "locked"
        locked.mkdir()
        locked.chmod(0o500)
        ok, messages = write(good, locked / "x.exr")
        assert ok == 0 and "Permission denied" in messages[-1]
        locked.chmod(0o700)

    # Bad inputs: an existing file stays untouched.
    existing = tmp_path / "existing.exr"
    assert write(good, existing)[0] == 1
    before = existing.read_bytes()
    volume = vtkImageData()
    volume.SetDimensions(4, 4, 2)
    b = vtk_numpy.numpy_to_vtk(np.ones(32, np.float32), deep=1)
    b.SetName("Depth")
    volume.GetPointData().AddArray(b)
    ok, messages = write(volume, existing)
    assert ok == 0 and "3D" in messages[-1] and str(existing) in messages[-1]

    strings = vtkImageData()
    strings.DeepCopy(good)
    s = vtkStringArray()
    s.SetName("Labels")
    s.SetNumberOfValues(16)
    strings.GetPointData().AddArray(s)
    ok, messages = write(strings, existing)
    assert ok == 0 and "'Labels'" in messages[-1] and "vtkStringArray" in messages[-1]

    # Names that only look alike get distinct channels: Depth -> Z, "Z" (1 component) -> Z.Y,
    # "Z.Y" (2 components) -> Z.Y.0/1; "denoised" (3 components) and Denoised both want
    # denoised.R/G/B: an error naming both and the channel.
    dup = vtkImageData()
    dup.SetDimensions(4, 4, 1)
    for name, comps in (("Depth", 1), ("Z", 1), ("Z.Y", 2), ("denoised", 3)):
        d = vtk_numpy.numpy_to_vtk(np.ones((16, comps), np.float32), deep=1)
        d.SetName(name)
        dup.GetPointData().AddArray(d)
    assert write(dup, tmp_path / "alike.exr")[0] == 1
    with OpenEXR.File(str(tmp_path / "alike.exr"), separate_channels=True) as f:
        assert sorted(f.channels()) == ["Z", "Z.Y", "Z.Y.0", "Z.Y.1", "denoised.B",
                                        "denoised.G", "denoised.R"]
    d = vtk_numpy.numpy_to_vtk(np.ones((16, 3), np.float32), deep=1)
    d.SetName("Denoised")
    dup.GetPointData().AddArray(d)
    ok, messages = write(dup, existing)
    assert ok == 0 and "'denoised.R'" in messages[-1] and "'Denoised'" in messages[-1]

    empty = vtkImageData()
    empty.SetDimensions(4, 4, 1)
    ok, messages = write(empty, existing)
    assert ok == 0 and "no point-data arrays" in messages[-1]
    assert existing.read_bytes() == before
    assert leftovers(tmp_path) == []


def test_reader_failures(tmp_path: Path) -> None:
    image, messages = read(tmp_path / "missing.exr")
    assert messages and "missing.exr" in messages[0] and "No such file" in messages[0]
    assert image.GetNumberOfPoints() == 0
    text = tmp_path / "text.exr"
    text.write_text("hello")
    image, messages = read(text)
    assert messages and "not an OpenEXR file" in messages[0]
    assert not ptv_filters.vtkPTVEXRPassReader.CanReadFile(str(text))
    truncated = tmp_path / "truncated.exr"
    image = vtkImageData()
    image.SetDimensions(64, 64, 1)
    a = vtk_numpy.numpy_to_vtk(np.random.default_rng(3).random((64 * 64, 3)), deep=1)
    a.SetName("Radiance")
    image.GetPointData().AddArray(a)
    assert write(image, truncated)[0] == 1
    assert ptv_filters.vtkPTVEXRPassReader.CanReadFile(str(truncated))
    data = truncated.read_bytes()
    truncated.write_bytes(data[: len(data) // 2])
    out, messages = read(truncated)
    assert messages and "truncated.exr" in messages[0]


def header_attributes(data: bytes) -> Dict[str, Tuple[int, str, int]]:
    """Name -> (offset of the int32 size, type, size) of a single-part EXR header's attributes."""
    found: Dict[str, Tuple[int, str, int]] = {}
    pos = 8  # magic and version
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        found[data[pos:name_end].decode()] = (type_end + 1, data[name_end + 1:type_end].decode(),
                                              size)
        pos = type_end + 5 + size
    return found


def test_reader_checks_the_header_layout(tmp_path: Path) -> None:
    """Sizes in the header that OpenEXR would trust are checked against the file first
    (fuzz_exr_pass_reader: a string attribute declaring 1.7 GB was allocated and zero-filled)."""
    good = tmp_path / "good.exr"
    image = vtkImageData()
    image.SetDimensions(8, 6, 1)
    a = vtk_numpy.numpy_to_vtk(np.arange(8 * 6 * 3, dtype=np.float32).reshape(-1, 3), deep=1)
    a.SetName("Radiance")
    image.GetPointData().AddArray(a)
    assert write(image, good)[0] == 1
    data = good.read_bytes()
    attrs = header_attributes(data)
    assert attrs["dataWindow"][1:] == ("box2i", 16) and attrs["channels"][1] == "chlist"
    assert attrs["ptv.passes"][1] == "string"
    out, messages = read(good)
    assert messages == [] and out.GetNumberOfPoints() == 48

    def damaged(name: str, offset: int, fmt: str, value: int, size: int = len(data)) -> Path:
        copy = bytearray(data[:size])
        struct.pack_into(fmt, copy, offset, value)
        path = tmp_path / f"{name}.exr"
        path.write_bytes(bytes(copy))
        return path

    window = attrs["dataWindow"][0] + 4  # xMin, yMin, xMax, yMax follow the size
    cases = [
        (damaged("string_size", attrs["ptv.passes"][0], "<i", 0x7FFFFFF0),
         "attribute 'ptv.passes' (string) declares 2147483632 bytes"),
        (damaged("negative_size", attrs["ptv.passes"][0], "<i", -5), "declares -5 bytes"),
        (damaged("box_size", attrs["dataWindow"][0], "<i", 20),
         "declares 20 bytes for a box2i (16 bytes)"),
        (damaged("tall_window", window + 12, "<i", 1 << 30), "the offset tables need"),
        (damaged("pixel_type", attrs["channels"][0] + 4 + 2, "<i", 7), "pixel type 7"),
        (damaged("version", 4, "<I", 3), "unsupported OpenEXR version 3"),
        (damaged("wide_window", window + 8, "<i", 1 << 30),
         "1073741825 x 6 pixels x 3 channels exceed MaximumNumberOfValues (2147483647)"),
        (damaged("header_cut", 0, "<i", 20000630, size=attrs["channels"][0] + 8),
         "truncated or corrupt"),
    ]
    for path, expected in cases:
        out, messages = read(path)
        assert messages and path.name in messages[0] and expected in messages[0], messages
        assert out.GetNumberOfPoints() == 0
    # The reader recovers on the next good file; a lower limit refuses it.
    out, messages = read(good)
    assert messages == [] and out.GetNumberOfPoints() == 48
    reader = ptv_filters.vtkPTVEXRPassReader()
    reader.SetMaximumNumberOfValues(100)
    errors = Errors(reader)
    reader.SetFileName(str(good))
    reader.Update()
    assert errors.messages and "8 x 6 pixels x 3 channels exceed" in errors.messages[0]
    assert reader.GetOutput().GetNumberOfPoints() == 0
