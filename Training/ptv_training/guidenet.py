"""GuideNet: the only learned part of the neural bilateral-grid denoiser (Meng et al. 2020).

A tiny fully convolutional network maps per-pixel features (see :mod:`ptv_training.features`)
to the grid's guides and blend weights::

    conv k x k, in -> hidden, LeakyReLU(0.2), conv k x k, hidden -> 2L - 1, sigmoid

with zero padding k // 2, so the output has the input's height and width (any size, odd sizes
included). Output channels: ``levels`` guides in [0, 1] (the grid multiplies them by 255 to get
range coordinates), then ``levels - 1`` blend weights in [0, 1]; the last level's weight is
``1 - sum(weights)`` and may go negative.

The original network is ``GuideNet(10)`` (5 x 5, 10 -> 20 -> 5): 7,525 parameters.
``hidden=0`` gives the smallest network, a single k x k conv ``in -> 2L - 1`` plus sigmoid
(for ablations).
"""
from __future__ import annotations

from typing import Dict, Tuple

import torch
from torch import nn


class GuideNet(nn.Module):
    """conv(k) -> LeakyReLU(0.2) -> conv(k) -> sigmoid, or a single conv when ``hidden == 0``.

    Input ``[N, in_channels, H, W]``; output ``[N, 2 * levels - 1, H, W]`` in [0, 1].
    """

    def __init__(self, in_channels: int, hidden: int = 20, kernel: int = 5,
                 levels: int = 3) -> None:
        super().__init__()
        if in_channels < 1:
            raise ValueError(f"in_channels must be >= 1, got {in_channels}")
        if hidden < 0:
            raise ValueError(f"hidden must be >= 0 (0 = single conv), got {hidden}")
        if kernel < 1 or kernel % 2 == 0:
            raise ValueError(f"kernel must be odd (same-size output), got {kernel}")
        if levels < 1:
            raise ValueError(f"levels must be >= 1, got {levels}")
        self.in_channels = in_channels
        self.hidden = hidden
        self.kernel = kernel
        self.levels = levels
        self.out_channels = 2 * levels - 1
        pad = kernel // 2
        if hidden > 0:
            self.body = nn.Sequential(
                nn.Conv2d(in_channels, hidden, kernel, padding=pad),
                nn.LeakyReLU(0.2),
                nn.Conv2d(hidden, self.out_channels, kernel, padding=pad),
            )
        else:
            self.body = nn.Sequential(
                nn.Conv2d(in_channels, self.out_channels, kernel, padding=pad))
        self.activation = nn.Sigmoid()

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        return self.activation(self.body(features))

    def split(self, output: torch.Tensor) -> Tuple[torch.Tensor, torch.Tensor]:
        """(guides ``[N, L, H, W]``, weights ``[N, L - 1, H, W]``) of a forward() output."""
        return output[:, :self.levels], output[:, self.levels:]

    def config(self) -> Dict[str, int]:
        """Constructor arguments (store them next to a checkpoint's state_dict)."""
        return {"in_channels": self.in_channels, "hidden": self.hidden,
                "kernel": self.kernel, "levels": self.levels}

    def extra_repr(self) -> str:
        return (f"in={self.in_channels}, hidden={self.hidden}, kernel={self.kernel}, "
                f"levels={self.levels}, params={count_parameters(self)}")


def count_parameters(model: nn.Module) -> int:
    """Number of trainable parameters."""
    return sum(p.numel() for p in model.parameters() if p.requires_grad)


def macs_per_pixel(model: GuideNet) -> int:
    """Multiply-accumulates per output pixel (bias and activations not counted)."""
    k2 = model.kernel * model.kernel
    if model.hidden > 0:
        return k2 * (model.in_channels * model.hidden + model.hidden * model.out_channels)
    return k2 * model.in_channels * model.out_channels
