"""How much can reusing frames raise "PSNR against the converged frame"? A study (docs/temporal.md).

Two measurements on one dataset at --size², the shipped model, the mapper's shown image (its
Converged pass), tone-mapped as in temporal_reuse.py:

* **still view** (the benchmark view): the reference's own noise (two independent --ref-spp
  references against each other; each against a --truth-spp one), and the mean of k denoised
  1-spp frames of independent seeds (k = 1, 2, 4, 16) and the denoised k-spp accumulation,
  against both references. A perfect reuse of k frames cannot beat these means.
* **orbit** (--frames views, --step degrees per frame, as temporal_reuse.py): one fresh frame
  per view and TemporalReprojection with each --histories MaximumHistory, against the
  --ref-spp and the --truth-spp converged views.

Prints a Markdown report (--out writes it atomically). Needs the compiled package
(``PYTHONPATH=<build>/python``) and a display (Xvfb); run it on an idle machine.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import temporal_reuse as tr  # noqa: E402
from pathtracedvolume.atomic import write_text  # noqa: E402
from pathtracedvolume.metrics import tonemap  # noqa: E402
from tqdm import tqdm  # noqa: E402


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--dataset", default="head")
    p.add_argument("--size", type=int, default=512, help="image size in pixels (square)")
    p.add_argument("--ref-spp", type=int, default=32,
                   help="spp of temporal_reuse.py's converged views (default 32)")
    p.add_argument("--truth-spp", type=int, default=256,
                   help="spp of the better reference (default 256)")
    p.add_argument("--frames", type=int, default=12, help="orbit views")
    p.add_argument("--step", type=float, default=2.0, help="orbit degrees per frame")
    p.add_argument("--histories", type=int, nargs="+", default=[1, 2, 4, 8])
    p.add_argument("--out", type=Path, default=None, help="write the Markdown report here")
    a = p.parse_args(argv)
    if a.ref_spp < 2 or a.truth_spp < 2 * a.ref_spp or a.frames < 2:
        p.error("need --ref-spp >= 2, --truth-spp >= 2 * --ref-spp and --frames >= 2")
    return a


def mean_of(frames: Sequence[np.ndarray], k: int) -> List[np.ndarray]:
    """Means of consecutive groups of k frames."""
    return [np.mean(frames[i:i + k], axis=0) for i in range(0, len(frames) - k + 1, k)]


def still_view(o: tr.Orbit, a: argparse.Namespace) -> List[str]:
    scene, mapper = o.scene, o.mapper
    o.view(0.0)
    mapper.DenoiseOff()
    refs = {}
    for name, spp, seed in (("ref a", a.ref_spp, 9000), ("ref b", a.ref_spp, 9100),
                            ("truth", a.truth_spp, 9200)):
        scene.render(seed, spp)
        refs[name] = tonemap(scene.grab("Radiance"))
    mapper.DenoiseOn()
    lines = [f"### Still view ({a.dataset}, {a.size}², azimuth {tr.AZIMUTH:g}°, "
             f"elevation {tr.ELEVATION:g}°)", "",
             f"Two {a.ref_spp}-spp references against each other: "
             f"{tr.psnr_vs(refs['ref a'], refs['ref b']):.2f} dB (an image equal to the truth "
             f"would score about 3 dB more against one of them); each against the "
             f"{a.truth_spp}-spp one: {tr.psnr_vs(refs['ref a'], refs['truth']):.2f} / "
             f"{tr.psnr_vs(refs['ref b'], refs['truth']):.2f} dB.", "",
             f"| shown image | vs {a.ref_spp} spp | vs {a.truth_spp} spp |", "|---|---|---|"]
    singles = []
    for k in tqdm(range(16), desc="denoised 1-spp frames", leave=False):
        scene.render(100 + k, 1)
        singles.append(tonemap(scene.grab("Converged")))
    for k in (1, 2, 4, 16):
        images = mean_of(singles, k)
        cells = [np.mean([tr.psnr_vs(i, refs[r]) for i in images]) for r in ("ref a", "truth")]
        lines.append(f"| mean of {k} denoised 1-spp frame(s) of independent seeds | "
                     f"{cells[0]:.2f} | {cells[1]:.2f} |")
    for k in (2, 4, 8):
        scene.render(300, k)
        shown = tonemap(scene.grab("Converged"))
        lines.append(f"| the denoised {k}-spp accumulation | {tr.psnr_vs(shown, refs['ref a']):.2f}"
                     f" | {tr.psnr_vs(shown, refs['truth']):.2f} |")
    return lines


def orbit(o: tr.Orbit, a: argparse.Namespace) -> List[str]:
    path = tr.orbit_path(a.frames, a.step)
    refs = {spp: o.references(path, spp, seed=1000 + spp) for spp in (a.ref_spp, a.truth_spp)}
    runs: Dict[str, Dict] = {"one fresh frame per view": o.run(path, False, 1, reseed=True)}
    for m in a.histories:
        runs[f"TemporalReprojection, MaximumHistory {m}"] = o.run(path, True, m)
    lines = [f"### Orbit ({a.frames} views, {a.step:g}° per frame)", "",
             f"| shown image | vs {a.ref_spp} spp: mean | gain | vs {a.truth_spp} spp: mean | "
             "gain |", "|---|---|---|---|---|"]
    base = {}
    for name, run in runs.items():
        cells = []
        for spp in (a.ref_spp, a.truth_spp):
            mean = float(np.mean(tr.psnr_per_frame(run["shown"], refs[spp])))
            base.setdefault(spp, mean)
            cells += [f"{mean:.2f}", f"{mean - base[spp]:+.2f}"]
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return lines


def main(argv: Optional[Sequence[str]] = None) -> int:
    a = parse_args(argv)
    o = tr.Orbit(a.dataset, a.size)
    command = "temporal_ceiling.py " + " ".join(sys.argv[1:] if argv is None else argv)
    lines = ["# How much can reuse raise PSNR against the converged frame?", "",
             f"`PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/"
             f"{command.strip()}` (shipped model, the shown Converged pass, tone-mapped).", ""]
    lines += still_view(o, a) + [""] + orbit(o, a)
    text = "\n".join(lines) + "\n"
    print(text)
    if a.out:
        write_text(a.out, text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
