"""Study (reverted in the next commit): the Coverage pass against the Table-1 views.

Run: PYTHONPATH=build/python xvfb-run -a .venv/bin/python Testing/Benchmarks/coverage_study.py 256 stent head concrete
"""
import sys, time, numpy as np
from pathlib import Path
sys.path.insert(0, "/work/main/Training")
from ptv_training import compare, evaluate, exr_io
from ptv_training.scene import Scene
from pathtracedvolume.scene import paper_preset
from pathtracedvolume.metrics import psnr
model = Path("/work/main/Data/Models/guidenet.onnx")
tm = lambda x: np.clip(np.maximum(x, 0) ** (1/2.2), 0, 1)
size = int(sys.argv[1])
for ds in sys.argv[2:]:
  for cam in (0, 1):
    v = compare.paper_view(ds, size, cam, 256, Path("/work/main/.cache/training/paper_views"))
    p, ref = v["inputs"], v["reference"]
    az, el = compare.PAPER_CAMERAS[cam]
    scene = Scene(ds, (size, size))
    scene.set_view({"dataset": ds, "transfer_function": paper_preset(ds), "azimuth": az, "elevation": el}, seed=compare.PAPER_SEEDS[0], max_frames=1)
    scene.render(1)
    rad = scene.get_pass("Radiance")
    assert np.array_equal(rad, p["Radiance"]), "not the same frame"
    cov = scene.get_pass("Coverage")[..., 0]
    ms = scene.mapper.GetLastCoverageTime()
    ours = evaluate.cpp_denoise(model, p, list(p.keys()))["output"]
    q = dict(p); q["Coverage"] = cov[..., None]
    masked = evaluate.cpp_denoise(model, q, list(q.keys()))["output"]
    z = ref.max(-1) == 0
    bad = (cov == 0) & ~z
    R = tm(ref)
    from skimage.metrics import structural_similarity as ss
    S = lambda a: ss(tm(a), R, channel_axis=2, data_range=1)
    print(f"SSIM ours {S(ours):.4f} masked {S(masked):.4f}")
    print(f"{ds} {size} cam{cam}: coverage0 {np.mean(cov==0):.3f} (ref==0 {z.mean():.3f}; cov0 but ref>0: {bad.sum()} px, max ref {ref[bad].max() if bad.any() else 0:.2e}) coverage {ms:.2f} ms | ours {psnr(tm(ours), R):.2f} masked {psnr(tm(masked), R):.2f}")
