#!/usr/bin/env python3
"""Evaluation report: quality against time, the paper's tables, temporal stability, a stress suite
and where the time goes, written as Markdown + PNG charts + CSV/JSON of every figure.

Sections (docs/measuring.md protocol: images tone-mapped clip(max(0,x)^(1/2.2),0,1), PSNR/SSIM
from scikit-image with data_range 1, timings = median of --repeats after a warm-up, all methods
in the same run), one module each in the package ``evaluation/`` beside this script:

1. Paper Table 1 per dataset (head, stent, concrete; "<Dataset> Two-Band (paper)" preset),
   --views camera orbits each: the 1..256-spp sweep, 1 spp denoised by vtkPTVDenoiser (the
   model's default level count, "ours", and every level of the model) and by OIDN (pyoidn RT, fast and balanced, albedo +
   normal) on the same 1-spp passes, against a --ref-spp reference of an independent seed
   (convergence: ref/2 vs ref).                                  (evaluation/table1.py)
2. PSNR against time per dataset and the quality-matched speed-up. (evaluation/table1.py)
2b. Quality against samples: the mapper's own accumulation of the Table-1 view (raw, Denoised,
   shown, OIDN fast and balanced on the same accumulation) at 1..256 frames, 256² and 512², and
   the frames each needs to reach 30/35/40 dB.                    (evaluation/samples.py)
3. Paper Tables 2-4 from the committed training studies (Training/results/), when present.
                                                                  (evaluation/training.py)
4. Temporal stability: per-pixel std over frames of different seeds (fixed view), the mapper's
   own accumulation when the camera stops, temporal PSNR over a camera orbit, and camera motion
   with temporal reuse (from results/temporal_reuse.json).        (evaluation/temporal.py)
5. Stress suite with a thumbnail gallery: translucent transfer function, fireflies, thin
   structures, exposure x0.01/x100, odd image sizes, mostly empty volume, unseen volume.
                                                                  (evaluation/stress.py)
6. Where the time goes: stages, image size, volume size and thread count.
                                                                  (evaluation/timing.py)

Each section module measures (VTK rendering, denoising) into rows of results.json and renders
those rows (Markdown, charts, CSVs); evaluation/common.py holds the shared helpers,
evaluation/scenes.py the scenes and the cache, evaluation/report.py the header and the runs.
``--render-only`` re-renders report.md, the charts and the CSVs from <out>/results.json without
measuring anything (no VTK); the galleries stay as the measuring run drew them.

Traced images that do not depend on the denoiser (references, spp sweeps, the orbit and stress
references) are cached under <cache>/bench/report, keyed by their parameters and by a fingerprint
of the tracer's output (a tiny render), so a changed tracer re-renders; --no-cache renders all.
Timings are always measured in the run itself.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional, Sequence

sys.path.insert(0, str(Path(__file__).resolve().parent))
from evaluation import report  # noqa: E402
from evaluation.common import parse_args  # noqa: E402


def main(argv: Optional[Sequence[str]] = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = parse_args(argv)
    if args.render_only:
        return report.render_only(args.out)
    return report.measure(args, argv)


if __name__ == "__main__":
    sys.exit(main())
