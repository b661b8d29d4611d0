#!/usr/bin/env python3
"""Render one of the project's datasets to a PNG with the path tracer (the README's main job).

vtkPathTracedVolumeMapper traces --spp frames of 1 sample per pixel and shows their running mean,
denoised by the neural bilateral grid (the shipped GuideNet, or its fixed-guide fallback);
--mapper stock renders the same scene with VTK's vtkFixedPointVolumeRayCastMapper instead, for
comparison. --passes-dir also writes every render pass as a float .vti image.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT / "Python"))  # after PYTHONPATH: a built package wins

from pathtracedvolume.atomic import atomic_path  # noqa: E402
from pathtracedvolume.scene import BACKGROUND, Scene  # noqa: E402
from tqdm import tqdm  # noqa: E402

DATASETS = ("head", "stent", "concrete")


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", choices=DATASETS, default="head",
                        help="dataset from the data cache (default: head)")
    parser.add_argument("--preset", default=None,
                        help="preset name (default: '<Dataset> Smooth'; the paper's: "
                        "'<Dataset> Two-Band (paper)')")
    parser.add_argument("--size", type=int, nargs=2, default=(512, 512), metavar=("W", "H"),
                        help="image size in pixels (default: 512 512)")
    parser.add_argument("--background", type=float, nargs=3, default=BACKGROUND,
                        metavar=("R", "G", "B"),
                        help="background = environment light colour (default: ParaView's)")
    parser.add_argument("--azimuth", type=float, default=0.0, help="camera azimuth in degrees")
    parser.add_argument("--elevation", type=float, default=0.0, help="camera elevation in degrees")
    parser.add_argument("--mapper", choices=("pathtraced", "stock"), default="pathtraced",
                        help="renderer (default: pathtraced)")
    parser.add_argument("--spp", type=int, default=64,
                        help="frames of 1 spp to accumulate (default: 64)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default: 0)")
    parser.add_argument("--no-denoise", action="store_true",
                        help="show the accumulated radiance without denoising")
    parser.add_argument("--output", type=Path, default=ROOT / "out" / "render.png",
                        help="PNG to write (folders are created)")
    parser.add_argument("--passes-dir", type=Path, default=None,
                        help="also write every render pass as <dir>/<Pass>.vti")
    return parser.parse_args(argv)


def render(args: argparse.Namespace) -> float:
    """Render and write the PNG (and passes); returns the render time in seconds."""
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    # pathtracedvolume.scene: the dataset, its preset, and the camera looking at the face.
    preset = args.preset or f"{args.dataset.capitalize()} Smooth"
    scene = Scene.of_dataset(args.dataset, tuple(args.size), preset=preset,
                             azimuth=args.azimuth, elevation=args.elevation,
                             mapper=args.mapper, denoise=not args.no_denoise,
                             background=args.background)
    mapper = scene.mapper
    if args.mapper == "pathtraced":
        mapper.SetSeed(args.seed)
        mapper.GetExpertOptions().SetMaximumAccumulatedFrames(max(1, args.spp))
        if args.passes_dir is not None:
            mapper.GetExpertOptions().ScatterPassesOn()  # every pass is written
    frames = max(1, args.spp) if args.mapper == "pathtraced" else 1
    start = time.perf_counter()
    for _ in tqdm(range(frames), desc="frames", unit="frame", disable=frames < 8):
        scene.render()
    seconds = time.perf_counter() - start

    if args.passes_dir is not None and args.mapper == "pathtraced":
        args.passes_dir.mkdir(parents=True, exist_ok=True)
        for i in range(mapper.GetNumberOfPasses()):
            name = mapper.GetPassName(i)
            image = vtkImageData()
            mapper.GetPass(name, image)
            pass_writer = vtkXMLImageDataWriter()
            target = args.passes_dir / f"{name}.vti"
            tmp_pass = target.with_suffix(".tmp.vti")
            pass_writer.SetFileName(str(tmp_pass))
            pass_writer.SetInputData(image)
            if pass_writer.Write() != 1:
                tmp_pass.unlink(missing_ok=True)
                raise OSError(f"cannot write {tmp_pass} (pass {name})")
            tmp_pass.replace(target)

    with atomic_path(args.output, suffix=".tmp.png") as tmp:
        writer = vtkPNGWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(scene.screenshot())
        writer.Write()
        if writer.GetErrorCode() != 0 or tmp.stat().st_size == 0:  # Write returns nothing
            raise OSError(f"cannot write {tmp} (VTK error code {writer.GetErrorCode()})")
    args.denoiser_status = (mapper.GetDenoiserStatus()
                            if args.mapper == "pathtraced" and not args.no_denoise else "")
    return seconds


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    seconds = render(args)
    what = (f"path traced, {args.spp} spp" if args.mapper == "pathtraced"
            else "stock CPU ray caster")
    if args.denoiser_status:
        what += f", denoised ({args.denoiser_status})"
    print(f"wrote {args.output} ({args.size[0]}x{args.size[1]}, {args.dataset}, {what}, "
          f"{seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
