"""The second training data set's generator: random transfer functions from a volume's histogram,
the held-out shapes the generator never draws, random view parameters and the train/validation
split (no rendering: fast)."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

from ptv_training import transfer  # noqa: E402


def ct_like_volume() -> np.ndarray:
    """60 % air at -1000, the rest spread over [-200, 2000] (a CT-like histogram)."""
    rng = np.random.default_rng(0)
    values = np.full(100_000, -1000.0)
    values[40_000:] = rng.uniform(-200.0, 2000.0, 60_000)
    return values


def points(preset: dict, key: str, stride: int) -> np.ndarray:
    return np.asarray(preset[key], dtype=np.float64).reshape(-1, stride)


def plateaus(preset: dict) -> list:
    """Widths of the opacity function's flat non-zero segments (bands, ramp tops)."""
    pts = points(preset, "Points", 4)
    return [b[0] - a[0] for a, b in zip(pts, pts[1:]) if a[1] > 0 and a[1] == b[1]]


def test_histogram_leaves_out_a_dominant_background() -> None:
    h = transfer.histogram_quantiles(ct_like_volume())
    assert h["range"] == [-1000.0, pytest.approx(2000.0, abs=1.0)]
    assert h["quantiles"][0] >= -200.0  # the air (60 % at the minimum) is left out
    assert len(h["quantiles"]) == 1001
    # A volume without such a background keeps every voxel.
    flat = transfer.histogram_quantiles(np.linspace(0.0, 1.0, 1000))
    assert flat["quantiles"][0] == 0.0 and flat["quantiles"][-1] == 1.0


def test_random_transfer_functions_are_valid_and_deterministic() -> None:
    from pathtracedvolume.presets import make_functions

    h = transfer.histogram_quantiles(ct_like_volume())
    lo, hi = h["range"]
    a = [transfer.random_transfer_function(h, np.random.default_rng([7, i])) for i in range(300)]
    b = [transfer.random_transfer_function(h, np.random.default_rng([7, i])) for i in range(300)]
    assert json.dumps(a) == json.dumps(b)  # same generator state -> same function
    kinds = {p["Name"].split(" x")[0] for p in a}
    assert kinds == {"random bands", "random ramp"}
    maxima = []
    for preset in a:
        make_functions(preset)  # VTK accepts it
        pts, rgb = points(preset, "Points", 4), points(preset, "RGBPoints", 4)
        for table in (pts, rgb):
            assert np.all(np.diff(table[:, 0]) > 0)
            assert table[0, 0] == lo and table[-1, 0] == hi
        assert np.all((pts[:, 1] >= 0) & (pts[:, 1] <= 1))
        assert np.all((rgb[:, 1:] >= 0) & (rgb[:, 1:] <= 1))
        maxima.append(pts[:, 1].max())
        # Bands are at least 1 % of the range wide (the held-out narrow bands are 0.3 %).
        if preset["Name"].startswith("random bands"):
            assert min(plateaus(preset)) >= 0.01 * (hi - lo) * (1 - 1e-9)
        assert len(pts) <= 14
    maxima = np.asarray(maxima)
    assert maxima.min() >= 0.02 - 1e-12 and maxima.max() <= 1.0
    assert maxima.min() < 0.05 and maxima.max() > 0.8  # the whole opacity range is drawn


def test_held_out_shapes_are_not_what_training_draws() -> None:
    from pathtracedvolume.presets import make_functions

    h = transfer.histogram_quantiles(ct_like_volume())
    lo, hi = h["range"]
    held = transfer.held_out_transfer_functions(h)
    assert sorted(held) == ["narrow", "smooth", "translucent"]
    for preset in held.values():
        make_functions(preset)
    assert points(held["translucent"], "Points", 4)[:, 1].max() <= 0.04
    assert len(plateaus(held["narrow"])) == 2
    assert max(plateaus(held["narrow"])) < 0.01 * (hi - lo)  # below the training minimum
    assert len(points(held["smooth"], "Points", 4)) > 14  # more points than any drawn function


