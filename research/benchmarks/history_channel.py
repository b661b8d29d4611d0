#!/usr/bin/env python3
"""Study: GuideNet checkpoints on the mapper's reprojected history, offline (torch).

The orbits of ``temporal_reuse.py`` (36 views 2° apart; head, the head with its opacity doubled
at frame 18, stent; 256² by default) are traced by the mapper twice with the same samples: with
TemporalReprojection (MaximumHistory 2) and with every history dropped (PTV_HISTORY_ANGLE=0).
Every frame's passes, HistoryLength included, are then denoised by each training run given
(``best.pt``, in torch with the grid's three levels, ``train.run_model``) and by the shipped model
through the C++ denoiser (``vtkPTVDenoiser``, three levels, colour only), and compared with the
converged views (``temporal_reuse.py``'s cached 32-spp references). Reported per case and model:
mean PSNR without and with history, and the history's gain over the same samples without it
(mean and worst frame; after the change for the transfer-function case).

The question: does a model that sees each pixel's history length (the ``history`` input
channel, ``Training/ptv_training/features.py``) turn the history into more than one that does
not? The shown image of the mapper is approximated by the denoised frame (while the camera
moves, its Converged pass is the denoised one). Writes ``--out``.md/.json atomically.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parents[1] / "Training"))
import ptvbench as pb  # noqa: E402
import temporal_reuse as tr  # noqa: E402
from evaluation.common import md_table  # noqa: E402

from pathtracedvolume.atomic import write_text  # noqa: E402
from pathtracedvolume.metrics import tonemap  # noqa: E402
from tqdm import tqdm  # noqa: E402

CASES = (("head", "orbit", None), ("head", "TF change at frame 18", 18), ("stent", "orbit", None))
SHIPPED = "shipped model (C++)"


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--run", type=Path, nargs="+", required=True, help="training runs (best.pt)")
    p.add_argument("--size", type=int, default=256, help="image size (default 256)")
    p.add_argument("--history", type=int, default=2, help="MaximumHistory (default 2)")
    p.add_argument("--out", type=Path, default=HERE / "results" / "history_channel",
                   help="results path without suffix")
    return p.parse_args(argv)


def trace(o: "tr.Orbit", path: Sequence[Dict[str, float]], history: int,
          tf_change: Optional[int]) -> List[Dict[str, np.ndarray]]:
    """Every frame's passes (and HistoryLength) along ``path``, Denoise off."""
    m = o.mapper
    m.DenoiseOff()
    m.SetTemporalReprojection(True)
    m.SetMaximumHistory(int(history))
    m.SetMaximumAccumulatedFrames(1024)
    m.SetSeed(4000)
    o.set_tf(False)
    m.ResetAccumulation()
    out = []
    for i, p in enumerate(path):
        o.set_tf(tf_change is not None and i >= tf_change)
        o.place(p)
        o.scene.window.Render()
        passes = {n: o.scene.grab(n) for n in pb.PASSES}
        passes["HistoryLength"] = o.scene.grab("HistoryLength")
        out.append(passes)
    o.set_tf(False)
    return out


class TorchRun:
    """A training run's best checkpoint, denoising passes in torch with every level."""

    def __init__(self, run: Path) -> None:
        import torch

        from ptv_training.guidenet import GuideNet
        self.ck = torch.load(run / "best.pt", weights_only=False)
        self.model = GuideNet(**self.ck["config"])
        self.model.load_state_dict(self.ck["model"])
        self.model.eval()

    def __call__(self, passes: Dict[str, np.ndarray]) -> np.ndarray:
        import torch

        from ptv_training.data import chw
        from ptv_training.features import build_features
        from ptv_training.train import run_model
        ck = self.ck
        features = torch.from_numpy(build_features(passes, ck["channels"]))[None]
        with torch.no_grad():
            out, _, _ = run_model(self.model, features, chw(passes["Radiance"])[None],
                                  chw(passes["Albedo"])[None],
                                  [tuple(level) for level in ck["levels"]], ck["clamp"],
                                  ck.get("demodulate", True))
        return out[0].permute(1, 2, 0).numpy()


def psnr(image: np.ndarray, reference: np.ndarray) -> float:
    """PSNR of a tone-mapped frame against a tone-mapped reference (data range 1)."""
    return float(-10.0 * np.log10(np.mean((tonemap(image) - reference) ** 2)))


def main(argv: Optional[Sequence[str]] = None) -> int:
    import torch

    args = parse_args(argv)
    torch.set_num_threads(2)
    shipped = pb.Ours(3, "", alpha=False)
    models: Dict[str, Any] = {SHIPPED: lambda p: shipped({k: p[k] for k in pb.PASSES})}
    for run in args.run:
        models[run.name] = TorchRun(run)
    rows: List[Dict[str, Any]] = []
    for dataset, case, change in tqdm(CASES, desc="cases"):
        o = tr.Orbit(dataset, args.size)
        path = tr.orbit_path(36, 2.0)
        refs = o.references(path, 32, 6000, change)
        with tr.history_angle(0.0):  # the same samples, every history dropped
            alone = trace(o, path, 1, change)
        kept = trace(o, path, args.history, change)
        after = range((change or 0) + 1, len(path))
        for name, denoise in models.items():
            a = [psnr(denoise(p), r) for p, r in zip(alone, refs)]
            h = [psnr(denoise(p), r) for p, r in zip(kept, refs)]
            gain = [h[i] - a[i] for i in after]
            rows.append({"dataset": dataset, "case": case, "model": name,
                         "psnr_alone": float(np.mean(a)), "psnr_history": float(np.mean(h)),
                         "gain_mean": float(np.mean(gain)), "gain_worst": float(np.min(gain)),
                         "alone_per_frame": a, "history_per_frame": h})
            print({k: v for k, v in rows[-1].items() if not k.endswith("per_frame")}, flush=True)
    command = ("PYTHONPATH=build/python xvfb-run -a .venv/bin/python "
               "Testing/Benchmarks/history_channel.py " +
               " ".join(sys.argv[1:] if argv is None else map(str, argv)))
    lines = ["# GuideNet checkpoints on the reprojected history (offline)", "",
             f"Command: `{command}`. {args.size}², 36-view orbits 2° apart, MaximumHistory "
             f"{args.history}; PSNR (dB, tone-mapped) of the denoised frame against the "
             "converged 32-spp view; gain: with history over the same samples without it "
             "(frames 1-35; after the change for the transfer-function case).", ""]
    lines += md_table(["dataset", "case", "model", "without history", "with history",
                       "gain (mean)", "gain (worst frame)"],
                      [[r["dataset"], r["case"], r["model"], f"{r['psnr_alone']:.2f}",
                        f"{r['psnr_history']:.2f}", f"{r['gain_mean']:+.2f}",
                        f"{r['gain_worst']:+.2f}"] for r in rows])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_text(args.out.with_suffix(".md"), "\n".join(lines) + "\n")
    write_text(args.out.with_suffix(".json"), json.dumps({"command": command, "rows": rows},
                                                         indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
