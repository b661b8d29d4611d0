"""CLI: the Coverage (or Footprint) pass for views rendered before it existed, and the study of
GuideNet's ``coverage`` channel.

At one sample a camera ray has an event with the probability of its opacity c and stores Alpha
1, else 0, so the 1-spp Alpha of a fog and of a solid are both 0 or 1. The mapper's Coverage
pass (``CoverageMarch``) is c itself: the camera ray marched on past its event (the top-level
README, "The Coverage pass"), a noise-free measure of how translucent the ray's material is --
below 1 in a fog or a thin translucent tube, 1 on an opaque surface. GuideNet reads it as the
``coverage`` channel (``features.py``); ``generate.py``, ``heldout.py`` and ``compare.py`` store
it with the other passes.

``add``: view files rendered before the pass existed get it, so the caches need not be rendered
again: for each view file (``generate.py``'s and ``heldout.py``'s EXR files) the view's first 4
frames are rendered again with its input seed, every stored pass of its 1, 2 and 4-frame
accumulations must come out bit-identical (else the file is left alone and reported: render it
again with its own command), and the Coverage channels are added (``coverage.A``,
``spp<k>.coverage.A``; atomic write, new digest). Likewise the 1-frame passes of
``compare.py``'s Table-1 views (``--paper-cache``, ``.npz``). Files that have it are skipped.
With ``--pass Footprint`` the same for the Footprint pass (``FootprintRays``: 0 where the
denoiser keeps a pixel black), which only the evaluation views (``heldout.py``, ``compare.py``)
carry.

``compare``: trained runs (``best.pt``) in torch (``train.run_model``, the C++ path's numbers to
1e-4) on the validation views, the Table-1 views and the held-out views, each at the level count
the denoiser uses there, and OIDN RT fast; mean PSNR per group to ``<out>.md`` / ``.json``.

Example::

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Training/ptv_training/coverage.py \\
        add .cache/training/v2/*.exr .cache/training/heldout/*.exr
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
PASSES = ("Coverage", "Footprint")


def render_inputs(scene: Any, view: Mapping[str, Any], seed: int, spps: Sequence[int],
                  footprint: bool = False) -> Dict[int, Dict[str, np.ndarray]]:
    """Every input pass (``exr_io.INPUT_PASSES``, Coverage included, and with ``footprint`` the
    Footprint pass) after each of ``spps`` frames of ``seed``, as ``generate.render_view``
    renders them (VTK row order)."""
    scene.set_view(view, seed=seed, denoise=False, max_frames=max(spps), footprint=footprint)
    names = exr_io.INPUT_PASSES + (("Footprint",) if footprint else ())
    out: Dict[int, Dict[str, np.ndarray]] = {}
    frames = 0
    for spp in sorted(spps):
        if scene.render(spp - frames) != spp:
            raise RuntimeError(f"accumulated another frame count than {spp}")
        frames = spp
        out[spp] = {name: scene.get_pass(name) for name in names}
    return out


def mismatch(stored: Mapping[str, np.ndarray], rendered: Mapping[str, np.ndarray],
             added: str = "Coverage") -> List[str]:
    """The stored passes (but ``added``) that the new rendering does not reproduce bit for
    bit."""
    return [name for name, image in stored.items() if name != added and
            not np.array_equal(np.asarray(image, np.float32).reshape(rendered[name].shape),
                               rendered[name])]


def paper_view_parameters(path: Path) -> Dict[str, Any]:
    """The view of a cached Table-1 file ``<dataset>_<size>_<camera>_<ref spp>.npz``."""
    from .compare import paper_view_meta

    dataset, _, camera, _ = path.stem.split("_")
    return paper_view_meta(dataset, int(camera))


def add_pass(files: Sequence[Path], paper_cache: Optional[Path],
             added: str = "Coverage") -> Dict[str, List[str]]:
    """Add the pass ``added`` (Coverage or Footprint) to the files that lack it; returns the
    files added, kept and refused (a stored pass not reproduced)."""
    from tqdm import tqdm

    from pathtracedvolume.atomic import atomic_path

    from .compare import PAPER_SEEDS
    from .scene import Scene

    jobs = [("view", f) for f in files]
    if paper_cache is not None:
        jobs += [("paper", f) for f in sorted(paper_cache.glob("*_*_*_*.npz"))]
    result: Dict[str, List[str]] = {"added": [], "kept": [], "refused": []}
    scenes: Dict[tuple, Scene] = {}
    channel = exr_io.ALL_PASS_CHANNELS[added][0]
    for kind, f in tqdm(jobs, desc=added, unit="view"):
        if kind == "view":
            channels, header = exr_io.read_exr(f)
            if channel in channels:
                result["kept"].append(str(f))
                continue
            view = exr_io.view_attribute(header) or {}
            seed, spps = int(view["input_seed"]), exr_io.INPUT_SPP
            size = tuple(int(v) for v in view.get("size", (256, 256)))
            stored = {spp: {name: np.stack([channels[exr_io.spp_prefix(spp) + c][::-1]
                                            for c in chans], -1)
                            for name, chans in exr_io.PASS_CHANNELS.items() if name != added}
                      for spp in spps}
        else:
            with np.load(f) as z:
                arrays = {k: z[k] for k in z.files}
            if added in arrays:
                result["kept"].append(str(f))
                continue
            view = paper_view_parameters(f)
            size_s = f.stem.split("_")[1]
            seed, spps, size = PAPER_SEEDS[0], (1,), (int(size_s), int(size_s))
            stored = {1: {k: v for k, v in arrays.items() if k in exr_io.PASS_CHANNELS}}
        key = (view["dataset"], size)
        if key not in scenes:
            scenes[key] = Scene(view["dataset"], size)
        rendered = render_inputs(scenes[key], view, seed, spps, added == "Footprint")
        bad = [f"{spp} spp {name}" for spp in spps
               for name in mismatch(stored[spp], rendered[spp], added)]
        if bad:
            result["refused"].append(f"{f}: {', '.join(bad)} not reproduced")
            continue
        if kind == "view":
            for spp in spps:
                channels[exr_io.spp_prefix(spp) + channel] = \
                    np.ascontiguousarray(rendered[spp][added][::-1, :, 0])
            attributes = {k: v.decode() if isinstance(v, bytes) else str(v)
                          for k, v in header.items()
                          if k.startswith("ptv.") and k != exr_io.DIGEST_ATTRIBUTE}
            exr_io.write_exr(f, channels, attributes)
        else:
            arrays[added] = rendered[1][added]
            with atomic_path(f) as tmp:
                with open(tmp, "wb") as fh:
                    np.savez(fh, **arrays)
        result["added"].append(str(f))
    return result


# --------------------------------------------------------------------------------------------
# compare: runs in torch on the validation, Table-1 and held-out views

def torch_denoise(model: Any, ck: Dict[str, Any], passes: Dict[str, np.ndarray],
                  levels: int) -> np.ndarray:
    """A run's output ``(H, W, 3)`` for ``passes`` with its finest ``levels`` levels."""
    import torch

    from .data import chw
    from .features import build_features
    from .train import run_model

    features = torch.from_numpy(build_features(passes, ck["channels"]))[None]
    radiance = chw(passes["Radiance"])[None]
    demodulate = ck.get("demodulate", True)
    albedo = chw(passes["Albedo"])[None]
    with torch.no_grad():
        out, _, _ = run_model(model, features, radiance, albedo, ck["levels"], ck["clamp"],
                              demodulate=demodulate, use_levels=levels)
    return out[0].permute(1, 2, 0).numpy()