def test_random_view_parameters_and_split(tmp_path: Path) -> None:
    from ptv_training import generate
    from ptv_training.data import split_views

    h = transfer.histogram_quantiles(ct_like_volume())
    view = generate.random_view_parameters("head", 3, 2023, 64, 16, h, split="val")
    again = generate.random_view_parameters("head", 3, 2023, 64, 16, h, split="val")
    other = generate.random_view_parameters("head", 4, 2023, 64, 16, h)
    assert view == again and view != other
    assert json.loads(json.dumps(view)) == view
    assert view["split"] == "val" and other["split"] == "train"
    assert 0.6 <= view["distance_factor"] <= 1.5
    assert all(0.0 <= c <= 1.0 for c in view["background"])
    assert 0.4 <= view["light"]["intensity"] <= 1.6

    # split_views follows the views' "split" (not the last-K rule) when every view has one.
    records = [{"file": f"head_{i:03d}.exr", "view": {"dataset": "head", "index": i,
                                                      "split": "val" if i == 1 else "train"}}
               for i in range(3)]
    (tmp_path / "manifest.json").write_text(json.dumps({"views": records}))
    train, val, _ = split_views(tmp_path, val_per_dataset=2)
    assert [p.name for p in val] == ["head_001.exr"]
    assert [p.name for p in train] == ["head_000.exr", "head_002.exr"]


def test_relative_mse_is_minimised_by_the_mean_of_noisy_targets() -> None:
    """The Noise2Noise property the 64-spp training targets rely on: with the denominator
    (the tone map's slope) detached, the gradient of the relative MSE (the tone-mapped MSE
    linearised at the output) vanishes at the targets' mean, while L1 on tone-mapped images
    settles at their (tone-mapped) median."""
    import torch

    from ptv_training.train import training_loss

    rng = np.random.default_rng(3)
    targets = torch.tensor(rng.exponential(0.5, (4096, 1, 1, 1)), dtype=torch.float32)
    for kind, expected in (("relmse", float(targets.mean())),
                           ("tmse", float(targets.mean())),
                           ("l1", float(targets.median()))):
        x = torch.full((1, 1, 1, 1), 0.3, requires_grad=True)
        opt = torch.optim.Adam([x], lr=0.01)
        for _ in range(1500):
            opt.zero_grad()
            training_loss(x.expand_as(targets), targets, kind).backward()
            opt.step()
        assert float(x) == pytest.approx(expected, rel=0.03), kind
    assert float(targets.median()) < 0.8 * float(targets.mean())  # the two really differ


@pytest.mark.parametrize("value", [0.005, 0.05, 0.3, 0.9, 2.0])
def test_tmse_is_the_tone_mapped_squared_error_to_first_order(value: float) -> None:
    """``--loss tmse`` of a small error is the squared error after the PSNR's tone map (whose
    slope is taken at no less than TMSE_FLOOR and no more than 1: beyond 1 the tone map clips,
    and the weight stays that of 1 so that such pixels are still pulled back)."""
    import torch

    from ptv_training.train import TMSE_FLOOR, training_loss

    delta = 1e-3 * value
    out = torch.full((1, 3, 2, 2), value)
    got = float(training_loss(out, out + delta, "tmse"))
    at = min(max(value, TMSE_FLOOR), 1.0)  # the tone map's slope there, central differences
    h = 1e-4 * at
    slope = ((at + h) ** (1 / 2.2) - (at - h) ** (1 / 2.2)) / (2 * h)
    assert got == pytest.approx((slope * delta) ** 2, rel=1e-3)


