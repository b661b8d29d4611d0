"""Export a :class:`~ptv_training.guidenet.GuideNet` to ONNX ("guidenet-v1") for the C++ side
(``vtkPTVDenoiser``, ONNX Runtime).

Contract: opset 17; the file holds ``GuideNet.core`` (the conv stack + sigmoid, with its coarse
context branch when the model has one, and a softmax over the blend logits with its softmax
blend), which runs at the reduced resolution h = ceil(H / s), w = ceil(W / s) of a guide
stride s; one input
``features`` ``[1, C, h, w]`` float32 (h, w dynamic; with s > 1 the caller average-pools the
full-resolution features, edge replicated, as ``GuideNet.forward`` does); one output
``guides_weights`` ``[1, out_channels, h, w]`` (with s > 1 the caller upsamples it bilinearly to
H x W, PyTorch's align_corners=False rule: see ``ptv_training.guidenet``); metadata_props::

    ptv.format          guidenet-v1
    ptv.input_channels  comma-separated channel names (ptv_training.features), in input order
    ptv.levels          "ss:sr" per level, finest first: "4:4,8:8,16:16"
    ptv.guide_scale     255 (guides in [0, 1] times this = grid range coordinate)
    ptv.guide_stride    s, one of 1, 2, 4, 8 (a model without this key has stride 1)
    ptv.default_levels  optional: how many of the finest levels the denoiser runs when not told
                        (its speed/quality choice; without the key, every level)
    ptv.outputs         guide0,...,guide{L-1},weight0,...,weight{L-2}, then pad0,pad1,... for
                        the padding channels beyond 2L - 1 (ignored)
    ptv.architecture    GuideNet constructor arguments (informative)

``export_image_model`` writes the U-Net baseline (``ptv_training.unet``) as "denoiser-v1": the
same input and metadata, one output ``radiance`` ``[1, 3, H, W]`` (the denoised image; no
``ptv.levels``/``ptv.guide_scale``).

The file is written to a temporary file next to ``path`` and moved into place (atomic).

CLI (random, seeded weights; useful for tests until a trained model exists)::

    python -m ptv_training.export_onnx OUT.onnx [--channels PAPER_10] [--hidden 20] \\
        [--stride 2] [--out-channels 8] ...
"""
from __future__ import annotations

import argparse
import io
import os
from pathlib import Path
from typing import Dict, Mapping, Optional, Sequence, Tuple

import torch
from pathtracedvolume.atomic import write_bytes

from .features import resolve_channels
from .guidenet import BLENDS, STRIDES, GuideNet, count_parameters, output_convs

FORMAT = "guidenet-v1"
IMAGE_FORMAT = "denoiser-v1"  # image-to-image baseline: output = denoised radiance
OPSET = 17
INPUT_NAME = "features"
OUTPUT_NAME = "guides_weights"
IMAGE_OUTPUT_NAME = "radiance"
DEFAULT_LEVELS: Tuple[Tuple[int, int], ...] = ((4, 4), (8, 8), (16, 16))
GUIDE_SCALE = 255
RESERVED_KEYS = ("ptv.format", "ptv.input_channels", "ptv.levels", "ptv.guide_scale",
                 "ptv.guide_stride", "ptv.outputs", "ptv.architecture", "ptv.default_levels")


def levels_string(levels: Sequence[Tuple[int, int]]) -> str:
    """((4, 4), (8, 8)) -> "4:4,8:8"."""
    return ",".join(f"{int(ss)}:{int(sr)}" for ss, sr in levels)


def outputs_string(num_levels: int, out_channels: Optional[int] = None) -> str:
    """(3) -> "guide0,guide1,guide2,weight0,weight1"; (3, 8) -> the same + ",pad0,pad1,pad2"."""
    needed = 2 * num_levels - 1
    pads = (out_channels or needed) - needed
    if pads < 0:
        raise ValueError(f"{out_channels} output channels for {num_levels} levels")
    return ",".join([f"guide{i}" for i in range(num_levels)] +
                    [f"weight{i}" for i in range(num_levels - 1)] +
                    [f"pad{i}" for i in range(pads)])


def level_order(levels: int, use_levels: int, out_channels: int) -> list:
    """Output channel order of a model with ``levels`` levels shipped with its finest
    ``use_levels``: guides 0..N-1, weights 0..N-2, then every other channel (unused padding)."""
    used = list(range(use_levels)) + [levels + i for i in range(use_levels - 1)]
    return used + [c for c in range(out_channels) if c not in used]


