"""study.py's seeds summary: each seed's unseen-volume gaps and their mean, computed from the
per-seed result files, with the verdict against the issue's 0.5 dB."""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

from ptv_training import study  # noqa: E402


def write_seed(results: Path, seed: int, all_: dict, unseen: dict) -> None:
    """A v3-loo result file: the in-domain run and one run per left-out volume."""
    runs = [{"name": "all", "psnr_1spp": dict(all_)}]
    for d, value in unseen.items():
        runs.append({"name": f"no_{d}", "psnr_1spp": {**all_, d: value}})
    stem = study.results_stem("v3-loo", seed)
    (results / f"{stem}.json").write_text(json.dumps({"seed": seed, "results": runs}))


def test_gaps_mean_and_verdict(tmp_path: Path) -> None:
    base = {"a": 30.0, "b": 20.0}
    write_seed(tmp_path, 0, base, {"a": 29.2, "b": 19.9})   # gaps -0.8, -0.1
    write_seed(tmp_path, 1, base, {"a": 29.9, "b": 20.1})   # gaps -0.1, +0.1
    assert study.main(["v3-loo", "--seeds-summary", "0", "1", "--results", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "v3-loo_seeds.json").read_text())
    assert summary["seeds"] == [0, 1]
    assert summary["gaps"]["0"] == pytest.approx({"a": -0.8, "b": -0.1})
    assert summary["mean"] == pytest.approx({"a": -0.45, "b": 0.0})
    text = (tmp_path / "v3-loo_seeds.md").read_text()
    assert "| a | -0.80 | -0.10 | -0.45 | yes |" in text
    assert "2 of 2 unseen volumes are within 0.5 dB" in text
    # A mean beyond the target is a 'no', and the worst volume is named with its seeds' range.
    write_seed(tmp_path, 2, base, {"a": 29.0, "b": 20.0})   # a: -1.0 -> mean of 3 -0.63
    assert study.main(["v3-loo", "--seeds-summary", "0", "1", "2",
                       "--results", str(tmp_path)]) == 0
    text = (tmp_path / "v3-loo_seeds.md").read_text()
    assert "| a | -0.80 | -0.10 | -1.00 | -0.63 | no |" in text
    assert "1 of 2 unseen volumes are within 0.5 dB" in text
    assert "the worst is a (-0.63; its seeds -1.00 to -0.10)" in text


def test_missing_seed_and_wrong_study_are_clear_errors(tmp_path: Path) -> None:
    write_seed(tmp_path, 0, {"a": 30.0}, {"a": 29.5})
    with pytest.raises(SystemExit, match="v3-loo_seed1.json is missing.*--seed 1"):
        study.main(["v3-loo", "--seeds-summary", "0", "1", "--results", str(tmp_path)])
    with pytest.raises(SystemExit, match="needs a leave-one-out study"):
        study.main(["ablation", "--seeds-summary", "0", "--results", str(tmp_path)])
    assert not (tmp_path / "v3-loo_seeds.md").exists()
