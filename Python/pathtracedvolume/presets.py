"""Transfer-function presets in ParaView's colour-map preset JSON format.

A preset file is a JSON list of objects such as::

    {"Name": "Head Two-Band (paper)",
     "ColorSpace": "RGB",
     "RGBPoints": [x0, r0, g0, b0, x1, r1, g1, b1, ...],
     "Points":    [x0, opacity0, midpoint0, sharpness0, ...]}

This is the format ParaView imports (Color Map Editor, "Import", or
``paraview.simple.ImportPresets``).  ``RGBPoints`` fills a
``vtkColorTransferFunction``, ``Points`` (the opacity map) a
``vtkPiecewiseFunction``.  The project's presets live in
``Data/TransferFunctions/`` (see ``scripts/make_transfer_functions.py``).

Only the standard library is imported at module import time; VTK
(``vtkmodules``) is imported by :func:`apply_preset` and
:func:`make_functions` when called.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any, Iterable, Mapping

from .datasets import repo_root

__all__ = [
    "apply_preset",
    "find_preset",
    "load_presets",
    "make_functions",
    "preset_names",
    "presets_dir",
]

# ParaView ColorSpace name -> suffix of vtkColorTransferFunction's
# SetColorSpaceTo<suffix>() method.
_SPACE_SUFFIX = {
    "RGB": "RGB",
    "HSV": "HSV",
    "Lab": "Lab",
    "CIELAB": "Lab",
    "Lab/CIEDE2000": "LabCIEDE2000",
    "Diverging": "Diverging",
    "Step": "Step",
}
_COLOR_SPACES = tuple(_SPACE_SUFFIX)


def presets_dir() -> Path:
    """Folder with the project's presets.

    ``$PTV_PRESETS_DIR`` when set, else ``$PTV_DATA_DIR/TransferFunctions``, else the plugin
    folder's ``Data/TransferFunctions`` when this package is the plugin folder's
    (``<plugin folder>/python/pathtracedvolume``: an install or the build tree), else
    ``<repository>/Data/TransferFunctions`` (the package used from the source tree).
    """
    env = os.environ.get("PTV_PRESETS_DIR")
    if env:
        return Path(env).expanduser().resolve()
    data = os.environ.get("PTV_DATA_DIR")
    if data:
        return Path(data).expanduser().resolve() / "TransferFunctions"
    plugin = Path(__file__).resolve().parents[2] / "Data" / "TransferFunctions"
    if plugin.is_dir():
        return plugin
    return repo_root() / "Data" / "TransferFunctions"


def _numbers(path: Path, label: str, field: str, value: Any,
             stride: int) -> list[float]:
    if not isinstance(value, list) or not value:
        raise ValueError(f"{path}: {label}: field {field!r} must be a "
                         "non-empty list of numbers")
    if len(value) % stride:
        raise ValueError(f"{path}: {label}: field {field!r} has {len(value)} "
                         f"numbers, not a multiple of {stride}")
    numbers = []
    for index, item in enumerate(value):
        if isinstance(item, bool) or not isinstance(item, (int, float)) \
                or not math.isfinite(item):
            raise ValueError(f"{path}: {label}: field {field!r}[{index}] is "
                             f"not a finite number: {item!r}")
        numbers.append(float(item))
    xs = numbers[::stride]
    for i in range(1, len(xs)):
        if xs[i] < xs[i - 1]:
            raise ValueError(f"{path}: {label}: field {field!r}: control "
                             f"point x values decrease ({xs[i - 1]} then "
                             f"{xs[i]})")
    return numbers


def _validate(path: Path, index: int, preset: Any) -> dict[str, Any]:
    label = f"preset #{index}"
    if not isinstance(preset, dict):
        raise ValueError(f"{path}: {label} is not a JSON object")
    name = preset.get("Name")
    if not isinstance(name, str) or not name:
        raise ValueError(f"{path}: {label}: field 'Name' must be a non-empty "
                         "string")
    label = f"preset #{index} ({name!r})"
    space = preset.get("ColorSpace", "RGB")
    if space not in _COLOR_SPACES:
        raise ValueError(f"{path}: {label}: field 'ColorSpace' is {space!r}; "
                         f"expected one of {', '.join(_COLOR_SPACES)}")
    if "RGBPoints" not in preset:
        raise ValueError(f"{path}: {label}: missing field 'RGBPoints'")
    rgb = _numbers(path, label, "RGBPoints", preset["RGBPoints"], 4)
    for i in range(0, len(rgb), 4):
        if not all(0.0 <= c <= 1.0 for c in rgb[i + 1:i + 4]):
            raise ValueError(f"{path}: {label}: field 'RGBPoints': colour "
                             f"{rgb[i + 1:i + 4]} at x={rgb[i]} is outside "
                             "[0, 1]")
    if "Points" in preset:
        points = _numbers(path, label, "Points", preset["Points"], 4)
        for i in range(0, len(points), 4):
            opacity, midpoint, sharpness = points[i + 1:i + 4]
            if not (0.0 <= opacity <= 1.0 and 0.0 <= midpoint <= 1.0
                    and 0.0 <= sharpness <= 1.0):
                raise ValueError(f"{path}: {label}: field 'Points': "
                                 f"(opacity, midpoint, sharpness) = "
                                 f"{points[i + 1:i + 4]} at x={points[i]} "
                                 "must lie in [0, 1]")
    return preset


def load_presets(path: Path | str) -> list[dict[str, Any]]:
    """Load and validate the presets of one ParaView preset JSON file.

    Args:
        path: a ``.json`` file holding a list of preset objects.

    Returns:
        The presets (as parsed, validated dictionaries), in file order.

    Raises:
        FileNotFoundError: if *path* does not exist.
        ValueError: if the JSON is malformed or a preset lacks or has an
            invalid field; the message names the file and the field.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: invalid JSON: {exc}") from exc
    if isinstance(data, dict):  # a single preset object is accepted too
        data = [data]
    if not isinstance(data, list) or not data:
        raise ValueError(f"{path}: expected a non-empty JSON list of presets")
    return [_validate(path, index, preset)
            for index, preset in enumerate(data)]