def metadata(model: GuideNet, channels: Sequence[str],
             levels: Sequence[Tuple[int, int]] = DEFAULT_LEVELS,
             extra_metadata: Optional[Mapping[str, str]] = None,
             use_levels: Optional[int] = None,
             default_levels: Optional[int] = None) -> Dict[str, str]:
    """The metadata_props an export writes (after checking them against the model).
    ``use_levels`` N < L ships the finest N levels: the grid blends s1 w1 + ... + sN (1 - sum),
    exactly what running the model with N levels does; the other outputs become padding.
    ``default_levels`` D <= N: the denoiser runs the finest D of them unless told otherwise."""
    channels = list(channels)
    resolve_channels(channels)  # unknown names raise
    if len(channels) != model.in_channels:
        raise ValueError(f"{len(channels)} channel names for a model with "
                         f"{model.in_channels} input channels")
    levels = [(int(ss), int(sr)) for ss, sr in levels]
    if len(levels) != model.levels:
        raise ValueError(f"{len(levels)} levels for a model with {model.levels}")
    if any(ss < 1 or sr < 1 for ss, sr in levels):
        raise ValueError(f"level steps must be positive: {levels}")
    n = model.levels if use_levels is None else int(use_levels)
    if not 1 <= n <= model.levels:
        raise ValueError(f"use_levels must be 1..{model.levels}, got {use_levels}")
    if 1 < n < model.levels and model.blend == "softmax":
        raise ValueError(f"use_levels {n} of {model.levels} levels needs the sigmoid blend: a "
                         "softmax blend's weights are a softmax over all the model's levels")
    levels = levels[:n]
    props = {
        "ptv.format": FORMAT,
        "ptv.input_channels": ",".join(channels),
        "ptv.levels": levels_string(levels),
        "ptv.guide_scale": str(GUIDE_SCALE),
        "ptv.guide_stride": str(model.stride),
        "ptv.outputs": outputs_string(n, model.out_channels),
        "ptv.architecture": ",".join(f"{k}={v}" for k, v in model.config().items()),
    }
    if default_levels is not None:
        if not 1 <= int(default_levels) <= n:
            raise ValueError(f"default_levels must be 1..{n}, got {default_levels}")
        props["ptv.default_levels"] = str(int(default_levels))
    for key, value in (extra_metadata or {}).items():
        if key in RESERVED_KEYS:
            raise ValueError(f"extra_metadata must not override {key!r}")
        props[str(key)] = str(value)
    return props


def export(model: GuideNet, path: str | os.PathLike, channels: Sequence[str],
           levels: Sequence[Tuple[int, int]] = DEFAULT_LEVELS,
           extra_metadata: Optional[Mapping[str, str]] = None,
           use_levels: Optional[int] = None,
           default_levels: Optional[int] = None) -> Path:
    """Write ``model.core`` as a guidenet-v1 ONNX file at ``path`` (atomically); returns the
    path. ``use_levels``: ship only the finest N levels (see :func:`metadata`); the final
    convolution's output channels are reordered so that the N - 1 weights follow the N guides.
    ``default_levels``: the level count the denoiser runs by default (``ptv.default_levels``)."""
    import copy

    props = metadata(model, channels, levels, extra_metadata, use_levels, default_levels)
    doc = (f"PathTracedVolume GuideNet ({props['ptv.architecture']}, "
           f"{count_parameters(model)} parameters)")
    core = model.core
    n = model.levels if use_levels is None else int(use_levels)
    if n != model.levels:
        core = copy.deepcopy(model.core)
        order = torch.tensor(level_order(model.levels, n, model.out_channels))
        with torch.no_grad():
            for last in output_convs(core):
                last.weight.copy_(last.weight[order])
                last.bias.copy_(last.bias[order])
    return _write(core, model.in_channels, OUTPUT_NAME, props, doc, Path(path))


def export_image_model(model: torch.nn.Module, path: str | os.PathLike,
                       channels: Sequence[str],
                       extra_metadata: Optional[Mapping[str, str]] = None) -> Path:
    """Write an image-to-image denoiser (``ptv_training.unet.UNet``: features -> radiance
    ``[1, 3, H, W]``) as a denoiser-v1 ONNX file (atomically); returns the path."""
    channels = list(channels)
    resolve_channels(channels)
    if len(channels) != model.in_channels:
        raise ValueError(f"{len(channels)} channel names for a model with "
                         f"{model.in_channels} input channels")
    props = {"ptv.format": IMAGE_FORMAT, "ptv.input_channels": ",".join(channels),
             "ptv.outputs": "radiance.r,radiance.g,radiance.b",
             "ptv.architecture": ",".join(f"{k}={v}" for k, v in model.config().items())}
    for key, value in (extra_metadata or {}).items():
        if key in RESERVED_KEYS:
            raise ValueError(f"extra_metadata must not override {key!r}")
        props[str(key)] = str(value)
    params = sum(p.numel() for p in model.parameters())
    doc = f"PathTracedVolume image denoiser ({props['ptv.architecture']}, {params} parameters)"
    return _write(model, model.in_channels, IMAGE_OUTPUT_NAME, props, doc, Path(path))


