"""PathTracedVolume: path-traced volume rendering with a neural bilateral-grid denoiser.

The compiled VTK classes (``vtkPTVOpenVDBReader``, ...) are importable from the wrapped modules
``pathtracedvolume.vtkPTVRendering`` and ``pathtracedvolume.vtkPTVFilters``, or directly from this
package (``pathtracedvolume.vtkPTVOpenVDBReader``), loaded on first use so that the pure-Python
helpers (:mod:`.datasets`, :mod:`.presets`) also work before the C++ part is built.
"""
from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"
_COMPILED = ("vtkPTVRendering", "vtkPTVFilters")


def __getattr__(name: str) -> Any:
    if name.startswith("vtk"):
        for module_name in _COMPILED:
            try:
                module = importlib.import_module(f"{__name__}.{module_name}")
            except ImportError as exc:
                raise ImportError(
                    f"pathtracedvolume: compiled module {module_name} is not available ({exc}); "
                    "build the project (scripts/setup.sh) and put <build>/python on PYTHONPATH"
                ) from exc
            if hasattr(module, name):
                return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
