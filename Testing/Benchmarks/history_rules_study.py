import os, sys
sys.path.insert(0, "/work/main/Testing/Benchmarks")
import numpy as np
import temporal_reuse as tr
size = int(os.environ.get("SIZE", "256"))
variants = sys.argv[1:]  # e.g. "M=2" "M=2,NEAREST" "M=4,NEAREST,CLIP=1"
for ds, case, tfc in (("head", "orbit", None), ("head", "tf", 18), ("stent", "orbit", None)):
    o = tr.Orbit(ds, size); path = tr.orbit_path(36, 2.0)
    refs = o.references(path, 32, 6000, tfc)
    for k in ("PTV_HISTORY_CLIP", "PTV_HISTORY_NEAREST", "PTV_HISTORY_FRINGE", "PTV_HISTORY_FEATURES", "PTV_HISTORY_ACCEPTALL"): os.environ.pop(k, None)
    with tr.history_angle(0.0):
        alone = o.run(path, True, 1, tf_change=tfc)
    pa = tr.psnr_per_frame(alone["shown"], refs)
    for v in variants:
        M = 2
        for k in ("PTV_HISTORY_CLIP", "PTV_HISTORY_NEAREST", "PTV_HISTORY_FRINGE", "PTV_HISTORY_FEATURES", "PTV_HISTORY_ACCEPTALL"): os.environ.pop(k, None)
        for part in v.split(","):
            if part.startswith("M="): M = int(part[2:])
            elif part in ("NEAREST", "FRINGE", "FEATURES"): os.environ["PTV_HISTORY_" + part] = "1"
            elif part == "ACCEPTALL": o.view(0.0); os.environ["PTV_HISTORY_ACCEPTALL"] = str(o.scene.renderer.GetActiveCamera().GetDistance())
            elif part.startswith("CLIP="): os.environ["PTV_HISTORY_CLIP"] = part[5:]
        r = o.run(path, True, M, tf_change=tfc)
        pr = tr.psnr_per_frame(r["shown"], refs); raw = tr.psnr_per_frame(r["raw"], refs)
        rng = range(tfc + 1, 36) if tfc else range(1, 36)
        dd = [pr[i] - pa[i] for i in rng]
        print(f"{ds:6s} {case:5s} {v:22s} psnr {np.mean(pr):.3f} (alone {np.mean(pa):.3f}) gain {np.mean(dd):+.3f} worst {min(dd):+.3f} raw {np.mean(raw):.2f} tpsnr {np.mean(tr.tpsnr(r['shown'])):.2f} reproj {np.median(r['reproject_ms'][1:]):.2f} ms", flush=True)
