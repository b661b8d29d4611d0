"""Start a GuideNet from a trained one (``train.py --init``), adapt only new input channels
(``train.py --adapt``) or hold its 1-spp samples to the trained one (``train.py --distill``).

``--init`` reads a guidenet-v1 ONNX file (the shipped ``Data/Models/guidenet.onnx``: its
initializers ``0.weight``, ``0.bias``, ``2.weight``, ``2.bias`` are ``GuideNet.core``'s) or a
training checkpoint (``best.pt``/``last.pt``). The architecture must match except for the input
channels: channels the new model shares with the init are copied by name, new channels start at
zero weight, so the new model's output equals the init's on any input.

``--adapt`` trains only the first convolution's weights of the new channels; everything else
stays the init's. Each such channel has a *neutral value* (``NEUTRAL``: ``history`` = 1, a pixel
whose mean holds one frame) and the first convolution's bias is kept at
``b0 - sum_taps(w_c) * neutral_c``, so an input whose new channel is neutral everywhere gives the
init model's output exactly, except within the network's reach of the image border (6 pixels
for two 3 x 3 convolutions at half resolution): the first convolution's zero padding leaves the
padded taps' share of the compensation there. A model adapted this way adds what the new
channel can tell without changing what the init model does on the inputs it was trained for: for
the history channel, every single 1-spp frame.

``--distill`` trains every weight; ``Teacher`` is the init model, frozen, whose output on each
1-spp sample (its own channels of the features) the new model's is also held to.
"""
from __future__ import annotations

from pathlib import Path
from typing import Dict, List, Sequence, Tuple

import torch
import torch.nn.functional as F

from .guidenet import GuideNet

#: Channel value at which an adapted channel must not change the init model's output.
NEUTRAL: Dict[str, float] = {"history": 1.0}


def load_init(path: Path) -> Tuple[Dict[str, torch.Tensor], List[str], Dict[str, int]]:
    """(state dict of ``GuideNet``, input channel names, architecture) of an ONNX file or
    checkpoint."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"--init {path}: no such file")
    if path.suffix == ".onnx":
        import onnx
        from onnx import numpy_helper
        proto = onnx.load(str(path))
        props = {p.key: p.value for p in proto.metadata_props}
        if props.get("ptv.format") != "guidenet-v1":
            raise ValueError(f"--init {path}: not a guidenet-v1 model "
                             f"(ptv.format {props.get('ptv.format')!r})")
        state = {f"core.{init.name}": torch.from_numpy(numpy_helper.to_array(init).copy())
                 for init in proto.graph.initializer}
        config = {k: int(v) for k, v in
                  (item.split("=") for item in props["ptv.architecture"].split(","))}
        return state, props["ptv.input_channels"].split(","), config
    ck = torch.load(path, weights_only=False)
    return dict(ck["model"]), list(ck["channels"]), dict(ck["config"])


def init_columns(init_channels: Sequence[str], channels: Sequence[str], path: Path) -> List[int]:
    """Where each of the init's channels sits among ``channels`` (all must be there)."""
    missing = [c for c in init_channels if c not in channels]
    if missing:
        raise ValueError(f"--init {path}: channels {missing} of the init are not inputs here")
    return [list(channels).index(c) for c in init_channels]


def warm_start(model: GuideNet, channels: Sequence[str], path: Path) -> List[str]:
    """Copy ``path``'s weights into ``model`` (module doc); returns the channels it lacks."""
    state, init_channels, config = load_init(path)
    mine = model.config()
    differs = {k: (v, mine.get(k)) for k, v in config.items()
               if k != "in_channels" and mine.get(k) != v}
    if differs:
        raise ValueError(f"--init {path}: architecture differs (init, this run): {differs}")
    columns = init_columns(init_channels, channels, path)
    new = [c for c in channels if c not in init_channels]
    first = state["core.0.weight"]
    weight = torch.zeros((first.shape[0], len(channels), *first.shape[2:]), dtype=first.dtype)
    weight[:, columns] = first
    state["core.0.weight"] = weight
    model.load_state_dict(state)
    return new


class ChannelAdapter:
    """Train only the first convolution's weights of ``adapt`` (module doc): freezes every other
    parameter, masks the other channels' gradients and computes the first bias from the adapted
    weights inside the graph (:meth:`bias`), so that neutral inputs keep the init's output;
    :meth:`project` stores it in the bias parameter after each optimizer step."""

    def __init__(self, model: GuideNet, channels: Sequence[str], adapt: Sequence[str]) -> None:
        unknown = [c for c in adapt if c not in channels]
        if unknown:
            raise ValueError(f"--adapt {unknown}: not among the input channels {list(channels)}")
        no_neutral = [c for c in adapt if c not in NEUTRAL]
        if no_neutral:
            raise ValueError(f"--adapt {no_neutral}: no neutral value known "
                             f"(adaptable: {sorted(NEUTRAL)})")
        self.conv = model.core[0]
        for p in model.parameters():
            p.requires_grad_(False)
        self.conv.weight.requires_grad_(True)
        self.index = torch.tensor([channels.index(c) for c in adapt])
        self.neutral = torch.tensor([NEUTRAL[c] for c in adapt], dtype=self.conv.weight.dtype)
        mask = torch.zeros_like(self.conv.weight)
        mask[:, self.index] = 1.0
        self.conv.weight.register_hook(lambda grad: grad * mask)
        with torch.no_grad():  # the init's bias, before any adapted weight
            self.bias0 = self.conv.bias.detach().clone() + self._compensation()
        # The bias is a function of the adapted weights inside the graph, so that their gradient
        # is that of w * (x - neutral) (the bias parameter itself is kept equal, :meth:`project`).
        conv = self.conv
        conv.forward = lambda x: F.conv2d(x, conv.weight, self.bias(), conv.stride,
                                          conv.padding, conv.dilation, conv.groups)
        self.project()

    def parameters(self) -> List[torch.nn.Parameter]:
        """What the optimizer trains."""
        return [self.conv.weight]

    def _compensation(self) -> torch.Tensor:
        w = self.conv.weight[:, self.index]  # (hidden, adapted, k, k)
        return (w.sum(dim=(2, 3)) * self.neutral).sum(dim=1)

    def bias(self) -> torch.Tensor:
        """b0 - sum over adapted channels and taps of w * neutral (differentiable in w)."""
        return self.bias0 - self._compensation()

    @torch.no_grad()
    def project(self) -> None:
        """Store :meth:`bias` in the convolution's bias (checkpoints and exports read it)."""
        self.conv.bias.copy_(self.bias())


class Teacher:
    """The init model, frozen (``train.py --distill``): its output on a batch's features
    restricted to its own channels, the target that holds the new model's 1-spp samples to it."""

    def __init__(self, channels: Sequence[str], path: Path) -> None:
        state, init_channels, config = load_init(path)
        self.model = GuideNet(**config)
        self.model.load_state_dict(state)
        self.model.eval()
        for p in self.model.parameters():
            p.requires_grad_(False)
        self.columns = init_columns(init_channels, channels, path)
