"""GuideNet: the only learned part of the neural bilateral-grid denoiser (Meng et al. 2020).

A tiny fully convolutional network maps per-pixel features (see :mod:`ptv_training.features`)
to the grid's guides and blend weights. ``self.core`` (what is exported to ONNX) is::

    conv k x k, in -> hidden, LeakyReLU(0.2), conv k2 x k2, hidden -> out_channels, sigmoid

with zero padding k // 2 (k2 // 2), so its output has its input's height and width (any size,
odd sizes included); ``kernel2`` defaults to ``kernel``. ``hidden=0`` gives the smallest
network, a single k x k conv ``in -> out_channels`` plus sigmoid (for ablations).

Output channels: ``levels`` (L) guides in [0, 1] (the grid multiplies them by 255 to get range
coordinates), then ``L - 1`` blend weights in [0, 1]; the last level's weight is
``1 - sum(weights)`` and may go negative. ``out_channels`` (default 2L - 1, at least 2L - 1) is
the number of channels the final conv produces; the channels beyond 2L - 1 are padding, ignored
by :meth:`GuideNet.split` (they exist because ONNX Runtime's fast NCHWc convolution wants channel
counts that are multiples of 8).

Blend ``"softmax"`` (an ablation, ``train.py --blend softmax``; needs ``out_channels >= 2L``): the
channels after the guides are L logits, and the activation is a softmax over them instead of a
sigmoid per weight. Its output keeps the layout above: channels L .. 2L - 2 are the first L - 1
softmax weights and channel 2L - 1 (padding to the grid) the last one, which is exactly
``1 - sum(weights)``, so the coarsest level gets a weight of its own, never negative, and the
C++ grid does not change.

Stride ``s`` in {1, 2, 4, 8}: the core runs at reduced resolution. ``forward(features)``, features
``[N, C, H, W]`` at full resolution:

1. if s > 1: ``low = F.avg_pool2d(F.pad(features, (0, pw, 0, ph), mode="replicate"), s)`` with
   ``ph = (-H) % s``, ``pw = (-W) % s``, i.e. low size h = ceil(H / s), w = ceil(W / s), each low
   pixel the mean of its s x s block with the image edge replicated;
2. ``out = self.core(low)`` (``low = features`` when s == 1);
3. if s > 1: ``out = F.interpolate(out, scale_factor=s, mode="bilinear", align_corners=False,
   recompute_scale_factor=False)[:, :, :H, :W]`` (source coordinate (y + 0.5) / s - 0.5 clamped
   at 0, neighbour index clamped at h - 1: PyTorch's rule);
4. returns ``[N, out_channels, H, W]``.

Context ``p`` > 0 (an ablation, ``train.py --context``): the core also pools its input to 1/p of
its resolution (each coarse cell the mean of the pixels it covers inside the image), runs
``conv 3 x 3, in -> context_hidden, LeakyReLU(0.2), conv 1 x 1 -> out_channels`` there (the
second convolution starts at zero) and adds that, bilinearly resized to the core's resolution,
to the second convolution's output before the sigmoid: each region of about 3p x 3p network
pixels shifts the guides and blend weights of its pixels (a fog seen as a whole can choose the
coarse levels). It is part of the exported graph; the C++ side does not change.

With s == 1 and out_channels == 2L - 1 this is exactly the original network. The original
network is ``GuideNet(10)`` (5 x 5, 10 -> 20 -> 5): 7,525 parameters. Checkpoints written before
``core`` existed (state_dict keys ``body.*``) still load.
"""
from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import torch
import torch.nn.functional as F
from torch import nn

STRIDES = (1, 2, 4, 8)
BLENDS = ("sigmoid", "softmax")


class SoftmaxBlend(nn.Module):
    """The core's last activation with ``blend="softmax"``: a sigmoid on every channel but the
    ``levels`` blend logits after the ``levels`` guides, which get a softmax (module doc)."""

    def __init__(self, levels: int) -> None:
        super().__init__()
        self.levels = levels

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        n = self.levels
        return torch.cat([torch.sigmoid(x[:, :n]), torch.softmax(x[:, n:2 * n], dim=1),
                          torch.sigmoid(x[:, 2 * n:])], dim=1)


