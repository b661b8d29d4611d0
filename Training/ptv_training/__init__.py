"""Training code of the PathTracedVolume denoiser (GuideNet, bilateral-grid reference)."""
import sys as _sys
from pathlib import Path as _Path

# The pure-Python part of the product package (pathtracedvolume.atomic, .datasets, ...), after
# PYTHONPATH so that a built package wins.
_PYTHON_DIR = str(_Path(__file__).resolve().parents[2] / "Python")
if _PYTHON_DIR not in _sys.path:
    _sys.path.append(_PYTHON_DIR)
