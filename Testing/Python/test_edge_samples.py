"""EdgeSamples (vtkPathTracedVolumeMapper, Rendering/Trace/ptvEdgeSamples.h): after a frame is traced,
the pixels whose 3x3 neighbourhood holds a camera ray of opacity >= 0.5 and one below 0.05 get
EdgeSamples - 1 more samples per frame sample from a stream of their own, when the frame is
denoised or with ComputeEdgeSamples."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pathtracedvolume")

from ptv_wavelet_scene import get_pass, wavelet_scene  # noqa: E402

import pathtracedvolume.vtkPTVRendering as ptv  # noqa: E402
from pathtracedvolume.edges import edge_mask  # noqa: E402

SIZE = (48, 36)  # (W, H)
TRACED = ["Radiance", "Alpha", "Albedo", "Depth", "Position", "Normal", "ScatterDepth",
          "ScatterPosition", "ScatterNormal", "Coverage", "Footprint"]


def render(count: int, compute: bool, denoise: bool = False, seed: int = 3,
           threads: int = 0, footprint: bool = False) -> tuple:
    """One fresh frame of the wavelet zoomed out (a silhouette against empty space)."""
    window, mapper, keep = wavelet_scene(SIZE, opacity=0.6, seed=seed, denoise=denoise)
    keep[3].GetActiveCamera().Zoom(0.6)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(1)
    mapper.GetExpertOptions().CoverageMarchOn()
    mapper.GetExpertOptions().SetFootprintRays(footprint)
    mapper.GetExpertOptions().SetEdgeSamples(count)
    mapper.GetExpertOptions().SetComputeEdgeSamples(compute)
    if threads:
        mapper.SetNumberOfThreads(threads)
    window.Render()
    passes = {name: get_pass(mapper, name, SIZE) for name in TRACED}
    return passes, mapper


def grid(a: np.ndarray) -> np.ndarray:
    return a.reshape(SIZE[1], SIZE[0], -1)


def test_only_edge_pixels_change() -> None:
    """The pixels outside the rule's mask (computed from the frame without edge samples) are
    bit-identical in every pass; the mask's pixels hold the mean of four samples (Alpha in
    quarters), some of them differ, and GetLastEdgeFraction is the mask's share."""
    plain, plain_mapper = render(4, compute=False)
    assert plain_mapper.GetStatistics().GetLastEdgeFraction() == 0.0
    edged, mapper = render(4, compute=True)
    mask = edge_mask(grid(plain["Coverage"])[..., 0])
    assert 0.02 < mask.mean() < 0.5, mask.mean()
    assert mapper.GetStatistics().GetLastEdgeFraction() == pytest.approx(mask.mean(), abs=1e-12)
    for name in TRACED:
        a, b = grid(plain[name]), grid(edged[name])
        assert np.array_equal(a[~mask], b[~mask]), name
    alpha = grid(edged["Alpha"])[..., 0][mask]
    assert np.allclose(alpha * 4, np.round(alpha * 4), atol=1e-5)
    assert ((alpha > 0) & (alpha < 1)).any()  # a mean of hits and misses somewhere
    changed = np.any(grid(plain["Radiance"]) != grid(edged["Radiance"]), axis=-1)
    assert changed[mask].mean() > 0.3


def test_sample_ratio_pass_marks_them() -> None:
    """The SampleRatio pass (what the denoiser leans towards each pixel's own mean by) is
    EdgeSamples on the rule's mask and 1 elsewhere; 1 everywhere without edge samples."""
    plain, plain_mapper = render(3, compute=False)
    assert np.all(get_pass(plain_mapper, "SampleRatio", SIZE) == 1.0)
    _, mapper = render(3, compute=True)
    mask = edge_mask(grid(plain["Coverage"])[..., 0])
    ratio = grid(get_pass(mapper, "SampleRatio", SIZE))[..., 0]
    assert mask.any() and np.all(ratio[mask] == 3.0) and np.all(ratio[~mask] == 1.0)


