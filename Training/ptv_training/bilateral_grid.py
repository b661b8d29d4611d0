"""Torch reference of the bilateral-grid part of the Neural Bilateral Grid denoiser.

The semantics (sanitising, demodulation, outlier clamp, grid sizes, tent weights, empty
cells, slice renormalisation, blend, re-modulation) are defined once, in the comment at the top
of ``Rendering/Kernels/ptvBilateralGrid.h``; this module implements exactly that, with the same
single-precision expressions as the C++ grid that ``vtkPTVDenoiser`` runs, so both agree up to
the summation order of the splat. In short, per image::

    D = sanitize(R) / (sanitize(A) + 0.01)            # NaN/Inf/negative -> 0; D = sanitize(R)
                                                      # without albedo (no demodulation)
    D = min(D, clamp * max(mean(luminance(D) over lit pixels), 1e-6))  # when clamp > 0
    per level (ss, sr): splat D into a ceil(W/ss) x ceil(H/ss) x ceil(256/sr) grid (tent-weighted
        normalized means, empty cells 0), slice it trilinearly at (u, v, guide / sr) over the
        non-empty neighbours (renormalized)
    out = s1 w1 + s2 w2 + s3 (1 - w1 - w2)             # 3 levels; 2: s1 w1 + s2 (1 - w1)
    result = out * (sanitize(A) + 0.01)                # result = out without albedo

Everything is batched ``(N, C, H, W)`` and differentiable with respect to the guides and the
blend weights (the radiance and albedo are data). Grids are ``(N, 3, GD, GH, GW)`` values and
``(N, GD, GH, GW)`` weight sums.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence, Tuple

import torch

DEMODULATION_EPSILON = 0.01
MAX_RADIANCE = 1e30
GUIDE_MAX = 255.0
GUIDE_RANGE = 256
MAX_STEP = 256
MIN_OUTLIER_MEAN = 1e-6
DEFAULT_LEVELS: Tuple[Tuple[int, int], ...] = ((4, 4), (8, 8), (16, 16))
LUMINANCE = (0.2126, 0.7152, 0.0722)
#: A level whose spatial step leaves fewer grid cells than this over the image only blurs it.
MIN_GRID_CELLS = 16

Tensor = torch.Tensor


SMALL_IMAGE_PIXELS = 256 * 256


def automatic_levels(levels: Sequence[Tuple[int, int]], default: int, height: int,
                     width: int) -> int:
    """The level count the C++ denoiser uses when none is asked for: every one of a model's
    ``levels`` on an image of at most SMALL_IMAGE_PIXELS pixels, else its ``default``
    (ptv.default_levels), less those too coarse for the image (:func:`fitting_levels`). The
    coarser levels pay most on small images and cost little there (ptvDenoiser.cxx)."""
    count = len(levels) if height * width <= SMALL_IMAGE_PIXELS else min(default, len(levels))
    return fitting_levels(list(levels)[:count], height, width)


def fitting_levels(levels: Sequence[Tuple[int, int]], height: int, width: int) -> int:
    """How many of a model's ``levels`` (finest first) an image of ``height`` x ``width``
    pixels uses when the level count is automatic: the coarser levels whose grid would have
    fewer than MIN_GRID_CELLS cells over the image, (width / step) (height / step), are dropped;
    the finest level always stays. Measured on the head CT (the shipped model, 1 spp against a
    512-spp reference): at 8-24 pixels a side one level beats two by 0.3-2.2 dB; at 32 (16 cells
    of the 8-pixel level) two are level with one. The C++ denoiser (ptvDenoiser.cxx) does the
    same."""
    count = len(levels)
    while count > 1:
        step = levels[count - 1][0]
        if (width / step) * (height / step) >= MIN_GRID_CELLS:
            break
        count -= 1
    return count


def grid_shape(height: int, width: int, spatial_step: int,
               range_step: int) -> Tuple[int, int, int]:
    """Grid size ``(GD, GH, GW) = (ceil(256 / sr), ceil(H / ss), ceil(W / ss))``."""
    _check_steps(spatial_step, range_step)
    return (math.ceil(GUIDE_RANGE / range_step), math.ceil(height / spatial_step),
            math.ceil(width / spatial_step))


def _check_steps(spatial_step: int, range_step: int) -> None:
    for name, step in (("spatial_step", spatial_step), ("range_step", range_step)):
        if not 1 <= int(step) <= MAX_STEP or int(step) != step:
            raise ValueError(f"{name} must be an integer in [1, {MAX_STEP}], got {step!r}")


def _divide(t: Tensor, divisor: int) -> Tensor:
    """``t / divisor`` correctly rounded in ``t``'s precision (as C++'s float division).

    The quotient is computed in float64 and rounded once more: for a division, rounding twice
    through a format with more than 2p + 2 bits gives the correctly rounded float32 result.
    """
    if t.dtype == torch.float32:
        return (t.double() / divisor).float()
    return t / divisor


def pixel_to_grid(size: int, spatial_step: int, dtype: torch.dtype = torch.float32,
                  device: Optional[torch.device] = None) -> Tensor:
    """Grid coordinates ``(x + 0.5) / ss - 0.5`` of pixel indices ``0 .. size - 1``."""
    x = torch.arange(size, dtype=torch.float64, device=device)
    return ((2.0 * x + 1.0 - spatial_step) / (2.0 * spatial_step)).to(dtype)


def sanitize_radiance(radiance: Tensor) -> Tensor:
    """NaN, +-Inf and negatives -> 0; finite values above 1e30 -> 1e30."""
    ok = torch.isfinite(radiance) & (radiance >= 0)
    return torch.where(ok, radiance, torch.zeros_like(radiance)).clamp_max(MAX_RADIANCE)


def sanitize_albedo(albedo: Tensor) -> Tensor:
    """NaN, +-Inf and negatives -> 0; values above 1 -> 1."""
    ok = torch.isfinite(albedo) & (albedo >= 0)
    return torch.where(ok, albedo, torch.zeros_like(albedo)).clamp_max(1.0)


def sanitize_guide(guide: Tensor) -> Tensor:
    """Guides clamped to [0, 255] (NaN -> 0, +Inf -> 255)."""
    return torch.nan_to_num(guide, nan=0.0, posinf=GUIDE_MAX, neginf=0.0).clamp(0.0, GUIDE_MAX)


def sanitize_blend_weights(weights: Tensor) -> Tensor:
    """Blend weights clamped to [0, 1] (NaN -> 0)."""
    return torch.nan_to_num(weights, nan=0.0, posinf=1.0, neginf=0.0).clamp(0.0, 1.0)


def guide_to_grid(guide: Tensor, range_step: int) -> Tensor:
    """Range coordinate ``clamp(g, 0, 255) / sr``."""
    return _divide(sanitize_guide(guide), range_step)


def tent(a: Tensor) -> Tensor:
    """Tent ``max(0, 1 - |a|)``."""
    return (1.0 - a.abs()).clamp_min(0.0)


def luminance(image: Tensor) -> Tensor:
    """Rec. 709 luminance ``(N, H, W)`` of an ``(N, 3, H, W)`` image."""
    return (LUMINANCE[0] * image[:, 0] + LUMINANCE[1] * image[:, 1]
            + LUMINANCE[2] * image[:, 2])


def demodulate(radiance: Tensor, albedo: Tensor) -> Tensor:
    """``sanitize(R) / (sanitize(A) + 0.01)`` per channel."""
    return sanitize_radiance(radiance) / (sanitize_albedo(albedo) + DEMODULATION_EPSILON)


def clamp_outliers(demod: Tensor, clamp: Optional[float]) -> Tensor:
    """Clamp each channel to ``clamp * max(m, 1e-6)`` per image (off if <= 0).

    ``m`` is the mean luminance over the lit pixels (luminance > 0; 0 when none is lit).
    """
    if clamp is None or not clamp > 0:
        return demod
    lum = luminance(demod).double()
    lit = (lum > 0).sum(dim=(-2, -1))
    mean = lum.sum(dim=(-2, -1)) / lit.clamp_min(1)
    limit = (float(clamp) * mean.clamp_min(MIN_OUTLIER_MEAN)).to(demod.dtype)
    return torch.minimum(demod, limit.view(-1, 1, 1, 1))


def _axis_corners(coord: Tensor, cells: int) -> Sequence[Tuple[Tensor, Tensor, Tensor]]:
    """For lower / upper neighbour: (index clamped into the grid, valid mask, tent weight)."""
    lower = torch.floor(coord).detach()
    corners = []
    for offset in (0, 1):
        index = lower + offset
        valid = (index >= 0) & (index < cells)
        weight = tent(coord - index)
        corners.append((index.long().clamp(0, cells - 1), valid, weight))
    return corners


def splat(demod: Tensor, guide: Tensor, spatial_step: int,
          range_step: int) -> Tuple[Tensor, Tensor]:
    """Splat ``demod`` ``(N, 3, H, W)`` guided by ``guide`` ``(N, 1, H, W)`` into one level.

    Returns the normalized cell means ``(N, 3, GD, GH, GW)`` (0 in empty cells) and the tent
    weight sums ``(N, GD, GH, GW)`` (0 = empty). Each pixel is scattered into its <= 8 cells with
    weight ``(t(u - i) t(v - j)) t(z - k)``: the same weights the C++ gather uses.
    """
    n, channels, height, width = demod.shape
    depth, grid_h, grid_w = grid_shape(height, width, spatial_step, range_step)
    cells = depth * grid_h * grid_w
    u = pixel_to_grid(width, spatial_step, demod.dtype, demod.device)
    v = pixel_to_grid(height, spatial_step, demod.dtype, demod.device)
    z = guide_to_grid(guide.reshape(n, height, width), range_step)
    x_corners = _axis_corners(u, grid_w)
    y_corners = _axis_corners(v, grid_h)
    z_corners = _axis_corners(z, depth)
    # One extra "dump" cell receives the contributions to cells outside the grid.
    values = demod.new_zeros(n, channels, cells + 1)
    weights = demod.new_zeros(n, cells + 1)
    flat_demod = demod.reshape(n, channels, height * width)
    for j, valid_j, ty in y_corners:
        for i, valid_i, tx in x_corners:
            wxy = tx.view(1, width) * ty.view(height, 1)
            column = (j.view(height, 1) * grid_w + i.view(1, width))
            valid_xy = valid_j.view(height, 1) & valid_i.view(1, width)
            for k, valid_k, tz in z_corners:
                weight = (wxy * tz).reshape(n, -1)
                index = torch.where(valid_xy & valid_k, k * (grid_h * grid_w) + column,
                                    torch.full_like(k, cells)).reshape(n, -1)
                # In place: scatter_add's backward needs only the index, not the buffer.
                weights.scatter_add_(1, index, weight)
                values.scatter_add_(2, index.unsqueeze(1).expand(-1, channels, -1),
                                    weight.unsqueeze(1) * flat_demod)
    weights = weights[:, :cells]
    values = values[..., :cells]
    occupied = weights > 0
    safe = torch.where(occupied, weights, torch.ones_like(weights))
    values = torch.where(occupied.unsqueeze(1), values / safe.unsqueeze(1),
                         torch.zeros_like(values))
    weights = torch.where(occupied, weights, torch.zeros_like(weights))
    return (values.reshape(n, channels, depth, grid_h, grid_w),
            weights.reshape(n, depth, grid_h, grid_w))


def slice_grid(values: Tensor, weights: Tensor, guide: Tensor, spatial_step: int,
               range_step: int) -> Tensor:
    """Slice one level at every pixel of ``guide`` ``(N, 1, H, W)``; returns ``(N, 3, H, W)``.

    Trilinear over the 8 neighbouring cells of ``(u, v, z)``; cells outside the grid and empty
    cells are dropped and the kept weights renormalized (0 where none is kept). Summation order
    as in C++: y neighbour, then x neighbour, then range neighbour.
    """
    n, channels, depth, grid_h, grid_w = values.shape
    height, width = guide.shape[-2:]
    if grid_shape(height, width, spatial_step, range_step) != (depth, grid_h, grid_w):
        raise ValueError(f"grid {tuple(values.shape[2:])} does not match a {height} x {width} "
                         f"image with steps ({spatial_step}, {range_step})")
    u = pixel_to_grid(width, spatial_step, values.dtype, values.device)
    v = pixel_to_grid(height, spatial_step, values.dtype, values.device)
    z = guide_to_grid(guide.reshape(n, height, width), range_step)
    flat_values = values.reshape(n, channels, -1)
    flat_weights = weights.detach().reshape(n, -1)  # only tested for > 0
    acc = values.new_zeros(n, channels, height * width)
    total = values.new_zeros(n, height * width)
    zero = values.new_zeros(())
    for j, valid_j, ty in _axis_corners(v, grid_h):
        for i, valid_i, tx in _axis_corners(u, grid_w):
            wxy = tx.view(1, width) * ty.view(height, 1)
            column = (j.view(height, 1) * grid_w + i.view(1, width))
            valid_xy = valid_j.view(height, 1) & valid_i.view(1, width)
            for k, valid_k, tz in _axis_corners(z, depth):
                index = (k * (grid_h * grid_w) + column).reshape(n, -1)
                keep = (valid_xy & valid_k).reshape(n, -1)
                keep = keep & (flat_weights.gather(1, index) > 0)
                weight = torch.where(keep, (wxy * tz).reshape(n, -1), zero)
                cell = flat_values.gather(2, index.unsqueeze(1).expand(-1, channels, -1))
                acc = acc + weight.unsqueeze(1) * cell
                total = total + weight
    kept = total > 0
    safe = torch.where(kept, total, torch.ones_like(total))
    out = torch.where(kept.unsqueeze(1), acc / safe.unsqueeze(1), torch.zeros_like(acc))
    return out.reshape(n, channels, height, width)


# The name the design uses; ``slice_grid`` avoids shadowing the builtin inside this module.
slice = slice_grid  # noqa: A001


def blend(slices: Sequence[Tensor], weights: Optional[Tensor]) -> Tensor:
    """Combine 1..3 level slices ``(N, 3, H, W)`` with ``L - 1`` blend weights ``(N, L-1, H, W)``.

    3 levels: ``s1 w1 + s2 w2 + s3 (1 - w1 - w2)``; 2: ``s1 w1 + s2 (1 - w1)``; 1: ``s1``. The
    weights are clamped to [0, 1] first (NaN -> 0).
    """
    levels = len(slices)
    if not 1 <= levels <= 3:
        raise ValueError(f"blend needs 1..3 slices, got {levels}")
    if levels == 1:
        return slices[0]
    if weights is None or weights.shape[1] != levels - 1:
        got = None if weights is None else tuple(weights.shape)
        raise ValueError(f"{levels} levels need {levels - 1} weight channels, got {got}")
    w = sanitize_blend_weights(weights)
    w1 = w[:, 0:1]
    if levels == 2:
        return slices[0] * w1 + slices[1] * (1.0 - w1)
    w2 = w[:, 1:2]
    return slices[0] * w1 + slices[1] * w2 + slices[2] * ((1.0 - w1) - w2)


def denoise(radiance: Tensor, albedo: Optional[Tensor], guides: Tensor, weights: Optional[Tensor],
            levels: Sequence[Tuple[int, int]] = DEFAULT_LEVELS,
            clamp: Optional[float] = 8.0) -> Tensor:
    """Bilateral-grid denoise, see the module docstring and ``ptvBilateralGrid.h``.

    Args:
        radiance: noisy HDR radiance ``(N, 3, H, W)`` (NaN/Inf/negatives are treated as 0).
        albedo: albedo ``(N, 3, H, W)``, or None: no demodulation (1-spp volume albedo is
            itself noisy, and re-modulating by it puts that noise back).
        guides: one guide per level ``(N, L, H, W)``, range [0, 255].
        weights: blend weights ``(N, L - 1, H, W)`` in [0, 1]; may be None when L == 1.
        levels: ``(spatial_step, range_step)`` of each of the L = 1..3 levels.
        clamp: outlier clamp factor on the mean demodulated luminance; 0 or None disables it.

    Returns:
        The denoised radiance ``(N, 3, H, W)``, finite everywhere.
    """
    if radiance.dim() != 4 or radiance.shape[1] != 3:
        raise ValueError(f"radiance must be (N, 3, H, W), got {tuple(radiance.shape)}")
    n, _, height, width = radiance.shape
    if height < 1 or width < 1 or n < 1:
        raise ValueError(f"radiance is empty: {tuple(radiance.shape)}")
    if albedo is not None and tuple(albedo.shape) != tuple(radiance.shape):
        raise ValueError(f"albedo shape {tuple(albedo.shape)} differs from radiance "
                         f"{tuple(radiance.shape)}")
    count = len(levels)
    if not 1 <= count <= 3:
        raise ValueError(f"1..3 levels expected, got {count}")
    if tuple(guides.shape) != (n, count, height, width):
        raise ValueError(f"guides must be {(n, count, height, width)}, got "
                         f"{tuple(guides.shape)}")
    if count > 1 and (weights is None
                      or tuple(weights.shape) != (n, count - 1, height, width)):
        got = None if weights is None else tuple(weights.shape)
        raise ValueError(f"weights must be {(n, count - 1, height, width)}, got {got}")
    if albedo is None:
        modulation: Optional[Tensor] = None
        demod = sanitize_radiance(radiance)
    else:
        modulation = sanitize_albedo(albedo) + DEMODULATION_EPSILON
        demod = sanitize_radiance(radiance) / modulation
    demod = clamp_outliers(demod, clamp)
    slices = []
    for index, (spatial_step, range_step) in enumerate(levels):
        guide = guides[:, index:index + 1]
        grid_values, grid_weights = splat(demod, guide, spatial_step, range_step)
        slices.append(slice_grid(grid_values, grid_weights, guide, spatial_step, range_step))
    out = blend(slices, weights)
    return out if modulation is None else out * modulation
