"""GuideNet: the torch network (Training/ptv_training/guidenet.py), the feature channels
(features.py), the ONNX export (export_onnx.py) and the network inside the C++ denoiser
vtkPTVDenoiser (ONNX Runtime behind a PIMPL; its input given as the image "Features", its
output read back with GetGuides/GetBlendWeights) against torch, plus the C++ side's handling of
bad models (a warning and the fixed guide, never a failure) and bad inputs (errors).

The C++ tests need the built package on PYTHONPATH (ctest sets it); VTK errors and warnings they
provoke are observed (ErrorEvent, WarningEvent) so that nothing reaches the output window."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ptv_vtk_messages import observe

REPO = Path(os.environ.get("PTV_SOURCE_DIR", Path(__file__).resolve().parents[2]))
TRAINING = REPO / "Training"
if str(TRAINING) not in sys.path:
    sys.path.append(str(TRAINING))

import torch  # noqa: E402

from ptv_training import features as F  # noqa: E402
from ptv_training.export_onnx import export  # noqa: E402
from ptv_training.guidenet import GuideNet, count_parameters, macs_per_pixel  # noqa: E402

SIZES = [(37, 23), (64, 48)]  # (W, H), odd sizes on purpose
TOL = 1e-5


# --- helpers -------------------------------------------------------------------------------------
def random_net(in_channels: int, seed: int, **kw) -> GuideNet:
    torch.manual_seed(seed)
    net = GuideNet(in_channels, **kw)
    # Default init keeps pre-activations small; widen them so that the sigmoid is exercised.
    with torch.no_grad():
        for p in net.parameters():
            p.mul_(3.0)
        if net.context:  # its last convolution starts at zero: give it weights of its own
            for p in net.core.context[2].parameters():
                p.normal_(0.0, 1.0)
    return net.eval()


def torch_forward(net: GuideNet, feats: np.ndarray) -> np.ndarray:
    with torch.no_grad():
        return net(torch.from_numpy(feats)[None]).numpy()[0]


def random_features(c: int, h: int, w: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((c, h, w), dtype=np.float32)


@pytest.fixture(scope="module")
def ptv():
    import pathtracedvolume.vtkPTVRendering as module
    return module


def to_image(feats: np.ndarray, name: str = "Features"):
    """(C, H, W) -> W x H x 1 vtkImageData with a C-component float point array."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData

    c, h, w = feats.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.SetSpacing(0.5, 2.0, 1.0)
    array = numpy_support.numpy_to_vtk(
        np.ascontiguousarray(feats.transpose(1, 2, 0).reshape(h * w, c)), deep=True)
    array.SetName(name)
    image.GetPointData().SetScalars(array)
    return image


def pass_image(array: np.ndarray, name: str):
    """(H, W) or (H, W, C) pass -> W x H x 1 vtkImageData (as to_image)."""
    if array.ndim == 2:
        array = array[:, :, None]
    return to_image(np.ascontiguousarray(array.transpose(2, 0, 1)), name)


def network_outputs(denoiser):
    """The last Execute()'s guides (L, H, W), in [0, 255] (the network's output x the guide
    scale 255), and blend weights (L - 1, H, W), from GetGuides / GetBlendWeights."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData

    result = []
    for name, get in (("Guides", denoiser.GetGuides), ("BlendWeights", denoiser.GetBlendWeights)):
        image = vtkImageData()
        get(image)
        w, h, _ = image.GetDimensions()
        array = image.GetPointData().GetArray(name)
        assert array is not None, name
        a = numpy_support.vtk_to_numpy(array)
        result.append(a.reshape(h, w, -1).transpose(2, 0, 1).copy())
    return result[0], result[1]


def denoised(denoiser) -> np.ndarray:
    """The output's "Denoised" array as (H, W, 3) (a copy: the next Execute() reuses it)."""
    from vtkmodules.util import numpy_support

    output = denoiser.GetOutput()
    scalars = output.GetPointData().GetScalars()
    assert scalars.GetName() == "Denoised" and scalars.GetNumberOfComponents() == 3
    w, h, _ = output.GetDimensions()
    return numpy_support.vtk_to_numpy(scalars).reshape(h, w, 3).copy()


# --- network -------------------------------------------------------------------------------------
def test_original_config_has_7525_parameters() -> None:
    net = GuideNet(10)
    assert count_parameters(net) == 7525  # (10*25*20 + 20) + (20*25*5 + 5)
    assert macs_per_pixel(net) == 7500
    assert net.out_channels == 5
    assert count_parameters(GuideNet(10, hidden=0)) == 10 * 25 * 5 + 5
    assert count_parameters(GuideNet(14, hidden=8, kernel=3)) == 14 * 9 * 8 + 8 + 8 * 9 * 5 + 5


@pytest.mark.parametrize("hidden", [20, 0])
def test_forward_same_size_in_unit_range(hidden: int) -> None:
    net = random_net(10, 0, hidden=hidden)
    out = net(torch.rand(2, 10, 23, 37))
    assert out.shape == (2, 5, 23, 37)
    assert float(out.min()) >= 0.0 and float(out.max()) <= 1.0
    guides, weights = net.split(out)
    assert guides.shape[1] == 3 and weights.shape[1] == 2


def test_bad_network_arguments() -> None:
    for kw in ({"kernel": 4}, {"hidden": -1}, {"levels": 0}, {"stride": 3}, {"stride": 0},
               {"stride": 16}, {"out_channels": 4}, {"levels": 2, "out_channels": 2}):
        with pytest.raises(ValueError):
            GuideNet(10, **kw)
    assert GuideNet(10, levels=2, out_channels=3).out_channels == 3


