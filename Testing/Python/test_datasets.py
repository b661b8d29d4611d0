"""Tests for the fetched datasets, the manifest and scripts/fetch_datasets.py.

Tests using the ``volume_path`` / ``package_path`` fixtures need the data
fetched by ``scripts/fetch_datasets.py``; they fail if it is missing unless
``PTV_ALLOW_MISSING_DATA=1`` (then they skip).  Nothing here modifies the
real cache: corruption and conversion tests work on copies in a temporary
cache.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pathtracedvolume import datasets as ds

from conftest import REPO_ROOT, SCRIPTS_DIR

FETCH_SCRIPT = SCRIPTS_DIR / "fetch_datasets.py"

# Independent expectations from the task description, cross-checking the
# manifest: VTK dimensions (x, y, z), spacing (x, y, z), dtype, value range.
EXPECTED = {
    "head": ((256, 256, 108), (0.957, 0.957, 1.5), np.int16, (-1024, 2986)),
    "stent": ((128, 128, 256), (1.0, 1.0, 1.0), np.int16, (0, 2000)),
    "concrete": ((100, 100, 100), (1.0, 1.0, 1.0), np.uint16, None),
    "mri": ((181, 217, 181), (1.0, 1.0, 1.0), np.uint8, (0, 254)),
    "snow": ((100, 100, 100), (1.0, 1.0, 1.0), np.uint16, None),
    "neutron": ((100, 100, 100), (1.0, 1.0, 1.0), np.uint16, None),
    "nuclei": ((57, 61, 31), (1.0, 1.0, 1.0), np.uint16, None),
}


def run_fetch(*args: str, env: dict | None = None
              ) -> subprocess.CompletedProcess:
    """Run the fetch script with this interpreter."""
    full_env = dict(os.environ)
    full_env.pop("PTV_CACHE_DIR", None)
    full_env.update(env or {})
    return subprocess.run([sys.executable, str(FETCH_SCRIPT), *args],
                          cwd=REPO_ROOT, env=full_env, text=True,
                          capture_output=True, timeout=300, check=False)


def read_with_vtk(path: Path) -> tuple[np.ndarray, tuple, tuple, tuple]:
    """Read a .vti with vtkXMLImageDataReader (independent of datasets.py)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader

    reader = vtkXMLImageDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    scalars = image.GetPointData().GetScalars()
    assert scalars is not None and scalars.GetName() == "ImageScalars"
    dims = image.GetDimensions()
    array = vtk_to_numpy(scalars).reshape(dims[::-1])
    return array, dims, image.GetSpacing(), image.GetOrigin()


# --------------------------------------------------------------------------
# Manifest and helpers (no data needed)
# --------------------------------------------------------------------------

def test_manifest_lists_the_datasets(manifest: dict) -> None:
    assert list(manifest["datasets"]) == list(EXPECTED)
    for name, entry in manifest["datasets"].items():
        dims, _, dtype, _ = EXPECTED[name]
        volume = entry["volume"]
        assert tuple(volume["dimensions_xyz"]) == dims
        assert tuple(reversed(volume["shape_zyx"])) == dims
        assert np.dtype(volume["dtype"]) == np.dtype(dtype)
        assert len(entry["source"]["sha256"]) == 64
        assert len(volume["raw_sha256"]) == 64
        assert entry["license"] and entry["orientation"]


def test_manifest_pins_the_given_packages(manifest: dict) -> None:
    sources = {name: (e["source"]["registry"], e["source"]["package"],
                      e["source"]["version"])
               for name, e in manifest["datasets"].items()}
    assert sources == {
        "head": ("debian", "invesalius-examples", "3.1.99998-4"),
        "stent": ("debian", "python3-imageio", "2.4.1-5"),
        "concrete": ("pypi", "spam", "0.9.1"),
        "mri": ("debian", "mricron-data", "1.2.20211006+dfsg-4"),
        "snow": ("pypi", "spam", "0.9.1"),
        "neutron": ("pypi", "spam", "0.9.1"),
        "nuclei": ("pypi", "stardist", "0.9.2"),
    }
    head = manifest["datasets"]["head"]["format_options"]
    assert head["matrix_md5"] == "66ab67efe8d69b70e276eb2202d20d34"


