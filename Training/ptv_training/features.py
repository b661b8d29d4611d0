"""GuideNet input features: the canonical channel list and how each channel is computed from the
mapper's named passes (``vtkPathTracedVolumeMapper::GetPass``).

This is the single definition of the features; the C++ side (the denoiser in the mapper) must
reproduce :func:`build_features` exactly, so every rule here is a per-pixel formula plus at most
one global min/max per frame and pass, computed in float32.

Passes (``passes[name]`` is ``(H, W, C)`` or ``(H, W)`` for one component, row ``j`` = image row
``j`` as VTK stores it)::

    Radiance         3  premultiplied HDR RGB (misses 0)
    Alpha            1  in [0, 1]
    Albedo           3  colour at the first non-transparent sample (misses 0)
    Depth            1  world distance eye -> first sample; misses = camera far distance
    Position         3  world position of the first sample (misses 0)
    Normal           3  unit normal there, or 0 (misses, unshaded samples)
    ScatterDepth     1  like Depth, for the scattering event
    ScatterPosition  3  like Position, for the scattering event
    ScatterNormal    3  like Normal, for the scattering event
    Coverage         1  the camera ray's opacity in [0, 1] (CoverageMarch; else Alpha)
    DepthSpread      1  study pass, not traced by the mapper (``data.with_edge_samples``): on
                        an edge pixel |dA - dB|, the world distance between the first-event
                        depths of its frame sample and of its edge samples' mean where both hit;
                        0 elsewhere

Channels (names are what ``ptv.input_channels`` of an exported model lists)::

    color.r/g/b         clip(max(0, radiance)^(1/2.2), 0, 1)          (tone-mapped noisy colour)
    alpha               clip(alpha, 0, 1)
    albedo.r/g/b        clip(albedo, 0, 1)
    normal.x/y/z        clip((n + 1) / 2, 0, 1); misses and unshaded samples (n = 0) give 0.5
                        -- no special case: 0.5 is the formula at n = 0 and means "no normal"
    depth               hit = d < 0.999 * far; (d - dmin) / (dmax - dmin) over hits, clipped to
                        [0, 1]; 0 for every hit when dmax == dmin; misses 1
    position.x/y/z      hit as for depth; per axis (p - pmin) / (pmax - pmin) over hits, clipped;
                        0 for every hit when the axis range is 0; misses 0
    scatter_normal.*    as normal.*, from ScatterNormal
    scatter_depth       as depth, from ScatterDepth (hits are scattering events)
    scatter_position.*  as position.*, from ScatterPosition with the ScatterDepth hit mask
    coverage            clip(Coverage, 0, 1): the camera ray's opacity, its expected Alpha
                        without the event's coin flip (the expert option CoverageMarch): below 1
                        in a fog or a thin translucent layer, 1 on an opaque surface
    depth_spread        clip(DepthSpread / (dmax - dmin), 0, 1) with the depth channel's range
                        over hits (0 for a zero range): how noisy the pixel's depth is. A study
                        channel (``research/training/results/noise_aware.md``): the C++ denoiser does not
                        build it, so a model that reads it cannot be shipped
    history             1 / max(1, HistoryLength) (NaN counts as 1, +inf gives 0): the share of
                        the newest frame in the pixel's mean (a still accumulation of k
                        frames: 1 / k; the mapper's reprojected history: its per-pixel count);
                        without a HistoryLength pass every pixel counts one frame (1)

``far`` is the frame's maximum of that depth pass (the pass itself, no camera needed): when any
pixel misses it is exactly the camera far distance. In a frame without misses the farthest 0.1 %
of depths count as misses (value 1), which only differs from the camera-far rule by < 0.1 % of
the depth range near the far end.

Caveat: accumulated passes are running means, so a pixel that hits in some frames and misses in
others has a depth between its hits and far; it counts as a hit (below 0.999 far) and stretches
dmax toward far. Features built from many accumulated frames should keep that in mind.

Presets: :data:`COLOR_ONLY` (3), :data:`PAPER_10` (the paper's 10: colour, albedo, normal, depth)
and :data:`VOLUME_FEATURES` (14: PAPER_10 + scatter normal + scatter depth). Positions are left
out of the presets: per-frame min/max normalised world positions change with every view and
volume (poor generalisation to unseen volumes), while GuideNet's 9 x 9 receptive field sees
locally what they carry -- depth discontinuities and orientation -- through depth and normals.
They stay available as channels for ablations.
"""
from __future__ import annotations