@pytest.mark.parametrize("hidden", [20, 0])
def test_stride1_is_the_original_formula(hidden: int) -> None:
    """stride 1, default out_channels: conv, LeakyReLU(0.2), conv, sigmoid, bit for bit; old
    checkpoints (keys "body.*") load."""
    import torch.nn.functional as tf

    net = random_net(10, 3, hidden=hidden)
    assert net.stride == 1 and net.out_channels == 5
    x = torch.rand(2, 10, 23, 37)
    convs = [m for m in net.core if isinstance(m, torch.nn.Conv2d)]
    with torch.no_grad():
        y = tf.conv2d(x, convs[0].weight, convs[0].bias, padding=2)
        if hidden:
            y = tf.conv2d(tf.leaky_relu(y, 0.2), convs[1].weight, convs[1].bias, padding=2)
        expected = torch.sigmoid(y)
        assert torch.equal(net(x), expected)
    old = {k.replace("core.", "body."): v.clone() for k, v in net.state_dict().items()}
    assert all(k.startswith("body.") for k in old)
    fresh = GuideNet(**net.config())
    fresh.load_state_dict(old)
    with torch.no_grad():
        assert torch.equal(fresh(x), expected)
    legacy = {k: v for k, v in net.config().items() if k not in ("stride", "out_channels")}
    assert GuideNet(**legacy).config() == net.config()  # checkpoint configs before stride


