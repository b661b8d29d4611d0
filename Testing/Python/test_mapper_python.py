"""The wrapped mapper from Python: passes arrive as numpy arrays of the viewport's shape, settings
round-trip, and accumulation converges (the spread between two independent seeds' means shrinks
like 1/sqrt(N)). Needs a display (ctest runs under Xvfb) and the built package on PYTHONPATH."""
from __future__ import annotations

import numpy as np
import pytest

import pathtracedvolume.vtkPTVRendering as ptv

from ptv_vtk_messages import observe  # noqa: E402
from ptv_wavelet_scene import get_pass as wavelet_pass, wavelet_scene  # noqa: E402

W, H = 40, 30


def make_scene(seed: int):
    return wavelet_scene((W, H), seed=seed)


def get_pass(mapper, name: str) -> np.ndarray:
    return wavelet_pass(mapper, name, (W, H))


def test_passes_are_numpy_arrays() -> None:
    window, mapper, _ = make_scene(0)
    window.Render()
    names = [mapper.GetPassName(i) for i in range(mapper.GetNumberOfPasses())]
    assert names[:3] == ["Radiance", "Alpha", "Albedo"]
    assert names[-7:] == ["Denoised", "Guides", "BlendWeights", "Converged", "HistoryLength",
                          "DenoisedAlpha", "SampleRatio"]
    for name in names[:-7] + ["HistoryLength", "SampleRatio"]:
        values = get_pass(mapper, name)
        assert values.dtype == np.float32
        assert values.shape in ((W * H,), (W * H, 3)), name
        assert np.isfinite(values).all(), name
    assert get_pass(mapper, "Alpha").max() == 1.0


SCATTER = ("ScatterDepth", "ScatterPosition", "ScatterNormal")


