"""One training view = one multi-channel float32 EXR: channel names, writing, reading.

Channel names follow the EXR conventions (``R,G,B``; ``albedo.R``; ``N.X``; ``Z``; ``P.X``)::

    pass (vtkPathTracedVolumeMapper)   1-spp channels             k-spp inputs (k = 2, 4)
    Radiance                           R, G, B                    spp<k>.R, spp<k>.G, spp<k>.B
    Alpha                              alpha.A                    spp<k>.alpha.A
    Albedo                             albedo.R/G/B               spp<k>.albedo.R/G/B
    Depth                              Z                          spp<k>.Z
    Position                           P.X/Y/Z                    spp<k>.P.X/Y/Z
    Normal                             N.X/Y/Z                    spp<k>.N.X/Y/Z
    ScatterDepth                       scatter.Z                  spp<k>.scatter.Z
    ScatterPosition                    scatter.P.X/Y/Z            spp<k>.scatter.P.X/Y/Z
    ScatterNormal                      scatter.N.X/Y/Z            spp<k>.scatter.N.X/Y/Z
    Coverage                           coverage.A                 spp<k>.coverage.A
    Footprint (optional)               footprint.A                spp<k>.footprint.A

plus radiance-only images: ``reference.R/G/B`` (R spp, an independent seed), ``reference_half.*``
(the first R/2 of those frames, for the convergence check) and ``spp16.*`` (16 spp from the
inputs' seed: the "16 spp" baseline; its first 1/2/4 frames are the inputs).

The Footprint pass (the denoiser keeps the pixels it marks empty black) is stored where it was
rendered -- the evaluation views of ``heldout.py`` and ``compare.py`` -- and is not required:
GuideNet does not read it, so the training views do without it.

Rows: EXR stores the top row first; VTK's passes are bottom row first. Files hold the image the
usual way up (top first); :func:`read_view` returns arrays in VTK order (row 0 = bottom), the
order ``ptv_training.features`` and ``vtkPTVDenoiser`` use. The header attribute ``ptv.view``
holds the JSON of the view's parameters (see ``generate.py``).

Only numpy and the ``OpenEXR`` bindings (PyPI ``OpenEXR``) are needed: no VTK.
"""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np
from pathtracedvolume.atomic import atomic_path

#: pass name -> EXR channel names (without spp prefix), component order.
PASS_CHANNELS: Dict[str, Tuple[str, ...]] = {
    "Radiance": ("R", "G", "B"),
    "Alpha": ("alpha.A",),
    "Albedo": ("albedo.R", "albedo.G", "albedo.B"),
    "Depth": ("Z",),
    "Position": ("P.X", "P.Y", "P.Z"),
    "Normal": ("N.X", "N.Y", "N.Z"),
    "ScatterDepth": ("scatter.Z",),
    "ScatterPosition": ("scatter.P.X", "scatter.P.Y", "scatter.P.Z"),
    "ScatterNormal": ("scatter.N.X", "scatter.N.Y", "scatter.N.Z"),
    "Coverage": ("coverage.A",),
}
INPUT_PASSES: Tuple[str, ...] = tuple(PASS_CHANNELS)
#: passes a view file may hold (written and read when present, never required)
OPTIONAL_PASS_CHANNELS: Dict[str, Tuple[str, ...]] = {"Footprint": ("footprint.A",)}
ALL_PASS_CHANNELS: Dict[str, Tuple[str, ...]] = {**PASS_CHANNELS, **OPTIONAL_PASS_CHANNELS}
INPUT_SPP: Tuple[int, ...] = (1, 2, 4)
#: radiance-only images: key -> channel prefix
RADIANCE_IMAGES: Dict[str, str] = {"reference": "reference.", "reference_half": "reference_half.",
                                   "spp16": "spp16."}
VIEW_ATTRIBUTE = "ptv.view"
#: header attribute: SHA-256 of the pixel data (see :func:`channels_digest`). EXR has no checksum
#: of its own and stores incompressible blocks raw, so a damaged byte would otherwise read fine.
DIGEST_ATTRIBUTE = "ptv.sha256"


