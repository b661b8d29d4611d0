"""Offline: temporal blend of the *denoised* frames (post-denoise TAA) along the orbit."""
import os, sys
sys.path.insert(0, "/work/main/Testing/Benchmarks")
import numpy as np
import temporal_reuse as tr
from scipy.ndimage import minimum_filter, maximum_filter, uniform_filter, map_coordinates

def collect(o, path, tfc=None, seed=4000):
    m = o.mapper
    m.SetTemporalReprojection(False); m.SetMaximumHistory(1); m.SetMaximumAccumulatedFrames(1024)
    o.set_tf(False); m.ResetAccumulation()
    F = []
    for i, p in enumerate(path):
        o.set_tf(tfc is not None and i >= tfc); o.view(p["azimuth"]); m.SetSeed(seed + i)
        o.scene.window.Render()
        cam = o.scene.renderer.GetActiveCamera()
        M = cam.GetCompositeProjectionTransformMatrix(1.0, -1, 1)
        F.append(dict(D=o.scene.grab("Converged").astype(np.float64), P=o.scene.grab("Position").astype(np.float64),
                      A=o.scene.grab("Alpha")[..., 0], Z=o.scene.grab("Depth")[..., 0],
                      M=np.array([[M.GetElement(r, c) for c in range(4)] for r in range(4)])))
    o.set_tf(False)
    return F

def taa(F, Mcap, gamma, box="minmax", postest=None, tfc=None):
    H, W, _ = F[0]["D"].shape
    out = [F[0]["D"]]; n = np.ones((H, W))
    ys, xs = np.mgrid[0:H, 0:W]
    for i in range(1, len(F)):
        f, g = F[i], F[i - 1]
        D = f["D"]
        if tfc is not None and i == tfc:
            out.append(D); n = np.ones((H, W)); continue
        hit = f["Z"] > 0
        hit = np.isfinite(f["Z"]) & (np.abs(f["P"]).sum(-1) > 0)
        P = f["P"]
        ph = np.concatenate([P, np.ones((H, W, 1))], -1) @ g["M"].T
        w = ph[..., 3]
        u = ((ph[..., 0] / w) + 1) * 0.5 * W - 0.5
        v = ((ph[..., 1] / w) + 1) * 0.5 * H - 0.5
        ok = hit & (w > 0) & (u > -0.5) & (u < W - 0.5) & (v > -0.5) & (v < H - 0.5)
        h = np.stack([map_coordinates(out[-1][..., c], [v, u], order=1, mode="nearest") for c in range(3)], -1)
        nh = map_coordinates(n, [v, u], order=1, mode="nearest")
        if box == "minmax":
            lo = np.stack([minimum_filter(D[..., c], 3) for c in range(3)], -1)
            hi = np.stack([maximum_filter(D[..., c], 3) for c in range(3)], -1)
        else:
            mu = np.stack([uniform_filter(D[..., c], 3) for c in range(3)], -1)
            sd = np.sqrt(np.maximum(np.stack([uniform_filter(D[..., c] ** 2, 3) for c in range(3)], -1) - mu ** 2, 0))
            lo, hi = mu - gamma * sd, mu + gamma * sd
        if gamma is not None:
            h = np.clip(h, lo, hi)
        nn = np.where(ok, np.minimum(nh, Mcap), 0)
        a = 1.0 / (nn + 1)
        out.append(h + (D - h) * a[..., None])
        n = nn + 1
    return out

size = int(os.environ.get("SIZE", "256"))
for ds, tfc in (("head", None), ("head", 18), ("stent", None)):
    o = tr.Orbit(ds, size); path = tr.orbit_path(36, 2.0)
    refs = o.references(path, 32, 6000, tfc)
    F = collect(o, path, tfc)
    base = tr.psnr_per_frame([tr.tonemap(f["D"].astype(np.float32)) for f in F], refs)
    print(f"{ds} tf={tfc} per frame {np.mean(base):.3f} tpsnr {np.mean(tr.tpsnr([tr.tonemap(f['D'].astype(np.float32)) for f in F])):.2f}", flush=True)
    for Mcap, gamma, box in ((1, None, "minmax"), (1, 0, "minmax"), (2, 0, "minmax"), (4, 0, "minmax"), (8, 0, "minmax"), (2, 1.0, "sigma"), (4, 1.0, "sigma"), (4, 1.5, "sigma")):
        out = taa(F, Mcap, gamma, box, tfc=tfc)
        sh = [tr.tonemap(x.astype(np.float32)) for x in out]
        pr = tr.psnr_per_frame(sh, refs)
        d = [pr[i] - base[i] for i in range(1, 36)]
        print(f"   M={Mcap} clamp={box if gamma is not None else 'none'} g={gamma}: psnr {np.mean(pr):.3f} gain {np.mean(d):+.3f} worst {min(d):+.3f} tpsnr {np.mean(tr.tpsnr(sh)):.2f}", flush=True)
