"""noise_aware.py's torch denoise: the one evaluate.py checks against the C++ denoiser, and its
masked blurs, which act only where the depth spread passes the threshold."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

import torch  # noqa: E402

from ptv_training import features as F  # noqa: E402
from ptv_training import noise_aware  # noqa: E402
from ptv_training.evaluate import torch_denoise  # noqa: E402
from ptv_training.guidenet import GuideNet  # noqa: E402

CHANNELS = F.PAPER_10 + ["coverage", "depth_spread"]
LEVELS = [(4, 4), (8, 8), (16, 16)]


def make_run(seed: int) -> dict:
    torch.manual_seed(seed)
    model = GuideNet(len(CHANNELS), hidden=8, kernel=3, levels=3, stride=2, out_channels=8)
    model.eval()
    return {"model": model, "ck": {"channels": CHANNELS, "levels": LEVELS, "clamp": 8.0,
                                   "demodulate": False}}


def make_passes(seed: int, h: int = 40, w: int = 48) -> dict:
    rng = np.random.default_rng(seed)
    hit = rng.random((h, w)) > 0.3
    unit = rng.normal(size=(h, w, 3))
    unit /= np.linalg.norm(unit, axis=2, keepdims=True)
    return {"Radiance": rng.gamma(1.0, 0.5, (h, w, 3)).astype(np.float32),
            "Albedo": rng.uniform(0, 1, (h, w, 3)).astype(np.float32),
            "Normal": np.where(hit[..., None], unit, 0).astype(np.float32),
            "Depth": np.where(hit, rng.uniform(2, 5, (h, w)), 10.0).astype(np.float32)[..., None],
            "Coverage": hit.astype(np.float32)[..., None],
            "DepthSpread": np.zeros((h, w, 1), np.float32)}


def test_denoise_is_evaluate_torch_path_with_one_default_level() -> None:
    run, passes = make_run(1), make_passes(2)
    ck = run["ck"]
    expected = torch_denoise(run["model"], CHANNELS, LEVELS, ck["clamp"], passes, False, None, 1)
    np.testing.assert_array_equal(noise_aware.denoise(run, passes), expected)


def test_masked_blur_acts_only_where_the_spread_passes_the_threshold() -> None:
    run, passes = make_run(3), make_passes(4)
    base = noise_aware.denoise(run, passes)
    for blur in noise_aware.BLURS:  # no spread anywhere: every blur leaves the image as it was
        np.testing.assert_array_equal(noise_aware.denoise(run, passes, blur), base)
    spread = passes["DepthSpread"]
    spread[10:30, 10:30] = 0.05 * 3.0  # 0.05 of the 3-unit depth range: between the thresholds
    assert 0.02 < F.build_features(passes, ["depth_spread"])[0, 20, 20] < 0.1
    for where in ("features", "guides"):
        above = noise_aware.denoise(run, passes, (where, 0.02, 1))
        below = noise_aware.denoise(run, passes, (where, 0.1, 1))
        assert np.abs(above - base).max() > 1e-4  # blurred where the spread is above 0.02
        # The spread channel itself moves the network's output; the threshold of 0.1 blurs
        # nothing, so it equals the plain denoise of the same passes.
        np.testing.assert_array_equal(below, noise_aware.denoise(run, passes))
