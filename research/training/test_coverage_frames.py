"""The expected-coverage study's tools: reinput.py traces a training folder's inputs again
under a tracer study switch and keeps its references; coverage_frames.py traces each view's
denoised frame in both modes.

Needs the built package on PYTHONPATH, a display (ctest runs the Python tests under Xvfb), the
head dataset and the OpenEXR Python package."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

import pathtracedvolume.vtkPTVRendering  # noqa: F401,E402
import OpenEXR  # noqa: F401,E402

VARIABLE = "PTV_EXPECTED_COVERAGE"
SWITCH = f"{VARIABLE}=1"


@pytest.fixture
def source(tmp_path: Path, volume_path) -> Path:
    """Two tiny training views of the head (32², 8-spp references), traced by generate.py."""
    volume_path("head")  # fails (or skips) clearly when the data is not fetched
    from ptv_training import generate

    folder = tmp_path / "src"
    assert generate.main(["--out", str(folder), "--datasets", "head", "--views", "2",
                          "--size", "32", "--reference-spp", "8", "--val-views", "1",
                          "--val-reference-spp", "8", "--no-progress", "--threads", "2"]) == 0
    return folder


def reinput_main(src: Path, out: Path, switch: str) -> dict:
    from ptv_training import reinput

    assert reinput.main(["--src", str(src), "--out", str(out), "--switch", switch,
                         "--no-progress", "--threads", "2"]) == 0
    assert VARIABLE not in os.environ  # the caller's environment is left as it was
    return json.loads((out / "manifest.json").read_text())


def test_reinput_traces_the_inputs_under_the_switch_and_keeps_the_references(
        source: Path, tmp_path: Path) -> None:
    from ptv_training import exr_io, reinput

    os.environ.pop(VARIABLE, None)
    manifest = reinput_main(source, tmp_path / "ec", SWITCH)
    original = json.loads((source / "manifest.json").read_text())
    assert manifest["complete"] and manifest["inputs_switch"] == SWITCH
    assert [r["view"] for r in manifest["views"]] == [r["view"] for r in original["views"]]
    assert manifest["reinput_timing"]["traced"] == 2
    fractional = 0
    for record in manifest["views"]:
        path = tmp_path / "ec" / record["file"]
        ok, why = exr_io.verify_view_file(path, record["view"], (32, 32))
        assert ok, why
        assert reinput.inputs_attribute(path) == SWITCH
        new, old = exr_io.read_view(path), exr_io.read_view(source / record["file"])
        assert new["view"] == old["view"]
        for key in ("reference", "reference_half"):  # kept bit for bit
            np.testing.assert_array_equal(new[key], old[key])
        # The coin flip's 1-spp Alpha is 0 or 1; the expected coverage's is the ray's opacity,
        # the Coverage pass itself.
        alpha_old = old["inputs"][1]["Alpha"]
        assert set(np.unique(alpha_old)) <= {0.0, 1.0}
        np.testing.assert_array_equal(new["inputs"][1]["Alpha"], new["inputs"][1]["Coverage"])
        a = new["inputs"][1]["Alpha"]
        fractional += int(np.count_nonzero((a > 0.01) & (a < 0.99)))
        # Same expectation: the mean opacity over the image agrees within the coin flip's noise
        # (a Bernoulli mean over n pixels: standard deviation at most 0.5 / sqrt(n)).
        assert abs(float(a.mean()) - float(alpha_old.mean())) < 4 * 0.5 / np.sqrt(a.size)
    assert fractional > 0

    # A rerun keeps every view; the flip itself (the switch at 0) gives the source's inputs
    # back bit for bit (the same seeds), and traces every view again in the same folder.
    again = reinput_main(source, tmp_path / "ec", SWITCH)
    assert again["reinput_timing"] == {**again["reinput_timing"], "traced": 0, "kept": 2}
    flip = reinput_main(source, tmp_path / "ec", f"{VARIABLE}=0")
    assert flip["reinput_timing"]["traced"] == 2
    for record in flip["views"]:
        new = exr_io.read_view(tmp_path / "ec" / record["file"])
        old = exr_io.read_view(source / record["file"])
        for spp, passes in old["inputs"].items():
            for name, image in passes.items():
                np.testing.assert_array_equal(new["inputs"][spp][name], image, err_msg=name)
        np.testing.assert_array_equal(new["spp16"], old["spp16"])


def test_reinput_rejects_what_it_cannot_do(source: Path, tmp_path: Path) -> None:
    from ptv_training import reinput

    with pytest.raises(ValueError, match="PTV_EXPECTED_COVERAGE"):
        reinput.parse_switch("PTV_NOT_A_SWITCH=1")
    with pytest.raises(ValueError):
        reinput.parse_switch(VARIABLE)  # no value
    for argv in (["--src", str(source), "--out", str(source), "--switch", SWITCH],
                 ["--src", str(tmp_path), "--out", str(tmp_path / "o"), "--switch", SWITCH]):
        with pytest.raises(SystemExit):
            reinput.parse_args(argv)
    incomplete = tmp_path / "incomplete"
    incomplete.mkdir()
    manifest = json.loads((source / "manifest.json").read_text())
    (incomplete / "manifest.json").write_text(json.dumps({**manifest, "complete": False}))
    assert reinput.main(["--src", str(incomplete), "--out", str(tmp_path / "o"),
                         "--switch", SWITCH]) == 1
    assert not (tmp_path / "o" / "manifest.json").exists()


def test_coverage_frames_traces_both_modes(source: Path) -> None:
    from ptv_training import coverage_frames as cf
    from ptv_training import exr_io

    record = json.loads((source / "manifest.json").read_text())["views"][0]
    view = exr_io.read_view(source / record["file"])
    item = {"group": "validation", "name": "head_000", "meta": view["view"],
            "seed": view["view"]["input_seed"], "reference": view["reference"]}
    model = ROOT / "Data" / "Models" / "guidenet.onnx"
    os.environ[VARIABLE] = "1"  # would make both modes one: refused
    try:
        with pytest.raises(RuntimeError, match=VARIABLE):
            cf.evaluate([item], [model], rounds=1, progress=False)
    finally:
        del os.environ[VARIABLE]
    rows = cf.evaluate([item], [model], rounds=1, progress=False)
    methods = {"trace ms", "noisy 1 spp", "shipped", cf.OIDN, f"{cf.BASELINE_SPP} spp"}
    for mode in cf.MODES:
        got = {r["method"]: r["value"] for r in rows if r["mode"] == mode}
        assert set(got) == methods
        assert all(np.isfinite(v) for v in got.values()) and got["trace ms"] > 0
    flip = {r["method"]: r["value"] for r in rows if r["mode"] == "flip"}
    expected = {r["method"]: r["value"] for r in rows if r["mode"] == "expected"}
    assert flip["noisy 1 spp"] != expected["noisy 1 spp"]  # the switch reached the tracer
    # The flip's denoised frame is the stored 1-spp frame with the mapper's edge samples:
    # outside the edge pixels it is the stored passes bit for bit (as heldout.edge_frame checks).
    from ptv_training.heldout import trace_frame
    from ptv_training.scene import Scene

    scene = Scene("head", (32, 32))
    mapper = trace_frame(scene, view["view"], view["view"]["input_seed"], 1, cf.EDGE_SAMPLES)
    stored = view["inputs"][1]
    changed = np.zeros((32, 32), bool)
    for name, image in stored.items():
        got = scene.get_pass(name).reshape(image.shape)
        changed |= np.any((got != image).reshape(32, 32, -1), axis=-1)
    assert changed.mean() <= mapper.GetLastEdgeFraction() + 1e-9

    lines = cf.table(rows, ["shipped"])
    assert lines[0] == "| PSNR (dB) | validation |"
    shipped = next(line for line in lines if line.startswith("| shipped, expected"))
    assert f"({expected['shipped'] - expected[cf.OIDN]:+.2f})" in shipped
    ratio = next(line for line in lines if line.startswith("| trace time"))
    assert f"{expected['trace ms'] / flip['trace ms']:.2f} ×" in ratio