def numpy_strided(net: GuideNet, feats: np.ndarray) -> np.ndarray:
    """Brute-force forward() of a strided net: s x s means with the edge replicated, the core
    (torch) on them, bilinear upsampling with PyTorch's clamping (align_corners=False)."""
    s = net.stride
    c, height, width = feats.shape
    h, w = -(-height // s), -(-width // s)
    low = np.zeros((c, h, w))
    for y in range(h):
        for x in range(w):
            rows = [min(y * s + i, height - 1) for i in range(s)]
            cols = [min(x * s + j, width - 1) for j in range(s)]
            low[:, y, x] = feats[:, rows][:, :, cols].astype(np.float64).mean(axis=(1, 2))
    with torch.no_grad():
        out = net.core(torch.from_numpy(low.astype(np.float32))[None]).numpy()[0]

    def taps(n_out: int, n_in: int):
        src = np.maximum((np.arange(n_out) + 0.5) / s - 0.5, 0.0)
        i0 = np.floor(src).astype(int)
        return i0, np.minimum(i0 + 1, n_in - 1), src - i0

    y0, y1, ly = taps(height, h)
    x0, x1, lx = taps(width, w)
    o = out.astype(np.float64)
    top = o[:, y0][:, :, x0] * (1 - lx) + o[:, y0][:, :, x1] * lx
    bottom = o[:, y1][:, :, x0] * (1 - lx) + o[:, y1][:, :, x1] * lx
    return top * (1 - ly)[:, None] + bottom * ly[:, None]


@pytest.mark.parametrize("stride", [2, 4])
@pytest.mark.parametrize("w,h", [(37, 23), (1, 1), (5, 9), (8, 12)])
def test_strided_forward_matches_numpy(stride: int, w: int, h: int) -> None:
    net = random_net(10, 7, hidden=16, kernel=3, stride=stride, out_channels=8)
    feats = random_features(10, h, w, 5)
    got = torch_forward(net, feats)
    assert got.shape == (8, h, w)
    diff = float(np.abs(got - numpy_strided(net, feats)).max())
    assert diff <= 1e-6, diff
    guides, weights = net.split(torch.from_numpy(got)[None])
    assert guides.shape[1] == 3 and weights.shape[1] == 2  # padding channels dropped


def test_config_and_macs_with_stride() -> None:
    net = GuideNet(10, hidden=16, kernel=3, stride=2, out_channels=8)
    assert net.config() == {"in_channels": 10, "hidden": 16, "kernel": 3, "levels": 3,
                            "stride": 2, "out_channels": 8}
    assert GuideNet(**net.config()).config() == net.config()
    assert "stride=2" in repr(net) and "out=8" in repr(net)
    assert macs_per_pixel(net) == 9 * (10 * 16 + 16 * 8) / 4
    assert macs_per_pixel(GuideNet(10, stride=4)) == 7500 / 16
    assert macs_per_pixel(GuideNet(3, hidden=0, kernel=3, stride=2)) == 9 * 3 * 5 / 4
    assert count_parameters(net) == 10 * 9 * 16 + 16 + 16 * 9 * 8 + 8


def test_second_kernel() -> None:
    """kernel2: the second conv's own size (padding k2 // 2: same-size output), counted in the
    MACs and parameters, kept in config() only when it differs (older configs compare equal)."""
    net = GuideNet(10, hidden=16, kernel=5, stride=2, out_channels=8, kernel2=3)
    assert net.core[0].kernel_size == (5, 5) and net.core[2].kernel_size == (3, 3)
    assert net.config()["kernel2"] == 3
    assert GuideNet(**net.config()).config() == net.config()
    assert "kernel=5/3" in repr(net)
    assert macs_per_pixel(net) == (25 * 10 * 16 + 9 * 16 * 8) / 4
    assert count_parameters(net) == 25 * 10 * 16 + 16 + 9 * 16 * 8 + 8
    same = GuideNet(10, hidden=16, kernel=3, kernel2=3)
    assert "kernel2" not in same.config() and same.kernel2 == 3
    with torch.no_grad():
        assert net(torch.rand(1, 10, 9, 14)).shape == (1, 8, 9, 14)
    for kw in ({"kernel2": 4}, {"kernel2": 0}, {"hidden": 0, "kernel2": 3}):
        with pytest.raises(ValueError):
            GuideNet(10, **kw)


# --- features ------------------------------------------------------------------------------------
def synthetic_passes(h: int, w: int, seed: int, far: float = 10.0):
    """Passes like the mapper's: about a third of the pixels miss (depth = far, zeros)."""
    rng = np.random.default_rng(seed)
    hit = rng.random((h, w)) > 0.35
    hit[0, 0] = True
    hit[0, 1] = False
    scatter = hit & (rng.random((h, w)) > 0.3)
    scatter[0, 0] = True

    def unit(n):
        v = rng.normal(size=(h, w, 3))
        return (v / np.linalg.norm(v, axis=2, keepdims=True)).astype(np.float32)

    def where(mask, a, miss):
        m = mask[:, :, None] if a.ndim == 3 else mask
        return np.where(m, a, np.float32(miss)).astype(np.float32)

    passes = {
        "Radiance": where(scatter, rng.normal(0.5, 2.0, (h, w, 3)).astype(np.float32), 0.0),
        "Alpha": scatter.astype(np.float32),
        "Albedo": where(hit, rng.uniform(-0.1, 1.2, (h, w, 3)).astype(np.float32), 0.0),
        "Depth": where(hit, rng.uniform(2.0, 5.0, (h, w)).astype(np.float32), far)[:, :, None],
        "Position": where(hit, rng.uniform(-3, 7, (h, w, 3)).astype(np.float32), 0.0),
        "Normal": where(hit, unit(hit), 0.0),
        "ScatterDepth": where(scatter, rng.uniform(2.5, 6.0, (h, w)).astype(np.float32), far),
        "ScatterPosition": where(scatter, rng.uniform(-2, 2, (h, w, 3)).astype(np.float32), 0),
        "ScatterNormal": where(scatter, unit(scatter), 0.0),
        # frames in each pixel's mean; below 1 and fractional as the mapper's faded history
        "HistoryLength": rng.uniform(0.0, 3.5, (h, w, 1)).astype(np.float32),
        # the camera ray's opacity: fractional, at least Alpha's support; out of [0, 1] at two
        # pixels (the channel clips)
        "Coverage": where(hit, np.maximum(scatter, rng.uniform(-0.1, 1.1, (h, w))), 0.0)[..., None],
        # the study pass: world distances, some beyond the depth range (the channel clips)
        "DepthSpread": where(hit, rng.uniform(0.0, 4.0, (h, w)), 0.0)[..., None],
    }
    return passes, hit, scatter


def test_presets_and_channel_names() -> None:
    assert len(F.COLOR_ONLY) == 3
    assert len(F.PAPER_10) == 10
    assert len(F.VOLUME_FEATURES) == 14
    assert F.PAPER_10[:3] == ["color.r", "color.g", "color.b"]
    assert F.PAPER_10[-1] == "depth"
    assert F.VOLUME_FEATURES[:10] == F.PAPER_10
    assert F.resolve_channels("PAPER_10") == F.PAPER_10
    assert F.resolve_channels("color,depth") == ["color.r", "color.g", "color.b", "depth"]
    assert F.required_passes(F.PAPER_10) == ["Radiance", "Albedo", "Normal", "Depth"]
    assert F.required_passes(["scatter_position.x"]) == ["ScatterPosition", "ScatterDepth"]
    with pytest.raises(ValueError, match="unknown feature channel"):
        F.resolve_channels("color,bogus")
    with pytest.raises(ValueError, match="duplicate"):
        F.resolve_channels("color,color.r")


def test_build_features_shapes_ranges_and_misses() -> None:
    h, w = 23, 37
    passes, hit, scatter = synthetic_passes(h, w, 1)
    channels = list(F.CHANNELS)
    feats = F.build_features(passes, channels)
    assert feats.shape == (len(channels), h, w)
    assert feats.dtype == np.float32
    assert feats.flags["C_CONTIGUOUS"]
    assert np.isfinite(feats).all()
    assert feats.min() >= 0.0 and feats.max() <= 1.0
    plane = {name: feats[i] for i, name in enumerate(channels)}

    radiance = passes["Radiance"]
    expected = np.clip(np.maximum(radiance[:, :, 1], 0) ** (1 / 2.2), 0, 1)
    np.testing.assert_allclose(plane["color.g"], expected, atol=1e-6)
    np.testing.assert_array_equal(plane["albedo.r"], np.clip(passes["Albedo"][:, :, 0], 0, 1))
    np.testing.assert_allclose(plane["normal.z"], (passes["Normal"][:, :, 2] + 1) / 2, atol=1e-7)
    # Misses: depth 1, position 0, normal 0.5, albedo/colour 0.
    assert (plane["depth"][~hit] == 1.0).all()
    assert (plane["position.y"][~hit] == 0.0).all()
    assert (plane["normal.x"][~hit] == 0.5).all()
    assert (plane["albedo.b"][~hit] == 0.0).all()
    assert (plane["scatter_depth"][~scatter] == 1.0).all()
    assert (plane["scatter_position.z"][~scatter] == 0.0).all()
    assert (plane["scatter_normal.y"][~scatter] == 0.5).all()
    # history: the newest frame's share of the mean, 1 / max(1, frames)
    frames = passes["HistoryLength"][:, :, 0]
    np.testing.assert_allclose(plane["history"], 1.0 / np.maximum(frames, 1.0), rtol=1e-6)
    assert (plane["history"][frames <= 1.0] == 1.0).all()
    no_count = {k: v for k, v in passes.items() if k != "HistoryLength"}
    assert (F.build_features(no_count, ["history", "depth"])[0] == 1.0).all()
    # coverage: clip(Coverage, 0, 1)
    np.testing.assert_array_equal(plane["coverage"], np.clip(passes["Coverage"][:, :, 0], 0, 1))
    # Hits span [0, 1] per frame.
    d = passes["Depth"][:, :, 0]
    assert plane["depth"][hit].min() == 0.0 and plane["depth"][hit].max() == 1.0
    np.testing.assert_allclose(plane["depth"][hit],
                               (d[hit] - d[hit].min()) / (d[hit].max() - d[hit].min()),
                               atol=1e-6)
    px = passes["Position"][:, :, 0][hit]
    np.testing.assert_allclose(plane["position.x"][hit], (px - px.min()) / (px.max() - px.min()),
                               atol=1e-6)
    assert plane["scatter_depth"][scatter].min() == 0.0
    assert plane["scatter_depth"][scatter].max() == 1.0
    # depth_spread: the spread over the depth channel's range of hits, clipped
    spread = passes["DepthSpread"][:, :, 0]
    np.testing.assert_allclose(plane["depth_spread"],
                               np.clip(spread / (d[hit].max() - d[hit].min()), 0, 1), atol=1e-6)
    assert plane["depth_spread"].max() == 1.0 and (plane["depth_spread"][~hit] == 0.0).all()

    # Channel order follows the request; presets work; (H, W) single-channel passes work.
    sub = F.build_features(passes, ["depth", "color.r"])
    np.testing.assert_array_equal(sub[0], plane["depth"])
    np.testing.assert_array_equal(sub[1], plane["color.r"])
    passes2 = dict(passes, Depth=passes["Depth"][:, :, 0])
    assert F.build_features(passes2, F.PAPER_10).shape == (10, h, w)
    assert F.build_features(passes, F.VOLUME_FEATURES).shape == (14, h, w)


def test_build_features_degenerate_frames() -> None:
    h, w = 5, 7
    passes, _, _ = synthetic_passes(h, w, 2)
    # Nothing hit: depth all far.
    empty = dict(passes, Depth=np.full((h, w, 1), 10.0, np.float32),
                 Position=np.zeros((h, w, 3), np.float32))
    feats = F.build_features(empty, ["depth", "position.x"])
    assert (feats[0] == 1.0).all() and (feats[1] == 0.0).all()
    # All hits at one depth: zero range -> 0 for hits.
    flat = dict(passes, Depth=np.where(np.arange(w)[None, :, None] < 3, 4.0, 10.0)
                .astype(np.float32) * np.ones((h, 1, 1), np.float32))
    feats = F.build_features(flat, ["depth"])
    assert (feats[0][:, :3] == 0.0).all() and (feats[0][:, 3:] == 1.0).all()
    # Errors.
    with pytest.raises(KeyError, match="Albedo"):
        F.build_features({"Radiance": passes["Radiance"]}, ["albedo.r"])
    with pytest.raises(ValueError, match="expected"):
        F.build_features(dict(passes, Normal=passes["Normal"][:, :, :2]), ["normal.x"])
    with pytest.raises(ValueError, match="unknown"):
        F.build_features(passes, ["nope"])


# --- export --------------------------------------------------------------------------------------
def test_export_checker_and_metadata(tmp_path: Path) -> None:
    import onnx

    net = random_net(14, 5, hidden=8)
    path = export(net, tmp_path / "sub" / "gn.onnx", F.VOLUME_FEATURES,
                  extra_metadata={"ptv.note": "test"})
    assert path.is_file()
    assert path.stat().st_size < 1_000_000
    assert [p.name for p in path.parent.iterdir()] == ["gn.onnx"]  # no temp file left
    model = onnx.load(str(path))
    onnx.checker.check_model(model)
    assert max(o.version for o in model.opset_import if o.domain in ("", "ai.onnx")) == 17
    props = {p.key: p.value for p in model.metadata_props}
    assert props["ptv.format"] == "guidenet-v1"
    assert props["ptv.input_channels"] == ",".join(F.VOLUME_FEATURES)
    assert props["ptv.levels"] == "4:4,8:8,16:16"
    assert props["ptv.guide_scale"] == "255"
    assert props["ptv.guide_stride"] == "1"
    assert props["ptv.outputs"] == "guide0,guide1,guide2,weight0,weight1"
    assert props["ptv.note"] == "test"
    (inp,), (out,) = model.graph.input, model.graph.output
    assert inp.name == "features" and out.name == "guides_weights"
    dims = [d.dim_value or d.dim_param for d in inp.type.tensor_type.shape.dim]
    assert dims[:2] == [1, 14] and all(isinstance(d, str) for d in dims[2:])
    dims = [d.dim_value or d.dim_param for d in out.type.tensor_type.shape.dim]
    assert dims[:2] == [1, 5] and all(isinstance(d, str) for d in dims[2:])

    with pytest.raises(ValueError, match="channel names"):
        export(net, tmp_path / "x.onnx", F.PAPER_10)
    with pytest.raises(ValueError, match="levels"):
        export(net, tmp_path / "x.onnx", F.VOLUME_FEATURES, levels=((4, 4), (8, 8)))
    with pytest.raises(ValueError, match="override"):
        export(net, tmp_path / "x.onnx", F.VOLUME_FEATURES,
               extra_metadata={"ptv.format": "x"})
    assert not (tmp_path / "x.onnx").exists()


def test_export_cli(tmp_path: Path) -> None:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        p for p in (env.get("PYTHONPATH", ""), str(TRAINING)) if p)
    cmd = [sys.executable, "-m", "ptv_training.export_onnx"]
    help_text = subprocess.run(cmd + ["--help"], env=env, check=True, capture_output=True,
                               text=True).stdout
    assert "--channels" in help_text and "--seed" in help_text
    assert "--stride" in help_text and "--out-channels" in help_text
    out = tmp_path / "cli.onnx"
    for _ in range(2):
        subprocess.run(cmd + [str(out), "--hidden", "0", "--seed", "7"], env=env, check=True,
                       capture_output=True)
    first = out.read_bytes()
    subprocess.run(cmd + [str(out), "--hidden", "0", "--seed", "7"], env=env, check=True,
                   capture_output=True)
    assert out.read_bytes() == first  # seeded: reproducible


