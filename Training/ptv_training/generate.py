"""Render the denoiser's training data: one multi-channel EXR per random view + a manifest.

For each dataset, ``--views`` random views are rendered at ``--size`` squared by
vtkPathTracedVolumeMapper (denoising off). What a view varies depends on ``--tf``:

* ``random`` (default, the data users bring): a transfer function drawn from the volume's own
  histogram (:mod:`ptv_training.transfer`: bands or ramps, opacity 0.02-1, random colours),
  camera over the sphere with a distance factor 0.6-1.5 (zoom), a positional key light in a
  random direction (elevation -30..80 degrees) with intensity 0.4-1.6, and a random environment
  (= background) colour: grey level log-uniform in [0.03, 1], tinted by up to 30 %;
* ``presets`` (the first data set, ``v1``): the dataset's two-band or smooth preset with band
  thresholds shifted by up to +-5 % of the data range and opacity scaled by 0.5-1.5, distance
  factor 0.8-1.3, a key light above the view (elevation 15-80 degrees, intensity 0.7-1.3), the
  default background. Only head, stent and concrete have presets.

The last ``--val-views`` views of each dataset are the validation split (``"split"`` in the
view): their reference has ``--val-reference-spp`` samples per pixel. Training views' references
have ``--reference-spp``: a noisy but unbiased target, which is all an L2-type (Noise2Noise) loss
needs, at a fraction of the cost. For each view:

* inputs: every pass after 1, 2 and 4 frames of one seed (the mapper denoises accumulated
  frames, so the model sees a few spp), and the radiance after 16 frames of the same seed (the
  "16 spp" baseline);
* reference: the radiance after ``--reference-spp`` frames of an independent seed, and after the
  first half of them (``reference_half``, for the convergence check).

Channel layout: :mod:`ptv_training.exr_io`. Each view is deterministic given (``--seed``,
dataset, view index) and written atomically; a rerun skips views whose file exists and
verifies (readable, every channel, finite, same parameters), so an interrupted run resumes.
``manifest.json`` lists the views, parameters, timings and, with ``--check-reference``, the
convergence check: PSNR(reference_half vs reference) and how much PSNRs of the 1- and 16-spp
images change when the reference is doubled (images tone-mapped
``clip(max(0, x)^(1/2.2), 0, 1)``, scikit-image PSNR with data_range 1).

Run under Xvfb with the built package on PYTHONPATH, e.g.::

    PYTHONPATH=build/python xvfb-run -a -n 951 -s "-screen 0 1024x768x24 -noreset" \\
        .venv/bin/python Training/ptv_training/generate.py --check-reference
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

if __package__ in (None, ""):  # run as a file: python Training/ptv_training/generate.py
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402
from pathtracedvolume.scene import BACKGROUND  # noqa: E402

from . import exr_io  # noqa: E402
from .scene import Scene, anchor_groups, ensure_paths, sample_threshold_shift  # noqa: E402

ensure_paths()

PRESET_DATASETS = ("head", "stent", "concrete")
FORMAT = "ptv-training-views-v1"
REPO_ROOT = Path(__file__).resolve().parents[2]
DEFAULT_OUT = REPO_ROOT / ".cache" / "training" / "v2"


def all_datasets() -> List[str]:
    """Every dataset of ``Data/datasets.json``."""
    from pathtracedvolume.datasets import dataset_names
    return list(dataset_names())


from pathtracedvolume.metrics import psnr, tonemap  # noqa: E402,F401 (the project's metrics)


def _rng(seed: int, dataset: str, index: int, stream: int = 0) -> np.random.Generator:
    key = hashlib.sha256(f"{seed}/{dataset}/{index}/{stream}".encode()).digest()
    return np.random.default_rng(int.from_bytes(key[:8], "little"))


def render_fields(rng: np.random.Generator, size: int, reference_spp: int,
                  input_spp: Sequence[int] = exr_io.INPUT_SPP) -> Dict[str, Any]:
    """What every view has besides its scene: the input and reference seeds (the next two draws
    of ``rng``), the size and the sample counts."""
    return {"input_seed": int(rng.integers(1, 2**31 - 1)),
            "reference_seed": int(rng.integers(1, 2**31 - 1)),
            "size": [size, size],
            "reference_spp": int(reference_spp),
            "input_spp": [int(k) for k in input_spp],
            "baseline_spp": 16}


def random_view_parameters(dataset: str, index: int, seed: int, size: int, reference_spp: int,
                           histogram: Dict[str, List[float]], split: str = "train",
                           elevation_limit: float = 75.0,
                           input_spp: Sequence[int] = exr_io.INPUT_SPP) -> Dict[str, Any]:
    """The random, deterministic parameters of view ``index`` of ``dataset`` for ``--tf random``
    (``histogram``: :func:`ptv_training.transfer.histogram_quantiles` of the volume)."""
    from .transfer import random_transfer_function

    rng = _rng(seed, dataset, index, stream=1)
    tf = random_transfer_function(histogram, rng)
    azimuth = float(rng.uniform(0.0, 360.0))
    elevation = float(np.degrees(np.arcsin(rng.uniform(-1.0, 1.0))))
    elevation = float(np.clip(elevation, -elevation_limit, elevation_limit))
    grey = float(np.exp(rng.uniform(np.log(0.03), np.log(1.0))))
    tint = rng.uniform(-0.3, 0.3, 3)
    background = [float(np.clip(grey * (1.0 + t), 0.0, 1.0)) for t in tint]
    return {
        "dataset": dataset,
        "index": index,
        "split": split,
        "transfer_function": tf,
        "azimuth": azimuth,
        "elevation": elevation,
        "distance_factor": float(rng.uniform(0.6, 1.5)),
        "light": {"azimuth": float(rng.uniform(-180.0, 180.0)),
                  "elevation": float(rng.uniform(-30.0, 80.0)),
                  "intensity": float(rng.uniform(0.4, 1.6))},
        "background": background,
        **render_fields(rng, size, reference_spp, input_spp),
    }


def view_parameters(dataset: str, index: int, seed: int, size: int, reference_spp: int,
                    elevation_limit: float = 75.0,
                    input_spp: Sequence[int] = exr_io.INPUT_SPP) -> Dict[str, Any]:
    """The random, deterministic parameters of view ``index`` of ``dataset`` for
    ``--tf presets`` (unchanged since the first data set: the same seed gives the same views)."""
    from pathtracedvolume.presets import find_preset

    rng = _rng(seed, dataset, index)
    kind = "Two-Band (paper)" if rng.random() < 0.5 else "Smooth"
    preset_name = f"{dataset.capitalize()} {kind}"
    preset = find_preset(preset_name)
    # Uniform directions on the sphere; |elevation| limited (VTK's Elevation degenerates at 90).
    azimuth = float(rng.uniform(0.0, 360.0))
    elevation = float(np.degrees(np.arcsin(rng.uniform(-1.0, 1.0))))
    elevation = float(np.clip(elevation, -elevation_limit, elevation_limit))
    shift = sample_threshold_shift(preset, rng, 0.05)
    view = {
        "dataset": dataset,
        "index": index,
        "preset": preset_name,
        "threshold_shift": shift,
        "opacity_scale": float(rng.uniform(0.5, 1.5)),
        "azimuth": azimuth,
        "elevation": elevation,
        "distance_factor": float(rng.uniform(0.8, 1.3)),
        "light": {"azimuth": float(rng.uniform(-135.0, 135.0)),
                  "elevation": float(rng.uniform(15.0, 80.0)),
                  "intensity": float(rng.uniform(0.7, 1.3))},
        "background": list(BACKGROUND),
        **render_fields(rng, size, reference_spp, input_spp),
    }
    assert len(shift) == len(anchor_groups(preset))
    return view


def render_inputs(scene: Scene, view: Dict[str, Any], footprint: bool = False
                  ) -> Tuple[Dict[int, Dict[str, np.ndarray]], np.ndarray]:
    """A view's inputs: ``({spp: {pass: image}}, the 16-spp radiance)``, one seed accumulated
    through the input sample counts and the baseline's; with ``footprint`` the inputs include
    the Footprint pass (evaluation views)."""
    inputs: Dict[int, Dict[str, np.ndarray]] = {}
    names = exr_io.INPUT_PASSES + (("Footprint",) if footprint else ())
    scene.set_view(view, seed=view["input_seed"], denoise=False,
                   max_frames=max(view["baseline_spp"], max(view["input_spp"])),
                   footprint=footprint)
    frames = 0
    for spp in sorted(set(view["input_spp"]) | {view["baseline_spp"]}):
        got = scene.render(spp - frames)
        frames = spp
        if got != spp:
            raise RuntimeError(f"accumulated {got} frames, expected {spp} (accumulation reset?)")
        if spp in view["input_spp"]:
            inputs[spp] = {name: scene.get_pass(name) for name in names}
        if spp == view["baseline_spp"]:
            spp16 = scene.get_pass("Radiance")
    return inputs, spp16


def render_view(scene: Scene, view: Dict[str, Any], footprint: bool = False) -> Dict[str, Any]:
    """Render one view: (channels for the EXR, timings, statistics); with ``footprint`` the
    inputs include the Footprint pass (evaluation views)."""
    timings: Dict[str, float] = {}
    t0 = time.perf_counter()
    inputs, spp16 = render_inputs(scene, view, footprint)
    timings["inputs_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    ref_spp = view["reference_spp"]
    scene.set_view(view, seed=view["reference_seed"], denoise=False, max_frames=ref_spp,
                   coverage=False)
    got = scene.render(ref_spp // 2)
    if got != ref_spp // 2:
        raise RuntimeError(f"reference: accumulated {got} frames, expected {ref_spp // 2}")
    half = scene.get_pass("Radiance")
    got = scene.render(ref_spp - ref_spp // 2)
    if got != ref_spp:
        raise RuntimeError(f"reference: accumulated {got} frames, expected {ref_spp}")
    reference = scene.get_pass("Radiance")
    timings["reference_s"] = time.perf_counter() - t0

    radiance = {"reference": reference, "reference_half": half, "spp16": spp16}
    channels = exr_io.pack_view(inputs, radiance)
    stats = {"coverage": float((inputs[1]["Alpha"] > 0).mean()),
             "mean_reference": float(reference.mean())}
    return {"channels": channels, "timings": timings, "stats": stats, "radiance": radiance,
            "inputs": inputs}


def reference_check(data: Dict[str, np.ndarray], noisy: np.ndarray) -> Dict[str, float]:
    """Convergence figures of one view (see the module doc)."""
    ref, half, spp16 = data["reference"], data["reference_half"], data["spp16"]
    out = {"psnr_half_vs_full": psnr(half, ref)}
    for name, image in (("1spp", noisy), ("16spp", spp16)):
        full = psnr(image, ref)
        out[f"psnr_{name}_vs_full"] = full
        out[f"psnr_{name}_vs_half"] = psnr(image, half)
        out[f"delta_db_{name}"] = full - out[f"psnr_{name}_vs_half"]
    return out


def _write_json(path: Path, data: Any) -> None:
    """Atomically: a temporary file in the same folder, renamed into place; none left on error."""
    write_text(path, json.dumps(data, indent=1, sort_keys=False) + "\n")


def remove_stale_temporaries(out: Path) -> int:
    """Delete the temporary files a killed run left (``.<name>.*.tmp.exr``, ``.manifest.json.*.tmp``);
    finished files are only ever renamed into place, so these are never needed. Not for two runs
    writing into one folder at the same time."""
    stale = [*out.glob(".*.tmp.exr"), *out.glob(".manifest.json.*.tmp")]
    for path in stale:
        path.unlink(missing_ok=True)
    return len(stale)


def summarize_checks(views: Sequence[Dict[str, Any]]) -> Dict[str, Any]:
    """Mean / min / max of every reference-check figure, overall and per dataset."""
    def agg(items: List[Dict[str, float]]) -> Dict[str, Dict[str, float]]:
        keys = items[0].keys() if items else []
        return {k: {"mean": float(np.mean([i[k] for i in items])),
                    "min": float(np.min([i[k] for i in items])),
                    "max": float(np.max([i[k] for i in items]))} for k in keys}
    checked = [v for v in views if v.get("reference_check")]
    out: Dict[str, Any] = {"views": len(checked),
                           "all": agg([v["reference_check"] for v in checked])}
    for ds in sorted({v["view"]["dataset"] for v in checked}):
        out[ds] = agg([v["reference_check"] for v in checked if v["view"]["dataset"] == ds])
    return out


def _spp_list(text: str) -> Tuple[int, ...]:
    """"1,4,16" -> (1, 4, 16): increasing positive counts that start at 1."""
    try:
        spps = tuple(int(k) for k in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a list of integers: {text!r}") from None
    if not spps or spps[0] != 1 or any(b <= a for a, b in zip(spps, spps[1:])):
        raise argparse.ArgumentTypeError(f"need increasing counts starting at 1, got {text!r}")
    return spps


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python Training/ptv_training/generate.py",
        description="Render training views (noisy 1/2/4-spp passes + references) to EXR files.",
        epilog="Resumable: views whose file exists and verifies are skipped.")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT,
                        help=f"output folder (default: {DEFAULT_OUT})")
    parser.add_argument("--tf", choices=("random", "presets"), default="random",
                        help="random: transfer functions, lights, zoom and environment drawn "
                             "per view (default); presets: the first data set's jittered presets")
    parser.add_argument("--datasets", nargs="+", default=None,
                        help="datasets (default: every dataset of Data/datasets.json with "
                             "--tf random, head stent concrete with --tf presets)")
    parser.add_argument("--views", type=int, default=48, help="views per dataset (default: 48)")
    parser.add_argument("--val-views", type=int, default=2,
                        help="the last K views of each dataset are validation views (default 2; "
                             "0 with --tf presets, whose split train.py makes)")
    parser.add_argument("--size", type=int, default=256, help="image size S (S x S; default 256)")
    parser.add_argument("--reference-spp", type=int, default=64,
                        help="reference samples per pixel R of training views (default: 64, a "
                             "noisy target for a Noise2Noise loss)")
    parser.add_argument("--val-reference-spp", type=int, default=1024,
                        help="reference samples per pixel of validation views (default: 1024)")
    parser.add_argument("--input-spp", type=_spp_list, default=exr_io.INPUT_SPP,
                        help="comma-separated input sample counts, each view's one seed "
                             "accumulated through them (default: 1,2,4)")
    parser.add_argument("--seed", type=int, default=2023, help="master seed (default: 2023)")
    parser.add_argument("--check-reference", action="store_true",
                        help="record the reference convergence check (PSNR of R/2 vs R, and the "
                             "change of the 1- and 16-spp PSNRs when R/2 -> R) in the manifest")
    parser.add_argument("--threads", type=int, default=0,
                        help="mapper threads (0 = every core, default)")
    parser.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = parser.parse_args(argv)
    if args.views < 1 or args.size < 8 or args.reference_spp < 2 or args.val_reference_spp < 2:
        parser.error("need --views >= 1, --size >= 8, reference spp >= 2")
    if not 0 <= args.val_views < args.views:
        parser.error(f"--val-views {args.val_views} must be in [0, --views)")
    known = PRESET_DATASETS if args.tf == "presets" else tuple(all_datasets())
    if args.datasets is None:
        args.datasets = list(known)
    unknown = sorted(set(args.datasets) - set(known))
    if unknown:
        parser.error(f"--datasets: {', '.join(unknown)} not available with --tf {args.tf} "
                     f"(known: {', '.join(known)})")
    return args


def dataset_histogram(dataset: str) -> Dict[str, List[float]]:
    """:func:`ptv_training.transfer.histogram_quantiles` of the dataset's volume."""
    from pathtracedvolume.scene import load_dataset
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from .transfer import histogram_quantiles
    image = load_dataset(dataset)
    return histogram_quantiles(vtk_to_numpy(image.GetPointData().GetScalars()))


