"""Smoke test of the evaluation report: ``Testing/Benchmarks/evaluate_report.py --quick`` runs end
to end on tiny images (every section: Table 1, training tables, temporal stability, stress suite,
timing) and writes a well-formed report, so the script cannot rot.

Checks: exit status 0 without VTK errors/warnings; report.md has every section and every image
it links exists; every CSV parses with a header and rows of the same width; results.json loads;
Table 1 has every method for every dataset with finite PSNR; every stress case ran and each
output image is finite. No timing or quality thresholds (tiny images: only correctness).
``--render-only`` rewrites report.md, every chart, CSV and results.json byte for byte from
results.json alone, without a display and without importing VTK; given a results.json of the
older layout it stops with a message naming the missing keys.
Needs a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Dict

import pytest

import pathtracedvolume.vtkPTVRendering  # noqa: F401
import pyoidn  # noqa: F401
from ptv_script_run import run_script

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "Testing" / "Benchmarks" / "evaluate_report.py"
METHODS = ("1 spp", "2 spp", "4 spp", "8 spp", "ours every level", "ours", "OIDN fast",
           "OIDN balanced")


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    base = os.environ.get("PTV_TEST_TEMP")
    out = (Path(base) if base else tmp_path_factory.mktemp("report")) / "evaluate_report_quick"
    shutil.rmtree(out, ignore_errors=True)
    run_script(SCRIPT, ["--quick", "--no-cache", "--out", str(out)])
    return out


def test_help() -> None:
    run = subprocess.run([sys.executable, str(SCRIPT), "--help"], capture_output=True, text=True,
                         timeout=120, cwd=ROOT)
    assert run.returncode == 0
    for option in ("--size", "--views", "--ref-spp", "--out", "--quick", "--render-only"):
        assert option in run.stdout


def test_report_markdown(report: Path) -> None:
    text = (report / "report.md").read_text()
    for heading in ("# PathTracedVolume evaluation report", "## 1. Paper Table 1",
                    "## 2. PSNR against time", "## 3. Paper Tables 2, 3, 4",
                    "## 4. Temporal stability", "## 5. Stress suite",
                    "## 6. Where the time goes", "evaluate_report.py --quick"):
        assert heading in text
    assert "median of 1 repeats" in text
    links = re.findall(r"\]\(([^)]+)\)", text)
    assert any(link.endswith(".png") for link in links)
    for link in links:
        assert (report / link).is_file(), link


def test_csv_and_json(report: Path) -> None:
    files = sorted(report.glob("*.csv"))
    assert {f.name for f in files} >= {"table1.csv", "speedup.csv", "stress.csv",
                                       "temporal_static.csv", "temporal_orbit.csv",
                                       "timing_image_size.csv", "timing_threads.csv"}
    for path in files:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        assert len(rows) >= 2, path
        assert all(len(r) == len(rows[0]) for r in rows), path
    results = json.loads((report / "results.json").read_text())
    assert results["machine"]["cores"]


def test_table1_complete(report: Path) -> None:
    with open(report / "table1.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for dataset in ("head", "stent", "concrete"):
        got = {r["method"]: r for r in rows if r["dataset"] == dataset}
        assert set(METHODS) <= set(got), (dataset, sorted(got))
        for r in got.values():
            assert math.isfinite(float(r["psnr"])) and float(r["frame_ms"]) >= 0


def test_stress_outputs_finite(report: Path) -> None:
    with open(report / "stress.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    cases = {r["case"] for r in rows}
    assert {"translucent", "fireflies", "8×8", "1000×7", "mostly empty",
            "unseen volume"} <= cases
    for r in rows:
        for key in ("noisy finite", "ours finite", "OIDN fast finite"):
            assert r[key] == "True", (r["case"], key)


# --render-only: run the script's main() in a fresh interpreter without a display and report
# whether VTK (or the compiled package) was imported.
RENDER_ONLY = """
import runpy, sys
sys.argv = [sys.argv[1], "--render-only", "--out", sys.argv[2]]
try:
    runpy.run_path(sys.argv[0], run_name="__main__")
except SystemExit as exc:
    code = exc.code
else:
    code = 0
loaded = sorted(m for m in sys.modules
                if m.startswith("vtkmodules") or m.startswith("pathtracedvolume.vtk"))
