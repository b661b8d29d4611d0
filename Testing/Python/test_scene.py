"""pathtracedvolume.scene, the scene set-up shared by the scripts, benchmarks and training: the
camera convention, images to and from NumPy, and a Scene that renders with either mapper."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pathtracedvolume import scene


def analytic_volume():
    """A small synthetic volume (vtkRTAnalyticSource, scalars 37..277) as vtkImageData."""
    from vtkmodules.vtkImagingCore import vtkRTAnalyticSource

    source = vtkRTAnalyticSource()
    source.SetWholeExtent(-12, 12, -12, 12, -12, 12)
    source.Update()
    return source.GetOutput()


def ramp_preset() -> dict:
    return {"Name": "test ramp", "Points": [37.0, 0.0, 0.5, 0.0, 277.0, 0.6, 0.5, 0.0],
            "RGBPoints": [37.0, 0.9, 0.6, 0.3, 277.0, 0.9, 0.9, 0.9]}


def test_place_camera_convention() -> None:
    """From -y with +z up; azimuth turns about +z (90 degrees: from +x), elevation raises the
    eye; the camera fits the props and looks at their centre."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    renderer = vtkRenderer()
    cam = scene.place_camera(renderer)
    eye = np.array(cam.GetPosition()) - np.array(cam.GetFocalPoint())
    assert eye[1] < 0 and abs(eye[0]) < 1e-9 and abs(eye[2]) < 1e-9
    assert np.allclose(cam.GetViewUp(), (0, 0, 1))
    cam = scene.place_camera(renderer, azimuth=90.0)
    eye = np.array(cam.GetPosition()) - np.array(cam.GetFocalPoint())
    assert eye[0] > 0 and abs(eye[1]) < 1e-9
    cam = scene.place_camera(renderer, elevation=30.0)
    eye = np.array(cam.GetPosition()) - np.array(cam.GetFocalPoint())
    assert math.isclose(math.degrees(math.atan2(eye[2], -eye[1])), 30.0, abs_tol=1e-6)
    assert abs(np.dot(cam.GetViewUp(), eye)) < 1e-9  # orthogonalised
    before = np.linalg.norm(eye)
    cam = scene.place_camera(renderer, elevation=30.0, dolly=2.0)
    eye = np.array(cam.GetPosition()) - np.array(cam.GetFocalPoint())
    assert math.isclose(np.linalg.norm(eye), before / 2.0, rel_tol=1e-9)


def test_numpy_to_image_round_trip() -> None:
    """(H, W, C) bottom row first <-> a W x H x 1 image with one named array (1 or 3 comps)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    rng = np.random.default_rng(0)
    for shape in ((5, 7, 3), (5, 7, 1), (5, 7)):
        a = rng.random(shape, dtype=np.float32)
        image = scene.numpy_to_image(a, "Radiance")
        assert image.GetDimensions() == (7, 5, 1)
        array = image.GetPointData().GetScalars()
        assert array.GetName() == "Radiance"
        assert array.GetNumberOfComponents() == (shape[2] if len(shape) == 3 else 1)
        back = vtk_to_numpy(array).reshape(5, 7, -1)
        assert np.array_equal(back, a.reshape(5, 7, -1))


@pytest.mark.parametrize("mapper", ["pathtraced", "stock"])
def test_scene_renders(mapper: str) -> None:
    """Both mappers render the volume inside the background; the path-traced one traces one
    frame per render and gives its passes as (H, W, C) arrays."""
    s = scene.Scene(analytic_volume(), scene.volume_property(ramp_preset()), size=(48, 40),
                    azimuth=20.0, mapper=mapper, denoise=False, threads=2)
    times = s.render(2)
    assert len(times) == 2 and all(t > 0 for t in times)
    from vtkmodules.util.numpy_support import vtk_to_numpy

    shot = s.screenshot()
    assert shot.GetDimensions()[:2] == (48, 40)
    rgb = vtk_to_numpy(shot.GetPointData().GetScalars()).reshape(40, 48, -1)[..., :3]
    background = np.round(255 * np.array(scene.BACKGROUND))
    corner = rgb[0, 0].astype(float)
    centre = rgb[20, 24].astype(float)
    assert np.abs(corner - background).max() <= 1, corner
    assert np.abs(centre - background).max() > 10, "the volume is not in the picture"
    if mapper == "pathtraced":
        assert s.mapper.GetAccumulatedFrames() == 2
        radiance = s.get_pass("Radiance")
        assert radiance.shape == (40, 48, 3) and radiance.dtype == np.float32
        assert s.get_pass("Depth").shape == (40, 48, 1)
        with pytest.raises(RuntimeError, match="no pass 'Bogus'"):
            s.get_pass("Bogus")


def test_scene_of_dataset_and_bad_mapper() -> None:
    """A bundled dataset with its paper preset; an unknown mapper name is an error."""
    s = scene.Scene.of_dataset("head", (32, 32), mapper="stock")
    assert s.mapper.GetInput().GetDimensions()[0] > 32
    with pytest.raises(ValueError, match="'pathtraced' or 'stock'"):
        scene.Scene(analytic_volume(), scene.volume_property(ramp_preset()), mapper="gpu")