def compare(runs: Sequence[Path], data: Path, heldout: Path, paper_cache: Path,
            out: Path, command: str) -> None:
    import torch
    from tqdm import tqdm

    from pathtracedvolume.metrics import psnr

    from .compare import oidn_fast
    from .data import sample_passes, split_views
    from .train import load_run

    torch.set_num_threads(2)
    _, val, _ = split_views(data, 2)
    cases: List[tuple] = []  # (group, name, passes, reference, levels)
    for f in val:
        v = exr_io.read_view(f)
        for levels in (1, 3):
            cases.append((f"validation, {levels} level{'s' * (levels > 1)}",
                          f.name, sample_passes(v, f, 1), v["reference"], levels))
    for f in sorted(heldout.glob("*.exr")):
        if f.name.endswith(".hist.exr"):
            continue
        v = exr_io.read_view(f)
        cases.append((f"held-out {v['view']['heldout']}", f.name, sample_passes(v, f, 1),
                      v["reference"], 3))
    for f in sorted(paper_cache.glob("*_*_*_*.npz")):
        dataset, size, _, _ = f.stem.split("_")
        with np.load(f) as z:
            arrays = {k: z[k] for k in z.files}
        reference = arrays.pop("reference")
        cases.append((f"Table 1 {dataset} {size}²", f.name, arrays, reference,
                      3 if int(size) <= 256 else 1))
    rows: List[Dict[str, Any]] = []
    models = [(run.name, *load_run(run)) for run in runs]
    for group, name, passes, reference, levels in tqdm(cases, desc="compare", unit="view"):
        rows.append({"group": group, "view": name, "method": "OIDN RT fast",
                     "psnr": psnr(oidn_fast(passes), reference)})
        for run_name, model, ck in models:
            image = torch_denoise(model, ck, passes, levels)
            rows.append({"group": group, "view": name, "method": run_name,
                         "psnr": psnr(image, reference)})
    methods = [m for m in dict.fromkeys(r["method"] for r in rows)]
    groups = list(dict.fromkeys(r["group"] for r in rows))
    table = {m: {g: float(np.mean([r["psnr"] for r in rows
                                   if r["method"] == m and r["group"] == g]))
                 for g in groups} for m in methods}
    for m in methods:
        for size in ("256²", "512²"):
            sel = [table[m][g] for g in groups if g.startswith("Table 1") and g.endswith(size)]
            if sel:
                table[m][f"Table 1 mean {size}"] = float(np.mean(sel))
    columns = list(table[methods[0]])
    lines = ["# Coverage channel: runs in torch against OIDN RT fast", "",
             f"Command: `{command}`. Mean PSNR (dB, tone-mapped) per group, 1-spp inputs; "
             "validation at 1 and 3 levels, held-out views at 3 (256²), Table 1 at 3 levels "
             "(256²) and 1 (512²).", "",
             "| method | " + " | ".join(columns) + " |", "|---|" + "---|" * len(columns)]
    for m in methods:
        lines.append(f"| {m} | " + " | ".join(f"{table[m][c]:.2f}" for c in columns) + " |")
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text(out.with_suffix(".md"), "\n".join(lines) + "\n")
    write_text(out.with_suffix(".json"),
               json.dumps({"command": command, "table": table, "rows": rows}, indent=1) + "\n")
    print("\n".join(lines))


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("add", help="add the Coverage pass to view files rendered before it")
    r.add_argument("files", type=Path, nargs="*", help="view EXR files")
    r.add_argument("--pass", dest="added", choices=PASSES, default="Coverage",
                   help="the pass to add (default Coverage)")
    r.add_argument("--paper-cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views",
                   help="compare.py's Table-1 views (default .cache/training/paper_views)")
    c = sub.add_parser("compare", help="runs in torch on validation, Table-1, held-out views")
    c.add_argument("--run", type=Path, nargs="+", required=True, help="training runs")
    c.add_argument("--data", type=Path, default=REPO_ROOT / ".cache" / "training" / "v2")
    c.add_argument("--heldout", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "heldout")
    c.add_argument("--paper-cache", type=Path,
                   default=REPO_ROOT / ".cache" / "training" / "paper_views")
    c.add_argument("--out", type=Path, required=True, help="results path without suffix")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    command = "python Training/ptv_training/coverage.py " + " ".join(
        sys.argv[1:] if argv is None else list(map(str, argv)))
    if args.command == "add":
        from .scene import ensure_paths

        ensure_paths()
        start = time.perf_counter()
        files = [f for f in args.files if not f.name.endswith((".cov.exr", ".hist.exr"))]
        result = add_pass(files, args.paper_cache, args.added)
        for line in result["refused"]:
            print(f"coverage.py: refused {line}", file=sys.stderr)
        print(f"coverage.py: {args.added} added to {len(result['added'])} files, "
              f"{len(result['kept'])} had it, {len(result['refused'])} refused, "
              f"{time.perf_counter() - start:.0f} s")
        return 1 if result["refused"] else 0
    compare(args.run, args.data, args.heldout, args.paper_cache, args.out, command)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
