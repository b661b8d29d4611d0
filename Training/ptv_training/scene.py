"""A path-traced scene from a plain parameter dict (the training views, the tests).

Needs the compiled package (``PYTHONPATH=<build>/python``) and a display (Xvfb). The volume,
its property, the camera convention and the passes come from ``pathtracedvolume.scene`` (the
camera: ``place_camera`` with azimuth, elevation and a dolly by ``distance_factor``); this module
adds what the training views vary: jittered transfer functions and a scene light.

View parameters (JSON-friendly)::

    dataset           a dataset of Data/datasets.json ("head", "mri", ...)
    transfer_function a preset dictionary ("Points", "RGBPoints"), used as is; or else
    preset            preset name ("Head Two-Band (paper)", "Head Smooth", ...) with
    threshold_shift   [dx, ...] per anchor group of the preset's transfer function (data units)
    opacity_scale     opacity multiplier (result clipped to [0, 1])
    azimuth, elevation, distance_factor
    light             {"azimuth", "elevation", "intensity"}: a positional scene light at
                      1.5 bounding-box diagonals from the centre; elevation is measured from the
                      plane orthogonal to the camera's view-up, azimuth from the eye direction
                      around the view-up (0 = light next to the camera)
    background        environment (= background) colour
"""
from __future__ import annotations

import math
from typing import Any, Dict, List, Mapping, Sequence, Tuple

import numpy as np

LIGHT_DISTANCE = 1.5  # bounding-box diagonals from the centre


def ensure_paths() -> None:
    """Append ``<repo>/Python`` to sys.path (after PYTHONPATH: the compiled package wins)."""
    import sys
    from pathlib import Path
    python_dir = str(Path(__file__).resolve().parents[2] / "Python")
    if python_dir not in sys.path:
        sys.path.append(python_dir)


def anchor_groups(preset: Mapping[str, Any], merge_fraction: float = 0.01) -> List[List[float]]:
    """The transfer function's interior control-point x values (colour and opacity), grouped:
    points closer than ``merge_fraction`` of the range form one threshold (a band edge)."""
    pts = np.asarray(preset["Points"], dtype=np.float64).reshape(-1, 4)
    rgb = np.asarray(preset["RGBPoints"], dtype=np.float64).reshape(-1, 4)
    lo, hi = pts[0, 0], pts[-1, 0]
    xs = sorted({float(x) for x in np.concatenate([pts[:, 0], rgb[:, 0]]) if lo < x < hi})
    groups: List[List[float]] = []
    for x in xs:
        if groups and x - groups[-1][-1] <= merge_fraction * (hi - lo):
            groups[-1].append(x)
        else:
            groups.append([x])
    return groups


def sample_threshold_shift(preset: Mapping[str, Any], rng: np.random.Generator,
                           fraction: float = 0.05, tries: int = 200) -> List[float]:
    """Per-group shifts uniform in +-``fraction`` of the data range that keep the groups in
    order (at least 0.2 % of the range apart) and inside the range; zeros if none is found."""
    pts = np.asarray(preset["Points"], dtype=np.float64).reshape(-1, 4)
    lo, hi = float(pts[0, 0]), float(pts[-1, 0])
    span = hi - lo
    groups = anchor_groups(preset)
    gap = 0.002 * span
    for _ in range(tries):
        shift = rng.uniform(-fraction, fraction, len(groups)) * span
        ok = True
        prev_end = lo
        for g, s in zip(groups, shift):
            if g[0] + s <= prev_end + (gap if prev_end > lo else 0.0):
                ok = False
                break
            prev_end = g[-1] + s
        if ok and prev_end < hi:
            return [float(s) for s in shift]
    return [0.0] * len(groups)


def jitter_preset(preset: Mapping[str, Any], threshold_shift: Sequence[float],
                  opacity_scale: float) -> Dict[str, Any]:
    """A copy of ``preset`` with each anchor group moved rigidly by its shift and opacities
    scaled (clipped to [0, 1])."""
    groups = anchor_groups(preset)
    if len(threshold_shift) != len(groups):
        raise ValueError(f"{len(threshold_shift)} shifts for {len(groups)} anchor groups")
    moved = {x: x + float(s) for g, s in zip(groups, threshold_shift) for x in g}
    pts = np.asarray(preset["Points"], dtype=np.float64).reshape(-1, 4).copy()
    rgb = np.asarray(preset["RGBPoints"], dtype=np.float64).reshape(-1, 4).copy()
    for table in (pts, rgb):
        table[:, 0] = [moved.get(float(x), float(x)) for x in table[:, 0]]
        if np.any(np.diff(table[:, 0]) <= 0):
            raise ValueError("jittered transfer function is not increasing")
    pts[:, 1] = np.clip(pts[:, 1] * float(opacity_scale), 0.0, 1.0)
    out = dict(preset)
    out["Points"] = [float(v) for v in pts.reshape(-1)]
    out["RGBPoints"] = [float(v) for v in rgb.reshape(-1)]
    return out


