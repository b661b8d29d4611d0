"""ParaView's parallel engine with the plugin: ``mpirun -np N pvbatch`` (mpi_render.py) with 1, 2 and
4 ranks, the head CT as "Path Traced Volume", 128x128.

The volume fits under ReplicateVolumeLimit, so every rank reads it whole and the ranks trace each
frame together (vtkPathTracedVolumeMapper::SetController). Checks:

1. N ranks at F frames accumulate the passes of 1 rank with N x SamplesPerFrame at F frames:
   the same samples (rank r traces block f N + r of frame f), averaged in another order, so the
   Radiance agrees to float rounding (<= 1e-5);
2. no seam: the composited screenshot of N ranks equals the 1-rank screenshot (<= 2/255 per
   pixel), with Denoise off and on (rank 0 denoises the same accumulation). (A volume split
   across ranks, ReplicateVolumeLimit 0, is mpi_distributed.py's);
3. PSNR against a 512-spp 1-rank reference: N ranks at the same total samples >= 1 rank - 0.3 dB;
4. a still render with a time budget on 2 ranks ends (the ranks agree when to stop) after
   several frames, its budget stop reported; no rank reports any other error or warning.

Run by ctest (PTV.ParaView.mpi_replicated) with the project venv's Python and the ParaView test
environment; needs ``mpirun`` (openmpi-bin) and an X display (ctest runs under Xvfb).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Dict, List

import numpy as np

import ptvpvtest  # noqa: E402 (this folder)

HERE = Path(__file__).resolve().parent
SIZE = 128
FRAMES = 8


def run(ranks: int, out: Path, *args: str) -> Dict:
    """mpi_render.py on ``ranks`` ranks into ``out``; its info.json."""
    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), "pvbatch",
           "--force-offscreen-rendering", str(HERE / "mpi_render.py"), "--out", str(out),
           "--size", str(SIZE), *args]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    log = done.stdout + done.stderr
    if done.returncode != 0 or not (out / "info.json").exists():
        print(log)
        raise SystemExit(f"FAILED: {' '.join(cmd)} exited with {done.returncode}")
    bad = [line for line in log.splitlines() if "ERR|" in line or "WARN|" in line]
    info = json.loads((out / "info.json").read_text())
    info["log_problems"] = bad
    return info


def read(reader, path: Path, array: str = "") -> np.ndarray:
    """``array`` (default: the active scalars) of the image ``reader`` reads from ``path``, as
    (H, W, C) float64."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    pd = image.GetPointData()
    values = pd.GetArray(array) if array else pd.GetScalars()
    return vtk_to_numpy(values).reshape(h, w, -1).astype(np.float64)


def radiance(path: Path) -> np.ndarray:
    from pathtracedvolume.vtkPTVFilters import vtkPTVEXRPassReader
    return read(vtkPTVEXRPassReader(), path, "Radiance")


def screenshot(path: Path) -> np.ndarray:
    from vtkmodules.vtkIOImage import vtkPNGReader
    return read(vtkPNGReader(), path)[..., :3]


def finish(check: ptvpvtest.Checks, infos: List[Dict]) -> int:
    """The last check (no VTK error or warning in any run's messages or log), PASS or FAIL, and
    the exit code."""
    problems = [m for info in infos for m in info["messages"] + info["log_problems"]]
    check(not problems, f"no VTK error or warning on any rank: {problems[:3]}")
    print("PASS" if not check.failures else f"FAIL: {len(check.failures)} check(s)")
    return 0 if not check.failures else 1


def main() -> int:
    from pathtracedvolume.metrics import psnr

    check = ptvpvtest.Checks()

    tmp = Path(tempfile.mkdtemp(prefix="mpi_", dir=os.environ.get("PTV_TEST_TEMP")))
    reference = run(1, tmp / "reference", "--frames", "32", "--spp-per-frame", "16")
    ref = radiance(tmp / "reference" / "passes.exr")
    infos = [reference]
    for ranks in (2, 4):
        one = run(1, tmp / f"one_{ranks}", "--frames", str(FRAMES), "--spp-per-frame",
                  str(ranks))
        many = run(ranks, tmp / f"ranks_{ranks}", "--frames", str(FRAMES))
        infos += [one, many]
        check(many["sampling_ranks"] == ranks and one["sampling_ranks"] == 1,
              f"{ranks} ranks trace together (NumberOfSamplingRanks {many['sampling_ranks']})")
        a = radiance(tmp / f"one_{ranks}" / "passes.exr")
        b = radiance(tmp / f"ranks_{ranks}" / "passes.exr")
        diff = float(np.abs(a - b).max())
        check(diff <= 1e-5, f"{ranks} ranks x {FRAMES} frames = 1 rank with {ranks} spp/frame: "
              f"max |Radiance diff| {diff:.2e} <= 1e-5")
        shot = float(np.abs(screenshot(tmp / f"one_{ranks}" / "screenshot.png")
                            - screenshot(tmp / f"ranks_{ranks}" / "screenshot.png")).max())
        check(shot <= 2, f"{ranks} ranks: no seam, screenshot = 1 rank's (max diff {shot:.0f}/255)")
        p_one, p_many = psnr(ref, a), psnr(ref, b)
        check(p_many >= p_one - 0.3, f"{ranks} ranks PSNR {p_many:.2f} dB >= 1 rank {p_one:.2f} "
              f"- 0.3 dB (same total spp, against a 512-spp reference)")

    # Denoised: rank 0 denoises the same accumulation.
    one = run(1, tmp / "one_2_denoised", "--frames", str(FRAMES), "--spp-per-frame", "2",
              "--denoise", "1")
    many = run(2, tmp / "ranks_2_denoised", "--frames", str(FRAMES), "--denoise", "1")
    infos += [one, many]
    shot = float(np.abs(screenshot(tmp / "one_2_denoised" / "screenshot.png")
                        - screenshot(tmp / "ranks_2_denoised" / "screenshot.png")).max())
    check(shot <= 2, f"2 ranks denoised: screenshot = 1 rank's (max diff {shot:.0f}/255)")

    # A still render with a time budget: the ranks agree when to stop.
    # Its target (60 dB) is out of reach, so the budget stop is reported: the one warning expected.
    still = run(2, tmp / "still_2", "--frames", "1", "--still-budget", "1.0")
    said = [m for m in still["messages"] + still["log_problems"] if "StillTimeBudget 1 s" in m]
    still["messages"] = [m for m in still["messages"] if m not in said]
    still["log_problems"] = [m for m in still["log_problems"] if m not in said]
    infos.append(still)
    check(still["accumulated_after_screenshot"] > 2,
          f"2-rank still render with a 1 s budget ended after "
          f"{still['accumulated_after_screenshot']} frames")
    check(bool(said), "the budget stop is reported")

    return finish(check, infos)


if __name__ == "__main__":
    sys.exit(main())
