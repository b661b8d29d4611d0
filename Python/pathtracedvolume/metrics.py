"""The project's image metrics, defined once (docs/measuring.md): the tone map
``clip(max(0, x)^(1/2.2), 0, 1)`` and PSNR / SSIM of tone-mapped images against a tone-mapped
reference (scikit-image, data range 1); temporal PSNR and flicker of tone-mapped frame
sequences. Plain NumPy; scikit-image is imported when used.
"""
from __future__ import annotations

import math
from typing import List, Sequence, Tuple

import numpy as np

GAMMA = 1.0 / 2.2


def tonemap(x: np.ndarray) -> np.ndarray:
    """``clip(max(0, x)^(1/2.2), 0, 1)`` as float32 (NaN maps to 0)."""
    return np.clip(np.power(np.maximum(np.nan_to_num(np.asarray(x, np.float32)), 0.0),
                            np.float32(GAMMA)), 0.0, 1.0)


def psnr(image: np.ndarray, reference: np.ndarray) -> float:
    """PSNR in dB of the tone-mapped ``image`` against the tone-mapped ``reference``."""
    from skimage.metrics import peak_signal_noise_ratio
    return float(peak_signal_noise_ratio(tonemap(reference), tonemap(image), data_range=1.0))


def quality(reference: np.ndarray, image: np.ndarray) -> Tuple[float, float]:
    """(PSNR, SSIM) of the tone-mapped ``image`` against the tone-mapped ``reference``. SSIM uses
    the largest odd window that fits (7 for ordinary images; NaN below 3 pixels)."""
    from skimage.metrics import structural_similarity
    ref, img = tonemap(reference), tonemap(image)
    win = min(7, *ref.shape[:2])
    win -= 1 - win % 2
    ssim = (float(structural_similarity(ref, img, data_range=1.0, channel_axis=2, win_size=win))
            if win >= 3 else float("nan"))
    return psnr(image, reference), ssim


def tpsnr(frames: Sequence[np.ndarray]) -> List[float]:
    """PSNR between consecutive tone-mapped frames (identical frames count as 100 dB)."""
    out = []
    for a, b in zip(frames[:-1], frames[1:]):
        mse = float(np.mean((np.asarray(a, np.float64) - b) ** 2))
        out.append(100.0 if mse == 0 else 10 * math.log10(1.0 / mse))
    return out


def flicker(frames: Sequence[np.ndarray]) -> float:
    """Per-pixel standard deviation over the tone-mapped frames, averaged over the image."""
    return float(np.mean(np.std(np.stack(frames), axis=0)))
