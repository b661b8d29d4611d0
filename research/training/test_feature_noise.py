"""feature_noise.py's noise figure: rms(1 spp - 4 spp) / std(4 spp) over the covered pixels."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

from ptv_training import feature_noise  # noqa: E402


def test_noise_figure_of_clean_noisy_and_uncovered_pixels() -> None:
    rng = np.random.default_rng(3)
    h, w = 200, 100
    covered = np.zeros((h, w, 1), np.float32)
    covered[:, : w // 2] = 1.0  # the left half; the right half must not count
    spread, noise = 2.0, 0.5
    four = {"Alpha": covered, "Coverage": covered,
            "Radiance": rng.normal(1.0, spread, (h, w, 3)).astype(np.float32),
            "Albedo": rng.uniform(0, 1, (h, w, 3)).astype(np.float32),
            "Depth": rng.normal(5.0, spread, (h, w, 1)).astype(np.float32),
            "Normal": rng.normal(0.0, spread, (h, w, 3)).astype(np.float32)}
    one = {k: v.copy() for k, v in four.items()}
    one["Depth"] += rng.normal(0.0, noise, one["Depth"].shape).astype(np.float32)
    one["Normal"] += rng.normal(0.0, 3 * noise, one["Normal"].shape).astype(np.float32)
    one["Radiance"][:, w // 2:] += 1e6  # uncovered: ignored
    figures = feature_noise.noise_figures({1: one, 4: four})
    assert figures["covered"] == pytest.approx(0.5)
    # The edge rule marks the covered column beside the empty half: 1 of 50 covered columns.
    assert figures["edges"] == pytest.approx(1 / 50)
    assert figures["Albedo"] == 0.0 and figures["Radiance"] == 0.0
    # 10^4 (depth) and 3 x 10^4 (normal) samples: the figures' relative sampling error is
    # about 1 %, so 5 % bounds them.
    assert figures["Depth"] == pytest.approx(noise / spread, rel=0.05)
    assert figures["Normal"] == pytest.approx(3 * noise / spread, rel=0.05)


def test_no_views_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(SystemExit, match="run heldout.py"):
        feature_noise.main(["--views-dir", str(tmp_path), "--results", str(tmp_path),
                           "--no-progress"])
