"""Tests for the transfer-function presets and pathtracedvolume.presets.

No fetched data is needed: the value ranges come from Data/datasets.json.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pathtracedvolume import presets as ptv_presets

from conftest import REPO_ROOT

PRESET_DIR = REPO_ROOT / "Data" / "TransferFunctions"
EDGE_FRACTION = 1e-3

# Documented band thresholds (t1, t2, t3, t4) of the two-band presets.
BANDS = {
    "head": ("Head", (-500.0, 200.0, 400.0, 2986.0)),
    "stent": ("Stent", (281.0, 469.0, 719.0, 2000.0)),
    "concrete": ("Concrete", (26000.0, 31700.0, 32300.0, 38064.0)),
}
YELLOW = (1.0, 1.0, 0.0)
WHITE = (1.0, 1.0, 1.0)


def functions(name: str):
    """(colour, opacity) VTK functions of the named preset."""
    return ptv_presets.make_functions(ptv_presets.find_preset(name))


def test_presets_dir_is_data_transferfunctions() -> None:
    # The built package reads the plugin folder's copy of Data/TransferFunctions (an install
    # carries its own): same files, same contents.
    found = ptv_presets.presets_dir()
    assert found.parts[-2:] == ("Data", "TransferFunctions")
    names = sorted(p.name for p in PRESET_DIR.glob("*.json"))
    assert sorted(p.name for p in found.glob("*.json")) == names
    for name in names:
        assert (found / name).read_bytes() == (PRESET_DIR / name).read_bytes(), name


def test_one_file_per_dataset_with_two_presets(manifest: dict) -> None:
    # The evaluation datasets have presets; the other training volumes get random transfer
    # functions (Training/ptv_training/transfer.py) and need none.
    files = sorted(p.stem for p in PRESET_DIR.glob("*.json"))
    assert files == sorted(BANDS)
    assert set(files) <= set(manifest["datasets"])
    for name, (title, _) in BANDS.items():
        presets = ptv_presets.load_presets(PRESET_DIR / f"{name}.json")
        assert [p["Name"] for p in presets] == [
            f"{title} Two-Band (paper)", f"{title} Smooth"]
        for preset in presets:
            assert preset["ColorSpace"] == "RGB"
            assert preset["Description"]


def test_every_preset_loads_and_applies() -> None:
    from vtkmodules.vtkRenderingCore import vtkVolumeProperty

    names = ptv_presets.preset_names()
    assert len(names) == 6
    for name in names:
        preset = ptv_presets.find_preset(name)
        volume_property = vtkVolumeProperty()
        color, opacity = ptv_presets.apply_preset(preset, volume_property)
        assert volume_property.GetRGBTransferFunction(0) is color
        assert volume_property.GetScalarOpacity(0) is opacity
        assert color.GetSize() == len(preset["RGBPoints"]) // 4
        assert opacity.GetSize() == len(preset["Points"]) // 4


@pytest.mark.parametrize("name", list(BANDS))
def test_presets_span_the_data_range(name: str, manifest: dict) -> None:
    lo, hi = manifest["datasets"][name]["volume"]["value_range"]
    for preset in ptv_presets.load_presets(PRESET_DIR / f"{name}.json"):
        for field in ("RGBPoints", "Points"):
            xs = preset[field][::4]
            assert (xs[0], xs[-1]) == (lo, hi), (preset["Name"], field)
            assert all(a < b for a, b in zip(xs, xs[1:]))


@pytest.mark.parametrize("name", list(BANDS))
def test_two_band_opacity_is_a_box(name: str, manifest: dict) -> None:
    title, (t1, t2, t3, t4) = BANDS[name]
    lo, hi = manifest["datasets"][name]["volume"]["value_range"]
    eps = EDGE_FRACTION * (hi - lo)
    color, opacity = functions(f"{title} Two-Band (paper)")

    # Inside the bands: exactly 0.7 / 1.0, edges included.
    for x in np.linspace(t1, t2, 101):
        assert opacity.GetValue(x) == pytest.approx(0.7, abs=1e-12)
    for x in np.linspace(t3, t4, 101):
        assert opacity.GetValue(x) == pytest.approx(1.0, abs=1e-12)
    # Just outside every edge (one and two edge widths out): exactly 0.
    outside = [t1 - eps, t1 - 2 * eps, t2 + eps, t2 + 2 * eps,
               t3 - eps, t3 - 2 * eps, (t2 + t3) / 2]
    if t4 < hi:
        outside += [t4 + eps, t4 + 2 * eps]
    else:
        assert t4 == hi  # band runs to the data maximum
    outside += list(np.linspace(lo, t1 - eps, 50))
    outside += list(np.linspace(t2 + eps, t3 - eps, 50))
    for x in outside:
        assert opacity.GetValue(x) == pytest.approx(0.0, abs=1e-12), x
    # Band midpoints and edges are coloured (1, 1, 0) and (1, 1, 1).
    for x in (t1, (t1 + t2) / 2, t2):
        assert color.GetColor(x) == pytest.approx(YELLOW, abs=1e-12)
    for x in (t3, (t3 + t4) / 2, t4):
        assert color.GetColor(x) == pytest.approx(WHITE, abs=1e-12)


@pytest.mark.parametrize("name", list(BANDS))
def test_smooth_preset_ramps(name: str, manifest: dict) -> None:
    title, (t1, t2, t3, t4) = BANDS[name]
    lo, hi = manifest["datasets"][name]["volume"]["value_range"]
    preset = ptv_presets.find_preset(f"{title} Smooth")
    assert len(preset["Points"]) // 4 >= 5
    assert len(preset["RGBPoints"]) // 4 >= 4
    _, opacity = ptv_presets.make_functions(preset)
    xs = np.linspace(lo, hi, 2001)
    values = np.array([opacity.GetValue(x) for x in xs])
    assert values[0] == 0.0
    assert np.all(np.diff(values) >= -1e-12)  # never decreases
    assert 0.0 < opacity.GetValue((t1 + t2) / 2) < opacity.GetValue(t3) \
        < opacity.GetValue(t4) <= 1.0


def test_unknown_preset_name_lists_available() -> None:
    with pytest.raises(KeyError) as info:
        ptv_presets.find_preset("No Such Preset")
    message = str(info.value)
    assert "No Such Preset" in message
    assert "Head Two-Band (paper)" in message and "Stent Smooth" in message


def test_malformed_json_names_file(tmp_path: Path) -> None:
    path = tmp_path / "broken.json"
    path.write_text("[{\"Name\": \"x\",", encoding="utf-8")
    with pytest.raises(ValueError, match="broken.json"):
        ptv_presets.load_presets(path)


@pytest.mark.parametrize("preset, field", [
    ({"ColorSpace": "RGB", "RGBPoints": [0, 0, 0, 0]}, "Name"),
    ({"Name": "a"}, "RGBPoints"),
    ({"Name": "a", "RGBPoints": [0, 0, 0]}, "RGBPoints"),
    ({"Name": "a", "RGBPoints": [0, 0, 0, 2]}, "RGBPoints"),
    ({"Name": "a", "RGBPoints": [1, 0, 0, 0, 0, 1, 1, 1]}, "RGBPoints"),
    ({"Name": "a", "RGBPoints": [0, 0, 0, 0], "Points": [0, 0.5]}, "Points"),
    ({"Name": "a", "RGBPoints": [0, 0, 0, 0], "Points": [0, "x", 0.5, 0]},
     "Points"),
    ({"Name": "a", "ColorSpace": "CMYK", "RGBPoints": [0, 0, 0, 0]},
     "ColorSpace"),
])
def test_invalid_fields_are_named(tmp_path: Path, preset: dict,
                                  field: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(json.dumps([preset]), encoding="utf-8")
    with pytest.raises(ValueError) as info:
        ptv_presets.load_presets(path)
    assert "bad.json" in str(info.value)
    assert repr(field) in str(info.value)


def test_modules_import_without_vtk() -> None:
    """Importing the modules pulls in no VTK extension module."""
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "import pathtracedvolume.datasets, pathtracedvolume.presets; "
            "print(sorted(m for m in sys.modules if m.startswith('vtk')))")
    result = subprocess.run([sys.executable, "-c", code,
                             str(REPO_ROOT / "Python")],
                            capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "[]"


def test_paraview_imports_the_presets(tmp_path: Path) -> None:
    """ParaView itself imports each file and applies RGBPoints and Points."""
    code = r"""