def spp_prefix(spp: int) -> str:
    """"" for 1 spp, "spp<k>." otherwise."""
    return "" if spp == 1 else f"spp{spp}."


def channel_names(input_spp: Iterable[int] = INPUT_SPP) -> List[str]:
    """Every channel a complete view file has."""
    names: List[str] = []
    for spp in input_spp:
        for chans in PASS_CHANNELS.values():
            names.extend(spp_prefix(spp) + c for c in chans)
    for prefix in RADIANCE_IMAGES.values():
        names.extend(prefix + c for c in "RGB")
    return names


def _as_hwc(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a, dtype=np.float32)
    return a[:, :, None] if a.ndim == 2 else a


def pack_passes(passes: Mapping[str, np.ndarray], prefix: str) -> Dict[str, np.ndarray]:
    """EXR channels ``prefix + channel`` (top row first) of every pass of
    :data:`PASS_CHANNELS` and those of :data:`OPTIONAL_PASS_CHANNELS` in ``passes``, each
    ``(H, W[, C])`` in VTK row order."""
    out: Dict[str, np.ndarray] = {}
    for name, chans in ALL_PASS_CHANNELS.items():
        if name in OPTIONAL_PASS_CHANNELS and name not in passes:
            continue
        a = _as_hwc(passes[name])
        if a.shape[2] != len(chans):
            raise ValueError(f"pass {name} has {a.shape[2]} components, expected {len(chans)}")
        for i, c in enumerate(chans):
            out[prefix + c] = np.ascontiguousarray(a[::-1, :, i])
    return out


def unpack_passes(channels: Mapping[str, np.ndarray], prefix: str) -> Dict[str, np.ndarray]:
    """The passes of :data:`PASS_CHANNELS` stored under ``prefix`` (:func:`pack_passes`), and
    those of :data:`OPTIONAL_PASS_CHANNELS` the file has, each ``(H, W, C)`` in VTK row order."""
    return {name: np.ascontiguousarray(np.stack([channels[prefix + c][::-1] for c in chans], -1))
            for name, chans in ALL_PASS_CHANNELS.items()
            if name in PASS_CHANNELS or all(prefix + c in channels for c in chans)}


def digest_matches(channels: Mapping[str, np.ndarray], header: Mapping[str, object]) -> bool:
    """Whether the header's ``ptv.sha256`` (when present) is that of ``channels``."""
    digest = header.get(DIGEST_ATTRIBUTE)
    if isinstance(digest, bytes):
        digest = digest.decode(errors="replace")
    return digest is None or str(digest) == channels_digest(channels)


def pack_view(inputs: Mapping[int, Mapping[str, np.ndarray]],
              radiance: Mapping[str, np.ndarray]) -> Dict[str, np.ndarray]:
    """EXR channels (top row first) from ``inputs[spp][pass]`` and ``radiance[key]``, all
    ``(H, W[, C])`` in VTK row order."""
    out: Dict[str, np.ndarray] = {}
    for spp, passes in inputs.items():
        out.update(pack_passes(passes, spp_prefix(spp)))
    for key, prefix in RADIANCE_IMAGES.items():
        a = _as_hwc(radiance[key])
        for i, c in enumerate("RGB"):
            out[prefix + c] = np.ascontiguousarray(a[::-1, :, i])
    return out