def test_export_strided_padded(tmp_path: Path) -> None:
    """A stride-2 model with 8 outputs: the file is model.core (reduced resolution), the
    metadata names the stride and the padding channels."""
    import onnx
    import onnxruntime as ort
    import torch.nn.functional as tf

    net = random_net(10, 13, hidden=16, kernel=3, stride=2, out_channels=8)
    path = export(net, tmp_path / "s2.onnx", F.PAPER_10)
    props = {p.key: p.value for p in onnx.load(str(path)).metadata_props}
    assert props["ptv.guide_stride"] == "2"
    outputs = props["ptv.outputs"].split(",")
    assert outputs == ["guide0", "guide1", "guide2", "weight0", "weight1", "pad0", "pad1",
                       "pad2"]
    assert "stride=2" in props["ptv.architecture"]
    session = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    for w, h in SIZES + [(1, 1), (5, 9)]:
        feats = torch.from_numpy(random_features(10, h, w, 4))[None]
        low = tf.avg_pool2d(tf.pad(feats, (0, (-w) % 2, 0, (-h) % 2), mode="replicate"), 2)
        (got,) = session.run(None, {"features": low.numpy()})
        assert got.shape == (1, 8, (h + 1) // 2, (w + 1) // 2)
        with torch.no_grad():
            expected = net.core(low).numpy()
        assert float(np.abs(got - expected).max()) <= TOL
    with pytest.raises(ValueError, match="override"):
        export(net, tmp_path / "x.onnx", F.PAPER_10, extra_metadata={"ptv.guide_stride": "1"})


def test_context_branch(tmp_path: Path) -> None:
    """--context P: the branch starts at zero (the output is the core's alone), a coarse cell
    is the mean of the pixels it covers inside the image, and the exported graph runs in ONNX
    Runtime as in torch at sizes that P does not divide, also shipped with fewer levels (the
    branch's outputs reordered with the core's)."""
    import onnxruntime as ort
    import torch.nn.functional as tf
    from ptv_training.export_onnx import level_order

    torch.manual_seed(3)
    fresh = GuideNet(10, hidden=8, kernel=3, stride=2, out_channels=8, context=4)
    plain = GuideNet(10, hidden=8, kernel=3, stride=2, out_channels=8)
    plain.core.load_state_dict({k[len("layers."):]: v for k, v in fresh.core.state_dict().items()
                                if k.startswith("layers.")})
    feats = torch.from_numpy(random_features(10, 19, 27, 5))[None]
    with torch.no_grad():
        assert torch.equal(fresh(feats), plain(feats))
    assert fresh.config()["context"] == 4 and fresh.config()["context_hidden"] == 16
    assert "context" not in plain.config()
    assert macs_per_pixel(fresh) == macs_per_pixel(plain) + (9 * 10 * 16 + 16 * 8) / 16 / 4
    with pytest.raises(ValueError, match="context"):
        GuideNet(10, context=-1)

    # The pooled cells: a 6 x 5 image in cells of 4 -> the 4 x 4, 4 x 1, 2 x 4 and 2 x 1 means.
    x = torch.arange(30.0).reshape(1, 1, 6, 5)
    ones = torch.ones_like(x)
    pooled = tf.avg_pool2d(x, 4, ceil_mode=True) / tf.avg_pool2d(ones, 4, ceil_mode=True)
    expected = torch.tensor([[x[0, 0, :4, :4].mean(), x[0, 0, :4, 4:].mean()],
                             [x[0, 0, 4:, :4].mean(), x[0, 0, 4:, 4:].mean()]])
    assert torch.allclose(pooled[0, 0], expected)

    net = random_net(10, 17, hidden=8, kernel=3, stride=2, out_channels=8, context=4)
    for levels in (3, 1):
        path = export(net, tmp_path / f"ctx{levels}.onnx", F.PAPER_10, use_levels=levels)
        session = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
        for w, h in SIZES + [(1, 1), (5, 9), (9, 5)]:
            low = torch.from_numpy(random_features(10, h, w, w * h))[None]
            (got,) = session.run(None, {"features": low.numpy()})
            with torch.no_grad():
                expected = net.core(low).numpy()[:, level_order(3, levels, 8)]
            assert float(np.abs(got - expected).max()) <= TOL, (levels, w, h)


def test_softmax_blend(tmp_path: Path) -> None:
    """--blend softmax: the weights after the guides are a softmax over the levels, the last one
    in the first padding channel equal to 1 - the others (the grid's coarsest weight); the grid
    blends the slices with those weights; ONNX Runtime runs it as torch; fewer levels, too few
    channels and an unknown blend are refused."""
    import onnxruntime as ort
    from ptv_training import bilateral_grid as bg

    net = random_net(10, 23, hidden=8, kernel=3, stride=2, out_channels=8, blend="softmax")
    assert net.config()["blend"] == "softmax" and "blend" not in GuideNet(10).config()
    feats = torch.from_numpy(random_features(10, 19, 27, 6))[None]
    with torch.no_grad():
        out = net(feats)
    guides, weights = net.split(out)
    assert guides.shape == (1, 3, 19, 27) and weights.shape == (1, 2, 19, 27)
    # Bilinear upsampling keeps the sum: the coarsest weight is the grid's 1 - w1 - w2.
    assert torch.allclose(out[:, 5], 1.0 - weights.sum(1), atol=1e-6)
    assert float(out[:, 3:6].min()) >= 0.0
    slices = [torch.rand(1, 3, 19, 27) for _ in range(3)]
    expected = sum(slices[i] * out[:, 3 + i:4 + i] for i in range(3))
    assert torch.allclose(bg.blend(slices, weights), expected, atol=1e-6)

    path = export(net, tmp_path / "softmax.onnx", F.PAPER_10)
    session = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    for w, h in SIZES + [(1, 1), (5, 9)]:
        low = torch.from_numpy(random_features(10, h, w, w + h))[None]
        (got,) = session.run(None, {"features": low.numpy()})
        with torch.no_grad():
            assert float(np.abs(got - net.core(low).numpy()).max()) <= TOL, (w, h)
    with pytest.raises(ValueError, match="sigmoid blend"):
        export(net, tmp_path / "x.onnx", F.PAPER_10, use_levels=2)
    export(net, tmp_path / "one.onnx", F.PAPER_10, use_levels=1)  # no weights: any blend
    with pytest.raises(ValueError, match="out_channels must be >= 6"):
        GuideNet(10, blend="softmax", out_channels=5)
    with pytest.raises(ValueError, match="blend must be one of"):
        GuideNet(10, blend="max")


@pytest.mark.parametrize("w,h", SIZES)
def test_onnxruntime_python_matches_torch(tmp_path: Path, w: int, h: int) -> None:
    import onnxruntime as ort
    net = random_net(10, 11)
    path = export(net, tmp_path / "gn.onnx", F.PAPER_10)
    session = ort.InferenceSession(str(path), providers=["CPUExecutionProvider"])
    feats = random_features(10, h, w, 3)
    (got,) = session.run(None, {"features": feats[None]})
    assert got.shape == (1, 5, h, w)
    diff = float(np.abs(got[0] - torch_forward(net, feats)).max())
    print(f"onnxruntime-python vs torch {w}x{h}: max |diff| = {diff:.3g}")
    assert diff <= TOL


# --- C++ network (vtkPTVDenoiser) ----------------------------------------------------------------
NETS = {
    "paper10": (F.PAPER_10, {}),
    "volume14_h8": (F.VOLUME_FEATURES, {"hidden": 8}),
    "color3_single_conv_k3": (F.COLOR_ONLY, {"hidden": 0, "kernel": 3}),
    "paper10_h16_k5k3": (F.PAPER_10, {"hidden": 16, "kernel2": 3}),
    "paper10_h8_context4": (F.PAPER_10, {"hidden": 8, "kernel": 3, "context": 4}),
    "paper10_h8_softmax": (F.PAPER_10, {"hidden": 8, "kernel": 3, "blend": "softmax",
                                        "out_channels": 8}),
}
PROVIDERS = ("CPUExecutionProvider", "CUDAExecutionProvider")


def network_status(denoiser, path: Path) -> str:
    """Check the status of a network run on given features (3 levels); return the provider."""
    status = denoiser.GetStatus()
    prefix = f"GuideNet {path} ("
    suffix = "), given features, 3 levels"
    assert status.startswith(prefix) and status.endswith(suffix), status
    provider = status[len(prefix):-len(suffix)]
    assert provider in PROVIDERS, status
    return provider


def set_frame(denoiser, passes, names=("Radiance", "Albedo")) -> None:
    for name in names:
        denoiser.SetImage(name, pass_image(passes[name], name))


@pytest.mark.parametrize("net_name", list(NETS))
def test_cxx_runner_matches_torch(ptv, tmp_path: Path, net_name: str) -> None:
    """Given features: the C++ guides (x 255) and weights match torch; the model's grid steps
    (4:4, 8:8, 16:16) are the ones used; the output has the Radiance image's geometry."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    channels, kw = NETS[net_name]
    net = random_net(len(channels), 21, **kw)
    path = export(net, tmp_path / f"{net_name}.onnx", channels)
    denoiser = ptv.vtkPTVDenoiser()
    # The network's 3 levels at any frame size (the automatic count drops levels too
    # coarse for a small frame: bilateral_grid.fitting_levels).
    denoiser.SetNumberOfLevels(3)
    messages = observe(denoiser)
    denoiser.SetNumberOfThreads(2)
    denoiser.SetModelFile(str(path))
    # Steps of its own that a running model overrides with those of its metadata.
    for level in range(3):
        denoiser.SetSpatialStep(level, 2)
        denoiser.SetRangeStep(level, 3)
    # The grid alone on the network's guides and weights, with the default steps (= the model's).
    grid = ptv.vtkPTVDenoiser()
    grid_messages = observe(grid)
    grid.SetNumberOfThreads(2)

    for seed, (w, h) in enumerate(SIZES * 2):  # twice: buffers reused across sizes
        feats = random_features(len(channels), h, w, 100 + seed)
        passes, _, _ = synthetic_passes(h, w, 200 + seed)
        set_frame(denoiser, passes)
        denoiser.SetImage("Features", to_image(feats))
        assert denoiser.Execute(), messages
        assert denoiser.GetNetworkActive()
        provider = network_status(denoiser, path)
        output = denoiser.GetOutput()
        assert output.GetDimensions() == (w, h, 1)
        assert output.GetSpacing() == (0.5, 2.0, 1.0)  # the Radiance image's
        result = denoised(denoiser)
        assert np.isfinite(result).all()
        guides, weights = network_outputs(denoiser)
        assert guides.shape == (3, h, w) and weights.shape == (2, h, w)
        expected = torch_forward(net, feats)
        # The guides are the network's output times the guide scale 255: compared / 255 at TOL
        # (an absolute 255 * TOL on the guides themselves).
        diff = max(float(np.abs(guides / 255.0 - expected[:3]).max()),
                   float(np.abs(weights - expected[3:5]).max()))
        print(f"vtkPTVDenoiser network ({net_name}, {provider}) vs torch {w}x{h}: "
              f"max |diff| = {diff:.3g}, {denoiser.GetLastGuideNetTime():.2f} ms")
        assert diff <= TOL
        assert denoiser.GetLastGuideNetTime() > 0.0

        set_frame(grid, passes)
        guide_image, weight_image = vtkImageData(), vtkImageData()
        denoiser.GetGuides(guide_image)
        denoiser.GetBlendWeights(weight_image)
        grid.SetImage("Guides", guide_image)
        grid.SetImage("BlendWeights", weight_image)
        assert grid.Execute(), grid_messages
        assert grid.GetStatus() == "given guides, 3 levels"
        assert np.array_equal(denoised(grid), result)

    # The channels the model expects, in its order: named by the component-count error.
    messages.clear()
    denoiser.SetImage("Features", to_image(random_features(len(channels) + 1, h, w, 0)))
    assert not denoiser.Execute()
    assert len(messages) == 1 and messages[0].startswith("ErrorEvent"), messages
    assert (f"'Features' has {len(channels) + 1} components but the model {path} expects "
            f"{len(channels)} channels: {','.join(channels)}") in messages[0], messages[0]
    assert grid_messages == []


def test_cxx_runner_threads_and_reload(ptv, tmp_path: Path) -> None:
    """The network's result does not depend on the thread count (the session is made again for
    each); switching models and back reproduces the first model's result."""
    net = random_net(10, 4)
    path = export(net, tmp_path / "gn.onnx", F.PAPER_10)
    other = export(random_net(10, 5), tmp_path / "other.onnx", F.PAPER_10)
    feats = random_features(10, 23, 37, 9)
    passes, _, _ = synthetic_passes(23, 37, 9)
    denoiser = ptv.vtkPTVDenoiser()
    # The network's 3 levels at any frame size (the automatic count drops levels too
    # coarse for a small frame: bilateral_grid.fitting_levels).
    denoiser.SetNumberOfLevels(3)
    messages = observe(denoiser)
    denoiser.SetModelFile(str(path))
    set_frame(denoiser, passes)
    denoiser.SetImage("Features", to_image(feats))

    results = []
    for threads in (1, 2, 0):
        denoiser.SetNumberOfThreads(threads)
        assert denoiser.Execute(), messages  # loads on demand
        assert denoiser.GetNetworkActive()
        results.append((*network_outputs(denoiser), denoised(denoiser)))
    assert denoiser.GetNumberOfThreads() == 0
    expected = torch_forward(net, feats)
    for guides, weights, result in results:
        assert float(np.abs(guides / 255.0 - expected[:3]).max()) <= TOL
        assert float(np.abs(weights - expected[3:]).max()) <= TOL
    for guides, weights, result in results[1:]:
        assert float(np.abs(guides - results[0][0]).max()) <= 255.0 * TOL
        assert float(np.abs(weights - results[0][1]).max()) <= TOL
        if np.array_equal(guides, results[0][0]) and np.array_equal(weights, results[0][1]):
            assert np.array_equal(result, results[0][2])  # the grid: bit-identical
    provider = network_status(denoiser, path)
    assert provider in str(denoiser)

    denoiser.SetModelFile(str(other))
    assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
    network_status(denoiser, other)
    assert float(np.abs(network_outputs(denoiser)[0] - results[-1][0]).max()) > 1.0
    denoiser.SetModelFile(str(path))
    assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
    guides, weights = network_outputs(denoiser)
    assert np.array_equal(guides, results[-1][0]) and np.array_equal(weights, results[-1][1])
    assert np.array_equal(denoised(denoiser), results[-1][2])
    assert messages == []