def make_view(args: argparse.Namespace, dataset: str, index: int,
              histograms: Dict[str, Dict[str, List[float]]]) -> Dict[str, Any]:
    """The parameters of view ``index`` of ``dataset`` under ``args``."""
    if args.tf == "presets":
        view = view_parameters(dataset, index, args.seed, args.size, args.reference_spp,
                               input_spp=args.input_spp)
        if args.val_views:
            view["split"] = "val" if index >= args.views - args.val_views else "train"
        return view
    if dataset not in histograms:
        histograms[dataset] = dataset_histogram(dataset)
    val = index >= args.views - args.val_views
    return random_view_parameters(
        dataset, index, args.seed, args.size,
        args.val_reference_spp if val else args.reference_spp, histograms[dataset],
        split="val" if val else "train", input_spp=args.input_spp)


def main(argv: Optional[Sequence[str]] = None) -> int:
    from tqdm import tqdm

    args = parse_args(argv)
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(out)
    manifest_path = out / "manifest.json"
    old: Dict[str, Any] = {}
    if manifest_path.is_file():
        try:
            old = {v["file"]: v for v in json.loads(manifest_path.read_text())["views"]}
        except (ValueError, KeyError):
            old = {}

    command = " ".join(sys.argv if argv is None else ["generate.py", *argv])
    jobs = [(ds, i) for ds in args.datasets for i in range(args.views)]
    records: List[Dict[str, Any]] = []
    scenes: Dict[str, Scene] = {}
    histograms: Dict[str, Dict[str, List[float]]] = {}
    started = time.perf_counter()
    rendered = skipped = 0
    bar = tqdm(jobs, desc="views", unit="view", disable=args.no_progress, dynamic_ncols=True)
    for ds, index in bar:
        view = make_view(args, ds, index, histograms)
        name = f"{ds}_{index:03d}.exr"
        path = out / name
        record = old.get(name)
        ok, _ = exr_io.verify_view_file(path, view, (args.size, args.size)) \
            if path.is_file() else (False, "missing")
        if ok and record is not None and record.get("view") == json.loads(json.dumps(view)) \
                and (record.get("reference_check") or not args.check_reference):
            records.append(record)
            skipped += 1
            continue
        if ds not in scenes:
            scenes.clear()  # one dataset's volume in memory at a time
            scenes[ds] = Scene(ds, (args.size, args.size), threads=args.threads)
        bar.set_postfix_str(name)
        if ok:  # the file is good but the manifest lost its record: re-read, do not re-render
            data = exr_io.read_view(path)
            result = {"timings": {}, "stats": {
                "coverage": float((data["inputs"][1]["Alpha"] > 0).mean()),
                "mean_reference": float(data["reference"].mean())},
                "radiance": data, "inputs": data["inputs"]}
        else:
            result = render_view(scenes[ds], view)
            exr_io.write_exr(path, result["channels"],
                             {exr_io.VIEW_ATTRIBUTE: json.dumps(view)})
            rendered += 1
        record = {"file": name, "view": view, "timings": result["timings"],
                  "stats": result["stats"], "bytes": path.stat().st_size}
        if args.check_reference:
            record["reference_check"] = reference_check(
                result["radiance"], result["inputs"][1]["Radiance"])
        records.append(record)
        _write_manifest(manifest_path, args, command, records, started, rendered, skipped,
                        final=False)
    _write_manifest(manifest_path, args, command, records, started, rendered, skipped, final=True)
    total = sum(r["bytes"] for r in records)
    print(f"{len(records)} views in {out} ({rendered} rendered, {skipped} kept; "
          f"{total / 2**20:.1f} MiB; {time.perf_counter() - started:.0f} s)")
    if args.check_reference and records:
        s = summarize_checks(records)["all"]
        print(f"reference check ({args.reference_spp} spp): PSNR(R/2 vs R) "
              f"{s['psnr_half_vs_full']['mean']:.2f} dB mean "
              f"(min {s['psnr_half_vs_full']['min']:.2f}); PSNR change when doubling: "
              f"1 spp {s['delta_db_1spp']['mean']:+.4f} dB, 16 spp "
              f"{s['delta_db_16spp']['mean']:+.4f} dB (max {s['delta_db_16spp']['max']:+.4f})")
    return 0