def channels_digest(channels: Mapping[str, np.ndarray]) -> str:
    """SHA-256 (hex) over the channel names and float32 pixels, in name order."""
    h = hashlib.sha256()
    for name in sorted(channels):
        a = np.ascontiguousarray(channels[name], dtype=np.float32)
        h.update(f"{name}:{a.shape}".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def write_exr(path: str | os.PathLike, channels: Mapping[str, np.ndarray],
              attributes: Optional[Mapping[str, str]] = None) -> Path:
    """Write float32 ``channels`` (each ``(H, W)``, top row first) ZIP-compressed, atomically
    (a temporary file in the same folder, then ``os.replace``), with the pixels' SHA-256 in the
    ``ptv.sha256`` attribute so that :func:`verify_view_file` detects damaged bytes."""
    import OpenEXR

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    for key, value in (attributes or {}).items():
        header[str(key)] = str(value)
    data = {k: np.ascontiguousarray(v, dtype=np.float32) for k, v in channels.items()}
    header[DIGEST_ATTRIBUTE] = channels_digest(data)
    with atomic_path(path, suffix=".tmp.exr") as tmp:
        with OpenEXR.File(header, data) as f:
            f.write(str(tmp))
    return path


def read_exr(path: str | os.PathLike) -> Tuple[Dict[str, np.ndarray], Dict[str, object]]:
    """(channels ``(H, W)`` float32 top row first, header) of an EXR file."""
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as f:
        header = dict(f.header())
        channels = {k: np.asarray(v.pixels, dtype=np.float32) for k, v in f.channels().items()}
    return channels, header


def view_attribute(header: Mapping[str, object]) -> Optional[dict]:
    """The parsed ``ptv.view`` JSON of a header, or None."""
    text = header.get(VIEW_ATTRIBUTE)
    if text is None:
        return None
    if isinstance(text, bytes):
        text = text.decode()
    try:
        return json.loads(str(text))
    except json.JSONDecodeError:
        return None


def input_spp(view: Optional[Mapping]) -> Sequence[int]:
    """The input sample counts a view lists (``generate.py --input-spp``); :data:`INPUT_SPP` for
    views made before the option, or no view."""
    return (view or {}).get("input_spp", INPUT_SPP)


def verify_view_file(path: str | os.PathLike, expected_view: Optional[Mapping] = None,
                     size: Optional[Tuple[int, int]] = None) -> Tuple[bool, str]:
    """(ok, why not): the file reads, has every channel, finite values, the expected size and,
    when given, the expected ``ptv.view`` parameters."""
    try:
        channels, header = read_exr(path)
    except Exception as exc:  # noqa: BLE001 -- any unreadable file is "not ok"
        return False, f"unreadable: {exc}"
    view = expected_view if expected_view is not None else view_attribute(header)
    missing = [c for c in channel_names(input_spp(view)) if c not in channels]
    if missing:
        return False, f"missing channels {missing[:4]}..."
    shapes = {v.shape for v in channels.values()}
    if len(shapes) != 1:
        return False, f"channel sizes differ: {shapes}"
    if size is not None and shapes.pop() != (size[1], size[0]):
        return False, "wrong size"
    if not digest_matches(channels, header):
        return False, "checksum mismatch (damaged pixel data)"
    if not all(np.isfinite(v).all() for v in channels.values()):
        return False, "non-finite values"
    if expected_view is not None:
        got = view_attribute(header)
        if got != json.loads(json.dumps(expected_view)):
            return False, "view parameters differ"
    return True, ""


def read_view(path: str | os.PathLike) -> Dict[str, object]:
    """A view file as ``{"inputs": {spp: {pass: (H, W, C)}}, "reference": (H, W, 3),
    "reference_half": ..., "spp16": ..., "view": dict}``, arrays in VTK row order."""
    channels, header = read_exr(path)

    def stack(names: Iterable[str]) -> np.ndarray:
        return np.ascontiguousarray(np.stack([channels[n][::-1] for n in names], axis=-1))

    inputs: Dict[int, Dict[str, np.ndarray]] = {}
    view = view_attribute(header)
    for spp in input_spp(view):
        prefix = spp_prefix(spp)
        if prefix + "R" not in channels:
            continue
        inputs[spp] = unpack_passes(channels, prefix)
    out: Dict[str, object] = {"inputs": inputs, "view": view}
    for key, prefix in RADIANCE_IMAGES.items():
        out[key] = stack(prefix + c for c in "RGB")
    return out