def test_default_model_file(ptv, monkeypatch) -> None:
    monkeypatch.delenv("PTV_DATA_DIR", raising=False)
    # Beside the library (the build tree's plugin folder), a copy of the shipped model; never the
    # source tree's (an install must not depend on it).
    default = Path(ptv.vtkPTVDenoiser.GetDefaultModelFile())
    assert default.parts[-3:] == ("Data", "Models", "guidenet.onnx")
    assert (default.parents[2] / "libvtkPTVRendering.so").exists(), default
    assert default.read_bytes() == (REPO / "Data" / "Models" / "guidenet.onnx").read_bytes()
    assert REPO / "Data" not in default.parents
    monkeypatch.setenv("PTV_DATA_DIR", "/somewhere/data")
    assert ptv.vtkPTVDenoiser.GetDefaultModelFile() == "/somewhere/data/Models/guidenet.onnx"
    assert ptv.vtkPTVDenoiser.GetRuntimeVersion().startswith("1.")


# --- bad models and inputs -----------------------------------------------------------------------
def edited_model(src: Path, dst: Path, edit) -> Path:
    import onnx

    model = onnx.load(str(src))
    edit(model)
    onnx.save(model, str(dst))
    return dst


def set_prop(key: str, value: str):
    def edit(model):
        for p in model.metadata_props:
            if p.key == key:
                p.value = value
    return edit


