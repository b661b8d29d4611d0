"""Training inputs with a reprojected history: what the mapper's denoiser sees while the camera
moves (``vtkPathTracedVolumeMapper`` with TemporalReprojection on).

For every view of a data folder (``generate.py``), the same scene is rendered along a short
camera path that ends at the view: ``--frames`` earlier views, each ``--step`` degrees (drawn
per view from the range) further back along a random direction of azimuth and elevation, then
the view itself, one 1-spp frame each, with TemporalReprojection on and MaximumHistory
``--max-history``. The view's passes after that last frame (Radiance and Alpha: the history
blended with the new frame; the other passes: the new frame's own, as the mapper has them)
and its HistoryLength are written to ``<view>.hist.exr`` beside the view file, channels
``hist.<channel>`` (``exr_io.PASS_CHANNELS``) and ``hist.count``. The view's reference serves as
the target (``data.load_samples`` with spp 0). Resumable: a finished, verified file is kept.

Usage: ``python -m ptv_training.history --data .cache/training/v2`` (``--help``).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Sequence

import numpy as np

if __package__ in (None, ""):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from ptv_training import exr_io  # noqa: E402
from ptv_training.scene import Scene, ensure_paths  # noqa: E402

PREFIX = "hist."
COUNT_CHANNEL = PREFIX + "count"
HISTORY_ATTRIBUTE = "ptv.history"


def history_file(view_file: Path) -> Path:
    """The history file of a view file: ``head_004.exr`` -> ``head_004.hist.exr``."""
    return view_file.with_name(view_file.stem + ".hist.exr")


def camera_path(view: Mapping[str, Any], frames: int, step: float, direction: float
                ) -> List[Dict[str, float]]:
    """Azimuth/elevation of the ``frames`` earlier views and the view itself (last)."""
    az0, el0 = float(view.get("azimuth", 0.0)), float(view.get("elevation", 0.0))
    da, de = step * math.cos(direction), step * math.sin(direction)
    return [{"azimuth": az0 - da * j, "elevation": el0 - de * j} for j in range(frames, -1, -1)]


def render_history(scene: Scene, view: Mapping[str, Any], path: Sequence[Mapping[str, float]],
                   seed: int, max_history: int) -> Dict[str, np.ndarray]:
    """The view's passes after the path's frames (one each), and its ``HistoryLength``."""
    from pathtracedvolume.scene import place_camera

    mapper = scene.set_view(view, seed=seed, denoise=False, max_frames=1024)
    mapper.SetTemporalReprojection(True)
    mapper.GetExpertOptions().SetMaximumHistory(int(max_history))
    for p in path:
        place_camera(scene.renderer, p["azimuth"], p["elevation"],
                     view.get("distance_factor", 1.0))
        scene.window.Render()
    passes = {name: scene.get_pass(name) for name in exr_io.INPUT_PASSES}
    passes["HistoryLength"] = scene.get_pass("HistoryLength")
    return passes


def pack(passes: Mapping[str, np.ndarray]) -> Dict[str, np.ndarray]:
    """EXR channels (top row first) of :func:`render_history`'s passes."""
    out = exr_io.pack_passes(passes, PREFIX)
    out[COUNT_CHANNEL] = np.ascontiguousarray(passes["HistoryLength"][::-1, :, 0])
    return out


def read_history(path: Path) -> Dict[str, np.ndarray]:
    """A history file's passes ``(H, W, C)`` in VTK row order (``HistoryLength`` included)."""
    channels, _ = exr_io.read_exr(path)
    out = exr_io.unpack_passes(channels, PREFIX)
    out["HistoryLength"] = np.ascontiguousarray(channels[COUNT_CHANNEL][::-1][..., None])
    return out


def is_complete(path: Path) -> bool:
    """Whether ``path`` is a readable history file whose pixels match its digest."""
    if not path.exists():
        return False
    try:
        channels, header = exr_io.read_exr(path)
    except Exception:  # noqa: BLE001 (a damaged or partial file: render it again)
        return False
    return (COUNT_CHANNEL in channels and exr_io.DIGEST_ATTRIBUTE in header
            and exr_io.digest_matches(channels, header))


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", type=Path, default=Path(".cache/training/v2"),
                   help="folder of generate.py (with manifest.json)")
    p.add_argument("--frames", type=int, default=2, help="earlier views on the path (default 2)")
    p.add_argument("--step", type=float, nargs=2, default=[1.0, 4.0], metavar=("MIN", "MAX"),
                   help="degrees between views, drawn per view (default 1 4)")
    p.add_argument("--max-history", type=int, default=2,
                   help="the mapper's MaximumHistory (default 2: the mapper's default until "
                        "2026-12-04, 1 since)")
    p.add_argument("--seed", type=int, default=7000, help="seed of the paths and the frames")
    p.add_argument("--datasets", nargs="*", default=None, help="only these datasets")
    a = p.parse_args(argv)
    if a.frames < 1 or a.max_history < 1 or not 0 <= a.step[0] <= a.step[1]:
        p.error("need --frames >= 1, --max-history >= 1, 0 <= step MIN <= MAX")
    return a


def main(argv: Optional[Sequence[str]] = None) -> int:
    from tqdm import tqdm

    args = parse_args(argv)
    ensure_paths()
    manifest_path = args.data / "manifest.json"
    if not manifest_path.exists():
        raise SystemExit(f"history.py: no {manifest_path} (run generate.py first)")
    records = json.loads(manifest_path.read_text())["views"]
    if args.datasets:
        records = [r for r in records if r["view"]["dataset"] in args.datasets]
    records.sort(key=lambda r: (r["view"]["dataset"], r["view"]["index"]))
    scenes: Dict[str, Scene] = {}
    start, made = time.perf_counter(), 0
    bar = tqdm(records, desc="history", unit="view")
    for record in bar:
        view = record["view"]
        target = history_file(args.data / record["file"])
        bar.set_postfix_str(target.name)
        if is_complete(target):
            continue
        rng = np.random.default_rng([args.seed, view["index"], sum(map(ord, view["dataset"]))])
        step = float(rng.uniform(args.step[0], args.step[1]))
        direction = float(rng.uniform(0.0, 2.0 * math.pi))
        seed = int(rng.integers(1, 2 ** 31 - 1))
        size = tuple(int(v) for v in view.get("size", (256, 256)))
        scene = scenes.get(view["dataset"])
        if scene is None or tuple(scene.size) != size:
            scene = scenes[view["dataset"]] = Scene(view["dataset"], size)
        path = camera_path(view, args.frames, step, direction)
        passes = render_history(scene, view, path, seed, args.max_history)
        info = {"frames": args.frames, "step": step, "direction": direction, "seed": seed,
                "max_history": args.max_history}
        exr_io.write_exr(target, pack(passes), {HISTORY_ATTRIBUTE: json.dumps(info)})
        made += 1
    print(f"history.py: {made} files written, {len(records) - made} kept, "
          f"{time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