def activation(blend: str, levels: int) -> nn.Module:
    """The core's last activation for ``blend`` (module doc)."""
    return SoftmaxBlend(levels) if blend == "softmax" else nn.Sigmoid()


class ContextCore(nn.Module):
    """The core's convolutions (``layers``: conv, LeakyReLU, conv) plus the coarse ``context``
    branch (module doc), summed before the ``last`` activation (a sigmoid, or SoftmaxBlend)."""

    def __init__(self, layers: list, in_channels: int, out_channels: int, pool: int,
                 hidden: int, last: nn.Module) -> None:
        super().__init__()
        self.pool = pool
        self.last = last
        self.layers = nn.Sequential(*layers)
        self.context = nn.Sequential(nn.Conv2d(in_channels, hidden, 3, padding=1),
                                     nn.LeakyReLU(0.2), nn.Conv2d(hidden, out_channels, 1))
        nn.init.zeros_(self.context[2].weight)
        nn.init.zeros_(self.context[2].bias)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        # The mean over each cell's pixels inside the image, written as a ratio of two pools so
        # that ONNX Runtime (which divides a ceil-mode edge cell by the whole kernel) agrees.
        ones = torch.ones_like(x[:, :1])
        pooled = (F.avg_pool2d(x, self.pool, ceil_mode=True)
                  / F.avg_pool2d(ones, self.pool, ceil_mode=True))
        out = self.layers(x)
        out = out + F.interpolate(self.context(pooled), size=out.shape[-2:], mode="bilinear",
                                  align_corners=False)
        return self.last(out)


def output_convs(core: nn.Module) -> list:
    """The convolutions whose output channels are the core's outputs (the last one, and the
    context branch's last one when there is one)."""
    if isinstance(core, ContextCore):
        return [core.layers[-1], core.context[-1]]
    return [m for m in core if isinstance(m, nn.Conv2d)][-1:]


