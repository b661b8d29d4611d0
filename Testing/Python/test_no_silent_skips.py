"""A broken build must fail its tests, never pass them by skipping (issue: honest tests).

Each case runs pytest in a subprocess the way ctest does and checks its exit status:
* a real test file with the build's compiled package hidden from ``PYTHONPATH`` fails;
* under ``PTV_SKIP_IS_FAILURE=1`` a skip for a missing dependency or dataset fails, a
  documented hardware skip ("no CUDA device") passes, and without the variable a skip passes.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


def _pytest(args: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args],
                          env=env, cwd=cwd, capture_output=True, text=True, timeout=600)


def _env(**changes: str) -> dict[str, str]:
    env = dict(os.environ)
    env.update(changes)
    return env


def test_hidden_compiled_package_fails() -> None:
    """test_mapper_python.py without ``<build>/python``: import error, non-zero exit."""
    build_python = os.environ.get("PYTHONPATH", "")
    assert build_python, "ctest sets PYTHONPATH to the build's python folder"
    import pathtracedvolume.vtkPTVRendering  # noqa: F401  (the build itself is fine)
    result = _pytest([str(HERE / "test_mapper_python.py")],
                     _env(PYTHONPATH="", PTV_SKIP_IS_FAILURE="1"), HERE)
    output = result.stdout + result.stderr
    assert result.returncode not in (0, 5), output
    assert "vtkPTVRendering" in output, output
    assert " passed" not in output.splitlines()[-1], output


SKIPPING_TESTS = '''
import pytest

def test_runs():
    assert True

def test_missing_dependency():
    pytest.skip("{reason}")
'''


@pytest.mark.parametrize("reason,strict,expect_ok", [
    ("dataset 'head' not fetched", "1", False),
    ("could not import 'onnxruntime'", "1", False),
    ("no CUDA device (CUDA driver not found)", "1", True),
    ("dataset 'head' not fetched", "0", True),
])
def test_skip_is_a_failure_under_ctest(tmp_path: Path, reason: str, strict: str,
                                       expect_ok: bool) -> None:
    (tmp_path / "test_skipping.py").write_text(SKIPPING_TESTS.format(reason=reason))
    env = _env(PTV_SKIP_IS_FAILURE=strict,
               PYTHONPATH=os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))
    result = _pytest(["-p", "ptv_no_skips", "-rs", "test_skipping.py"], env, tmp_path)
    output = result.stdout + result.stderr
    assert "1 passed, 1 skipped" in output, output
    assert (result.returncode == 0) == expect_ok, output
    if not expect_ok:
        assert "a skip is a failure under ctest" in output and reason in output, output


def test_module_level_skip_fails(tmp_path: Path) -> None:
    """``pytest.importorskip`` at the top of a file (what the test files used to do) fails."""
    (tmp_path / "test_module_skip.py").write_text(
        'import pytest\npytest.importorskip("ptv_module_that_does_not_exist")\n'
        "def test_never():\n    assert True\n")
    env = _env(PTV_SKIP_IS_FAILURE="1",
               PYTHONPATH=os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))
    result = _pytest(["-p", "ptv_no_skips", "test_module_skip.py"], env, tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode != 0, output
    assert "ptv_module_that_does_not_exist" in output, output