def test_cache_dir_honours_environment(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PTV_CACHE_DIR", str(tmp_path))
    assert ds.cache_dir() == tmp_path.resolve()
    monkeypatch.delenv("PTV_CACHE_DIR")
    assert ds.cache_dir() == REPO_ROOT / ".cache"


def test_dataset_path_missing_points_to_fetch_script(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PTV_CACHE_DIR", str(tmp_path))
    with pytest.raises(FileNotFoundError, match="scripts/fetch_datasets.py"):
        ds.dataset_path("head")


def test_unknown_dataset_name() -> None:
    with pytest.raises(KeyError, match="available: head, stent, concrete"):
        ds.dataset_path("nonexistent")


def test_raw_sha256_is_little_endian_c_order() -> None:
    array = np.arange(6, dtype=">u2").reshape(2, 3)
    expected = hashlib.sha256(np.arange(6, dtype="<u2").tobytes()).hexdigest()
    assert ds.raw_sha256(array) == expected
    assert ds.raw_sha256(np.asfortranarray(array)) == expected


def test_script_help() -> None:
    result = run_fetch("--help")
    assert result.returncode == 0
    assert "--cache" in result.stdout and "PTV_CACHE_DIR" in result.stdout


def test_script_rejects_unknown_name(tmp_path: Path) -> None:
    result = run_fetch("--cache", str(tmp_path), "nonexistent")
    assert result.returncode == 2
    assert "unknown dataset" in result.stderr
    assert not any(tmp_path.iterdir())


# --------------------------------------------------------------------------
# The fetched volumes
# --------------------------------------------------------------------------

@pytest.mark.parametrize("name", list(EXPECTED))
def test_vti_reads_back_as_expected(name: str, manifest: dict,
                                    volume_path) -> None:
    array, dims, spacing, origin = read_with_vtk(volume_path(name))
    exp_dims, exp_spacing, exp_dtype, exp_range = EXPECTED[name]
    volume = manifest["datasets"][name]["volume"]
    assert dims == exp_dims
    assert spacing == pytest.approx(exp_spacing, abs=1e-3)
    assert spacing == pytest.approx(volume["spacing_xyz"], rel=1e-9)
    assert origin == pytest.approx(volume["origin_xyz"])
    assert array.dtype == np.dtype(exp_dtype)
    value_range = (int(array.min()), int(array.max()))
    assert value_range == tuple(volume["value_range"])
    if exp_range is not None:
        assert value_range == exp_range
    digest = hashlib.sha256(
        np.ascontiguousarray(array).astype(array.dtype.newbyteorder("<"))
        .tobytes()).hexdigest()
    assert digest == volume["raw_sha256"]


@pytest.mark.parametrize("name", list(EXPECTED))
def test_vti_is_appended_raw_zlib(name: str, volume_path) -> None:
    with open(volume_path(name), "rb") as stream:
        header = stream.read(2048).decode("latin-1")
    assert 'compressor="vtkZLibDataCompressor"' in header
    assert 'format="appended"' in header
    assert '<AppendedData encoding="raw">' in header
    assert 'Name="ImageScalars"' in header


@pytest.mark.parametrize("name", list(EXPECTED))
def test_verify_volume_helper(name: str, volume_path) -> None:
    volume_path(name)
    info = ds.verify_volume(name)
    assert info.array_name == ds.ARRAY_NAME


@pytest.mark.parametrize("name", list(EXPECTED))
def test_downloads_match_manifest(name: str, manifest: dict,
                                  package_path) -> None:
    path = package_path(name)
    source = manifest["datasets"][name]["source"]
    assert ds.sha256_file(path) == source["sha256"]


def test_head_is_upright_lps(volume_path) -> None:
    """Superior is +z, anterior is -y (face at low y), as documented."""
    array, _, _, _ = read_with_vtk(volume_path("head"))
    body = (array > -300).sum(axis=(1, 2))
    # The skull narrows towards the vertex at high z.
    assert body[-8:].mean() < 0.5 * body[:8].mean()
    # Teeth (enamel > 1500 HU) in the lowest slices sit in the anterior half.
    teeth_y = np.nonzero(array[:10] > 1500)[1]
    assert teeth_y.size > 100
    assert teeth_y.mean() < array.shape[1] / 2


def test_rerun_is_idempotent(volume_path, real_cache: Path) -> None:
    paths = [volume_path(name) for name in EXPECTED]
    before = [p.stat().st_mtime_ns for p in paths]
    result = run_fetch("--cache", str(real_cache))
    assert result.returncode == 0, result.stderr
    assert result.stderr.count("up to date") == len(paths)
    assert [p.stat().st_mtime_ns for p in paths] == before


def test_check_mode(volume_path, package_path, real_cache: Path) -> None:
    for name in EXPECTED:
        volume_path(name)
        package_path(name)
    result = run_fetch("--check", "--cache", str(real_cache))
    assert result.returncode == 0, result.stderr


# --------------------------------------------------------------------------
# Working on copies in a temporary cache
# --------------------------------------------------------------------------

def test_corrupted_download_is_detected(tmp_path: Path, manifest: dict,
                                        package_path) -> None:
    source = manifest["datasets"]["stent"]["source"]
    real = package_path("stent")
    real_digest = ds.sha256_file(real)
    copy = tmp_path / "downloads" / source["file"]
    copy.parent.mkdir()
    shutil.copyfile(real, copy)
    with open(copy, "r+b") as stream:
        stream.seek(1000)
        byte = stream.read(1)
        stream.seek(1000)
        stream.write(bytes([byte[0] ^ 0xFF]))
    corrupt_digest = ds.sha256_file(copy)

    result = run_fetch("--cache", str(tmp_path), "stent")

    assert result.returncode == 1
    assert str(copy) in result.stderr
    assert source["sha256"] in result.stderr
    assert corrupt_digest in result.stderr
    assert "mismatch" in result.stderr
    # Nothing deleted, nothing converted, the real cache untouched.
    assert copy.is_file() and ds.sha256_file(copy) == corrupt_digest
    assert sorted(p.name for p in (tmp_path / "downloads").iterdir()) == \
        [source["file"]]
    assert not (tmp_path / "data" / "stent.vti").exists()
    assert ds.sha256_file(real) == real_digest


def test_corrupted_download_raises_checksum_error(tmp_path: Path,
                                                  manifest: dict,
                                                  fetch_module,
                                                  package_path) -> None:
    entry = manifest["datasets"]["concrete"]
    copy = tmp_path / "downloads" / entry["source"]["file"]
    copy.parent.mkdir()
    data = bytearray(package_path("concrete").read_bytes())
    data[-100] ^= 0x01
    copy.write_bytes(bytes(data))
    with pytest.raises(ds.ChecksumError) as info:
        fetch_module.fetch_package("concrete", entry, tmp_path)
    assert info.value.expected == entry["source"]["sha256"]
    assert info.value.actual == ds.sha256_file(copy)
    assert info.value.path == copy


def test_conversion_from_cached_package(tmp_path: Path, package_path,
                                        volume_path) -> None:
    """Convert from a copied package (no network) and compare voxels."""
    downloads = tmp_path / "downloads"
    downloads.mkdir()
    package = package_path("stent")
    shutil.copyfile(package, downloads / package.name)
    result = run_fetch("--cache", str(tmp_path), "stent")
    assert result.returncode == 0, result.stderr
    produced = tmp_path / "data" / "stent.vti"
    assert read_with_vtk(produced)[0].tobytes() == \
        read_with_vtk(volume_path("stent"))[0].tobytes()
    # Only the package and the volume are left: no temporary files.
    left = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")
                  if p.is_file())
    assert left == ["data/stent.vti", f"downloads/{package.name}"]


def test_failed_write_leaves_no_partial_file(tmp_path: Path, manifest: dict,
                                             fetch_module,
                                             monkeypatch: pytest.MonkeyPatch
                                             ) -> None:
    entry = manifest["datasets"]["stent"]
    array = np.zeros(entry["volume"]["shape_zyx"], dtype=np.int16)

    def broken_writer(array, spacing, origin, path):
        Path(path).write_bytes(b"<VTKFile partial")
        raise fetch_module.FetchError("simulated failure")

    monkeypatch.setattr(fetch_module, "write_vti", broken_writer)
    with pytest.raises(fetch_module.FetchError):
        fetch_module.install_vti("stent", array, entry, manifest, tmp_path)
    assert list((tmp_path / "data").iterdir()) == []


def test_wrong_voxels_are_rejected_before_writing(tmp_path: Path,
                                                  manifest: dict,
                                                  fetch_module) -> None:
    entry = manifest["datasets"]["stent"]
    array = np.zeros(entry["volume"]["shape_zyx"], dtype=np.int16)
    array[0, 0, 0] = 2000
    with pytest.raises(ds.VolumeMismatchError, match="raw sha256"):
        fetch_module.convert_array("stent", entry, array, None)


def test_tiff_readers_agree(tmp_path: Path, manifest: dict, fetch_module,
                            package_path) -> None:
    """tifffile, PIL and vtkTIFFReader give the same concrete voxels."""
    entry = manifest["datasets"]["concrete"]
    member = fetch_module.extract_member("concrete", entry,
                                         package_path("concrete"), tmp_path)
    for backend in fetch_module.TIFF_BACKENDS:
        # Every backend is installed by scripts/setup.sh: one missing is a failure.
        array, _ = fetch_module.read_tiff_stack("concrete", member, {},
                                                backend=backend)
        converted = fetch_module.convert_array("concrete", entry, array, None)
        assert ds.raw_sha256(converted) == entry["volume"]["raw_sha256"], \
            backend


def test_fresh_download_with_wrong_hash_is_rejected(
        tmp_path: Path, manifest: dict, fetch_module,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A registry file that differs from the pin is kept aside, not used."""
    entry = manifest["datasets"]["stent"]
    file_name = entry["source"]["file"]

    def fake_download(source, into: Path) -> None:
        (into / file_name).write_bytes(b"not the pinned package")

    monkeypatch.setitem(fetch_module.DOWNLOADERS, "debian", fake_download)
    with pytest.raises(ds.ChecksumError) as info:
        fetch_module.fetch_package("stent", entry, tmp_path)
    downloads = tmp_path / "downloads"
    assert info.value.path == downloads / (file_name + ".rejected")
    assert info.value.expected == entry["source"]["sha256"]
    assert sorted(p.name for p in downloads.iterdir()) == \
        [file_name + ".rejected"]


def test_nifti_reader_rejects_bad_files(tmp_path: Path) -> None:
    """Not NIfTI-1, a 4-D image, and scaled intensities each give a clear FetchError."""
    import gzip
    import struct
    sys.path.insert(0, str(SCRIPTS_DIR))
    import fetch_datasets as fd

    def nifti(dim0: int = 3, slope: float = 1.0, datatype: int = 2) -> bytes:
        header = bytearray(352)
        header[0:4] = struct.pack("<i", 348)
        header[40:56] = struct.pack("<8h", dim0, 2, 3, 4, 1, 1, 1, 1)
        header[70:72] = struct.pack("<h", datatype)
        header[76:108] = struct.pack("<8f", 1, 0.5, 0.5, 2.0, 1, 1, 1, 1)
        header[108:112] = struct.pack("<f", 352.0)
        header[112:120] = struct.pack("<2f", slope, 0.0)
        return bytes(header) + bytes(range(24))

    good = tmp_path / "good.nii.gz"
    good.write_bytes(gzip.compress(nifti()))
    array, spacing = fd.read_nifti_gz("t", good, {})
    assert array.shape == (4, 3, 2) and spacing == (0.5, 0.5, 2.0)
    assert array[1, 0, 1] == 7  # x fastest: (z=1, y=0, x=1) is voxel 1 + 2 * 3 = 7
    for data, message in ((b"\0" * 400, "sizeof_hdr"), (nifti(dim0=4), "4 dimensions"),
                          (nifti(slope=2.0), "scl_slope"), (nifti(datatype=128), "datatype")):
        bad = tmp_path / "bad.nii.gz"
        bad.write_bytes(gzip.compress(data))
        with pytest.raises(fd.FetchError, match=message):
            fd.read_nifti_gz("t", bad, {})