class Scene:
    """Reader + volume + renderer + offscreen window for one dataset; :meth:`set_view` applies a
    view's parameters (a new mapper each time, so nothing carries over between views)."""

    def __init__(self, dataset: str, size: Tuple[int, int] = (128, 128),
                 threads: int = 0) -> None:
        ensure_paths()
        from pathtracedvolume.scene import load_dataset
        from vtkmodules.vtkRenderingCore import vtkRenderWindow
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (OpenGL factories)

        self.dataset = dataset
        self.data = load_dataset(dataset)
        self.window = vtkRenderWindow()
        self.window.SetOffScreenRendering(1)
        self.window.SetSize(*size)
        self.size = size
        self.threads = threads
        self.renderer = None
        self.mapper = None
        self._keep: list = []

    def set_view(self, view: Mapping[str, Any], seed: int = 0, denoise: bool = False,
                 max_frames: int = 1024, coverage: bool = True, footprint: bool = False) -> Any:
        """Build mapper/volume/renderer/camera/light for ``view``; returns the mapper. With
        ``coverage`` the mapper traces the Coverage pass (CoverageMarch; a reference's
        radiance does not need it, and it changes no other pass), with ``footprint`` the
        Footprint pass (FootprintRays: evaluation views, which the denoiser reads as the
        mapper's frame loop gives it; it changes no other pass either). The mapper keeps every
        pass (ScatterPasses: the Scatter* passes too, which the EXR files hold)."""
        from pathtracedvolume import vtkPathTracedVolumeMapper
        from pathtracedvolume.presets import find_preset
        from pathtracedvolume.scene import BACKGROUND, place_camera, volume_property
        from vtkmodules.vtkRenderingCore import vtkLight, vtkRenderer, vtkVolume

        if view["dataset"] != self.dataset:
            raise ValueError(f"view of {view['dataset']!r} on a {self.dataset!r} scene")
        if "transfer_function" in view:
            preset = view["transfer_function"]
            shift = None
        else:
            preset = find_preset(view["preset"])
            shift = view.get("threshold_shift")
        if shift is not None or ("preset" in view and view.get("opacity_scale", 1.0) != 1.0):
            preset = jitter_preset(preset, shift or [0.0] * len(anchor_groups(preset)),
                                   view.get("opacity_scale", 1.0))
        prop = volume_property(preset)

        mapper = vtkPathTracedVolumeMapper()
        mapper.ConvergeStillRendersOff()  # the data's sample counts are set frame by frame
        mapper.SetInputData(self.data)
        mapper.SetSeed(int(seed))
        mapper.GetExpertOptions().SetMaximumAccumulatedFrames(int(max_frames))
        mapper.SetDenoise(bool(denoise))
        mapper.GetExpertOptions().SetCoverageMarch(bool(coverage))  # GuideNet's "coverage" channel
        mapper.GetExpertOptions().SetFootprintRays(bool(footprint))  # the denoiser's empty pixels
        mapper.GetExpertOptions().ScatterPassesOn()  # every pass goes to the training EXRs
        if self.threads:
            mapper.SetNumberOfThreads(int(self.threads))
        volume = vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)

        renderer = vtkRenderer()
        renderer.AddVolume(volume)
        renderer.SetBackground(*view.get("background", BACKGROUND))
        camera = place_camera(renderer, view.get("azimuth", 0.0), view.get("elevation", 0.0),
                              view.get("distance_factor", 1.0))

        light_spec = view.get("light")
        if light_spec is not None:
            bounds = volume.GetBounds()
            center = np.array([(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
                               (bounds[4] + bounds[5]) / 2])
            diag = math.sqrt(sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)))
            up = np.array(camera.GetViewUp(), dtype=np.float64)
            up /= np.linalg.norm(up)
            to_eye = np.array(camera.GetPosition()) - np.array(camera.GetFocalPoint())
            to_eye -= up * np.dot(to_eye, up)
            to_eye /= np.linalg.norm(to_eye)
            side = np.cross(up, to_eye)
            az = math.radians(float(light_spec["azimuth"]))
            el = math.radians(float(light_spec["elevation"]))
            direction = (math.cos(el) * (math.cos(az) * to_eye + math.sin(az) * side)
                         + math.sin(el) * up)
            light = vtkLight()
            light.SetLightTypeToSceneLight()
            light.SetPositional(True)
            light.SetConeAngle(180.0)
            light.SetPosition(*(center + LIGHT_DISTANCE * diag * direction))
            light.SetFocalPoint(*center)
            light.SetIntensity(float(light_spec.get("intensity", 1.0)))
            light.SetDiffuseColor(1.0, 1.0, 1.0)
            renderer.AddLight(light)
            self._keep = [light]
        else:
            self._keep = []

        if self.renderer is not None:
            self.window.RemoveRenderer(self.renderer)
        self.window.AddRenderer(renderer)
        self.renderer = renderer
        self.mapper = mapper
        self._keep += [prop, volume]
        return mapper

    def render(self, frames: int = 1) -> int:
        """Render ``frames`` times; returns the mapper's accumulated frame count."""
        for _ in range(frames):
            self.window.Render()
        return int(self.mapper.GetAccumulatedFrames())

    def get_pass(self, name: str) -> np.ndarray:
        """Pass ``name`` as ``(H, W, C)`` float32 (VTK row order: bottom row first)."""
        from pathtracedvolume.scene import get_pass
        return get_pass(self.mapper, name)
