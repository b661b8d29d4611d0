"""train.py --init/--adapt (Training/ptv_training/warm_start.py): a GuideNet started from an
exported model gives that model's output exactly; adapting only the history channel's first-layer
weights keeps the init's output for a one-frame history (history = 1 everywhere) away from the
border, changes it for longer histories, and trains nothing else. Bad inits fail clearly."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
import torch

REPO = Path(os.environ.get("PTV_SOURCE_DIR", Path(__file__).resolve().parents[2]))
if str(REPO / "Training") not in sys.path:
    sys.path.append(str(REPO / "Training"))

from ptv_training import features as F  # noqa: E402
from ptv_training.export_onnx import export  # noqa: E402
from ptv_training.guidenet import GuideNet  # noqa: E402
from ptv_training.warm_start import ChannelAdapter, load_init, warm_start  # noqa: E402

ARCH = dict(hidden=8, kernel=3, levels=3, stride=2, out_channels=8)
PAPER = F.resolve_channels("PAPER_10")
WITH_HISTORY = PAPER + ["history"]
#: Two 3 x 3 convolutions at half resolution and the bilinear upsampling reach 6 pixels.
REACH = 6


@pytest.fixture()
def init_model(tmp_path: Path):
    torch.manual_seed(3)
    net = GuideNet(len(PAPER), **ARCH).eval()
    with torch.no_grad():
        for p in net.parameters():
            p.mul_(3.0)  # exercise the sigmoid
    path = export(net, tmp_path / "init.onnx", PAPER)
    return net, path


def features(history: float, size: int = 40) -> tuple:
    torch.manual_seed(5)
    x = torch.rand(1, len(PAPER), size, size + 6)
    return x, torch.cat([x, torch.full((1, 1, size, size + 6), history)], 1)


@pytest.mark.parametrize("source", ["onnx", "checkpoint"])
def test_init_reproduces_the_model(init_model, tmp_path: Path, source: str) -> None:
    net, path = init_model
    if source == "checkpoint":
        path = tmp_path / "best.pt"
        torch.save({"model": net.state_dict(), "channels": PAPER, "config": net.config()}, path)
    model = GuideNet(len(WITH_HISTORY), **ARCH).eval()
    assert warm_start(model, WITH_HISTORY, path) == ["history"]
    x, x_hist = features(0.25)
    with torch.no_grad():
        assert (model(x_hist) - net(x)).abs().max() <= 1e-6  # new channel at zero weight


def test_adapter_keeps_one_frame_output(init_model) -> None:
    net, path = init_model
    model = GuideNet(len(WITH_HISTORY), **ARCH).eval()
    warm_start(model, WITH_HISTORY, path)
    adapter = ChannelAdapter(model, WITH_HISTORY, ["history"])
    before = {k: v.clone() for k, v in model.state_dict().items()}
    optimizer = torch.optim.Adam(adapter.parameters(), lr=0.1)
    x, x_hist = features(0.5)
    for _ in range(3):  # train towards anything: the history column must move, nothing else
        loss = model(x_hist).square().mean()
        optimizer.zero_grad()
        loss.backward()
        optimizer.step()
        adapter.project()
    after = model.state_dict()
    assert torch.equal(after["core.0.weight"][:, :-1], before["core.0.weight"][:, :-1])
    assert torch.equal(after["core.2.weight"], before["core.2.weight"])
    assert torch.equal(after["core.2.bias"], before["core.2.bias"])
    assert after["core.0.weight"][:, -1].abs().min() > 0
    with torch.no_grad():
        x, one = features(1.0)
        diff = (model(one) - net(x)).abs()[0].amax(0)
        assert diff[REACH:-REACH, REACH:-REACH].max() <= 1e-6
        assert diff.max() > 1e-4  # the border keeps part of the compensation (documented)
        _, longer = features(0.25)
        assert (model(longer) - net(x)).abs().max() > 1e-3


def test_bad_inits_fail_clearly(init_model, tmp_path: Path) -> None:
    _, path = init_model
    with pytest.raises(FileNotFoundError, match="no such file"):
        load_init(tmp_path / "missing.onnx")
    wider = GuideNet(len(WITH_HISTORY), **{**ARCH, "hidden": 16})
    with pytest.raises(ValueError, match="architecture differs.*hidden"):
        warm_start(wider, WITH_HISTORY, path)
    fewer = GuideNet(len(PAPER) - 1, **ARCH)
    with pytest.raises(ValueError, match=r"\['depth'\].*not inputs here"):
        warm_start(fewer, PAPER[:-1], path)
    model = GuideNet(len(WITH_HISTORY), **ARCH)
    warm_start(model, WITH_HISTORY, path)
    with pytest.raises(ValueError, match="no neutral value known"):
        ChannelAdapter(model, WITH_HISTORY, ["depth"])
    with pytest.raises(ValueError, match="not among the input channels"):
        ChannelAdapter(model, WITH_HISTORY, ["alpha"])


def test_adapter_gradient_is_that_of_the_shifted_channel(init_model) -> None:
    """The adapted weights train as w * (history - 1): the same gradient as a model fed the
    shifted channel with the init's bias held (without the bias inside the graph they would train
    as a bias that the compensation then removes, and longer histories would get worse)."""
    net, path = init_model
    model = GuideNet(len(WITH_HISTORY), **ARCH)
    warm_start(model, WITH_HISTORY, path)
    with torch.no_grad():
        model.core[0].weight[:, -1] = 0.2  # away from zero, where both forms differ
    adapter = ChannelAdapter(model, WITH_HISTORY, ["history"])
    shifted = GuideNet(len(WITH_HISTORY), **ARCH)
    shifted.load_state_dict(model.state_dict())
    with torch.no_grad():
        shifted.core[0].bias.copy_(adapter.bias0)
    torch.manual_seed(7)
    x = torch.rand(1, len(WITH_HISTORY), 48, 54)
    x[:, -1] = torch.rand(48, 54) * 0.75 + 0.25
    y = x.clone()
    y[:, -1] -= 1.0
    # A loss on pixels whose whole receptive field lies away from the zero padding: there both
    # forms are the same function of the weights, so their gradients must agree.
    inner = (slice(None), slice(None), slice(2 * REACH, -2 * REACH), slice(2 * REACH, -2 * REACH))
    model(x)[inner].square().mean().backward()
    shifted(y)[inner].square().mean().backward()
    g, g_ref = model.core[0].weight.grad[:, -1], shifted.core[0].weight.grad[:, -1]
    assert g_ref.abs().max() > 0
    assert (g - g_ref).abs().max() <= 1e-4 * g_ref.abs().max()