def test_aux_spp_takes_every_pass_but_radiance_from_the_longer_accumulation(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """``train.py --aux-spp``: a 1- or 2-spp sample keeps its own radiance and takes the
    auxiliary passes of the 4-spp accumulation; the 4-spp sample and aux_spp 0 are unchanged."""
    import torch

    from ptv_training import data
    from ptv_training.exr_io import PASS_CHANNELS
    from ptv_training.features import PAPER_10, build_features

    rng = np.random.default_rng(3)
    inputs = {spp: {name: rng.uniform(0.1, 1.0, (6, 5, len(ch))).astype(np.float32)
                    for name, ch in PASS_CHANNELS.items()} for spp in (1, 2, 4)}
    for spp in inputs:  # hits everywhere, so every feature depends on its pass
        inputs[spp]["Depth"] *= 0.5
    image = rng.uniform(0.1, 1.0, (6, 5, 3)).astype(np.float32)
    view = {"inputs": inputs, "reference": image, "spp16": image, "view": {"dataset": "toy"}}
    monkeypatch.setattr(data.exr_io, "read_view", lambda path: view)

    plain = data.load_samples([Path("toy_000.exr")], PAPER_10, (1, 2, 4))
    mixed = data.load_samples([Path("toy_000.exr")], PAPER_10, (1, 2, 4), aux_spp=4)
    for spp, a, b in zip((1, 2, 4), plain, mixed):
        assert torch.equal(a.radiance, b.radiance)  # always the sample's own radiance
        passes = dict(inputs[4], Radiance=inputs[spp]["Radiance"],
                      HistoryLength=np.full((6, 5, 1), spp, np.float32))
        assert torch.equal(b.features, torch.from_numpy(build_features(passes, PAPER_10)))
        assert torch.equal(a.features, b.features) == (spp == 4)


def test_edge_samples_take_the_edge_pixels_from_the_longer_accumulation(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """``train.py --edge-samples 2``: a 1-spp sample's edge pixels (its Coverage's, the mapper's
    rule) take every pass from the 2-spp accumulation, a 2-spp sample's from the 4-spp one; all
    other pixels, the 4-spp sample (no 8-spp accumulation) and edge_samples 0 are unchanged."""
    import torch

    from pathtracedvolume.edges import edge_mask
    from ptv_training import data
    from ptv_training.exr_io import PASS_CHANNELS

    rng = np.random.default_rng(4)
    h, w = 9, 8
    inputs = {spp: {name: rng.uniform(0.1, 1.0, (h, w, len(ch))).astype(np.float32)
                    for name, ch in PASS_CHANNELS.items()} for spp in (1, 2, 4)}
    for spp in inputs:  # an opaque block in empty space: its rim and the ring around it are edges
        coverage = np.zeros((h, w, 1), np.float32)
        coverage[3:6, 2:5] = 0.9
        inputs[spp]["Coverage"] = coverage
    image = rng.uniform(0.1, 1.0, (h, w, 3)).astype(np.float32)
    view = {"inputs": inputs, "reference": image, "spp16": image, "view": {"dataset": "toy"}}
    monkeypatch.setattr(data.exr_io, "read_view", lambda path: view)

    mask = edge_mask(inputs[1]["Coverage"][..., 0])
    assert mask.sum() == 5 * 5 - 1 and not mask[4, 3]  # the ring around the block, its rim
    plain = data.load_samples([Path("toy_000.exr")], ["coverage"], (1, 2, 4), keep_passes=True)
    edged = data.load_samples([Path("toy_000.exr")], ["coverage"], (1, 2, 4), keep_passes=True,
                              edge_samples=2)
    for spp, a, b in zip((1, 2, 4), plain, edged):
        for name in PASS_CHANNELS:
            more = inputs[2 * spp][name] if spp < 4 else inputs[spp][name]
            np.testing.assert_array_equal(b.passes[name][mask], more[mask])
            np.testing.assert_array_equal(b.passes[name][~mask], inputs[spp][name][~mask])
            np.testing.assert_array_equal(a.passes[name], inputs[spp][name])
        assert torch.equal(b.radiance, data.chw(b.passes["Radiance"]))
        assert (b.passes["HistoryLength"] == spp).all()
        # DepthSpread: |frame samples' depth - the other samples' mean| on edges where both
        # hit (below 0.999 of the largest depth), 0 elsewhere and without edge samples
        assert (a.passes["DepthSpread"] == 0).all()
        if spp < 4:
            d_a = inputs[spp]["Depth"][..., 0]
            d_b = 2 * inputs[2 * spp]["Depth"][..., 0] - d_a
            far = 0.999 * max(d_a.max(), inputs[2 * spp]["Depth"].max())
            both = mask & (d_a < far) & (d_b < far)
            assert both.sum() >= 10
            np.testing.assert_allclose(b.passes["DepthSpread"][..., 0],
                                       np.where(both, np.abs(d_a - d_b), 0), atol=1e-6)
        else:
            assert (b.passes["DepthSpread"] == 0).all()