class GuideNet(nn.Module):
    """conv(k) -> LeakyReLU(0.2) -> conv(k) -> sigmoid (or a single conv when ``hidden == 0``)
    at 1 / ``stride`` resolution, bilinearly upsampled back.

    Input ``[N, in_channels, H, W]``; output ``[N, out_channels, H, W]`` in [0, 1].
    """

    def __init__(self, in_channels: int, hidden: int = 20, kernel: int = 5, levels: int = 3,
                 stride: int = 1, out_channels: Optional[int] = None,
                 kernel2: Optional[int] = None, context: int = 0,
                 context_hidden: int = 16, blend: str = "sigmoid") -> None:
        super().__init__()
        if in_channels < 1:
            raise ValueError(f"in_channels must be >= 1, got {in_channels}")
        if hidden < 0:
            raise ValueError(f"hidden must be >= 0 (0 = single conv), got {hidden}")
        if kernel < 1 or kernel % 2 == 0:
            raise ValueError(f"kernel must be odd (same-size output), got {kernel}")
        if kernel2 is None:
            kernel2 = kernel
        if kernel2 < 1 or kernel2 % 2 == 0:
            raise ValueError(f"kernel2 must be odd (same-size output), got {kernel2}")
        if hidden == 0 and kernel2 != kernel:
            raise ValueError("kernel2 needs a hidden layer (hidden > 0)")
        if levels < 1:
            raise ValueError(f"levels must be >= 1, got {levels}")
        if stride not in STRIDES:
            raise ValueError(f"stride must be one of {STRIDES}, got {stride}")
        if blend not in BLENDS:
            raise ValueError(f"blend must be one of {BLENDS}, got {blend!r}")
        needed = 2 * levels - 1 if blend == "sigmoid" else 2 * levels
        if out_channels is None:
            out_channels = needed
        if out_channels < needed:
            raise ValueError(f"out_channels must be >= {needed} ({levels} levels, {blend} "
                             f"blend), got {out_channels}")
        self.in_channels = in_channels
        self.hidden = hidden
        self.kernel = kernel
        self.kernel2 = kernel2
        self.levels = levels
        self.stride = stride
        self.out_channels = out_channels
        self.blend = blend
        if context < 0 or (context and context_hidden < 1):
            raise ValueError(f"context must be >= 0 and context_hidden >= 1, got {context}, "
                             f"{context_hidden}")
        self.context = context
        self.context_hidden = context_hidden
        pad = kernel // 2
        if hidden > 0:
            layers = [nn.Conv2d(in_channels, hidden, kernel, padding=pad), nn.LeakyReLU(0.2),
                      nn.Conv2d(hidden, out_channels, kernel2, padding=kernel2 // 2)]
        else:
            layers = [nn.Conv2d(in_channels, out_channels, kernel, padding=pad)]
        last = activation(blend, levels)
        if context:
            self.core: nn.Module = ContextCore(layers, in_channels, out_channels, context,
                                               context_hidden, last)
        else:
            self.core = nn.Sequential(*layers, last)

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        s = self.stride
        if s == 1:
            return self.core(features)
        height, width = features.shape[-2:]
        padded = F.pad(features, (0, (-width) % s, 0, (-height) % s), mode="replicate")
        out = self.core(F.avg_pool2d(padded, s))
        out = F.interpolate(out, scale_factor=s, mode="bilinear", align_corners=False,
                            recompute_scale_factor=False)
        return out[:, :, :height, :width]

    def split(self, output: torch.Tensor) -> Tuple[torch.Tensor, torch.Tensor]:
        """(guides ``[N, L, H, W]``, weights ``[N, L - 1, H, W]``) of a forward() output
        (padding channels dropped)."""
        return output[:, :self.levels], output[:, self.levels:2 * self.levels - 1]

    def config(self) -> Dict[str, int]:
        """Constructor arguments (store them next to a checkpoint's state_dict); ``kernel2``
        only when it differs from ``kernel``, so older checkpoints' configs compare equal."""
        config = {"in_channels": self.in_channels, "hidden": self.hidden,
                  "kernel": self.kernel, "levels": self.levels, "stride": self.stride,
                  "out_channels": self.out_channels}
        if self.kernel2 != self.kernel:
            config["kernel2"] = self.kernel2
        if self.context:
            config["context"] = self.context
            config["context_hidden"] = self.context_hidden
        if self.blend != "sigmoid":
            config["blend"] = self.blend
        return config

    def extra_repr(self) -> str:
        kernels = (f"{self.kernel}" if self.kernel2 == self.kernel
                   else f"{self.kernel}/{self.kernel2}")
        blend = f"blend={self.blend}, " if self.blend != "sigmoid" else ""
        return (f"in={self.in_channels}, hidden={self.hidden}, kernel={kernels}, "
                f"levels={self.levels}, stride={self.stride}, out={self.out_channels}, "
                f"{blend}params={count_parameters(self)}")

    def _load_from_state_dict(self, state_dict: Dict[str, Any], prefix: str,
                              *args: Any, **kwargs: Any) -> None:
        # Old checkpoints: "body.<i>.*" is today's "core.<i>.*" (same layer indices).
        old = prefix + "body."
        for key in [k for k in state_dict if k.startswith(old)]:
            state_dict[prefix + "core." + key[len(old):]] = state_dict.pop(key)
        super()._load_from_state_dict(state_dict, prefix, *args, **kwargs)


def count_parameters(model: nn.Module) -> int:
    """Number of parameters (frozen ones too: the model's size)."""
    return sum(p.numel() for p in model.parameters())


def macs_per_pixel(model: GuideNet) -> float:
    """Multiply-accumulates per full-resolution pixel (bias, activations, pooling and
    upsampling not counted): the core's MACs per reduced pixel / stride^2; an int when exact."""
    k1 = model.kernel * model.kernel
    if model.hidden > 0:
        k2 = model.kernel2 * model.kernel2
        macs = k1 * model.in_channels * model.hidden + k2 * model.hidden * model.out_channels
    else:
        macs = k1 * model.in_channels * model.out_channels
    if model.context:
        macs += (9 * model.in_channels * model.context_hidden
                 + model.context_hidden * model.out_channels) / model.context ** 2
    s2 = model.stride * model.stride
    return macs // s2 if macs % s2 == 0 else macs / s2
