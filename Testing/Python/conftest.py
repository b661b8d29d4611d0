"""Shared pytest setup for the PathTracedVolume Python tests.

Puts ``<repository>/Python`` on ``sys.path`` so that ``pathtracedvolume.*``
imports from the source tree, and provides fixtures for the fetched data.

Tests that need the fetched datasets fail when ``<cache>/data/<name>.vti``
(or the downloaded package) is missing, unless ``PTV_ALLOW_MISSING_DATA=1``
is set, in which case they are skipped.  Fetch the data with
``/usr/bin/python3 scripts/fetch_datasets.py``.

A missing module, dependency, dataset or model is never a skip under ctest
and CI: the test files import what they need at the top (an ImportError
fails the collection), and with ``PTV_SKIP_IS_FAILURE=1`` (set by ctest,
``Testing/CMakeLists.txt``) any skipped test fails the session, except a
documented hardware skip ("no CUDA device"): see ``ptv_no_skips.py``.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path
from types import ModuleType
from typing import Callable

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
PYTHON_DIR = REPO_ROOT / "Python"
SCRIPTS_DIR = REPO_ROOT / "scripts"


def _use_source_package() -> None:
    """Make ``pathtracedvolume.*`` importable from ``<repository>/Python``.

    Without another ``pathtracedvolume`` on the path, ``Python/`` goes first
    on ``sys.path``.  If one is already importable (the build tree on
    PYTHONPATH, as under ctest), it is kept, so that its compiled modules stay
    importable, and the source folder is appended to its ``__path__``.
    """
    if importlib.util.find_spec("pathtracedvolume") is None:
        sys.path.insert(0, str(PYTHON_DIR))
        return
    import pathtracedvolume
    source = str(PYTHON_DIR / "pathtracedvolume")
    if source not in list(pathtracedvolume.__path__):
        pathtracedvolume.__path__.append(source)


_use_source_package()

from pathtracedvolume import datasets as ds  # noqa: E402

# Under ctest a skip fails the session: the hooks of Testing/Python/ptv_no_skips.py.
from ptv_no_skips import (pytest_collectreport, pytest_runtest_logreport,  # noqa: E402,F401
                          pytest_sessionfinish)


def missing_data(message: str) -> None:
    """Fail (or skip with ``PTV_ALLOW_MISSING_DATA=1``) for absent data."""
    message += (" -- run `/usr/bin/python3 scripts/fetch_datasets.py` first "
                "(or set PTV_ALLOW_MISSING_DATA=1 to skip)")
    if os.environ.get("PTV_ALLOW_MISSING_DATA") == "1":
        pytest.skip(message)
    pytest.fail(message, pytrace=False)


@pytest.fixture(scope="session")
def manifest() -> dict:
    """The parsed ``Data/datasets.json``."""
    return ds.load_manifest()


@pytest.fixture(scope="session")
def real_cache() -> Path:
    """The real cache folder (``$PTV_CACHE_DIR`` or ``<repo>/.cache``)."""
    return ds.cache_dir()


@pytest.fixture
def volume_path(real_cache: Path) -> Callable[[str], Path]:
    """Return a function giving the fetched ``.vti`` of a dataset."""
    def get(name: str) -> Path:
        path = ds.vti_path(name, real_cache)
        if not path.is_file():
            missing_data(f"dataset {name!r} not fetched ({path} missing)")
        return path
    return get


@pytest.fixture
def package_path(real_cache: Path,
                 manifest: dict) -> Callable[[str], Path]:
    """Return a function giving the downloaded package file of a dataset."""
    def get(name: str) -> Path:
        source = manifest["datasets"][name]["source"]
        path = ds.downloads_dir(real_cache) / source["file"]
        if not path.is_file():
            missing_data(f"package of {name!r} not downloaded ({path} "
                         "missing)")
        return path
    return get


@pytest.fixture(scope="session")
def fetch_module() -> ModuleType:
    """``scripts/fetch_datasets.py`` imported as a module."""
    path = SCRIPTS_DIR / "fetch_datasets.py"
    spec = importlib.util.spec_from_file_location("fetch_datasets", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
