"""pathtracedvolume.metrics: the one definition of the tone map, PSNR/SSIM and the temporal
metrics (docs/measuring.md)."""
import math

import numpy as np

from pathtracedvolume import metrics


def test_tonemap_is_clipped_gamma() -> None:
    x = np.array([-1.0, 0.0, 0.25, 1.0, 4.0, np.nan, np.inf], np.float64)
    y = metrics.tonemap(x)
    assert y.dtype == np.float32
    expected = [0.0, 0.0, 0.25 ** (1 / 2.2), 1.0, 1.0, 0.0, 1.0]
    assert np.allclose(y, expected, atol=1e-7)


def test_psnr_is_mse_of_tone_mapped_images() -> None:
    rng = np.random.default_rng(3)
    ref = rng.uniform(0.0, 1.5, (16, 16, 3)).astype(np.float32)
    img = ref + rng.normal(0.0, 0.02, ref.shape).astype(np.float32)
    mse = float(np.mean((metrics.tonemap(img).astype(np.float64) - metrics.tonemap(ref)) ** 2))
    assert math.isclose(metrics.psnr(img, ref), -10 * math.log10(mse), rel_tol=1e-5)
    psnr, ssim = metrics.quality(ref, img)
    assert psnr == metrics.psnr(img, ref) and 0.0 < ssim < 1.0
    assert metrics.quality(ref, ref)[1] == 1.0


def test_quality_window_fits_small_images() -> None:
    tiny = np.full((2, 2, 3), 0.5, np.float32)
    assert math.isnan(metrics.quality(tiny, tiny)[1])  # no 3x3 window fits
    five = np.full((5, 5, 3), 0.5, np.float32)
    assert metrics.quality(five, five * 0.9)[1] < 1.0  # a 5x5 window


def test_tpsnr_and_flicker_of_frame_sequences() -> None:
    a = np.full((4, 4, 3), 0.5, np.float32)
    b = a + np.float32(0.1)  # every pixel 0.1 apart: PSNR 20 dB, std 0.05 over the pair
    assert np.allclose(metrics.tpsnr([a, b, b]), [20.0, 100.0], atol=1e-4)
    assert math.isclose(metrics.flicker([a, b]), 0.05, rel_tol=1e-5)
    assert metrics.flicker([a, a, a]) == 0.0
