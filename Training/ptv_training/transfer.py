"""Random transfer functions for the training views, and the held-out ones the study tests.

Users load their own volume and drag the transfer function, so the training views do not use our
presets: every view gets a transfer function drawn from the volume's own histogram.

:func:`histogram_quantiles` summarises a volume once: its value range and the quantiles of its
*occupied* voxels. A background is left out: the voxels in the lowest 5 % of the value range when
they are more than 20 % of the volume (air around a CT scan, the zero background of an MRI).
:func:`random_transfer_function` then draws, deterministically from an ``np.random.Generator``:

* **bands** (probability 0.6): one to three non-overlapping bands. Each band's centre is a
  quantile ``u ~ U(0.05, 0.995)`` of the occupied voxels, so bands sit where the data is. Its
  width is log-uniform in 1-25 % of the value range, and each edge ramp log-uniform in 0.1-50 %
  of the width. Its opacity is log-uniform in [0.02, 1] and its
  colour random (HSV: any hue, saturation 0-1, value 0.5-1).
* **ramp** (probability 0.4): opacity rising linearly from 0 at a quantile ``u ~ U(0, 0.9)``
  to a log-uniform maximum in [0.02, 1] over 2-60 % of the range, then flat to the top, with a
  three-colour map spread over the ramp.

The result is a preset dictionary (``Points``: x, opacity, 0.5, 0; ``RGBPoints``: x, r, g, b), as
:func:`pathtracedvolume.presets.make_functions` takes, and JSON-friendly, so it is stored with
the view.

:func:`held_out_transfer_functions` gives three shapes the generator never draws, for the
held-out transfer-function table: *translucent* (one ramp over the whole occupied range with
opacity at most 0.04), *smooth* (two Gaussian bumps sampled at 33 points each, opacity 0.5 and
0.15) and *narrow* (two bands 0.3 % of the range wide, below the generator's 1 % minimum, with
edges 0.05 % wide).
"""
from __future__ import annotations

import colorsys
from typing import Any, Dict, List, Sequence, Tuple

import numpy as np

QUANTILE_LEVELS = np.linspace(0.0, 1.0, 1001)

Preset = Dict[str, Any]


def histogram_quantiles(values: np.ndarray) -> Dict[str, List[float]]:
    """``{"range": [min, max], "quantiles": q}``: q are the occupied voxels' quantiles at 0,
    0.001, ..., 1 (1001 numbers; the background rule is in the module doc)."""
    flat = np.asarray(values, dtype=np.float64).reshape(-1)
    lo, hi = float(flat.min()), float(flat.max())
    background = flat <= lo + 0.05 * (hi - lo)
    occupied = flat[~background] if background.mean() > 0.2 and not background.all() else flat
    return {"range": [lo, hi],
            "quantiles": [float(v) for v in np.quantile(occupied, QUANTILE_LEVELS)]}


def _at(quantiles: Sequence[float], u: float) -> float:
    return float(np.interp(u, QUANTILE_LEVELS, quantiles))


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(np.exp(rng.uniform(np.log(lo), np.log(hi))))


def _colour(rng: np.random.Generator) -> List[float]:
    r, g, b = colorsys.hsv_to_rgb(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0),
                                  rng.uniform(0.5, 1.0))
    return [float(r), float(g), float(b)]


def _preset(name: str, opacity: Sequence[Tuple[float, float]],
            colours: Sequence[Tuple[float, Sequence[float]]]) -> Preset:
    """A preset from sorted (x, opacity) and (x, rgb) points; of points at the same x (a
    quantile that equals the range's end) the last one is kept."""
    def dedupe(points):
        out: list = []
        for point in points:
            if out and point[0] == out[-1][0]:
                out[-1] = point
            else:
                out.append(point)
        return out
    opacity, colours = dedupe(opacity), dedupe(colours)
    for points in (opacity, colours):
        xs = [p[0] for p in points]
        if any(b <= a for a, b in zip(xs, xs[1:])):
            raise ValueError(f"{name}: control points not strictly increasing: {xs}")
    return {"Name": name, "ColorSpace": "RGB",
            "Points": [float(v) for x, a in opacity for v in (x, a, 0.5, 0.0)],
            "RGBPoints": [float(v) for x, c in colours for v in (x, *c)]}


def _bands(name: str, lo: float, hi: float,
           bands: Sequence[Tuple[float, float, float, float, Sequence[float]]]) -> Preset:
    """Bands (start, end, edge, opacity, colour), sorted and separated, on [lo, hi]: opacity 0
    outside, linear edges of width ``edge`` just outside each band, the band's colour constant
    inside it and interpolated between bands."""
    opacity: List[Tuple[float, float]] = [(lo, 0.0)]
    colours: List[Tuple[float, Sequence[float]]] = []
    for start, end, edge, alpha, colour in bands:
        for x, a in ((start - edge, 0.0), (start, alpha), (end, alpha), (end + edge, 0.0)):
            x = min(max(x, lo), hi)
            if x > opacity[-1][0]:
                opacity.append((x, a))
            else:  # a band edge clipped at the range's end: keep the larger opacity there
                opacity[-1] = (opacity[-1][0], max(opacity[-1][1], a))
        colours += [(start, colour), (end, colour)]
    if opacity[-1][0] < hi:
        opacity.append((hi, 0.0))
    colours = [(lo, colours[0][1])] * (colours[0][0] > lo) + colours
    if colours[-1][0] < hi:
        colours.append((hi, colours[-1][1]))
    return _preset(name, opacity, colours)


