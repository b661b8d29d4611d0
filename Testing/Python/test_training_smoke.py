"""Smoke test of the training pipeline (CI, < 2 minutes on 2 cores): render 2 tiny views
(32 x 32, 16-spp reference), check the EXR layout and that a rerun resumes, train a few steps,
export to ONNX and run the exported model in C++ through vtkPTVDenoiser.

Needs the built package on PYTHONPATH, a display (ctest runs the Python tests under Xvfb), the
head dataset, and the OpenEXR / onnx Python packages."""
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

import pathtracedvolume.vtkPTVRendering  # noqa: F401
import OpenEXR  # noqa: F401
import onnx  # noqa: F401
import torch


def test_cosine_learning_rate() -> None:
    """--lr-schedule cosine: the rate falls from --lr to 1 % of it at --max-steps along a cosine
    (half-way: the mean of the two), never rises, and the schedule needs --max-steps."""
    from ptv_training import train

    rates = [train.cosine_rate(1e-3, k, 100) for k in range(0, 121)]
    assert rates[0] == pytest.approx(1e-3, rel=1e-12)
    assert rates[50] == pytest.approx(0.5 * (1e-3 + 1e-5), rel=1e-12)
    assert rates[100] == pytest.approx(1e-5, rel=1e-12) and rates[120] == rates[100]
    assert all(b <= a for a, b in zip(rates, rates[1:]))
    with pytest.raises(SystemExit, match="needs --max-steps"):
        train.main(["--out", "/nonexistent/run", "--lr-schedule", "cosine"])


