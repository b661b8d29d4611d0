"""Smoke test of the temporal-reuse benchmark behind docs/temporal.md on tiny images, so the
script cannot rot and the history fade keeps its two measured properties.

* ``temporal_reuse.py`` on a small run (64², 12-view orbits, 4-view stress paths,
  MaximumHistory 4): exits 0 and writes every stress case. Two checks
  of the fade (1 - turn / 8°, the turn being the rotation between the two views): the fast
  orbit (8° per frame, the fade's end) keeps no history on any frame (HistoryLength 1 exactly:
  float camera matrices once left it 1.0001), and the roll (4° per frame, which leaves the
  central ray where it was) caps the history at 4 x 0.5 frames, so from its third frame on a
  pixel holds at most 1 + 2 = 3 (1, 2, 3, 3; with the central ray's turn: 1, 2, 3, 4).

No quality thresholds: tiny images and few frames. Needs a display (ctest runs under Xvfb) and
the built package on PYTHONPATH.
"""
from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

import pathtracedvolume.vtkPTVRendering  # noqa: F401
import pyoidn  # noqa: F401
from ptv_script_run import run_script

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "Testing" / "Benchmarks"


def run(script: str, args: list, out: Path) -> None:
    shutil.rmtree(out, ignore_errors=True)
    run_script(BENCH / script, [*args, "--out", str(out)])


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    base = os.environ.get("PTV_TEST_TEMP")
    return (Path(base) if base else tmp_path_factory.mktemp("temporal")) / "temporal_bench"


def test_temporal_reuse_quick(work: Path) -> None:
    out = work / "temporal_reuse"
    run("temporal_reuse.py", ["--size", "64", "--frames", "12", "--ref-spp", "4",
                              "--static-frames", "4", "--histories", "4", "--default-history",
                              "4", "--datasets-orbit", "head", "--datasets-static", "head"],
        out)
    data = json.loads((out / "temporal_reuse.json").read_text())
    ours = {r["case"]: r for r in data["rows"] if r["method"] == "ours + reprojection (M=4)"}
    assert set(ours) == {"orbit", "TF change mid-orbit", "fast orbit (8.0°/frame)",
                         "roll (4°/frame)", "pan (2 % of the width per frame)"}
    assert ours["fast orbit (8.0°/frame)"]["history_max"] == [1.0] * len(
        ours["fast orbit (8.0°/frame)"]["history_max"])
    roll = ours["roll (4°/frame)"]["history_max"]
    assert len(roll) == 4 and all(abs(h - e) < 1e-4 for h, e in zip(roll, (1, 2, 3, 3))), roll
    assert "without reuse (TemporalReprojection off)" in (out / "temporal_reuse.md").read_text()
