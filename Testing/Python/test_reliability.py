"""Reliability of the files the project writes and reads (issue #9; docs/reliability.md):

- corrupt, truncated, empty and incomplete ``.exr`` views are rejected with a reason, never crash;
- a failed EXR/JSON write leaves neither a partial file nor a temporary one, and keeps the old file;
- an interrupted ``generate.py`` (killed after its first view) resumes: finished views are kept
  as they are (same inode, same bytes), the rest is rendered, stale temporaries are removed;
- a damaged finished view is detected on the rerun and rendered again.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
if str(ROOT / "Training") not in sys.path:
    sys.path.append(str(ROOT / "Training"))  # appended: the compiled package stays first

import OpenEXR  # noqa: F401
from ptv_training import exr_io  # noqa: E402
from pathtracedvolume.atomic import atomic_path, write_bytes, write_text  # noqa: E402


def _view_channels(w: int = 5, h: int = 4) -> dict:
    rng = np.random.default_rng(7)
    return {n: rng.random((h, w), dtype=np.float32) for n in exr_io.channel_names()}


@pytest.fixture
def good_view(tmp_path: Path) -> Path:
    path = tmp_path / "good.exr"
    exr_io.write_exr(path, _view_channels(), {exr_io.VIEW_ATTRIBUTE: json.dumps({"v": 1})})
    assert exr_io.verify_view_file(path, {"v": 1}, (5, 4)) == (True, "")
    return path


# --- reading bad EXR files ---------------------------------------------------------------------
@pytest.mark.parametrize("cut", [0, 4, 100, 0.5, -1])
def test_truncated_exr_is_rejected(good_view: Path, tmp_path: Path, cut) -> None:
    data = good_view.read_bytes()
    n = int(len(data) * cut) if isinstance(cut, float) else (len(data) + cut if cut < 0 else cut)
    bad = tmp_path / "cut.exr"
    bad.write_bytes(data[:n])
    with pytest.raises(Exception):
        exr_io.read_exr(bad)
    ok, why = exr_io.verify_view_file(bad)
    assert not ok and why.startswith("unreadable"), why


def test_random_bytes_and_damaged_bytes_are_rejected(good_view: Path, tmp_path: Path) -> None:
    rng = np.random.default_rng(3)
    bad = tmp_path / "bad.exr"
    bad.write_bytes(rng.integers(0, 256, 4096, dtype=np.uint8).tobytes())
    ok, why = exr_io.verify_view_file(bad)
    assert not ok and why.startswith("unreadable"), why
    # Damage in the pixel data: EXR stores incompressible blocks raw, without a checksum, so only
    # the ptv.sha256 attribute (exr_io.write_exr) tells; never a crash, never an exception.
    data = bytearray(good_view.read_bytes())
    outcomes = set()
    for i in range(len(data) // 2, len(data), max(1, len(data) // 64)):
        damaged = bytearray(data)
        damaged[i] ^= 0xFF
        bad.write_bytes(bytes(damaged))
        ok, why = exr_io.verify_view_file(bad, {"v": 1}, (5, 4))
        outcomes.add("ok" if ok else why.split(":")[0])
    assert "checksum mismatch (damaged pixel data)" in outcomes, outcomes


def test_incomplete_views_say_why(tmp_path: Path) -> None:
    channels = _view_channels()
    partial = tmp_path / "partial.exr"
    exr_io.write_exr(partial, {k: v for k, v in channels.items() if not k.startswith("spp4.")})
    ok, why = exr_io.verify_view_file(partial)
    assert not ok and why.startswith("missing channels"), why

    nan = tmp_path / "nan.exr"
    channels_nan = dict(channels)
    channels_nan["R"] = channels["R"].copy()
    channels_nan["R"][1, 2] = np.nan
    exr_io.write_exr(nan, channels_nan)
    assert exr_io.verify_view_file(nan) == (False, "non-finite values")

    good = tmp_path / "good.exr"
    exr_io.write_exr(good, channels, {exr_io.VIEW_ATTRIBUTE: json.dumps({"v": 1})})
    assert exr_io.verify_view_file(good, size=(4, 5)) == (False, "wrong size")
    assert exr_io.verify_view_file(good, {"v": 2}) == (False, "view parameters differ")


# --- failed writes leave nothing ---------------------------------------------------------------
def _leftovers(folder: Path) -> list:
    return sorted(p.name for p in folder.iterdir() if ".tmp" in p.name)


def test_failed_exr_write_leaves_no_partial_file(good_view: Path, monkeypatch) -> None:
    import OpenEXR

    folder = good_view.parent
    before = good_view.read_bytes()

    class Exploding(OpenEXR.File):  # writes half a file, then fails (disk full, kill, ...)
        def write(self, path):
            super().write(path)
            data = Path(path).read_bytes()
            Path(path).write_bytes(data[: len(data) // 2])
            raise OSError(28, "No space left on device (simulated)")

    monkeypatch.setattr(OpenEXR, "File", Exploding)
    with pytest.raises(OSError, match="No space left"):
        exr_io.write_exr(good_view, _view_channels())
    assert good_view.read_bytes() == before, "the old file must be untouched"
    assert _leftovers(folder) == []


def test_exr_write_onto_a_folder_or_unwritable_path(tmp_path: Path) -> None:
    folder = tmp_path / "view.exr"
    folder.mkdir()
    with pytest.raises(OSError):
        exr_io.write_exr(folder, _view_channels())
    assert folder.is_dir() and _leftovers(tmp_path) == []
    with pytest.raises(OSError):
        exr_io.write_exr("/proc/ptv-no/view.exr", _view_channels())


def test_failed_manifest_write_leaves_no_temporary(tmp_path: Path) -> None:
    import pathtracedvolume.vtkPTVRendering  # noqa: F401
    from ptv_training import generate

    target = tmp_path / "manifest.json"
    target.write_text('{"old": true}\n')
    with pytest.raises(TypeError):
        generate._write_json(target, {"bad": object()})  # not JSON: fails half-way
    assert json.loads(target.read_text()) == {"old": True}
    assert _leftovers(tmp_path) == []


# --- generate.py: interrupted runs resume ------------------------------------------------------
def _generate_cmd(out: Path) -> list:
    return [sys.executable, str(ROOT / "Training" / "ptv_training" / "generate.py"),
            "--out", str(out), "--datasets", "head", "--views", "3", "--size", "16",
            "--reference-spp", "4", "--threads", "1", "--no-progress"]


def test_interrupted_generate_resumes(tmp_path: Path, volume_path) -> None:
    import pathtracedvolume.vtkPTVRendering  # noqa: F401
    volume_path("head")
    out = tmp_path / "views"
    first = out / "head_000.exr"
    proc = subprocess.Popen(_generate_cmd(out), stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    deadline = time.monotonic() + 300
    while not first.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert first.exists(), proc.communicate()[0].decode(errors="replace")
    proc.send_signal(signal.SIGKILL)  # no cleanup handler runs: the hardest interruption
    proc.wait()
    finished = sorted(p.name for p in out.glob("head_*.exr"))
    assert "head_000.exr" in finished and len(finished) < 3, finished
    for name in finished:  # whatever is under a final name is complete
        assert exr_io.verify_view_file(out / name, size=(16, 16))[0], name
    kept = {name: ((out / name).stat().st_ino, (out / name).read_bytes()) for name in finished}
    # A temporary as a kill in the middle of a write leaves it (whether or not this run did).
    (out / ".head_002.exr.abc123.tmp.exr").write_bytes(b"half a file")

    done = subprocess.run(_generate_cmd(out), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["complete"] and len(manifest["views"]) == 3
    assert manifest["timing"]["rendered"] == 3 - len(finished)
    for name, (inode, data) in kept.items():  # finished views were neither redone nor touched
        assert (out / name).stat().st_ino == inode and (out / name).read_bytes() == data, name
    for record in manifest["views"]:
        ok, why = exr_io.verify_view_file(out / record["file"], record["view"], (16, 16))
        assert ok, (record["file"], why)
    assert _leftovers(out) == []

    # A damaged finished view is detected and rendered again; the others are kept.
    damaged = out / "head_001.exr"
    damaged.write_bytes(damaged.read_bytes()[:200])
    done = subprocess.run(_generate_cmd(out), capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["timing"]["rendered"] == 1 and manifest["timing"]["kept"] == 2
    assert exr_io.verify_view_file(damaged, size=(16, 16))[0]


def test_generate_with_its_own_input_sample_counts(tmp_path: Path, volume_path) -> None:
    import pathtracedvolume.vtkPTVRendering  # noqa: F401
    from ptv_training import data, generate
    volume_path("head")
    out = tmp_path / "counts"
    cmd = _generate_cmd(out)
    cmd[cmd.index("--views") + 1] = "1"
    cmd += ["--val-views", "0"]
    done = subprocess.run(cmd + ["--input-spp", "1,4,16"], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    manifest = json.loads((out / "manifest.json").read_text())
    view = manifest["views"][0]["view"]
    assert view["input_spp"] == [1, 4, 16] and manifest["parameters"]["input_spp"] == [1, 4, 16]
    assert exr_io.verify_view_file(out / "head_000.exr", view, (16, 16)) == (True, "")
    read = exr_io.read_view(out / "head_000.exr")
    assert sorted(read["inputs"]) == [1, 4, 16]
    one, sixteen = read["inputs"][1]["Radiance"], read["inputs"][16]["Radiance"]
    assert one.shape == sixteen.shape == (16, 16, 3) and not np.array_equal(one, sixteen)
    # The 16-spp input and the 16-spp baseline are one accumulation of one seed.
    np.testing.assert_array_equal(sixteen, read["spp16"])
    passes = data.sample_passes(read, out / "head_000.exr", 4)
    assert np.all(passes["HistoryLength"] == 4)  # the history channel sees 1/4
    # Only the counts differ from a default view: the same seeds, camera and transfer function.
    h = generate.dataset_histogram("head")
    default = generate.random_view_parameters("head", 0, 2023, 16, 4, h)
    assert {k: v for k, v in default.items() if k != "input_spp"} == \
        {k: v for k, v in view.items() if k != "input_spp"}
    # A file missing one count's passes is incomplete.
    channels, header = exr_io.read_exr(out / "head_000.exr")
    partial = tmp_path / "partial.exr"
    exr_io.write_exr(partial, {k: v for k, v in channels.items() if not k.startswith("spp16.")},
                     {exr_io.VIEW_ATTRIBUTE: json.dumps(view)})
    ok, why = exr_io.verify_view_file(partial)
    assert not ok and why.startswith("missing channels"), why
    for bad in ("2,4", "1,4,4", "1,x"):
        refused = subprocess.run(cmd + ["--input-spp", bad], capture_output=True, text=True)
        assert refused.returncode == 2 and "--input-spp" in refused.stderr, refused.stderr


def test_atomic_writes_keep_the_old_file_until_the_new_one_is_complete(tmp_path: Path) -> None:
    """pathtracedvolume.atomic, used by every Python writer of the project (views, checkpoints,
    models, cards, benchmark results, report pages and charts, presets)."""
    target = tmp_path / "sub" / "card.json"
    write_text(target, "old\n")
    assert target.read_text() == "old\n"
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's 0600

    class Interrupted(Exception):
        pass

    with pytest.raises(Interrupted):
        with atomic_path(target) as tmp:
            tmp.write_text("half of the new ")
            assert target.read_text() == "old\n"  # nothing visible before the rename
            raise Interrupted()
    assert target.read_text() == "old\n"
    assert sorted(p.name for p in target.parent.iterdir()) == ["card.json"]  # no temporary left
    write_bytes(target, b"new\n")
    assert target.read_bytes() == b"new\n"
    assert sorted(p.name for p in target.parent.iterdir()) == ["card.json"]
    with pytest.raises(OSError):
        write_text(target / "inside-a-file.json", "x")  # its parent is a file, not a folder
