"""The paper's comparison system: an image-to-image U-Net denoiser in the style of Hofmann et al.
2020 (NDPT, public code nihofm/ndptmvd), trained by the same pipeline on the same features.

Architecture (``UNet(in_channels, width=16)``), LeakyReLU(0.2) after every 3 x 3 conv::

    enc1  (in -> w -> w)            full resolution
    enc2  (w -> 2w -> 2w)           1/2   (2 x 2 max-pool, ceil mode: odd sizes work)
    mid   (2w -> 4w -> 4w)          1/4
    dec2  (4w + 2w -> 2w -> 2w)     1/2   (nearest upsampling to the skip's size, concat)
    dec1  (2w + w -> w -> w)        full
    out   1 x 1 conv w -> 3, softplus + 0.002 = the tone-mapped estimate t >= 0.002

The radiance is ``t ** 2.2`` (the inverse of the tone curve below 1, unbounded above), so the L1
loss on tone-mapped images sees ``clip(t, 0, 1)``. The 0.002 floor keeps the radiance above the
loss's 1e-6 cut-off, below which the tone curve passes no gradient: without it one large early
step can push every output there and the network never recovers (seen: all-black output). It
costs at most 0.002 of tone-mapped error on black pixels (54 dB). Unlike the bilateral grid, the network writes
the image itself, so every pixel costs all of its MACs (about 8x GuideNet's at width 16).

Exported as ``ptv.format = denoiser-v1`` (one output ``radiance`` [1, 3, H, W]); the C++
denoiser runs it through the same ONNX Runtime session and skips the grid.
"""
from __future__ import annotations

from typing import Dict

import torch
import torch.nn.functional as F
from torch import nn

GAMMA = 2.2
T_FLOOR = 0.002  # smallest tone-mapped output (see the module docstring)


def _block(cin: int, cout: int) -> nn.Sequential:
    return nn.Sequential(nn.Conv2d(cin, cout, 3, padding=1), nn.LeakyReLU(0.2),
                         nn.Conv2d(cout, cout, 3, padding=1), nn.LeakyReLU(0.2))


class UNet(nn.Module):
    """Two-level U-Net from features ``[N, C, H, W]`` to radiance ``[N, 3, H, W]`` (any H, W)."""

    def __init__(self, in_channels: int, width: int = 16) -> None:
        super().__init__()
        if in_channels < 1 or width < 1:
            raise ValueError(f"in_channels and width must be >= 1, got {in_channels}, {width}")
        self.in_channels = in_channels
        self.width = width
        w = width
        self.enc1 = _block(in_channels, w)
        self.enc2 = _block(w, 2 * w)
        self.mid = _block(2 * w, 4 * w)
        self.dec2 = _block(4 * w + 2 * w, 2 * w)
        self.dec1 = _block(2 * w + w, w)
        self.out = nn.Conv2d(w, 3, 1)
        with torch.no_grad():  # start near a mid-grey image: softplus(-1.05) + floor ~ 0.3
            self.out.bias.fill_(-1.05)

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        e1 = self.enc1(features)
        e2 = self.enc2(F.max_pool2d(e1, 2, ceil_mode=True))
        m = self.mid(F.max_pool2d(e2, 2, ceil_mode=True))
        d2 = self.dec2(torch.cat([F.interpolate(m, size=e2.shape[-2:], mode="nearest"), e2], 1))
        d1 = self.dec1(torch.cat([F.interpolate(d2, size=e1.shape[-2:], mode="nearest"), e1], 1))
        return (F.softplus(self.out(d1)) + T_FLOOR) ** GAMMA

    def config(self) -> Dict[str, int]:
        """Constructor arguments (stored next to a checkpoint's state_dict)."""
        return {"in_channels": self.in_channels, "width": self.width}


def macs_per_pixel(model: UNet) -> int:
    """Multiply-accumulates per output pixel (convolutions; the 1/2 and 1/4 levels weighted by
    their share of pixels)."""
    total = 0.0
    for module, scale in ((model.enc1, 1.0), (model.enc2, 0.25), (model.mid, 1 / 16),
                          (model.dec2, 0.25), (model.dec1, 1.0), (model.out, 1.0)):
        for conv in (m for m in module.modules() if isinstance(m, nn.Conv2d)):
            k = conv.kernel_size[0] * conv.kernel_size[1]
            total += scale * conv.in_channels * conv.out_channels * k
    return int(round(total))
