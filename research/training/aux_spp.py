"""CLI (study): how much would anti-aliased auxiliary features buy? 1-spp radiance with the
auxiliary passes (albedo, normal, depth, ...) of a K-spp accumulation of the same seed.

The mapper has no such input: each frame's features come from its one sample per pixel, so a
thin structure (the stent's wires) is hit or missed by the features as by the radiance. This
study asks what a denoiser would gain if the features were traced with K jittered rays per pixel
(first-event rays only, no shading) before anyone builds that. Inputs, each view:

- Table-1 views (``compare.paper_view``: head, stent, concrete, paper presets, cameras 30/10
  and 150/-20, 256² and 512², 1-spp input of seed 1, 256-spp reference of seed 100003) plus the
  same view accumulated to K spp with seed 1 (its first frame is the 1-spp input), rendered once
  into ``--paper-cache``;
- the training data's validation views (``.cache/training/v2``: ``spp4.*`` passes).

``--model NAME=FILE`` models denoise the plain 1-spp passes, ``--aux-model NAME=FILE`` models
(trained with ``train.py --aux-spp K``) the 1-spp radiance with the K-spp auxiliary passes, both
through the C++ ``vtkPTVDenoiser`` (the automatic level count); OIDN RT fast gets both inputs.
Mean PSNR per group (tone-mapped, scikit-image, data_range 1). Writes ``--out``.md/.json.

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Training/ptv_training/aux_spp.py \\
        --model shipped=Data/Models/guidenet.onnx --aux-model aux4=aux4.onnx
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402
from .compare import (PAPER_CAMERAS, PAPER_DATASETS, PAPER_SEEDS, oidn_fast,  # noqa: E402
                      paper_view, paper_view_meta)
from .data import split_views, with_aux_passes  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]


def paper_aux_view(dataset: str, size: int, camera: int, spp: int,
                   cache: Path) -> Dict[str, np.ndarray]:
    """The Table-1 view's passes accumulated to ``spp`` frames of the input's seed (cached)."""
    from pathtracedvolume.atomic import atomic_path

    from .scene import Scene

    path = cache / f"{dataset}_{size}_{camera}_aux{spp}.npz"
    if not path.is_file():
        view = paper_view_meta(dataset, camera)
        scene = Scene(dataset, (size, size))
        scene.set_view(view, seed=PAPER_SEEDS[0], max_frames=spp)
        if scene.render(spp) != spp:
            raise RuntimeError(f"{path.name}: the view did not accumulate {spp} frames")
        cache.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, **{name: scene.get_pass(name) for name in exr_io.INPUT_PASSES})
    with np.load(path) as z:
        return {k: z[k] for k in z.files}


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="python Training/ptv_training/aux_spp.py",
                                description=__doc__.split("\n\n")[0])
    p.add_argument("--model", nargs="*", default=[], metavar="NAME=FILE",
                   help="models fed the plain 1-spp passes")
    p.add_argument("--aux-model", nargs="*", default=[], metavar="NAME=FILE",
                   help="models fed 1-spp radiance with the K-spp auxiliary passes")
    p.add_argument("--aux-spp", type=int, default=4, choices=(2, 4),
                   help="K: the auxiliary passes' samples (default 4)")
    p.add_argument("--sizes", type=int, nargs="*", default=[256, 512],
                   help="Table-1 view sizes (default 256 512)")
    p.add_argument("--paper-reference-spp", type=int, default=256,
                   help="samples of the Table-1 views' references (default 256)")
    p.add_argument("--data", type=Path, default=REPO_ROOT / ".cache" / "training" / "v2",
                   help="training data with the validation views (default .cache/training/v2)")
    p.add_argument("--paper-cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views",
                   help="rendered Table-1 views (default .cache/training/paper_views)")
    p.add_argument("--out", type=Path, default=REPO_ROOT / "research" / "training" / "results" / "aux_spp",
                   help="write OUT.md and OUT.json (default research/training/results/aux_spp)")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    from pathtracedvolume.metrics import psnr
    from tqdm import tqdm

    from .evaluate import cpp_denoise

    args = parse_args(argv)
    k = args.aux_spp
    command = "python Training/ptv_training/aux_spp.py " + " ".join(
        sys.argv[1:] if argv is None else list(map(str, argv)))

    def named(items: Sequence[str]) -> Dict[str, Path]:
        return {n: Path(f) for n, f in (item.split("=", 1) for item in items)}

    plain_models, aux_models = named(args.model), named(args.aux_model)
    cases = [(f"Table 1 {ds} {size}²", f"{ds}_{size}_{cam}", size, ds, cam)
             for size in args.sizes for ds in PAPER_DATASETS for cam in range(len(PAPER_CAMERAS))]
    _, val, _ = split_views(args.data, 2)
    rows: List[Dict[str, object]] = []
    for item in tqdm(cases + list(val), desc="views", unit="view"):
        if isinstance(item, tuple):
            group, name, size, ds, cam = item
            view = paper_view(ds, size, cam, args.paper_reference_spp, args.paper_cache)
            plain, reference = view["inputs"], view["reference"]
            aux = paper_aux_view(ds, size, cam, k, args.paper_cache)
        else:
            view = exr_io.read_view(item)
            group, name = f"validation {view['view']['dataset']}", item.name
            plain, reference, aux = view["inputs"][1], view["reference"], view["inputs"][k]
        mixed = with_aux_passes(plain, aux)
        images = {"noisy 1 spp": plain["Radiance"], "OIDN RT fast": oidn_fast(plain),
                  f"OIDN RT fast, {k}-spp features": oidn_fast(mixed)}
        for label, model in plain_models.items():
            images[label] = cpp_denoise(model, plain, sorted(plain), threads=2)["output"]
        for label, model in aux_models.items():
            images[f"{label}, {k}-spp features"] = cpp_denoise(model, mixed, sorted(mixed),
                                                               threads=2)["output"]
        rows += [{"group": group, "view": name, "method": m, "psnr": psnr(image, reference)}
                 for m, image in images.items()]
    groups = list(dict.fromkeys(str(r["group"]) for r in rows))
    paper = [g for g in groups if g.startswith("Table 1")]
    valid = [g for g in groups if g.startswith("validation")]
    methods = list(dict.fromkeys(str(r["method"]) for r in rows))

    def mean(method: str, among: Sequence[str]) -> float:
        values = [float(r["psnr"]) for r in rows if r["method"] == method and r["group"] in among]
        return float(np.mean(values)) if values else float("nan")

    lines = ["# Anti-aliased auxiliary features: what they would buy (study)\n",
             f"Command: `{command}`. 1-spp radiance; the `{k}-spp features` rows take every "
             f"other pass from {k} frames of the same seed. Mean PSNR (dB), tone-mapped, "
             "scikit-image, data_range 1; models through the C++ `vtkPTVDenoiser`.\n",
             "| method | " + " | ".join(g[len("Table 1 "):] for g in paper)
             + f" | validation mean ({len(val)} views) |",
             "|---|" + "---|" * (len(paper) + 1)]
    lines += [f"| {m} | " + " | ".join(f"{mean(m, [g]):.2f}" for g in paper)
              + f" | {mean(m, valid):.2f} |" for m in methods]
    write_text(args.out.with_suffix(".md"), "\n".join(lines) + "\n")
    write_text(args.out.with_suffix(".json"),
               json.dumps({"command": command, "aux_spp": k, "rows": rows}, indent=1) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
