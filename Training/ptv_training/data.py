"""Training samples from the generated views (``generate.py``): features, radiance, albedo and
reference as tensors, the train/validation split, the 8 dihedral augmentations, metrics.

A sample is one (view, spp) pair: the features of that spp's accumulated passes (spp 0: the
passes after a reprojected history, ``history.py``)
(:func:`ptv_training.features.build_features`), its radiance and albedo (the bilateral grid's
data) and the view's reference radiance. Features are per-pixel formulas plus per-frame min/max,
so flipping/rotating the image commutes with building them; normals and positions are
world-space, so an image-space flip/rotation only permutes pixels and leaves their values alone.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
import torch

from pathtracedvolume import metrics

from . import exr_io
from .features import build_features

Tensor = torch.Tensor


tonemap_np = metrics.tonemap  # the NumPy tone map (pathtracedvolume.metrics)


def tonemap(x: Tensor, eps: float = 1e-6) -> Tensor:
    """Differentiable ``clip(max(0, x)^(1/2.2), 0, 1)`` (values below ``eps`` get no gradient,
    which keeps the power's infinite slope at 0 out of the backward pass)."""
    return torch.clamp(torch.clamp_min(x, eps) ** (1.0 / 2.2), 0.0, 1.0)


psnr = metrics.psnr  # PSNR of tone-mapped images (pathtracedvolume.metrics)


def chw(a: np.ndarray) -> Tensor:
    """``(H, W, C)`` -> contiguous ``(C, H, W)`` float32 tensor."""
    return torch.from_numpy(np.ascontiguousarray(np.transpose(a, (2, 0, 1)), dtype=np.float32))


@dataclass
class Sample:
    """One (view, spp) pair, tensors ``(C, H, W)``."""
    name: str
    dataset: str
    spp: int
    features: Tensor
    radiance: Tensor
    albedo: Tensor
    reference: Tensor
    spp16: Optional[Tensor] = None
    passes: Dict[str, np.ndarray] = field(default_factory=dict, repr=False)


def load_samples(files: Sequence[Path], channels: Sequence[str], spps: Sequence[int] = (1, 2, 4),
                 keep_passes: bool = False, progress: bool = False,
                 aux_spp: int = 0, edge_samples: int = 0) -> List[Sample]:
    """Samples for every file and spp (in that order). ``aux_spp`` > 0: every still sample of
    fewer spp takes its auxiliary passes (all but Radiance) from the view's ``aux_spp``
    accumulation (:func:`with_aux_passes`). ``edge_samples`` K > 1: the input the mapper
    denoises with EdgeSamples K (:func:`with_edge_samples`) wherever the view has it."""
    from tqdm import tqdm

    samples: List[Sample] = []
    for path in tqdm(list(files), desc="loading", unit="view", disable=not progress):
        view = exr_io.read_view(path)
        meta = view["view"] or {}
        dataset = str(meta.get("dataset", Path(path).stem.split("_")[0]))
        reference, spp16 = chw(view["reference"]), chw(view["spp16"])  # shared by the spps
        for spp in spps:
            passes = sample_passes(view, Path(path), spp, edge_samples)
            if aux_spp and spp != HISTORY_SPP and spp < aux_spp:
                passes = with_aux_passes(passes, view["inputs"][aux_spp])
            samples.append(Sample(
                name=Path(path).stem, dataset=dataset, spp=spp,
                features=torch.from_numpy(build_features(passes, channels)),
                radiance=chw(passes["Radiance"]), albedo=chw(passes["Albedo"]),
                reference=reference, spp16=spp16,
                passes=dict(passes) if keep_passes else {}))
    return samples


#: The ``spp`` of a sample whose input is the view seen through the mapper's reprojected history
#: (``history.py``: a few 1-spp frames along a short camera path ending at the view).
HISTORY_SPP = 0


def sample_passes(view: Dict, path: Path, spp: int, edge_samples: int = 0
                  ) -> Dict[str, np.ndarray]:
    """The input passes of one (view, spp) sample of ``view`` (``exr_io.read_view(path)``), with
    a HistoryLength pass: the reprojected history's own for spp 0, ``spp`` frames everywhere
    for a still accumulation. ``edge_samples`` K > 1: a still sample's edge pixels from the
    view's K spp-spp accumulation where it has one (:func:`with_edge_samples`)."""
    passes = view["inputs"][spp] if spp != HISTORY_SPP else _history_passes(path)
    if edge_samples > 1 and spp != HISTORY_SPP and spp * edge_samples in view["inputs"]:
        passes = with_edge_samples(passes, view["inputs"][spp * edge_samples], edge_samples)
    if "DepthSpread" not in passes:  # no edge samples: no disagreement measured
        passes = dict(passes)
        passes["DepthSpread"] = np.zeros(passes["Radiance"].shape[:2] + (1,), np.float32)
    if "HistoryLength" not in passes:
        passes = dict(passes)
        passes["HistoryLength"] = np.full(passes["Radiance"].shape[:2] + (1,),
                                          np.float32(spp), np.float32)
    return passes


def with_aux_passes(passes: Dict[str, np.ndarray], aux: Dict[str, np.ndarray]
                    ) -> Dict[str, np.ndarray]:
    """``passes`` with every auxiliary pass (all but Radiance and HistoryLength) replaced by
    ``aux``'s: the radiance of few samples with the anti-aliased features of more (the study
    of ``train.py --aux-spp``, ``research/training/aux_spp.py``)."""
    out = dict(passes)
    out.update({name: image for name, image in aux.items()
                if name not in ("Radiance", "HistoryLength")})
    return out


def with_edge_samples(passes: Dict[str, np.ndarray], more: Dict[str, np.ndarray],
                      samples: int = 2) -> Dict[str, np.ndarray]:
    """``passes`` (s spp) with the edge pixels of its Coverage (the mapper's rule,
    :func:`pathtracedvolume.edges.edge_mask`) taking every pass from ``more``, the same seed's
    accumulation of K s samples: what the mapper denoises with EdgeSamples K, whose edge pixels
    hold K samples per frame. Two differences, both small: the mapper's extra samples complete
    the frame sample's jitter into a lattice (here the next frames' independent jitters; at
    EdgeSamples 2 a lattice is worth 0.1-0.2 dB more, ``Testing/Benchmarks/results/
    edge_samples.md``), and above 1 spp it finds the edges in each frame, here in the s-spp
    mean. HistoryLength stays the frame count.

    Also a study pass ``DepthSpread`` (``features.py``, ``research/training/noise_aware.py``):
    on the edge pixels |dA - dB| between the first-event depth of the frame's own samples (A,
    ``passes``) and the mean of the ``samples`` - 1 others (B, from ``more``) where both hit, 0
    elsewhere: the disagreement the mapper's edge samples could measure per pixel."""
    from pathtracedvolume.edges import edge_mask

    mask = edge_mask(passes["Coverage"][..., 0])
    out = dict(passes)
    for name, image in more.items():
        if name in out and name != "HistoryLength":
            out[name] = np.where(mask[..., None], image, out[name])
    out["DepthSpread"] = _depth_spread(passes["Depth"], more["Depth"], samples, mask)
    return out


def _depth_spread(depth_a: np.ndarray, depth_all: np.ndarray, samples: int,
                  mask: np.ndarray) -> np.ndarray:
    """|dA - dB| (H, W, 1) on ``mask`` where both hit (below 0.999 of the frames' far
    depth), 0 elsewhere; dB = (K all - A) / (K - 1), the other samples' mean."""
    from .features import HIT_FRACTION

    a = depth_a[..., 0].astype(np.float32)
    k = np.float32(max(samples, 2))
    b = (k * depth_all[..., 0].astype(np.float32) - a) / (k - np.float32(1))
    limit = HIT_FRACTION * max(float(a.max()), float(depth_all.max()))
    both = mask & (a < limit) & (b < limit)
    return np.where(both, np.abs(a - b), np.float32(0)).astype(np.float32)[..., None]


def _history_passes(path: Path) -> Dict[str, np.ndarray]:
    from .history import history_file, read_history

    target = history_file(path)
    if not target.exists():
        raise FileNotFoundError(f"{target}: no history input for {path.name} (spp 0 needs "
                                f"history.py --data {path.parent})")
    return read_history(target)


def split_views(data_dir: Path, val_per_dataset: int) -> Tuple[List[Path], List[Path], dict]:
    """(train files, validation files, manifest). Views that carry a ``"split"`` (``generate.py
    --val-views``) go where it says, in index order; otherwise the last ``val_per_dataset``
    views of each dataset (by index) are held out for validation."""
    manifest = json.loads((data_dir / "manifest.json").read_text())
    by_dataset: Dict[str, List[Tuple[int, Path]]] = {}
    train: List[Path] = []
    val: List[Path] = []
    records = sorted(manifest["views"], key=lambda r: (r["view"]["dataset"], r["view"]["index"]))
    if records and all("split" in r["view"] for r in records):
        for record in records:
            (val if record["view"]["split"] == "val" else train).append(
                data_dir / record["file"])
        return train, val, manifest
    for record in manifest["views"]:
        view = record["view"]
        entry = (view["index"], data_dir / record["file"])
        by_dataset.setdefault(view["dataset"], []).append(entry)
    for ds in sorted(by_dataset):
        items = [p for _, p in sorted(by_dataset[ds])]
        k = min(val_per_dataset, max(len(items) - 1, 0))
        train += items[:len(items) - k]
        val += items[len(items) - k:]
    return train, val, manifest


def dihedral(x: Tensor, k: int) -> Tensor:
    """The ``k``-th (0..7) of the 8 flips/rotations of ``(..., H, W)`` tensors."""
    if k & 4:
        x = torch.flip(x, dims=(-1,))
    return torch.rot90(x, k & 3, dims=(-2, -1)) if k & 3 else x


def batch(samples: Sequence[Sample], transforms: Optional[Sequence[int]] = None
          ) -> Tuple[Tensor, Tensor, Tensor, Tensor]:
    """Stacked (features, radiance, albedo, reference), each sample transformed alike."""
    out = []
    for attr in ("features", "radiance", "albedo", "reference"):
        items = [getattr(s, attr) for s in samples]
        if transforms is not None:
            items = [dihedral(t, k) for t, k in zip(items, transforms)]
        out.append(torch.stack(items, 0))
    return tuple(out)  # type: ignore[return-value]