def test_mapper_denoises_without_the_sample_ratio() -> None:
    """The mapper's Denoised pass on a view's first frame is vtkPTVDenoiser's on the traced
    passes alone: the SampleRatio pass, which would lean the edge pixels towards their own means
    (and differs from it on the edge pixels only), is not given (docs/decisions.md)."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    from ptv_wavelet_scene import set_traced_passes

    window, mapper, scene = wavelet_scene(SIZE, opacity=0.6, seed=3, denoise=True)
    scene[3].GetActiveCamera().Zoom(0.6)
    mapper.GetExpertOptions().SetMaximumAccumulatedFrames(1)
    window.Render()
    denoised = grid(get_pass(mapper, "Denoised", SIZE))

    def vtk_denoise(with_ratio: bool) -> np.ndarray:
        denoiser = ptv.vtkPTVDenoiser()
        denoiser.SetModelFile(mapper.GetDenoiserModelFile())
        denoiser.DenoiseAlphaOn()
        images = set_traced_passes(mapper, denoiser)
        if with_ratio:
            image = vtkImageData()
            assert mapper.GetPass("SampleRatio", image)
            images.append(image)
            denoiser.SetImage("SampleRatio", image)
        assert denoiser.Execute()
        out = denoiser.GetOutput().GetPointData().GetArray("Denoised")
        return grid(np.array([out.GetTuple3(i) for i in range(out.GetNumberOfTuples())],
                             np.float32))

    assert np.array_equal(denoised, vtk_denoise(False))
    edges = grid(get_pass(mapper, "SampleRatio", SIZE))[..., 0] > 1
    differ = np.any(vtk_denoise(True) != denoised, axis=-1)
    assert edges.any() and differ.any() and not differ[~edges].any()


def test_frames_are_deterministic_and_thread_independent() -> None:
    """The same seed gives the same frame, on one thread or two; EdgeSamples 1 is the plain
    frame."""
    a, _ = render(4, compute=True, threads=1)
    b, _ = render(4, compute=True, threads=2)
    for name in TRACED:
        assert np.array_equal(a[name], b[name]), name
    off, mapper = render(1, compute=True)
    plain, _ = render(4, compute=False)
    assert mapper.GetStatistics().GetLastEdgeFraction() == 0.0
    for name in TRACED:
        assert np.array_equal(off[name], plain[name]), name


def test_denoised_frame_gets_them_by_default() -> None:
    """With Denoise on (ComputeEdgeSamples off) the frame loop traces them: the accumulated
    passes are those of ComputeEdgeSamples (and FootprintRays, which it traces too) without
    denoising."""
    denoised, mapper = render(4, compute=False, denoise=True)
    assert mapper.GetStatistics().GetLastEdgeFraction() > 0.02
    asked, _ = render(4, compute=True, footprint=True)
    for name in TRACED:
        assert np.array_equal(denoised[name], asked[name]), name


def test_a_camera_move_drops_the_edges_history() -> None:
    """After a camera move the edge pixels start again from the new frame (HistoryLength 1):
    their history lags behind the silhouette, which moves with the view; other pixels of the
    volume keep theirs. The rule's pixels come from the same move without edge samples (the
    same frame samples)."""
    def moved(count: int) -> dict:
        window, mapper, keep = wavelet_scene(SIZE, opacity=0.6, seed=3)
        keep[3].GetActiveCamera().Zoom(0.6)
        mapper.GetExpertOptions().CoverageMarchOn()
        mapper.GetExpertOptions().SetEdgeSamples(count)
        mapper.GetExpertOptions().ComputeEdgeSamplesOn()
        for _ in range(3):
            window.Render()
        keep[3].GetActiveCamera().Azimuth(1.0)
        window.Render()
        assert mapper.GetStatistics().GetReprojectionReuse() > 0.3
        return {name: get_pass(mapper, name, SIZE) for name in ("Coverage", "HistoryLength")}

    plain, edged = moved(1), moved(2)
    mask = edge_mask(grid(plain["Coverage"])[..., 0])
    assert mask.mean() > 0.02
    history = grid(edged["HistoryLength"])[..., 0]
    before = grid(plain["HistoryLength"])[..., 0] > 1.0  # kept a history without edge samples
    assert np.all(history[mask] == 1.0)
    assert before[mask].any()  # some of them had one
    kept = before & ~mask
    assert kept.mean() > 0.05 and (history[kept] > 1.0).mean() > 0.9


@pytest.mark.parametrize("count", [2, 3, 4])
def test_the_mean_is_unbiased(count: int) -> None:
    """Edge samples change a pixel's variance, not its expectation, whichever lattice their
    jitter forms (2: the opposite point; 3: a rank-1 lattice; 4: a 2 x 2 grid): over many fresh
    frames the radiance summed over the band of edge pixels agrees with the plain frames' within
    4 standard errors of the difference of two independent means (a misweighted mean, e.g. the
    extra samples counted as one, moves it by many), and varies less."""
    frames = 24
    band = np.zeros((SIZE[1], SIZE[0]), bool)
    images = {False: [], True: []}
    for seed in range(100, 100 + frames):
        for compute in (False, True):
            passes, _ = render(count, compute=compute, seed=seed)
            images[compute].append(grid(passes["Radiance"]).sum(axis=-1))
            if not compute:
                band |= edge_mask(grid(passes["Coverage"])[..., 0])
    a, b = (np.array([image[band].sum() for image in images[c]]) for c in (False, True))
    se = math.sqrt(a.var(ddof=1) / frames + b.var(ddof=1) / frames)
    assert abs(a.mean() - b.mean()) < 4 * se, (a.mean(), b.mean(), se)
    assert b.var(ddof=1) < a.var(ddof=1)


def test_edge_samples_in_the_settings() -> None:
    """Documented properties with their defaults and range, printed by PrintSelf."""
    mapper = ptv.vtkPathTracedVolumeMapper()
    options = mapper.GetExpertOptions()
    assert options.GetEdgeSamples() == 3 and not options.GetComputeEdgeSamples()
    assert mapper.GetStatistics().GetLastEdgeFraction() == 0.0
    mapper.GetExpertOptions().SetEdgeSamples(0)
    assert mapper.GetExpertOptions().GetEdgeSamples() == 1
    mapper.GetExpertOptions().SetEdgeSamples(1000)
    assert mapper.GetExpertOptions().GetEdgeSamples() == 64
    mapper.GetExpertOptions().ComputeEdgeSamplesOn()
    text = str(mapper)
    assert "EdgeSamples: 64" in text and "ComputeEdgeSamples: 1" in text