def _write(model: torch.nn.Module, in_channels: int, output_name: str, props: Dict[str, str],
           doc: str, path: Path) -> Path:
    """Trace ``model`` (opset 17, dynamic H and W), attach ``props``, check, write atomically."""
    import onnx  # local: keeps `import ptv_training.*` free of onnx/protobuf

    was_training = model.training
    model.eval()
    try:
        dummy = torch.zeros(1, in_channels, 16, 24, dtype=torch.float32)
        buffer = io.BytesIO()
        with torch.no_grad():
            torch.onnx.export(
                model, dummy, buffer, opset_version=OPSET, export_params=True,
                do_constant_folding=True, input_names=[INPUT_NAME], output_names=[output_name],
                dynamic_axes={INPUT_NAME: {2: "height", 3: "width"},
                              output_name: {2: "height", 3: "width"}})
    finally:
        model.train(was_training)
    proto = onnx.load_from_string(buffer.getvalue())
    del proto.metadata_props[:]
    for key, value in props.items():
        entry = proto.metadata_props.add()
        entry.key = key
        entry.value = value
    proto.doc_string = doc
    onnx.checker.check_model(proto)
    data = proto.SerializeToString()

    return write_bytes(path, data)


def parse_levels(text: str) -> Tuple[Tuple[int, int], ...]:
    """ "4:4,8:8,16:16" -> ((4, 4), (8, 8), (16, 16))."""
    try:
        levels = tuple((int(a), int(b)) for a, b in
                       (item.split(":") for item in text.split(",") if item.strip()))
    except ValueError:
        raise argparse.ArgumentTypeError(f"levels must look like 4:4,8:8,16:16, got {text!r}") \
            from None
    if not levels:
        raise argparse.ArgumentTypeError("at least one level is needed")
    return levels


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m ptv_training.export_onnx",
        description="Export a randomly initialised (seeded) GuideNet as a guidenet-v1 ONNX "
                    "model (for tests and timing until a trained model exists).")
    parser.add_argument("output", type=Path, help="the .onnx file to write")
    parser.add_argument("--channels", default="PAPER_10",
                        help="preset (COLOR_ONLY, PAPER_10, VOLUME_FEATURES) or comma-separated "
                             "channel/group names (default: PAPER_10)")
    parser.add_argument("--hidden", type=int, default=20,
                        help="hidden channels; 0 = a single conv (default: 20)")
    parser.add_argument("--kernel", type=int, default=5, help="odd kernel size (default: 5)")
    parser.add_argument("--kernel2", type=int, default=0,
                        help="odd kernel size of the second conv (default: 0 = --kernel)")
    parser.add_argument("--levels", type=parse_levels, default=DEFAULT_LEVELS,
                        help="ss:sr per level (default: 4:4,8:8,16:16)")
    parser.add_argument("--stride", type=int, default=1, choices=STRIDES,
                        help="guide stride: the network runs at 1/stride resolution "
                             "(default: 1)")
    parser.add_argument("--out-channels", type=int, default=0,
                        help="output channels incl. padding, >= 2 * levels - 1 "
                             "(default: 0 = 2 * levels - 1)")
    parser.add_argument("--blend", choices=BLENDS, default="sigmoid",
                        help="blend weights: a sigmoid each (default) or a softmax over the "
                             "levels (needs out-channels >= 2 * levels)")
    parser.add_argument("--seed", type=int, default=0, help="torch seed (default: 0)")
    args = parser.parse_args(argv)

    channels = resolve_channels(args.channels)
    torch.manual_seed(args.seed)
    model = GuideNet(len(channels), hidden=args.hidden, kernel=args.kernel,
                     levels=len(args.levels), stride=args.stride,
                     out_channels=args.out_channels or None, kernel2=args.kernel2 or None,
                     blend=args.blend)
    path = export(model, args.output, channels, args.levels,
                  extra_metadata={"ptv.weights": f"random seed {args.seed}"})
    print(f"wrote {path} ({path.stat().st_size} bytes): {len(channels)} channels, "
          f"{count_parameters(model)} parameters, levels {levels_string(args.levels)}, "
          f"stride {model.stride}, {model.out_channels} outputs")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