def test_generate_train_export_and_load_in_cpp(tmp_path: Path, volume_path) -> None:
    volume_path("head")  # fails (or skips) clearly when the data is not fetched
    from ptv_training import evaluate, exr_io, generate, train
    from ptv_training.features import build_features, required_passes, resolve_channels

    data = tmp_path / "views"
    common = ["--out", str(data), "--datasets", "head", "--views", "2", "--size", "32",
              "--reference-spp", "8", "--val-views", "1", "--val-reference-spp", "16",
              "--check-reference", "--no-progress", "--threads", "2"]
    assert generate.main(common) == 0
    manifest = json.loads((data / "manifest.json").read_text())
    assert manifest["complete"] and len(manifest["views"]) == 2
    # Random transfer functions; the last view is the validation view with the larger reference.
    views = [r["view"] for r in manifest["views"]]
    assert all("transfer_function" in v for v in views)
    assert [(v["split"], v["reference_spp"]) for v in views] == [("train", 8), ("val", 16)]
    assert manifest["timing"]["rendered"] == 2
    assert "psnr_half_vs_full" in manifest["reference_check"]["all"]
    first = data / manifest["views"][0]["file"]
    ok, why = exr_io.verify_view_file(first, manifest["views"][0]["view"], (32, 32))
    assert ok, why
    view = exr_io.read_view(first)
    assert sorted(view["inputs"]) == [1, 2, 4]
    assert view["inputs"][1]["Radiance"].shape == (32, 32, 3)
    assert view["inputs"][1]["Depth"].shape == (32, 32, 1)
    assert view["reference"].shape == (32, 32, 3) and view["reference"].max() > 0
    # The 1-spp input is the first frame of the 16-spp baseline: same seed, so 16 spp is closer
    # to the (independent) reference.
    err1 = np.abs(view["inputs"][1]["Radiance"] - view["reference"]).mean()
    err16 = np.abs(view["spp16"] - view["reference"]).mean()
    assert err16 < err1

    # A rerun verifies the files and renders nothing.
    assert generate.main(common) == 0
    assert json.loads((data / "manifest.json").read_text())["timing"]["rendered"] == 0

    # The first data set's jittered presets still render (its views are unchanged).
    presets = tmp_path / "presets"
    assert generate.main(["--out", str(presets), "--tf", "presets", "--datasets", "stent",
                          "--views", "1", "--val-views", "0", "--size", "16",
                          "--reference-spp", "4", "--no-progress"]) == 0
    first_view = json.loads((presets / "manifest.json").read_text())["views"][0]["view"]
    assert first_view["preset"].startswith("Stent ") and "split" not in first_view
    assert first_view == generate.view_parameters("stent", 0, 2023, 16, 4)

    # history.py: each view seen through the mapper's reprojected history (a few frames along a
    # short camera path); a rerun keeps the verified files, and spp 0 trains on them.
    from ptv_training import history
    assert history.main(["--data", str(data)]) == 0
    hist = history.read_history(history.history_file(first))
    counts = hist["HistoryLength"][hist["Alpha"][..., 0] > 0]
    assert counts.size and counts.min() >= 1 and counts.max() <= 3.0 + 1e-6
    assert counts.max() > 1  # some pixels kept their history
    assert hist["Radiance"].shape == (32, 32, 3) and np.isfinite(hist["Radiance"]).all()
    stamp = history.history_file(first).stat().st_mtime_ns
    assert history.main(["--data", str(data)]) == 0
    assert history.history_file(first).stat().st_mtime_ns == stamp
    assert train.main(["--data", str(data), "--out", str(tmp_path / "run_hist"),
                       "--val-per-dataset", "1", "--hidden", "4", "--batch", "2",
                       "--max-steps", "2", "--threads", "2", "--spp", "1,0",
                       "--no-progress"]) == 0
    last = (tmp_path / "run_hist" / "log.csv").read_text().splitlines()
    header, row = last[0].split(","), last[-1].split(",")
    assert np.isfinite(float(row[header.index("val_psnr_history")]))

    run = tmp_path / "run"
    model_file = tmp_path / "model.onnx"
    assert train.main(["--data", str(data), "--out", str(run), "--val-per-dataset", "1",
                       "--hidden", "4", "--batch", "2", "--max-steps", "3", "--threads", "2",
                       "--edge-samples", "2", "--export", str(model_file),
                       "--no-progress"]) == 0
    log = (run / "log.csv").read_text().splitlines()
    assert len(log) >= 2 and log[0].startswith("epoch,")
    assert (run / "best.pt").is_file() and (run / "guides_best.png").is_file()
    assert model_file.is_file() and model_file.stat().st_size < 1 << 20
    # evaluate.py: the C++ path against torch on the validation views' edge-sampled inputs (the
    # run's --edge-samples), the model card
    assert json.loads((run / "run.json").read_text())["args"]["edge_samples"] == 2
    card = tmp_path / "card.json"
    assert evaluate.main(["--run", str(run), "--model", str(model_file), "--card", str(card),
                          "--threads", "2"]) == 0
    assert json.loads(card.read_text())["training"]["command"]

    # --extra-data: every view of another folder (generated with --val-views 0, another seed)
    # joins the training split; validation stays --data's; a folder with validation views is
    # refused.
    extra = tmp_path / "extra"
    assert generate.main(["--out", str(extra), "--datasets", "head", "--views", "1",
                          "--val-views", "0", "--size", "32", "--reference-spp", "8",
                          "--seed", "7", "--no-progress", "--threads", "2"]) == 0
    small = ["--val-per-dataset", "1", "--hidden", "4", "--batch", "2", "--max-steps", "1",
             "--threads", "2", "--no-progress"]
    assert train.main(["--data", str(data), "--out", str(tmp_path / "run_extra"),
                       "--extra-data", str(extra), *small]) == 0
    info = json.loads((tmp_path / "run_extra" / "run.json").read_text())
    assert len(info["train_views"]) == 2 and info["val_views"] == ["head_001.exr"]
    assert info["extra_data"] == [str(extra)]
    with pytest.raises(SystemExit, match="validation views"):
        train.main(["--data", str(data), "--out", str(tmp_path / "run_bad_extra"),
                    "--extra-data", str(data), *small])

    # --small-stride: the steps that run every level (the small-image case) run GuideNet at
    # that stride, the one-level steps at --stride; validation and the checkpoint keep --stride.
    seen = []
    original = train.run_model

    def spy(model, *a, **k):
        use = a[6] if len(a) > 6 else k.get("use_levels")
        seen.append((use, getattr(model, "stride", None)))
        return original(model, *a, **k)

    train.run_model = spy
    try:
        assert train.main(["--data", str(data), "--out", str(tmp_path / "run_small"),
                           "--val-per-dataset", "1", "--hidden", "4", "--batch", "2",
                           "--max-steps", "8", "--threads", "2", "--stride", "2",
                           "--level-counts", "1,3", "--small-stride", "1",
                           "--no-progress"]) == 0
    finally:
        train.run_model = original
    assert {(3, 1), (1, 2)} <= set(seen)  # both kinds of step ran (8 draws)
    assert all(st == (1 if use == 3 else 2) for use, st in seen)  # validation: None -> 2
    assert torch.load(tmp_path / "run_small" / "best.pt")["config"]["stride"] == 2
    with pytest.raises(SystemExit):  # every level always: no step would run at stride 2
        train.main(["--data", str(data), "--out", str(tmp_path / "bad"), "--small-stride", "1"])

    # --init/--adapt: the exported model plus a history channel of which only the first-layer
    # weights train; everything else stays the init's.
    adapted = tmp_path / "run_adapt"
    assert train.main(["--data", str(data), "--out", str(adapted), "--val-per-dataset", "1",
                       "--hidden", "4", "--batch", "2", "--max-steps", "2", "--threads", "2",
                       "--channels", "VOLUME_FEATURES,history", "--spp", "1,0",
                       "--init", str(model_file), "--adapt", "history", "--no-progress"]) == 0
    init = torch.load(run / "best.pt")["model"]
    new = torch.load(adapted / "last.pt")["model"]
    assert torch.equal(new["core.0.weight"][:, :-1], init["core.0.weight"])
    assert torch.equal(new["core.2.weight"], init["core.2.weight"])
    assert new["core.0.weight"][:, -1].abs().max() > 0
    assert torch.allclose(new["core.0.bias"],
                          init["core.0.bias"] - new["core.0.weight"][:, -1].sum((1, 2)))
    # --distill: every weight trains, the 1-spp samples also held to the init's output.
    assert train.main(["--data", str(data), "--out", str(tmp_path / "run_distill"),
                       "--val-per-dataset", "1", "--hidden", "4", "--batch", "2",
                       "--max-steps", "2", "--threads", "2", "--channels",
                       "VOLUME_FEATURES,history", "--spp", "1,0", "--init", str(model_file),
                       "--distill", "1", "--no-progress"]) == 0
    moved = torch.load(tmp_path / "run_distill" / "last.pt")["model"]
    assert not torch.equal(moved["core.2.weight"], init["core.2.weight"])

    channels = resolve_channels("VOLUME_FEATURES")
    passes = exr_io.read_view(data / json.loads((run / "run.json").read_text())["val_views"][0])
    passes = passes["inputs"][1]
    result = evaluate.cpp_denoise(model_file, passes, required_passes(channels), threads=2)
    assert result["network_active"], result["status"]
    assert result["output"].shape == (32, 32, 3)
    assert np.isfinite(result["output"]).all()

    # The C++ result is the torch pipeline's.
    ck = torch.load(run / "best.pt")
    from ptv_training.guidenet import GuideNet
    model = GuideNet(**ck["config"])
    model.load_state_dict(ck["model"])
    model.eval()
    expected = evaluate.torch_denoise(model, channels, [tuple(l) for l in ck["levels"]],
                                      ck["clamp"], passes)
    span = float(expected.max() - expected.min()) or 1.0
    assert np.abs(result["output"] - expected).max() <= 1e-4 * span

    # The same pipeline for a model trained without demodulation and for the U-Net baseline:
    # exported, loaded in C++, and equal to torch there too.
    from ptv_training.unet import UNet
    for extra in (["--no-demodulate", "--lr-schedule", "cosine", "--level-counts", "1,3"],
                  ["--arch", "unet", "--width", "4"]):
        run = tmp_path / ("run_" + extra[-1].strip("-"))
        model_file = run.with_suffix(".onnx")
        assert train.main(["--data", str(data), "--out", str(run), "--val-per-dataset", "1",
                           "--hidden", "4", "--batch", "2", "--max-steps", "2", "--threads", "2",
                           "--export", str(model_file), "--no-progress", *extra]) == 0
        result = evaluate.cpp_denoise(model_file, passes, required_passes(channels), threads=2)
        assert result["network_active"], result["status"]
        ck = torch.load(run / "best.pt")
        if "--arch" in extra:
            assert "image model" in result["status"]
            net = UNet(**ck["config"])
            net.load_state_dict(ck["model"])
            net.eval()
            features = torch.from_numpy(build_features(passes, channels))[None]
            with torch.no_grad():
                expected = net(features)[0].permute(1, 2, 0).numpy()
        else:
            assert not ck["demodulate"] and "no demodulation" in result["status"]
            model = GuideNet(**ck["config"])
            model.load_state_dict(ck["model"])
            model.eval()
            expected = evaluate.torch_denoise(model, channels, [tuple(l) for l in ck["levels"]],
                                              ck["clamp"], passes, demodulate=False)
        span = float(expected.max() - expected.min()) or 1.0
        assert np.isfinite(result["output"]).all()
        assert np.abs(result["output"] - expected).max() <= 1e-4 * span, extra
        if "cosine" in extra:  # two steps of two: the rate of the second is the floor's mean
            rates = [float(r.split(",")[10]) for r in (run / "log.csv").read_text().splitlines()[1:]]
            assert rates[-1] == pytest.approx(train.cosine_rate(1e-3, 1, 2), rel=1e-6)

    # compare.py: the runs at 1 and 2 levels on the validation view and on the report's Table-1
    # views (tiny, a 4-spp reference), every method a finite PSNR in both tables.
    from ptv_training import compare
    out = tmp_path / "compare"
    assert compare.main(["--data", str(data), "--run", str(tmp_path / "run"),
                         str(tmp_path / "run_1,3"), "--levels", "1", "2",
                         "--paper-views", "12", "--paper-reference-spp", "4",
                         "--paper-cache", str(tmp_path / "paper"), "--out", str(out)]) == 0
    table = out.with_suffix(".md").read_text()
    rows = json.loads(out.with_suffix(".json").read_text())["rows"]
    methods = {r["method"] for r in rows}
    assert {"run, 1 level", "run, 2 levels", "run_1,3, 1 level",
            "OIDN RT fast"} <= methods
    assert {r["dataset"] for r in rows} >= {"head", "Table 1 stent 12²", "Table 1 concrete 12²"}
    assert all(np.isfinite(r["psnr"]) for r in rows)
    assert "| mean 12² |" in table and len(list((tmp_path / "paper").glob("*.npz"))) == 6