def test_scatter_passes_are_kept_only_when_asked_for() -> None:
    """The Scatter* passes are kept only with the expert option ScatterPasses (default off) or
    a DisplayPass of one: by default GetPass of one fails with an error that names the option and
    GetPasses leaves them out (Normal is there); turning the option on restarts the accumulation
    and keeps them, finite and not all 0; a DisplayPass of ScatterDepth keeps it without the
    option, the same frame bit for bit."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    window, mapper, _ = wavelet_scene((W, H), seed=0, scatter_passes=False)
    assert not mapper.GetExpertOptions().GetScatterPasses()
    window.Render()
    messages = observe(mapper)
    assert not mapper.GetPass("ScatterNormal", vtkImageData())
    assert len(messages) == 1 and messages[0].startswith("ErrorEvent"), messages
    assert "ScatterPasses" in messages[0], messages
    passes = vtkImageData()
    assert mapper.GetPasses(passes)
    assert passes.GetPointData().GetArray("Normal") is not None
    assert all(passes.GetPointData().GetArray(name) is None for name in SCATTER)

    mapper.GetExpertOptions().ScatterPassesOn()
    assert mapper.GetExpertOptions().GetScatterPasses()
    window.Render()
    assert mapper.GetAccumulatedFrames() == 1  # the accumulation restarted
    for name in SCATTER:
        values = get_pass(mapper, name)
        assert np.isfinite(values).all() and np.abs(values).max() > 0, name
    assert mapper.GetPasses(passes)
    assert all(passes.GetPointData().GetArray(name) is not None for name in SCATTER)
    assert len(messages) == 1, messages

    kept_window, kept, _ = wavelet_scene((W, H), seed=0)  # ScatterPasses on from the start
    kept_window.Render()
    shown_window, shown, _ = wavelet_scene((W, H), seed=0, scatter_passes=False)
    shown.SetDisplayPass("ScatterDepth")
    shown_window.Render()
    depth = get_pass(shown, "ScatterDepth")
    assert np.isfinite(depth).all()
    np.testing.assert_array_equal(depth, get_pass(kept, "ScatterDepth"))


def test_settings_round_trip() -> None:
    mapper = ptv.vtkPathTracedVolumeMapper()
    mapper.ConvergeStillRendersOff()  # frame by frame
    assert mapper.GetSamplesPerFrame() == 1
    assert mapper.GetExpertOptions().GetMaximumAccumulatedFrames() == 1024
    mapper.SetSamplesPerFrame(0)  # clamped to the documented range
    assert mapper.GetSamplesPerFrame() == 1
    mapper.SetDisplayPass("Normal")
    assert mapper.GetDisplayPass() == "Normal"
    assert isinstance(mapper.GetCudaStatus(), str) and mapper.GetCudaStatus()


def test_independent_means_converge() -> None:
    """E|mean_a - mean_b|^2 = 2 Var / N, so the RMS gap between two seeds' N-frame means falls
    like N^-1/2: from N=4 to N=64 it must shrink by 4 (accept 2.5..6.4, a wide band for 1200
    pixels of a heavy-tailed estimator)."""
    gaps = {}
    for frames in (4, 64):
        means = []
        for seed in (1, 2):
            window, mapper, _ = make_scene(seed)
            mapper.GetExpertOptions().SetMaximumAccumulatedFrames(frames)
            for _ in range(frames):
                window.Render()
            assert mapper.GetAccumulatedFrames() == frames
            means.append(get_pass(mapper, "Radiance"))
        gaps[frames] = float(np.sqrt(np.mean((means[0] - means[1]) ** 2)))
    ratio = gaps[4] / gaps[64]
    assert 2.5 < ratio < 6.4, gaps


def test_ambient_occlusion_reach() -> None:
    """AmbientOcclusionReach: 1 (the default) is the whole volume, bit for bit; 0 is the
    unoccluded environment (AmbientOcclusion off), bit for bit; in between, environment rays
    see only nearby occluders, so the image lies between the two. The key light is off, so only
    the environment lights the volume; 64 frames of one seed for every setting (the same
    events: only the environment rays' length differs), compared by their mean radiance."""
    def mean_radiance(**settings) -> np.ndarray:
        window, mapper, _ = make_scene(3)
        mapper.SetLightIntensity(0.0)
        for key, value in settings.items():
            target = mapper if hasattr(mapper, f"Set{key}") else mapper.GetExpertOptions()
            getattr(target, f"Set{key}")(value)
        mapper.GetExpertOptions().SetMaximumAccumulatedFrames(64)
        for _ in range(64):
            window.Render()
        return get_pass(mapper, "Radiance")

    mapper = ptv.vtkPathTracedVolumeMapper()
    assert mapper.GetExpertOptions().GetAmbientOcclusionReach() == 1.0
    mapper.GetExpertOptions().SetAmbientOcclusionReach(2.0)  # clamped to the documented range
    assert mapper.GetExpertOptions().GetAmbientOcclusionReach() == 1.0
    full = mean_radiance()
    assert np.array_equal(full, mean_radiance(AmbientOcclusionReach=1.0))
    open_sky = mean_radiance(AmbientOcclusion=False)
    assert np.array_equal(open_sky, mean_radiance(AmbientOcclusionReach=0.0))
    local = mean_radiance(AmbientOcclusionReach=0.1)
    assert full.mean() < local.mean() < open_sky.mean(), (full.mean(), local.mean(),
                                                          open_sky.mean())


TRANSLUCENT = 0.05  # the wavelet's opacity ramp ends here: most rays come out translucent


def frame_means(seeds: range, expected: bool) -> np.ndarray:
    """The image mean of one fresh 1-spp frame's Radiance per seed (ExpectedCoverage as given)."""
    means = []
    for seed in seeds:
        window, mapper, _ = wavelet_scene((W, H), seed=seed, opacity=TRANSLUCENT)
        mapper.GetExpertOptions().SetExpectedCoverage(expected)
        window.Render()
        means.append(float(get_pass(mapper, "Radiance").mean()))
    return np.array(means)


def test_expected_coverage() -> None:
    """ExpectedCoverage (default off): a camera ray's Alpha is its opacity, the Coverage pass
    itself, fractional in the translucent wavelet where the coin flip gives 0 or 1; turning it
    on restarts the accumulation (a mapper with it on from the start gives the same frame bit for
    bit); the
    expectation is kept: over 24 seeds the mean radiance of both modes agrees within 5 standard
    errors of the difference (measured from the seeds' spread), and the expected coverage's
    spread is smaller."""
    window, mapper, _ = wavelet_scene((W, H), seed=3, opacity=TRANSLUCENT)
    assert not mapper.GetExpertOptions().GetExpectedCoverage()
    window.Render()
    assert set(np.unique(get_pass(mapper, "Alpha"))) <= {0.0, 1.0}
    mapper.GetExpertOptions().ExpectedCoverageOn()
    window.Render()
    assert mapper.GetAccumulatedFrames() == 1  # a new estimator: the accumulation restarted
    alpha = get_pass(mapper, "Alpha")
    np.testing.assert_array_equal(alpha, get_pass(mapper, "Coverage"))
    assert ((alpha > 0.01) & (alpha < 0.99)).mean() > 0.25
    window2, mapper2, _ = wavelet_scene((W, H), seed=3, opacity=TRANSLUCENT)
    mapper2.GetExpertOptions().ExpectedCoverageOn()
    window2.Render()
    for name in ("Radiance", "Alpha", "Depth", "Albedo"):
        np.testing.assert_array_equal(get_pass(mapper2, name), get_pass(mapper, name), name)

    flip, expected = frame_means(range(10, 34), False), frame_means(range(10, 34), True)
    error = np.sqrt(flip.var(ddof=1) / flip.size + expected.var(ddof=1) / expected.size)
    assert abs(flip.mean() - expected.mean()) < 5 * error, (flip.mean(), expected.mean(), error)
    assert expected.std() < flip.std()


def test_only_documented_environment_variables() -> None:
    """The product's C++ reads only the environment variables the README documents, and none of
    them changes the image (issue #61): PTV_DATA_DIR and the diagnostic PTV_PORTABLE_KERNELS."""
    import os
    import re
    from pathlib import Path

    root = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
    read = {}
    for folder in ("Rendering", "Filters", "Plugin"):
        for path in (root / folder).rglob("*"):
            if path.suffix not in {".h", ".cxx", ".cu", ".cuh"}:
                continue
            text = path.read_text(errors="replace")
            calls = re.findall(r"getenv\s*\(([^)]*)\)", text)
            for arg in calls:
                name = arg.strip().strip('"')
                assert re.fullmatch(r"PTV_[A-Z_]+", name), f"{path}: getenv({arg}) is not a literal"
                read.setdefault(name, []).append(path.relative_to(root).as_posix())
    assert set(read) == {"PTV_DATA_DIR", "PTV_PORTABLE_KERNELS"}, read
    readme = (root / "README.md").read_text()
    for name in read:
        assert f"`{name}" in readme, f"{name} is not documented in README.md"