def _write_manifest(path: Path, args: argparse.Namespace, command: str,
                    records: List[Dict[str, Any]],
                    started: float, rendered: int, skipped: int, final: bool) -> None:
    view_seconds = [sum(r["timings"].values()) for r in records if r["timings"]]
    data = {
        "format": FORMAT,
        "complete": final,
        "command": command,
        "parameters": {"tf": args.tf, "datasets": args.datasets, "views": args.views,
                       "val_views": args.val_views, "size": args.size,
                       "reference_spp": args.reference_spp,
                       "val_reference_spp": args.val_reference_spp, "seed": args.seed,
                       "input_spp": list(args.input_spp), "baseline_spp": 16,
                       **({"threshold_jitter": 0.05, "opacity_scale": [0.5, 1.5],
                           "distance_factor": [0.8, 1.3]} if args.tf == "presets" else
                          {"distance_factor": [0.6, 1.5], "light_elevation": [-30, 80],
                           "light_intensity": [0.4, 1.6], "background_grey": [0.03, 1.0]})},
        "channels": exr_io.channel_names(args.input_spp),
        "row_order": "EXR top row first; ptv_training.exr_io.read_view returns VTK order",
        "machine": {"platform": platform.platform(), "cpus": os.cpu_count()},
        "timing": {"this_run_s": time.perf_counter() - started, "rendered": rendered,
                   "kept": skipped,
                   "median_view_s": float(np.median(view_seconds)) if view_seconds else None},
        "bytes": sum(r["bytes"] for r in records),
        "views": records,
    }
    if args.check_reference and records:
        data["reference_check"] = summarize_checks(records)
    _write_json(path, data)


if __name__ == "__main__":
    raise SystemExit(main())
