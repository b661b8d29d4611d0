"""Copy a training-data folder with its inputs traced again under a tracer study switch.

A study of a change to the 1-spp estimator (for instance ``PTV_EXPECTED_COVERAGE=1``, the
camera ray's expected coverage instead of its coin flip: ``Rendering/Kernels/ptvIntegrator.h``,
step 4b) needs a model trained on inputs traced that way. The references do not change (the
switch keeps every pass's expectation), and they are four fifths of the data's render time, so
this tool traces only each view's inputs again (the 1, 2 and 4-spp passes and the 16-spp
baseline, the same seeds as ``generate.py``) and keeps the source's references. The views'
parameters and the split stay the source's, so a model trained on the copy is compared with
one trained on the source view for view.

Each view is written atomically with the switch in its ``ptv.inputs`` attribute; a rerun skips
views whose file verifies and carries the same switch (resumable). ``manifest.json`` is the
source's with ``inputs_switch``, ``inputs_from`` and this run's timings added; it is written
once every view is done, so a stopped run leaves none (nothing can train on a half copy),
and a resumed run records ``inputs_s`` only for the views it traced (the others keep the
source's).

Run under Xvfb with the built package on PYTHONPATH, e.g.::

    PYTHONPATH=build/python xvfb-run -a .venv/bin/python Training/ptv_training/reinput.py \\
        --src .cache/training/v2 --out .cache/training/v2_ec --switch PTV_EXPECTED_COVERAGE=1
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple

if __package__ in (None, ""):  # run as a file: python Training/ptv_training/reinput.py
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

from pathtracedvolume.atomic import write_text  # noqa: E402

from . import exr_io  # noqa: E402
from .generate import remove_stale_temporaries, render_inputs  # noqa: E402
from .scene import Scene, ensure_paths  # noqa: E402

ensure_paths()

#: header attribute: the study switch the view's inputs were traced under.
INPUTS_ATTRIBUTE = "ptv.inputs"
#: the tracer's study switches this tool accepts (each read by the mapper from the environment).
SWITCHES = ("PTV_EXPECTED_COVERAGE",)


def parse_switch(text: str) -> Dict[str, str]:
    """``NAME=VALUE`` as ``{NAME: VALUE}``; ValueError unless NAME is a known study switch."""
    name, sep, value = text.partition("=")
    if not sep or name not in SWITCHES or not value:
        raise ValueError(f"--switch {text!r}: expected NAME=VALUE with NAME one of "
                         f"{', '.join(SWITCHES)}")
    return {name: value}


def inputs_attribute(path: Path) -> Optional[str]:
    """The ``ptv.inputs`` attribute of a view file, or None (no file, no attribute)."""
    try:
        _, header = exr_io.read_exr(path)
    except Exception:  # noqa: BLE001 -- an unreadable file is traced again
        return None
    value = header.get(INPUTS_ATTRIBUTE)
    return value.decode() if isinstance(value, bytes) else value


def reinput_view(scene: Scene, src: Path, dst: Path, switch: str) -> float:
    """Trace ``src``'s inputs again (the environment holds the switch), keep its radiance
    images, write ``dst`` atomically; returns the inputs' seconds."""
    data = exr_io.read_view(src)
    view = data["view"]
    t0 = time.perf_counter()
    inputs, spp16 = render_inputs(scene, view)
    seconds = time.perf_counter() - t0
    radiance = {"reference": data["reference"], "reference_half": data["reference_half"],
                "spp16": spp16}
    exr_io.write_exr(dst, exr_io.pack_view(inputs, radiance),
                     {exr_io.VIEW_ATTRIBUTE: json.dumps(view), INPUTS_ATTRIBUTE: switch})
    return seconds


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="python Training/ptv_training/reinput.py",
        description="Copy a training-data folder, its inputs traced again under a tracer study "
                    "switch (references kept).",
        epilog="Resumable: views whose file verifies under the same switch are skipped.")
    parser.add_argument("--src", type=Path, required=True,
                        help="a folder written by generate.py (manifest.json + views)")
    parser.add_argument("--out", type=Path, required=True, help="the copy's folder")
    parser.add_argument("--switch", required=True,
                        help=f"NAME=VALUE, NAME one of {', '.join(SWITCHES)}")
    parser.add_argument("--threads", type=int, default=0,
                        help="mapper threads (0 = every core, default)")
    parser.add_argument("--no-progress", action="store_true", help="no tqdm progress bar")
    args = parser.parse_args(argv)
    try:
        args.env = parse_switch(args.switch)
    except ValueError as exc:
        parser.error(str(exc))
    if args.src.resolve() == args.out.resolve():
        parser.error("--out must differ from --src")
    if not (args.src / "manifest.json").is_file():
        parser.error(f"--src {args.src}: no manifest.json")
    return args


def trace_all(args: argparse.Namespace, records: List[Dict[str, Any]]) -> Tuple[int, int]:
    """Trace every view of ``records`` missing from ``args.out`` (or traced under another
    switch) again, updating its record's timings and size; returns (traced, kept)."""
    from tqdm import tqdm

    scene: Optional[Scene] = None
    traced = kept = 0
    for record in tqdm(records, desc="views", unit="view", disable=args.no_progress):
        src, dst = args.src / record["file"], args.out / record["file"]
        view = record["view"]
        size = tuple(view["size"])
        ok, _ = exr_io.verify_view_file(dst, view, size) if dst.is_file() else (False, "")
        if ok and inputs_attribute(dst) == args.switch:
            kept += 1
            continue
        if scene is None or scene.dataset != view["dataset"]:
            scene = None  # one dataset's volume in memory at a time
            scene = Scene(view["dataset"], size, threads=args.threads)
        record["timings"] = {**record.get("timings", {}),
                             "inputs_s": reinput_view(scene, src, dst, args.switch)}
        record["bytes"] = dst.stat().st_size
        traced += 1
    return traced, kept


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    manifest: Dict[str, Any] = json.loads((args.src / "manifest.json").read_text())
    if not manifest.get("complete"):
        print(f"reinput: {args.src} is not complete (generate.py still running or stopped)",
              file=sys.stderr)
        return 1
    args.out.mkdir(parents=True, exist_ok=True)
    remove_stale_temporaries(args.out)
    records: List[Dict[str, Any]] = manifest["views"]
    started = time.perf_counter()
    saved = {name: os.environ.get(name) for name in args.env}
    os.environ.update(args.env)
    try:
        traced, kept = trace_all(args, records)
    finally:  # the caller's environment as it was (tests call main() in their own process)
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
    manifest.update({
        "command": " ".join(sys.argv if argv is None else ["reinput.py", *argv]),
        "inputs_from": str(args.src), "inputs_switch": args.switch,
        "reinput_timing": {"this_run_s": time.perf_counter() - started, "traced": traced,
                           "kept": kept},
        "bytes": sum(r["bytes"] for r in records)})
    write_text(args.out / "manifest.json", json.dumps(manifest, indent=1) + "\n")
    print(f"{len(records)} views in {args.out} ({traced} traced under {args.switch}, "
          f"{kept} kept; {time.perf_counter() - started:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