from typing import Dict, Iterable, List, Mapping, Sequence, Tuple

import numpy as np

GAMMA = np.float32(1.0 / 2.2)
HIT_FRACTION = np.float32(0.999)  # depth < HIT_FRACTION * far is a hit

# kind -> (pass, hit-mask pass or None); each channel: name -> (kind, component)
_KINDS: Dict[str, Tuple[str, str | None]] = {
    "color": ("Radiance", None),
    "alpha": ("Alpha", None),
    "albedo": ("Albedo", None),
    "normal": ("Normal", None),
    "depth": ("Depth", "Depth"),
    "position": ("Position", "Depth"),
    "scatter_normal": ("ScatterNormal", None),
    "scatter_depth": ("ScatterDepth", "ScatterDepth"),
    "scatter_position": ("ScatterPosition", "ScatterDepth"),
    "history": ("HistoryLength", None),
    "coverage": ("Coverage", None),
    "depth_spread": ("DepthSpread", "Depth"),
}
_SUFFIXES = {"color": "rgb", "albedo": "rgb", "normal": "xyz", "position": "xyz",
             "scatter_normal": "xyz", "scatter_position": "xyz"}

#: Every channel name -> (kind, component index).
CHANNELS: Dict[str, Tuple[str, int]] = {}
for _kind in _KINDS:
    if _kind in _SUFFIXES:
        for _i, _s in enumerate(_SUFFIXES[_kind]):
            CHANNELS[f"{_kind}.{_s}"] = (_kind, _i)
    else:
        CHANNELS[_kind] = (_kind, 0)

#: Channel groups ("color" -> ["color.r", "color.g", "color.b"], "depth" -> ["depth"]).
GROUPS: Dict[str, List[str]] = {k: [c for c in CHANNELS if CHANNELS[c][0] == k] for k in _KINDS}

COLOR_ONLY: List[str] = GROUPS["color"]
PAPER_10: List[str] = GROUPS["color"] + GROUPS["albedo"] + GROUPS["normal"] + GROUPS["depth"]
VOLUME_FEATURES: List[str] = PAPER_10 + GROUPS["scatter_normal"] + GROUPS["scatter_depth"]

#: Named presets.
PRESETS: Dict[str, List[str]] = {
    "COLOR_ONLY": COLOR_ONLY,
    "PAPER_10": PAPER_10,
    "VOLUME_FEATURES": VOLUME_FEATURES,
}


def resolve_channels(spec: str | Iterable[str]) -> List[str]:
    """Channel names from a preset name ("PAPER_10"), or from names and group names, given as a
    comma-separated string or an iterable ("color,depth" -> color.r, color.g, color.b, depth)."""
    if isinstance(spec, str):
        if spec in PRESETS:
            return list(PRESETS[spec])
        items = [s.strip() for s in spec.split(",") if s.strip()]
    else:
        items = list(spec)
    out: List[str] = []
    for item in items:
        if item in PRESETS:
            out.extend(PRESETS[item])
        elif item in GROUPS:
            out.extend(GROUPS[item])
        elif item in CHANNELS:
            out.append(item)
        else:
            raise ValueError(f"unknown feature channel {item!r}; known: {', '.join(CHANNELS)} "
                             f"(groups {', '.join(GROUPS)}; presets {', '.join(PRESETS)})")
    if len(set(out)) != len(out):
        raise ValueError(f"duplicate channels in {out}")
    return out


def required_passes(channels: Sequence[str]) -> List[str]:
    """Pass names that :func:`build_features` reads for ``channels``."""
    needed: List[str] = []
    for name in channels:
        kind = _channel(name)[0]
        for p in _KINDS[kind]:
            if p is not None and p not in needed:
                needed.append(p)
    return needed


def _channel(name: str) -> Tuple[str, int]:
    try:
        return CHANNELS[name]
    except KeyError:
        raise ValueError(f"unknown feature channel {name!r}; known: {', '.join(CHANNELS)}") \
            from None


def _pass(passes: Mapping[str, np.ndarray], name: str, components: int) -> np.ndarray:
    if name not in passes:
        raise KeyError(f"pass {name!r} is needed but missing (have: {', '.join(passes)})")
    a = np.asarray(passes[name], dtype=np.float32)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] != components:
        raise ValueError(f"pass {name!r} has shape {a.shape}, expected (H, W, {components})")
    return a


