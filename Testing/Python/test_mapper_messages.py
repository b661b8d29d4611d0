"""What the mapper says when a script gets something wrong (issue #59): each problem is reported
once, names the offending value and says what happens instead.

* Out-of-range values of the range-checked properties are clamped with a warning that names the
  value and what was set (SamplesPerFrame 0 / 100000, StillQuality NaN, ...).
* An unknown DisplayPass is reported once, however many renders follow, and the default image
  (Converged with Denoise on) is shown instead of Radiance (the old fallback).
* After a render that traced nothing, GetPasses says so instead of "before the first render".
Needs a display (ctest runs under Xvfb) and the built package on PYTHONPATH.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from pathtracedvolume import vtkPathTracedVolumeMapper
from ptv_vtk_messages import observe
from ptv_wavelet_scene import read_window, wavelet_scene


@pytest.mark.parametrize("setter, value, expected", [
    ("SamplesPerFrame", 0, 1), ("SamplesPerFrame", -3, 1), ("SamplesPerFrame", 100000, 4096),
    ("StillQuality", 5.0, 10.0), ("MaximumStillFrames", 0, 1), ("EdgeSamples", 100, 64),
    ("LightIntensity", -1.0, 0.0), ("AmbientOcclusionReach", 2.0, 1.0),
    ("DenoiserNumberOfLevels", 7, 3), ("NumberOfThreads", -1, 0), ("Backend", 9, 2)])
def test_clamped_values_are_reported_once(setter: str, value, expected) -> None:
    mapper = vtkPathTracedVolumeMapper()
    if not hasattr(mapper, f"Set{setter}"):  # an expert option (vtkPTVExpertOptions)
        mapper = mapper.GetExpertOptions()
    messages = observe(mapper)
    getattr(mapper, f"Set{setter}")(value)
    assert getattr(mapper, f"Get{setter}")() == expected
    assert len(messages) == 1, messages
    assert messages[0].startswith("WarningEvent") and f"({value:g})" in messages[0], messages
    assert f"set to {expected:g}" in messages[0], messages
    getattr(mapper, f"Set{setter}")(expected)  # in range: nothing said
    assert len(messages) == 1, messages


def test_nan_keeps_the_current_value() -> None:
    mapper = vtkPathTracedVolumeMapper()
    messages = observe(mapper)
    mapper.SetStillQuality(math.nan)
    assert mapper.GetStillQuality() == 40.0
    assert len(messages) == 1 and "nan" in messages[0], messages


def test_unknown_display_pass_is_reported_once_and_shows_the_default() -> None:
    window, mapper, keep = wavelet_scene((48, 48), denoise=True)
    # later renders trace nothing: the same passes
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(4)
    messages = observe(mapper)
    shown = {}
    for name in ("", "Radiance", "NoSuchPass"):
        mapper.SetDisplayPass(name)
        for _ in range(5):
            window.Render()
        shown[name] = read_window(window)
    errors = [m for m in messages if "NoSuchPass" in m]
    assert len(errors) == 1, messages
    assert "default image" in errors[0], errors
    assert np.array_equal(shown["NoSuchPass"], shown[""])
    assert not np.array_equal(shown["NoSuchPass"], shown["Radiance"])  # the old fallback
    del keep


def test_passes_after_a_failed_render_say_the_render_failed() -> None:
    from vtkmodules.vtkCommonDataModel import vtkImageData

    window, mapper, keep = wavelet_scene((32, 32))
    empty = vtkImageData()  # no scalars: the render fails
    empty.SetDimensions(4, 4, 4)
    mapper.SetInputData(empty)
    messages = observe(mapper)
    window.Render()
    assert any(m.startswith("ErrorEvent") for m in messages), messages
    before = len(messages)
    out = vtkImageData()
    assert not mapper.GetPasses(out)
    said = messages[before:]
    assert len(said) == 1 and "the last render traced no frame" in said[0], said
    del keep
