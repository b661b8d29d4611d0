"""The edge pixels of a frame (the rule of the mapper's EdgeSamples, ``docs/edge-samples.md``):
pixels whose 3x3 neighbourhood (clamped at the image's border) holds a camera ray of opacity
(the Coverage pass) of at least ``HIGH`` and one below ``LOW``. Plain NumPy, so that pvpython,
the tests, the benchmarks and the training data use one definition (the C++ one is
Rendering/Trace/ptvEdgeSamples.h's FindEdgePixels).
"""
from __future__ import annotations

import numpy as np

HIGH = 0.5  #: ptvEdgeSamples.h kEdgeHigh
LOW = 0.05  #: ptvEdgeSamples.h kEdgeLow


def edge_mask(coverage: np.ndarray) -> np.ndarray:
    """Boolean ``(H, W)`` mask of the edge pixels of a ``(H, W)`` Coverage image (NaN counts
    as neither high nor low, as in the C++)."""
    coverage = np.asarray(coverage, np.float32)
    if coverage.ndim != 2:
        raise ValueError(f"edge_mask: expected an (H, W) Coverage image, got shape "
                         f"{coverage.shape}")
    c = np.pad(coverage, 1, mode="edge")
    h, w = coverage.shape
    windows = np.stack([c[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)])
    with np.errstate(invalid="ignore"):
        return np.any(windows >= HIGH, axis=0) & np.any(windows < LOW, axis=0)