def hit_mask(depth: np.ndarray) -> np.ndarray:
    """Hits of a depth pass ``(H, W)``: depth < 0.999 * (the frame's maximum depth)."""
    far = depth.max() if depth.size else np.float32(0)
    return depth < HIT_FRACTION * far


def _normalize_hits(values: np.ndarray, hits: np.ndarray, miss: float) -> np.ndarray:
    """(v - min) / (max - min) over ``hits`` (clipped; 0 for a zero range), ``miss`` elsewhere."""
    out = np.full(values.shape, np.float32(miss), dtype=np.float32)
    if hits.any():
        lo = values[hits].min()
        hi = values[hits].max()
        rng = np.float32(hi - lo)
        if rng > 0:
            out[hits] = np.clip((values[hits] - lo) / rng, 0.0, 1.0)
        else:
            out[hits] = 0.0
    return out


def _scale_by_hit_range(values: np.ndarray, depth: np.ndarray, hits: np.ndarray) -> np.ndarray:
    """clip(v / (max - min of ``depth`` over ``hits``), 0, 1); 0 for a zero range or no hits."""
    if not hits.any():
        return np.zeros(values.shape, np.float32)
    rng = np.float32(depth[hits].max() - depth[hits].min())
    if rng <= 0:
        return np.zeros(values.shape, np.float32)
    return np.clip(values / rng, 0.0, 1.0).astype(np.float32)


def build_features(passes: Mapping[str, np.ndarray], channels: Sequence[str]) -> np.ndarray:
    """Features ``(C, H, W)`` float32 for ``channels`` from the named passes (see module doc)."""
    channels = list(channels)
    if not channels:
        raise ValueError("no channels requested")
    cache: Dict[str, np.ndarray] = {}
    masks: Dict[str, np.ndarray] = {}
    planes: List[np.ndarray] = []
    shape: Tuple[int, int] | None = None
    components = {"Radiance": 3, "Alpha": 1, "Albedo": 3, "Depth": 1, "Position": 3,
                  "Normal": 3, "ScatterDepth": 1, "ScatterPosition": 3, "ScatterNormal": 3,
                  "HistoryLength": 1, "Coverage": 1, "DepthSpread": 1}

    def get(name: str) -> np.ndarray:
        nonlocal shape
        if name not in cache:
            cache[name] = _pass(passes, name, components[name])
            if shape is None:
                shape = cache[name].shape[:2]
            elif cache[name].shape[:2] != shape:
                raise ValueError(f"pass {name!r} is {cache[name].shape[:2]}, others {shape}")
        return cache[name]

    def mask(name: str) -> np.ndarray:
        if name not in masks:
            masks[name] = hit_mask(get(name)[:, :, 0])
        return masks[name]

    for name in channels:
        kind, comp = _channel(name)
        source, mask_pass = _KINDS[kind]
        if kind == "history" and source not in passes:  # one frame everywhere (as the C++)
            if shape is None:
                shape = get("Radiance").shape[:2]
            planes.append(np.ones(shape, np.float32))
            continue
        x = get(source)[:, :, comp]
        if kind == "color":
            plane = np.clip(np.power(np.maximum(x, np.float32(0)), GAMMA), 0.0, 1.0)
        elif kind == "history":  # 1 / frames in the pixel's mean: its noise variance scale
            frames = np.where(np.isnan(x), np.float32(1), x)  # NaN: one frame (as the C++)
            plane = np.float32(1) / np.maximum(frames, np.float32(1))
        elif kind in ("alpha", "albedo", "coverage"):
            plane = np.clip(x, 0.0, 1.0)
        elif kind in ("normal", "scatter_normal"):
            plane = np.clip((x + np.float32(1)) * np.float32(0.5), 0.0, 1.0)
        elif kind in ("depth", "scatter_depth"):
            plane = _normalize_hits(x, mask(mask_pass), miss=1.0)
        elif kind == "depth_spread":
            plane = _scale_by_hit_range(x, get(mask_pass)[:, :, 0], mask(mask_pass))
        else:  # position, scatter_position
            plane = _normalize_hits(x, mask(mask_pass), miss=0.0)
        planes.append(plane.astype(np.float32, copy=False))
    return np.ascontiguousarray(np.stack(planes, axis=0), dtype=np.float32)
