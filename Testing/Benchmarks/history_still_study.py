import os, sys
sys.path.insert(0, "/work/main/Testing/Benchmarks")
import numpy as np
import temporal_reuse as tr
tr.CACHE = tr.CACHE.parent / "temporal_reuse_steps"
o = tr.Orbit("head", 256); m = o.mapper
path = [{"azimuth": 0.0, "pan": 1e-4 * i} for i in range(12)]
refs = o.references(path, 32, 6000, None)
def go(env, moving=True, M=8):
    for k in ("PTV_HISTORY_FRINGE", "PTV_HISTORY_FEATURES", "PTV_HISTORY_ACCEPTALL"): os.environ.pop(k, None)
    for k in env: os.environ[k] = str(o.scene.renderer.GetActiveCamera().GetDistance()) if k == "PTV_HISTORY_ACCEPTALL" else "1"
    m.SetTemporalReprojection(True); m.SetMaximumHistory(M); m.SetSeed(4000); m.ResetAccumulation()
    res = []
    with tr.history_angle(180.0):
        for i, p in enumerate(path):
            o.view(0.0, p["pan"] if moving else 0.0); o.scene.window.Render()
            res.append((tr.psnr_vs(tr.tonemap(o.scene.grab("Radiance")), refs[i]), tr.psnr_vs(tr.tonemap(o.scene.grab("Converged")), refs[i])))
    return res
for name, env, moving in (("pan, ACCEPTALL", ["PTV_HISTORY_ACCEPTALL"], True), ("pan, ACCEPTALL+FEATURES", ["PTV_HISTORY_ACCEPTALL", "PTV_HISTORY_FEATURES"], True), ("true static accumulation", [], False), ("pan 1e-4, today", [], True), ("pan, FRINGE", ["PTV_HISTORY_FRINGE"], True), ("pan, FRINGE+FEATURES", ["PTV_HISTORY_FRINGE", "PTV_HISTORY_FEATURES"], True), ("pan, FEATURES", ["PTV_HISTORY_FEATURES"], True)):
    r = go(env, moving)
    print(f"{name:26s} " + " ".join(f"{i}:{a:.2f}/{b:.2f}" for i, (a, b) in enumerate(r) if i in (0, 1, 2, 3, 5, 8, 11)), flush=True)
