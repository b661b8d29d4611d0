"""Where the reprojected history enters the denoised image: the grid's input or the guide.

The mapper denoises the accumulated passes, so the history reaches the shown image twice: as the
radiance the bilateral grid splats and averages, and as the noisy colour GuideNet reads to
predict the guides and blend weights. This splits the two on the orbits of
``temporal_reuse.py`` (same samples with and without history, PTV_HISTORY_ANGLE=0), with
vtkPTVDenoiser fed each frame's passes from both runs:

* **both** (what the mapper shows): guides and radiance from the accumulated passes;
* **grid input only**: guides and blend weights predicted from the fresh 1-spp frame, the grid
  run on the accumulated radiance (the "Guides"/"BlendWeights" images);
* **guide only**: guides from the accumulated passes, the grid run on the fresh radiance;
* **none**: the fresh frame alone (the benchmark's "no history").

Reported: PSNR against the converged views (tone-mapped, as ``temporal_reuse.py``), the gain of
each variant over "none" (mean and worst frame, frames 1+, and after the transfer-function
change for that case). The "both" column equals the mapper's own Denoised pass (checked; the
shown image mixes it with the raw mean, ptvConvergence).

Usage: ``PYTHONPATH=build/python xvfb-run -a .venv/bin/python
Testing/Benchmarks/history_split.py --help``.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
import temporal_reuse as tr  # noqa: E402

VARIANTS = ("both", "grid input only", "guide only", "none")
CASES = ("orbit", "TF change mid-orbit")  # the change at the middle frame, as temporal_reuse.py


def parse_args(argv: Optional[List[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--datasets", nargs="+", default=["head", "stent"])
    p.add_argument("--size", type=int, default=256, help="image size in pixels (square)")
    p.add_argument("--frames", type=int, default=36,
                   help="views per orbit (2 degrees apart; the transfer function changes at the "
                   "middle one)")
    p.add_argument("--ref-spp", type=int, default=256, help="spp of each converged view")
    p.add_argument("--history", type=int, default=1, help="MaximumHistory")
    p.add_argument("--out", type=Path, required=True, help="results folder (md, json)")
    a = p.parse_args(argv)
    if a.frames < 3:
        p.error(f"--frames must be at least 3 (frames after the change), got {a.frames}")
    return a


class Split:
    """Two vtkPTVDenoisers: one runs the network on a set of passes (its denoised image, guides
    and blend weights), the other runs the grid alone on another set's radiance with given
    guides and weights."""

    def __init__(self) -> None:
        self.net = pb.Ours()
        self.grid = pb.Ours()

    def network(self, passes: pb.Passes) -> Tuple[np.ndarray, Any, Any]:
        """The denoised image of ``passes`` and the guides and weights the network predicted."""
        from vtkmodules.vtkCommonDataModel import vtkImageData
        denoised = self.net(passes)
        guides, weights = vtkImageData(), vtkImageData()
        self.net.den.GetGuides(guides)
        self.net.den.GetBlendWeights(weights)
        return denoised, guides, weights

    def with_guides(self, passes: pb.Passes, guides: Any, weights: Any) -> np.ndarray:
        """The grid on ``passes``' radiance with the given guides and weights."""
        self.grid.set_passes(passes)
        self.grid.den.SetImage("Albedo", None)  # a model without demodulation: none given
        self.grid.den.SetImage("Guides", guides)
        self.grid.den.SetImage("BlendWeights", weights)
        return self.grid.execute()


def run_case(o: tr.Orbit, tf_change: Optional[int], a: argparse.Namespace,
             split: Split) -> Dict[str, Any]:
    path = tr.orbit_path(a.frames, 2.0)
    refs = o.references(path, a.ref_spp, 6000, tf_change)

    def collect(angle: Optional[float]):
        frames: List[pb.Passes] = []
        with tr.history_angle(angle):
            o.run(path, True, a.history, tf_change=tf_change,
                  on_frame=lambda i: frames.append(
                      {**o.scene.passes(), "Denoised": o.scene.grab("Denoised")}))
        return frames

    fresh = collect(0.0)
    acc = collect(None)
    psnr: Dict[str, List[float]] = {v: [] for v in VARIANTS}
    mapper: List[float] = []
    for i in tqdm(range(len(path)), desc=o.dataset, leave=False):
        both, acc_guides, acc_weights = split.network(acc[i])
        none, fresh_guides, fresh_weights = split.network(fresh[i])
        images = {"both": both, "none": none,
                  "grid input only": split.with_guides(acc[i], fresh_guides, fresh_weights),
                  "guide only": split.with_guides(fresh[i], acc_guides, acc_weights)}
        for v in VARIANTS:
            psnr[v].append(tr.psnr_vs(tr.tonemap(images[v]), refs[i]))
        mapper.append(tr.psnr_vs(tr.tonemap(acc[i]["Denoised"]), refs[i]))
    parts = {"frames 1+": slice(1, None)}
    if tf_change is not None:
        parts["after the change"] = slice(tf_change + 1, None)
    gains: Dict[str, Dict[str, Dict[str, float]]] = {}
    for v in VARIANTS[:-1]:
        d = np.array(psnr[v]) - np.array(psnr["none"])
        gains[v] = {k: {"mean": float(d[s].mean()), "worst": float(d[s].min())}
                    for k, s in parts.items()}
    return {"psnr": psnr, "gains": gains,
            "both_vs_mapper_max_db": float(np.abs(np.array(psnr["both"]) - mapper).max())}


def markdown(results: Dict[str, Dict[str, Any]], command: str) -> str:
    md = ["# Where the history enters the denoised image", "", f"`{command}` (idle machine).", "",
          "Gain over the same samples without history, dB: mean (worst frame).", "",
          "| dataset | case | part | both (the mapper) | grid input only | guide only |",
          "|---|---|---|---|---|---|"]
    for key, r in results.items():
        dataset, case = key.split(" / ")
        for part in r["gains"]["both"]:
            cells = [f"{r['gains'][v][part]['mean']:+.2f} ({r['gains'][v][part]['worst']:+.2f})"
                     for v in VARIANTS[:-1]]
            md.append(f"| {dataset} | {case} | {part} | " + " | ".join(cells) + " |")
    md += ["", "PSNR without history (mean): " + ", ".join(
        f"{k} {np.mean(r['psnr']['none']):.2f} dB" for k, r in results.items()) + "."]
    return "\n".join(md) + "\n"


def main(argv: Optional[List[str]] = None) -> int:
    a = parse_args(argv)
    command = " ".join(["PYTHONPATH=build/python xvfb-run -a .venv/bin/python",
                        "Testing/Benchmarks/history_split.py"] + sys.argv[1:])
    split = Split()
    results: Dict[str, Dict[str, Any]] = {}
    for dataset in a.datasets:
        o = tr.Orbit(dataset, a.size)
        for case in CASES:
            r = run_case(o, a.frames // 2 if case != "orbit" else None, a, split)
            if r["both_vs_mapper_max_db"] > 1e-6:
                raise SystemExit(f"{dataset} {case}: the 'both' variant differs from the "
                                 f"mapper's Denoised pass by {r['both_vs_mapper_max_db']:.3g} dB")
            results[f"{dataset} / {case}"] = r
    a.out.mkdir(parents=True, exist_ok=True)
    text = markdown(results, command)
    tr.write_text(a.out / "history_split.md", text)
    tr.write_text(a.out / "history_split.json",
                  json.dumps({"command": command, "results": results}, indent=1))
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