def random_transfer_function(histogram: Dict[str, List[float]],
                             rng: np.random.Generator) -> Preset:
    """One random transfer function for a volume with this :func:`histogram_quantiles`."""
    lo, hi = histogram["range"]
    quantiles = histogram["quantiles"]
    span = hi - lo
    if span <= 0:
        raise ValueError(f"constant volume (range [{lo}, {hi}])")
    if rng.random() < 0.6:
        count = int(rng.integers(1, 4))
        bands: List[Tuple[float, float, float, float, Sequence[float]]] = []
        for _ in range(20 * count):
            if len(bands) == count:
                break
            centre = _at(quantiles, rng.uniform(0.05, 0.995))
            width = _log_uniform(rng, 0.01, 0.25) * span
            edge = _log_uniform(rng, 0.001, 0.5) * width
            start, end = max(centre - width / 2, lo), min(centre + width / 2, hi)
            candidate = (start, end, edge, _log_uniform(rng, 0.02, 1.0), _colour(rng))
            gap = 1e-3 * span
            if end - start < 1e-6 * span or any(
                    start - edge < b[1] + b[2] + gap and b[0] - b[2] < end + edge + gap
                    for b in bands):
                continue
            bands.append(candidate)
        bands.sort(key=lambda b: b[0])
        return _bands(f"random bands x{len(bands)}", lo, hi, bands)
    start = _at(quantiles, rng.uniform(0.0, 0.9))
    end = min(start + rng.uniform(0.02, 0.6) * span, hi)
    if end - start < 1e-3 * span:
        start = end - 1e-3 * span
    alpha = _log_uniform(rng, 0.02, 1.0)
    opacity = [(lo, 0.0), (start, 0.0), (end, alpha)] + [(hi, alpha)] * (end < hi)
    if start <= lo:
        opacity = opacity[1:]
    mid = (start + end) / 2
    colours = [(lo, _colour(rng))] * (start > lo) + [(start, _colour(rng)), (mid, _colour(rng)),
                                                     (end, _colour(rng))]
    if end < hi:
        colours.append((hi, colours[-1][1]))
    return _preset("random ramp", opacity, colours)


def held_out_transfer_functions(histogram: Dict[str, List[float]]) -> Dict[str, Preset]:
    """The three held-out shapes (module doc), placed by the volume's occupied quantiles."""
    lo, hi = histogram["range"]
    quantiles = histogram["quantiles"]
    span = hi - lo
    warm, cool, bone = [1.0, 0.62, 0.35], [0.45, 0.7, 1.0], [0.98, 0.95, 0.9]

    start = _at(quantiles, 0.2)
    top = max(_at(quantiles, 0.999), start + 0.01 * span)
    translucent = _preset("held-out translucent",
                          [(lo, 0.0), (start, 0.0), (top, 0.04)] + [(hi, 0.04)] * (top < hi),
                          [(lo, cool), (start, cool), (top, warm)] + [(hi, warm)] * (top < hi))

    opacity: List[Tuple[float, float]] = [(lo, 0.0)]
    colours: List[Tuple[float, Sequence[float]]] = [(lo, cool)]
    for u, sigma, peak, colour in ((0.5, 0.03, 0.15, cool), (0.95, 0.04, 0.5, warm)):
        centre = _at(quantiles, u)
        for t in np.linspace(-3.0, 3.0, 33):
            x = centre + t * sigma * span
            if opacity[-1][0] < x < hi:
                opacity.append((x, peak * float(np.exp(-0.5 * t * t))))
        if colours[-1][0] < centre < hi:
            colours.append((centre, colour))
    opacity.append((hi, 0.0))
    colours.append((hi, warm))
    smooth = _preset("held-out smooth", opacity, colours)

    narrow_bands = []
    for u, alpha, colour in ((0.5, 0.6, cool), (0.97, 0.9, bone)):
        centre = _at(quantiles, u)
        half = 0.0015 * span
        start, end = max(centre - half, lo + 0.001 * span), min(centre + half, hi - 0.001 * span)
        if narrow_bands and start - 0.0005 * span <= narrow_bands[-1][1] + 0.0015 * span:
            start = narrow_bands[-1][1] + 0.003 * span
            end = start + 2 * half
        narrow_bands.append((start, end, 0.0005 * span, alpha, colour))
    narrow = _bands("held-out narrow", lo, hi, narrow_bands)
    return {"translucent": translucent, "smooth": smooth, "narrow": narrow}