print("VTK modules imported:", loaded, file=sys.stderr)
sys.exit(code)
"""


def render_only(out: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    return subprocess.run([sys.executable, "-c", RENDER_ONLY, str(SCRIPT), str(out)],
                          capture_output=True, text=True, timeout=300, cwd=ROOT, env=env)


def files_of(folder: Path) -> Dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


@pytest.fixture
def copy_of(report: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the quick report with only results.json and the galleries."""
    base = os.environ.get("PTV_TEST_TEMP")
    out = (Path(base) if base else tmp_path_factory.mktemp("report")) / "evaluate_report_render"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    shutil.copy2(report / "results.json", out / "results.json")
    shutil.copytree(report / "gallery", out / "gallery")
    return out


def test_render_only_reproduces_the_report(report: Path, copy_of: Path) -> None:
    """Every file of the measuring run (report.md, charts, CSVs, timing_scaling.json,
    results.json) comes back byte for byte: the header's date, duration, command and cache
    counts are stored in results.json, so no line differs."""
    run = render_only(copy_of)
    log = (run.stdout + run.stderr)[-4000:]
    assert run.returncode == 0, log
    assert "Traceback" not in log, log
    assert "VTK modules imported: []" in run.stderr, log
    want, got = files_of(report), files_of(copy_of)
    assert sorted(got) == sorted(want)
    assert [name for name in want if got[name] != want[name]] == []


def test_render_only_refuses_an_old_results_json(report: Path, copy_of: Path) -> None:
    """A results.json of the older layout (no per-view rows, chart rows, orbit series, training
    texts, temporal-reuse input, run facts) stops with the missing keys named, writes nothing."""
    results = json.loads((report / "results.json").read_text())
    for key in ("table1_per_view", "psnr_time", "training_tables", "run"):
        del results[key]
    del results["temporal"]["orbit_tpsnr"]
    (copy_of / "results.json").write_text(json.dumps(results))
    run = render_only(copy_of)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "Traceback" not in run.stderr, run.stderr
    for key in ("table1_per_view", "psnr_time", "training_tables", "run.generated_utc",
                "temporal.orbit_tpsnr"):
        assert key in run.stderr, run.stderr
    assert not (copy_of / "report.md").exists()


def test_a_trace_leaves_the_scene_mapper_settings() -> None:
    """``Scenes.trace`` sets EdgeSamples for its own frames only: the quality-against-samples
    section denoises through the same scene's mapper and must see the mapper's defaults (a
    trace once left EdgeSamples at 1 there)."""
    sys.path.insert(0, str(ROOT / "Testing" / "Benchmarks"))
    from evaluation.scenes import Scenes

    from pathtracedvolume import vtkPTVExpertOptions

    defaults = vtkPTVExpertOptions()
    scenes = Scenes(threads=1)
    spec = {"volume": "head", "size": [16, 12]}
    options = scenes.scene(spec).mapper.GetExpertOptions()
    for edge_samples in (1, 3):
        data = scenes.trace(spec, 5, 2, {2: ["Radiance"]}, edge_samples=edge_samples)
        assert data["Radiance@2"].shape == (12, 16, 3)
        assert options.GetEdgeSamples() == defaults.GetEdgeSamples()
        assert options.GetComputeEdgeSamples() == defaults.GetComputeEdgeSamples()


def test_the_samples_section_denoises_with_the_model_given(tmp_path: Path) -> None:
    """``--model`` reaches the mapper of the quality-against-samples section (it once measured
    the shipped model whatever the option said), and the scene gets its default back after."""
    sys.path.insert(0, str(ROOT / "Testing" / "Benchmarks"))
    from evaluation.samples import denoising
    from evaluation.scenes import Scenes

    scenes = Scenes(threads=1)
    scene = scenes.scene({"volume": "head", "size": [16, 12]})
    shipped = ROOT / "Data" / "Models" / "guidenet.onnx"
    copy = tmp_path / "other model.onnx"
    copy.write_bytes(shipped.read_bytes())
    for model, named in (("", "guidenet.onnx"), (str(copy), "other model.onnx")):
        with denoising(scene.mapper, model):
            scene.render(seed=1, frames=1)
            assert scene.mapper.GetDenoise()
            assert named in scene.mapper.GetDenoiserStatus(), scene.mapper.GetDenoiserStatus()
        assert not scene.mapper.GetDenoise() and not scene.mapper.GetDenoiserModelFile()