def add_prop(key: str, value: str):
    def edit(model):
        p = model.metadata_props.add()
        p.key, p.value = key, value
    return edit


def drop_props(model) -> None:
    del model.metadata_props[:]


def bad_models(tmp_path: Path):
    good = export(random_net(14, 1, hidden=8), tmp_path / "good.onnx", F.VOLUME_FEATURES)
    data = good.read_bytes()
    truncated = tmp_path / "truncated.onnx"
    truncated.write_bytes(data[:len(data) // 2])
    garbage = tmp_path / "random.onnx"
    garbage.write_bytes(np.random.default_rng(0).integers(0, 256, 4096, np.uint8).tobytes())
    empty = tmp_path / "empty.onnx"
    empty.write_bytes(b"")
    ten = ",".join(F.PAPER_10)
    return good, {
        "missing": (tmp_path / "does_not_exist.onnx",
                    ["does_not_exist.onnx", "no GuideNet model at"]),
        "truncated": (truncated, ["truncated.onnx", "ONNX Runtime could not load"]),
        "random_bytes": (garbage, ["random.onnx", "ONNX Runtime could not load"]),
        "empty": (empty, ["empty.onnx", "ONNX Runtime could not load"]),
        "channel_count": (
            edited_model(good, tmp_path / "channels.onnx", set_prop("ptv.input_channels", ten)),
            [f"model declares 14 input channels but ptv.input_channels lists 10: {ten}"]),
        "no_metadata": (edited_model(good, tmp_path / "nometa.onnx", drop_props),
                        ["ptv.format is missing", "ptv.input_channels is missing",
                         "ptv.levels is missing"]),
        "wrong_format": (
            edited_model(good, tmp_path / "format.onnx", set_prop("ptv.format", "guidenet-v0")),
            ['ptv.format is "guidenet-v0", expected "guidenet-v1"']),
        "level_count": (
            edited_model(good, tmp_path / "levels.onnx", set_prop("ptv.levels", "4:4,8:8")),
            ["model outputs 5 channels but ptv.levels lists 2 levels"]),
        "bad_levels": (
            edited_model(good, tmp_path / "badlevels.onnx", set_prop("ptv.levels", "4x4")),
            ['ptv.levels "4x4" is not a list']),
        "default_levels_above": (
            edited_model(good, tmp_path / "default4.onnx", add_prop("ptv.default_levels", "4")),
            ['ptv.default_levels "4" is above the model\'s 3 levels']),
        "default_levels_zero": (
            edited_model(good, tmp_path / "default0.onnx", add_prop("ptv.default_levels", "0")),
            ['ptv.default_levels "0" is not a positive integer']),
    }


def test_cxx_runner_rejects_bad_models(ptv, tmp_path: Path, monkeypatch) -> None:
    """A model that cannot be used never fails Execute(): one warning saying why, then the
    fixed guide (the same result as UseNetwork off); the next good model runs again."""
    monkeypatch.delenv("PTV_DATA_DIR", raising=False)
    good, cases = bad_models(tmp_path)
    h, w = 4, 5
    passes, _, _ = synthetic_passes(h, w, 0)
    frame = ("Radiance", "Albedo", "Depth", "Normal")  # what the fixed guide needs

    fixed = ptv.vtkPTVDenoiser()
    fixed_messages = observe(fixed)
    fixed.SetNumberOfThreads(1)
    fixed.UseNetworkOff()
    set_frame(fixed, passes, frame)
    assert fixed.Execute(), fixed_messages
    assert fixed_messages == []  # off on purpose: no warning
    assert not fixed.GetNetworkActive()
    assert fixed.GetStatus() == "fixed guide: UseNetwork is off"
    expected_result = denoised(fixed)
    assert network_outputs(fixed)[0].shape == (3, h, w)  # 3 levels

    denoiser = ptv.vtkPTVDenoiser()
    # The network's 3 levels at any frame size (the automatic count drops levels too
    # coarse for a small frame: bilateral_grid.fitting_levels).
    denoiser.SetNumberOfLevels(3)
    messages = observe(denoiser)
    denoiser.SetNumberOfThreads(1)
    set_frame(denoiser, passes, frame)
    features = to_image(random_features(14, h, w, 0))
    denoiser.SetImage("Features", features)
    for name, (path, expected) in cases.items():
        denoiser.SetModelFile(str(good))
        assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
        assert messages == []
        denoiser.SetModelFile(str(path))
        assert denoiser.Execute(), (name, messages)
        assert len(messages) == 1, (name, messages)
        print(f"{name}: {messages[0].strip()}")
        assert messages[0].startswith("WarningEvent")
        for text in expected + ["; denoising with a fixed guide (no network), the given "
                                "'Features' unused"]:
            assert text in messages[0], (name, text, messages[0])
        assert not denoiser.GetNetworkActive()
        status = denoiser.GetStatus()
        assert status.startswith("fixed guide: "), status
        for text in expected:
            assert text in status, (name, text, status)
        assert np.array_equal(denoised(denoiser), expected_result), name
        # Executing again with the same model: the same fallback, warned about once only.
        messages.clear()
        assert denoiser.Execute()
        assert messages == [], (name, messages)
        assert denoiser.GetStatus() == status and not denoiser.GetNetworkActive()
        assert np.array_equal(denoised(denoiser), expected_result), name
    # The same bad model after a good one is reported again.
    path = cases["truncated"][0]
    denoiser.SetModelFile(str(good))
    assert denoiser.Execute() and denoiser.GetNetworkActive()
    messages.clear()
    denoiser.SetModelFile(str(path))
    assert denoiser.Execute() and len(messages) == 1, messages
    assert "truncated.onnx" in messages[0] and messages[0].startswith("WarningEvent")
    # A model file that appears (or changes) after a failed load is loaded at the next Execute,
    # without setting ModelFile again.
    later = tmp_path / "written_later.onnx"
    denoiser.SetModelFile(str(later))
    messages.clear()
    assert denoiser.Execute() and not denoiser.GetNetworkActive()
    assert len(messages) == 1 and "no GuideNet model at" in messages[0], messages
    later.write_bytes(good.read_bytes())
    messages.clear()
    assert denoiser.Execute() and denoiser.GetNetworkActive(), (messages, denoiser.GetStatus())
    assert messages == []
    # Without the passes the fixed guide needs, the error says why the fixed guide is in use.
    denoiser.SetModelFile(str(path))
    denoiser.SetImage("Depth", None)
    messages.clear()
    assert not denoiser.Execute()
    assert len(messages) == 1 and messages[0].startswith("ErrorEvent"), messages
    for text in ("the fixed guide (", "truncated.onnx", ") cannot run: ", "'Depth'"):
        assert text in messages[0], (text, messages[0])
    set_frame(denoiser, passes, frame + ("Coverage",))  # the shipped model reads "coverage"
    messages.clear()
    # Still alive and usable; no model file set = the shipped one (on features from the passes).
    denoiser.SetModelFile(str(good))
    assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
    network_status(denoiser, good)
    denoiser.SetModelFile(None)
    assert denoiser.GetModelFile() is None
    denoiser.SetImage("Features", None)
    assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
    assert denoiser.GetStatus().startswith(
        f"GuideNet {ptv.vtkPTVDenoiser.GetDefaultModelFile()} ("), denoiser.GetStatus()
    assert messages == []


def test_cxx_runner_rejects_bad_inputs(ptv, tmp_path: Path) -> None:
    """Inputs that do not fit are errors: Execute() fails with one message naming the image and
    the problem, and the output keeps the last result."""
    from vtkmodules.util import numpy_support
    from vtkmodules.vtkCommonDataModel import vtkImageData

    path = export(random_net(10, 2), tmp_path / "gn.onnx", F.PAPER_10)
    h, w = 6, 5
    passes, _, _ = synthetic_passes(h, w, 0)
    denoiser = ptv.vtkPTVDenoiser()
    messages = observe(denoiser)
    denoiser.SetModelFile(str(path))
    set_frame(denoiser, passes)
    good_features = to_image(random_features(10, h, w, 0))
    denoiser.SetImage("Features", good_features)
    assert denoiser.Execute() and denoiser.GetNetworkActive(), messages
    first = denoised(denoiser)

    def fails(name, image, *texts):
        denoiser.SetImage(name, image)
        messages.clear()
        assert not denoiser.Execute()
        assert len(messages) == 1 and messages[0].startswith("ErrorEvent"), messages
        for text in texts:
            assert text in messages[0], (text, messages[0])
        assert np.array_equal(denoised(denoiser), first)

    fails("Features", to_image(random_features(14, h, w, 0)),
          f"'Features' has 14 components but the model {path} expects 10 channels: color.r,")
    double_image = to_image(random_features(10, h, w, 0))
    double_image.GetPointData().SetScalars(numpy_support.numpy_to_vtk(
        np.zeros((h * w, 10), np.float64), deep=True))
    fails("Features", double_image, "Image 'Features' holds double values", "expected float")
    volume = to_image(random_features(10, h, w, 0))
    volume.SetDimensions(5, 3, 2)
    fails("Features", volume, "Image 'Features' must be a W x H x 1 image", "got 5 x 3 x 2")
    no_array = vtkImageData()
    no_array.SetDimensions(w, h, 1)
    fails("Features", no_array, "Image 'Features' has no point array")
    fails("Features", to_image(random_features(10, h + 1, w, 0)),
          f"'Features' is {w} x {h + 1} but the model runs at 1/1 resolution: expected "
          f"{w} x {h} for a {w} x {h} frame")
    denoiser.SetImage("Features", good_features)
    # The passes.
    fails("Albedo", pass_image(passes["Albedo"][1:], "Albedo"),
          f"Image 'Albedo' is {w} x {h - 1} but the other images are {w} x {h}.")
    fails("Albedo", pass_image(passes["Albedo"][:, :, :2], "Albedo"),
          "Image 'Albedo' has 2 components; the pass has 3.")
    fails("Albedo", None, "the model divides the radiance by the Albedo pass, which is missing")
    denoiser.SetImage("Albedo", pass_image(passes["Albedo"], "Albedo"))
    fails("Radiance", None, "No Radiance image")
    denoiser.SetImage("Radiance", pass_image(passes["Radiance"], "Radiance"))
    messages.clear()
    denoiser.SetImage("Bogus", good_features)
    assert len(messages) == 1 and "Unknown image name 'Bogus'" in messages[0], messages
    # And a good run afterwards.
    messages.clear()
    assert denoiser.Execute() and denoiser.GetNetworkActive()
    assert np.array_equal(denoised(denoiser), first)
    assert messages == []