def _preset_files(paths: Iterable[Path | str] | None) -> list[Path]:
    if paths is not None:
        return [Path(p) for p in paths]
    folder = presets_dir()
    if not folder.is_dir():
        raise FileNotFoundError(f"presets folder {folder} does not exist")
    return sorted(folder.glob("*.json"))


def preset_names(paths: Iterable[Path | str] | None = None) -> list[str]:
    """Names of the presets in *paths* (default: :func:`presets_dir`)."""
    return [preset["Name"] for path in _preset_files(paths)
            for preset in load_presets(path)]


def find_preset(name: str,
                paths: Iterable[Path | str] | None = None) -> dict[str, Any]:
    """Return the preset called *name*.

    Args:
        name: exact preset name, e.g. ``"Head Two-Band (paper)"``.
        paths: preset files to search (default: all ``*.json`` files in
            :func:`presets_dir`).

    Raises:
        KeyError: if no preset has that name; the message lists the
            available names.
    """
    available = []
    for path in _preset_files(paths):
        for preset in load_presets(path):
            if preset["Name"] == name:
                return preset
            available.append(preset["Name"])
    raise KeyError(f"unknown preset {name!r}; available: "
                   + ", ".join(repr(n) for n in available))


def make_functions(preset: Mapping[str, Any]) -> tuple[Any, Any]:
    """Build the colour and opacity functions described by *preset*.

    Returns:
        ``(vtkColorTransferFunction, vtkPiecewiseFunction)``.

    Raises:
        ValueError: if the preset has no opacity ``Points``.
    """
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction

    name = preset.get("Name", "<unnamed>")
    if "Points" not in preset:
        raise ValueError(f"preset {name!r}: field 'Points' (opacity map) is "
                         "required for volume rendering")
    color = vtkColorTransferFunction()
    space = preset.get("ColorSpace", "RGB")
    setter = getattr(color, "SetColorSpaceTo" + _SPACE_SUFFIX.get(space, "?"),
                     None)
    if setter is None:
        raise ValueError(f"preset {name!r}: unsupported ColorSpace {space!r}")
    setter()
    rgb = [float(v) for v in preset["RGBPoints"]]
    for i in range(0, len(rgb), 4):
        color.AddRGBPoint(rgb[i], rgb[i + 1], rgb[i + 2], rgb[i + 3])
    nan = preset.get("NanColor")
    if isinstance(nan, list) and len(nan) >= 3:
        color.SetNanColor(*(float(c) for c in nan[:3]))

    opacity = vtkPiecewiseFunction()
    points = [float(v) for v in preset["Points"]]
    for i in range(0, len(points), 4):
        opacity.AddPoint(points[i], points[i + 1], points[i + 2],
                         points[i + 3])
    return color, opacity


def apply_preset(preset: Mapping[str, Any], volume_property: Any,
                 component: int = 0) -> tuple[Any, Any]:
    """Set a preset's colour and opacity functions on a ``vtkVolumeProperty``.

    Args:
        preset: a preset dictionary (see :func:`load_presets`,
            :func:`find_preset`).
        volume_property: the ``vtkVolumeProperty`` to modify.
        component: scalar component the functions apply to.

    Returns:
        The new ``(vtkColorTransferFunction, vtkPiecewiseFunction)``.
    """
    color, opacity = make_functions(preset)
    volume_property.SetColor(component, color)
    volume_property.SetScalarOpacity(component, opacity)
    return color, opacity