import json, sys
from paraview.simple import (GetColorTransferFunction,
                             GetOpacityTransferFunction, ImportPresets)
result = {}
for path in sys.argv[1:]:
    assert ImportPresets(path), path
    for preset in json.load(open(path)):
        lut = GetColorTransferFunction("ImageScalars")
        pwf = GetOpacityTransferFunction("ImageScalars")
        ok = lut.ApplyPreset(preset["Name"], False) and \
            pwf.ApplyPreset(preset["Name"], False)
        space = lut.ColorSpace
        space = space.GetData() if hasattr(space, "GetData") else space
        result[preset["Name"]] = [bool(ok), list(lut.RGBPoints),
                                  list(pwf.Points), str(space)]
print(json.dumps(result))
"""
    env = dict(os.environ, HOME=str(tmp_path),
               XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_CACHE_HOME=str(tmp_path / "cache"))
    files = sorted(str(p) for p in PRESET_DIR.glob("*.json"))
    result = subprocess.run([sys.executable, "-c", code, *files], env=env,
                            capture_output=True, text=True, timeout=300,
                            check=False)
    assert result.returncode == 0, result.stderr
    applied = json.loads(result.stdout.strip().splitlines()[-1])
    for path in files:
        for preset in ptv_presets.load_presets(path):
            ok, rgb, points, space = applied[preset["Name"]]
            assert ok
            assert rgb == pytest.approx(preset["RGBPoints"])
            assert points == pytest.approx(preset["Points"])
            assert space == "RGB"
