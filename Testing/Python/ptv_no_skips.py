"""pytest plugin: under ctest and CI, a skipped test is a failed session.

pytest exits 0 when every test skipped, so a skip on a missing module, dependency, dataset or
model would let ctest print *Passed* for code that never ran.  With ``PTV_SKIP_IS_FAILURE=1``
(set for every Python test by ``Testing/CMakeLists.txt``) this plugin turns the session's exit
status into a failure when any test skipped, and names each one.  The only allowed skip is the
documented hardware one: a reason starting with ``HARDWARE_SKIP_PREFIX`` (no CUDA device).

Loaded by ``conftest.py`` (``pytest_plugins``) and, in ``test_no_silent_skips.py``, with
``-p ptv_no_skips`` on throw-away test files.
"""
from __future__ import annotations

import os

import pytest

HARDWARE_SKIP_PREFIX = "no CUDA device"
_skipped: list[tuple[str, str]] = []


def _reason(report: pytest.TestReport) -> str:
    text = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
    return str(text).removeprefix("Skipped: ")


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    """Remember every skipped test with its reason."""
    if report.skipped:
        _skipped.append((report.nodeid, _reason(report)))


def pytest_collectreport(report: pytest.CollectReport) -> None:
    """A module-level skip (``pytest.skip(..., allow_module_level=True)``) counts too."""
    if report.skipped:
        _skipped.append((report.nodeid, _reason(report)))


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """Under ``PTV_SKIP_IS_FAILURE=1``, any skip other than a hardware one fails the session."""
    if os.environ.get("PTV_SKIP_IS_FAILURE") != "1":
        return
    bad = [(node, why) for node, why in _skipped if not why.startswith(HARDWARE_SKIP_PREFIX)]
    for node, why in bad:
        print(f"\nFAILED (a skip is a failure under ctest): {node}: {why}")
    if bad and session.exitstatus == pytest.ExitCode.OK:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
