"""Temporal reuse while the camera moves (vtkPathTracedVolumeMapper TemporalReprojection).

Every method runs in the same process on the same views, at --size² with the shipped model:

* **orbits** (--datasets-orbit, --frames views, --step degrees of azimuth per frame, from the
  benchmark view azimuth 30°, elevation 10°): what the mapper shows while the camera moves (the
  Converged pass: the denoised accumulation) with TemporalReprojection off (today: one fresh
  frame per view) and on for each --histories value of MaximumHistory; OIDN fast on each
  view's fresh 1-spp passes; and the converged orbit (--ref-spp per view, another seed). Mean
  temporal PSNR (consecutive tone-mapped frames) and PSNR against the converged view;
* **stress**: the head orbit with the transfer function changed at its middle frame (the
  history must be dropped), a fast orbit (--fast-step degrees per frame), a roll of the fixed
  view (--roll-step degrees per frame about the view direction: the central ray stays, the
  image turns) and a pan that brings unseen parts into view; every frame's PSNR with history
  against the same frame without (TemporalReprojection off, a new seed per view: what the
  mapper shows without reuse; other random samples, so a single frame's difference carries
  their spread, about +-0.3 dB, and the means are what to read);
* **static flicker** (--datasets-static, --static-frames frames of the fixed benchmark view):
  the mapper's own still view (its accumulation), ours per fresh frame and OIDN fast per
  fresh frame (new seeds); per-pixel std of the tone-mapped frames;
* **cost**: the mapper's LastReprojectionTime against the whole render (window.Render(), Denoise
  on) of each moving frame, medians.

Writes Testing/Benchmarks/results/temporal_reuse.{json,csv,png,md}. Needs the compiled package
(``PYTHONPATH=<build>/python``), pyoidn and a display (Xvfb). Run it on an idle machine.
Usage: ``python Testing/Benchmarks/temporal_reuse.py --help``.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import statistics
import sys
import time
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ptvbench as pb  # noqa: E402
from pathtracedvolume.atomic import atomic_path, write_text  # noqa: E402
from pathtracedvolume.metrics import flicker, tonemap, tpsnr  # noqa: E402
from tqdm import tqdm  # noqa: E402

RESULTS = pb.ROOT / "Testing" / "Benchmarks" / "results"
CACHE = pb.ROOT / ".cache" / "temporal_reuse"
AZIMUTH, ELEVATION = 30.0, 10.0


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--size", type=int, default=512, help="image size in pixels (square)")
    p.add_argument("--frames", type=int, default=36, help="views per orbit")
    p.add_argument("--step", type=float, default=2.0, help="orbit degrees per frame")
    p.add_argument("--fast-step", type=float, default=8.0, help="fast orbit degrees per frame")
    p.add_argument("--roll-step", type=float, default=4.0, help="roll degrees per frame")
    p.add_argument("--ref-spp", type=int, default=32, help="spp of each converged view")
    p.add_argument("--histories", type=int, nargs="+", default=[1, 2, 4, 8],
                   help="MaximumHistory values to run")
    p.add_argument("--default-history", type=int, default=1,
                   help="the MaximumHistory the verdicts are about (the mapper's default)")
    p.add_argument("--datasets-orbit", nargs="+", default=["head", "stent"])
    p.add_argument("--datasets-static", nargs="+", default=["head", "stent", "concrete"])
    p.add_argument("--static-frames", type=int, default=16, help="frames of the fixed view")
    p.add_argument("--model", default="",
                   help="GuideNet ONNX file the mapper denoises with (default: the shipped one)")
    p.add_argument("--quick", action="store_true", help="a small run (tests, smoke checks)")
    p.add_argument("--out", type=Path, default=RESULTS, help="results folder")
    a = p.parse_args(argv)
    if a.quick:
        a.size, a.frames, a.ref_spp, a.static_frames = 64, 6, 4, 4
        a.histories, a.default_history = [4], 4
        a.datasets_orbit, a.datasets_static = ["head"], ["head"]
    if a.default_history not in a.histories:
        p.error("--default-history must be one of --histories")
    return a


def psnr_vs(image: np.ndarray, reference: np.ndarray) -> float:
    """PSNR of two tone-mapped images (100 dB when identical)."""
    mse = float(np.mean((image.astype(np.float64) - reference) ** 2))
    return 100.0 if mse == 0 else -10.0 * np.log10(mse)


class Orbit:
    """One dataset's scene and the camera paths of the benchmark."""

    def __init__(self, dataset: str, size: int, model: str = "") -> None:
        self.dataset = dataset
        self.scene = pb.scene_for(dataset, (size, size))
        self.mapper = self.scene.mapper
        self.mapper.DenoiseOn()
        if model:  # another GuideNet than the shipped one
            self.mapper.SetDenoiserModelFile(str(model))
        self.size = size

    def view(self, azimuth: float, pan: float = 0.0, roll: float = 0.0) -> None:
        """The benchmark view turned by ``azimuth``, moved sideways by ``pan`` (fraction of
        the image width) and rolled by ``roll`` degrees about its direction."""
        self.scene.orbit(AZIMUTH + azimuth, ELEVATION)
        if roll:
            self.scene.renderer.GetActiveCamera().Roll(roll)
            self.scene.renderer.ResetCameraClippingRange()
        if pan:
            cam = self.scene.renderer.GetActiveCamera()
            cam.OrthogonalizeViewUp()
            d = np.array(cam.GetDirectionOfProjection())
            up = np.array(cam.GetViewUp())
            right = np.cross(d, up)
            dist = cam.GetDistance()
            width = 2 * dist * np.tan(np.radians(cam.GetViewAngle() / 2))
            shift = right * pan * width
            cam.SetPosition(*(np.array(cam.GetPosition()) + shift))
            cam.SetFocalPoint(*(np.array(cam.GetFocalPoint()) + shift))
            self.scene.renderer.ResetCameraClippingRange()

    def place(self, p: Dict[str, float]) -> None:
        """The view of one entry of a camera path (``azimuth``, optional ``pan`` and ``roll``)."""
        self.view(p["azimuth"], p.get("pan", 0.0), p.get("roll", 0.0))

    def references(self, path: Sequence[Dict[str, float]], spp: int, seed: int,
                   tf_change: Optional[int] = None) -> List[np.ndarray]:
        """Tone-mapped converged views (cached in .cache/temporal_reuse)."""
        key = "_".join(f"{p['azimuth']:g}:{p.get('pan', 0):g}"
                       + (f":{p['roll']:g}" if p.get("roll") else "") for p in path)
        digest = hashlib.sha1(key.encode()).hexdigest()[:10]
        name = f"{self.dataset}_{self.size}_{spp}_{seed}_{tf_change}_{digest}"
        target = CACHE / f"{name}.npz"
        if target.exists():
            return list(np.load(target)["refs"])
        refs = []
        self.mapper.DenoiseOff()  # the raw mean of spp frames
        for i, p in enumerate(tqdm(path, desc=f"converged {self.dataset}", leave=False)):
            self.set_tf(tf_change is not None and i >= tf_change)
            self.place(p)
            self.scene.render(seed + i, spp)
            refs.append(tonemap(self.scene.grab("Radiance")))
        self.set_tf(False)
        self.mapper.DenoiseOn()
        CACHE.mkdir(parents=True, exist_ok=True)
        with atomic_path(target, suffix=".tmp.npz") as tmp:
            np.savez(tmp, refs=np.stack(refs))
        return refs

    def set_tf(self, changed: bool) -> None:
        """The paper preset, or (changed) its opacity doubled: a transfer-function edit."""
        fn = self.scene.prop.GetScalarOpacity()
        if not hasattr(self, "_points"):
            self._points = []
            for i in range(fn.GetSize()):
                node = [0.0] * 4
                fn.GetNodeValue(i, node)
                self._points.append(node)
            self._changed = False
        if changed == self._changed:
            return
        fn.RemoveAllPoints()
        for x, y, mid, sharp in self._points:
            fn.AddPoint(x, min(1.0, y * (2.0 if changed else 1.0)), mid, sharp)
        self._changed = changed

    def run(self, path: Sequence[Dict[str, float]], reprojection: bool, history: int,
            seed: int = 4000, tf_change: Optional[int] = None,
            on_frame: Optional[Callable[[int], None]] = None,
            reseed: bool = False) -> Dict[str, Any]:
        """Render the path one frame per view (Denoise on); returns the shown (Converged) and
        raw frames tone-mapped, the history lengths and timings. ``reseed``: seed + i for view
        i (with reprojection off, each view is otherwise a first frame of the same seed: the
        same random numbers per pixel in every view)."""
        m = self.mapper
        m.SetTemporalReprojection(bool(reprojection))
        m.GetExpertOptions().SetMaximumHistory(int(history))
        m.GetExpertOptions().SetMaximumAccumulatedFrames(1024)
        m.SetSeed(seed)
        self.set_tf(False)
        m.ResetAccumulation()
        out: Dict[str, Any] = {"shown": [], "raw": [], "history_max": [], "render_ms": [],
                               "reproject_ms": [], "trace_ms": [], "reuse": []}
        for i, p in enumerate(path):
            self.set_tf(tf_change is not None and i >= tf_change)
            self.place(p)
            if reseed:
                m.SetSeed(seed + i)
            start = time.perf_counter()
            self.scene.window.Render()
            out["render_ms"].append(1000 * (time.perf_counter() - start))
            out["reproject_ms"].append(m.GetStatistics().GetLastReprojectionTime())
            out["trace_ms"].append(m.GetStatistics().GetLastTraceTime())
            out["reuse"].append(m.GetStatistics().GetReprojectionReuse())
            out["shown"].append(tonemap(self.scene.grab("Converged")))
            out["raw"].append(tonemap(self.scene.grab("Radiance")))
            out["history_max"].append(float(self.scene.grab("HistoryLength").max()))
            if on_frame is not None:
                on_frame(i)
        self.set_tf(False)
        return out


def orbit_path(frames: int, step: float) -> List[Dict[str, float]]:
    return [{"azimuth": i * step} for i in range(frames)]


def roll_path(frames: int, step: float) -> List[Dict[str, float]]:
    """The benchmark view rolled by ``step`` degrees per frame about its direction."""
    return [{"azimuth": 0.0, "roll": i * step} for i in range(frames)]


def pan_path(frames: int) -> List[Dict[str, float]]:
    """Sideways by 2 % of the image width per frame: the far side comes into view."""
    return [{"azimuth": 0.0, "pan": 0.02 * i} for i in range(frames)]


def psnr_per_frame(frames: Sequence[np.ndarray], refs: Sequence[np.ndarray]) -> List[float]:
    """PSNR of each frame against its converged view."""
    return [psnr_vs(f, r) for f, r in zip(frames, refs)]


def sequence_row(dataset: str, case: str, method: str, frames: Sequence[np.ndarray],
                 refs: Sequence[np.ndarray]) -> Dict[str, Any]:
    tp = tpsnr(frames)
    per = psnr_per_frame(frames, refs)
    return {"dataset": dataset, "case": case, "method": method, "frames": len(frames),
            "tpsnr_mean": float(np.mean(tp)) if tp else float("nan"),
            "tpsnr_min": float(np.min(tp)) if tp else float("nan"),
            "psnr_mean": float(np.mean(per)), "psnr_min": float(np.min(per)),
            "psnr_per_frame": per, "tpsnr_per_pair": tp}


def run_case(o: Orbit, case: str, path: Sequence[Dict[str, float]], a: argparse.Namespace,
             rows: List[Dict[str, Any]], costs: List[Dict[str, Any]],
             tf_change: Optional[int] = None, histories: Sequence[int] = (),
             with_oidn: bool = True) -> None:
    refs = o.references(path, a.ref_spp, 6000, tf_change)
    oidn_frames: List[np.ndarray] = []

    def oidn_frame(i: int) -> None:
        oidn_frames.append(tonemap(pb.oidn(o.scene.passes(), "fast")))
    base = o.run(path, False, 1, tf_change=tf_change, reseed=True,
                 on_frame=oidn_frame if with_oidn else None)
    # Without reuse: what the mapper shows with TemporalReprojection off (a new seed per view).
    paired = sequence_row(o.dataset, case, "ours per frame, new seed (report)", base["shown"],
                          refs)
    paired["raw_psnr_per_frame"] = psnr_per_frame(base["raw"], refs)
    paired["raw_psnr_mean"] = float(np.mean(paired["raw_psnr_per_frame"]))
    same = o.run(path, False, 1, tf_change=tf_change)
    rows += [paired, sequence_row(o.dataset, case, "noisy 1 spp", base["raw"], refs),
             sequence_row(o.dataset, case, "ours per frame, one seed (mapper today)",
                          same["shown"], refs)]
    if with_oidn:
        rows.append(sequence_row(o.dataset, case, "OIDN fast per frame", oidn_frames, refs))
    if case == "orbit":
        rows.append(sequence_row(o.dataset, case, f"converged ({a.ref_spp} spp)", refs, refs))
    for h in histories:
        r = o.run(path, True, h, tf_change=tf_change)
        row = sequence_row(o.dataset, case, f"ours + reprojection (M={h})", r["shown"], refs)
        row["raw_psnr_per_frame"] = psnr_per_frame(r["raw"], refs)
        row["raw_psnr_mean"] = float(np.mean(row["raw_psnr_per_frame"]))
        row["never_below"] = min(x - y for x, y in zip(row["psnr_per_frame"],
                                                       paired["psnr_per_frame"]))
        row["history_max"] = r["history_max"]
        if tf_change is not None:
            row["history_max_at_change"] = r["history_max"][tf_change]
            row["gains_around_change"] = gains_around(row, paired, tf_change)
        row["reuse_mean"] = float(np.mean(r["reuse"][1:])) if len(path) > 1 else 0.0
        rows.append(row)
        moving = slice(1, None)
        costs.append({"dataset": o.dataset, "case": case, "history": h,
                      "render_ms": statistics.median(r["render_ms"][moving]),
                      "trace_ms": statistics.median(r["trace_ms"][moving]),
                      "reproject_ms": statistics.median(r["reproject_ms"][moving])})


def gains_around(row: Dict[str, Any], alone: Dict[str, Any], change: int
                 ) -> Dict[str, Dict[str, float]]:
    """What the history adds over the run without it (dB, raw mean and shown image),
    over the moving frames before a change and over those after the frame of the change."""
    out = {}
    for part, frames in (("before", range(1, change)),
                         ("after", range(change + 1, len(row["psnr_per_frame"])))):
        raw = [row["raw_psnr_per_frame"][i] - alone["raw_psnr_per_frame"][i] for i in frames]
        shown = [row["psnr_per_frame"][i] - alone["psnr_per_frame"][i] for i in frames]
        if not shown:  # too short a path for this part
            raw = shown = [float("nan")]
        out[part] = {"raw_mean": float(np.mean(raw)), "shown_mean": float(np.mean(shown)),
                     "shown_worst": float(np.min(shown)), "frames": len(frames)}
    return out


def static_flicker(o: Orbit, frames: int) -> List[Dict[str, Any]]:
    o.view(0.0)
    seqs: Dict[str, List[np.ndarray]] = {"mapper, still view (accumulates)": [],
                                         "ours per fresh frame": [],
                                         "OIDN fast per fresh frame": []}
    m = o.mapper
    m.SetTemporalReprojection(True)
    m.GetExpertOptions().SetMaximumAccumulatedFrames(1024)
    m.SetSeed(3000)
    m.ResetAccumulation()
    for _ in range(frames):
        o.scene.window.Render()
        seqs["mapper, still view (accumulates)"].append(tonemap(o.scene.grab("Converged")))
    for i in range(frames):
        o.scene.render(2000 + i, 1)
        seqs["ours per fresh frame"].append(tonemap(o.scene.grab("Converged")))
        seqs["OIDN fast per fresh frame"].append(tonemap(pb.oidn(o.scene.passes(), "fast")))
    oidn = flicker(seqs["OIDN fast per fresh frame"])
    return [{"dataset": o.dataset, "method": k, "flicker_std": flicker(v),
             "ratio_to_oidn": flicker(v) / oidn} for k, v in seqs.items()]


COLORS = {"ours per frame, new seed (report)": "tab:blue", "OIDN fast per frame": "tab:orange",
          "ours per frame, one seed (mapper today)": "tab:cyan"}


def chart(path: Path, rows: Sequence[Dict[str, Any]], a: argparse.Namespace) -> None:
    """tPSNR per frame pair and PSNR per frame of each orbit's methods (from ``rows``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    orbits = [r for r in rows if r["case"] == "orbit" and r["method"] != "noisy 1 spp"]
    datasets = list(dict.fromkeys(r["dataset"] for r in orbits))
    fig, axes = plt.subplots(2, len(datasets), figsize=(6 * len(datasets), 7), squeeze=False)
    shades = plt.get_cmap("Greens")
    histories = sorted(a.histories)
    for col, ds in enumerate(datasets):
        for r in (r for r in orbits if r["dataset"] == ds):
            name = r["method"]
            if name.startswith("ours + reprojection"):
                h = int(name.split("M=")[1].rstrip(")"))
                color = shades(0.4 + 0.6 * histories.index(h) / max(len(histories) - 1, 1))
            else:
                color = COLORS.get(name, "tab:gray")
            style = "--" if name.startswith("converged") else "-"
            axes[0][col].plot(np.arange(1, len(r["tpsnr_per_pair"]) + 1), r["tpsnr_per_pair"],
                              style, color=color, label=name)
            if not name.startswith("converged"):
                axes[1][col].plot(r["psnr_per_frame"], style, color=color, label=name)
        axes[0][col].set_title(f"{ds}: {a.step}° per frame, {a.size}²")
        axes[0][col].set_ylabel("temporal PSNR [dB]")
        axes[0][col].set_xlabel("frame pair")
        axes[1][col].set_ylabel("PSNR vs converged view [dB]")
        axes[1][col].set_xlabel("frame")
        for ax in axes[:, col]:
            ax.grid(alpha=0.3)
            ax.legend(fontsize=6)
    fig.tight_layout()
    with atomic_path(path, suffix=".tmp.png") as tmp:
        fig.savefig(tmp, dpi=90)
    plt.close(fig)


def markdown(rows: Sequence[Dict[str, Any]], flick: Sequence[Dict[str, Any]],
             costs: Sequence[Dict[str, Any]], a: argparse.Namespace, command: str) -> str:
    md = ["# Temporal reuse while the camera moves", "",
          f"`{command}` (idle machine; {a.size}², "
          f"{'model ' + Path(a.model).name if a.model else 'shipped model'}, Denoise on, "
          "the mapper's "
          "shown image = its Converged pass).", "",
          "| dataset | case | method | mean tPSNR | min tPSNR | PSNR vs converged (mean) | "
          "min | raw PSNR | worst frame vs no history |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        reference = r["method"].startswith("converged")  # its own reference: no PSNR
        psnr = "n/a | n/a" if reference else f"{r['psnr_mean']:.2f} | {r['psnr_min']:.2f}"
        md.append(f"| {r['dataset']} | {r['case']} | {r['method']} | {r['tpsnr_mean']:.2f} | "
                  f"{r['tpsnr_min']:.2f} | {psnr} | "
                  f"{r.get('raw_psnr_mean', float('nan')):.2f} | "
                  f"{r.get('never_below', float('nan')):+.2f} |")
    for r in rows:
        if "history_max_at_change" not in r:
            continue
        g = r["gains_around_change"]
        md.append(f"\n{r['dataset']}, {r['case']}, {r['method']}: longest history in the frame "
                  f"of the change {r['history_max_at_change']:.0f} (1 = dropped). Over the run "
                  "without reuse (TemporalReprojection off), the history adds to the raw mean "
                  "/ to the shown "
                  f"image: before the change {g['before']['raw_mean']:+.2f} / "
                  f"{g['before']['shown_mean']:+.2f} dB (worst frame "
                  f"{g['before']['shown_worst']:+.2f}), after it {g['after']['raw_mean']:+.2f}"
                  f" / {g['after']['shown_mean']:+.2f} dB (worst frame "
                  f"{g['after']['shown_worst']:+.2f}).")
    md += ["", "Static view flicker (per-pixel std of tone-mapped frames, "
           f"{a.static_frames} frames):", "", "| dataset | method | flicker | ÷ OIDN fast |",
           "|---|---|---|---|"]
    md += [f"| {r['dataset']} | {r['method']} | {r['flicker_std']:.4f} | "
           f"{r['ratio_to_oidn']:.3f} |" for r in flick]
    md += ["", "Cost (medians over the moving frames):", "",
           "| dataset | case | M | render ms | trace ms | reprojection ms | ÷ render |",
           "|---|---|---|---|---|---|---|"]
    md += [f"| {c['dataset']} | {c['case']} | {c['history']} | {c['render_ms']:.1f} | "
           f"{c['trace_ms']:.1f} | {c['reproject_ms']:.2f} | "
           f"{c['reproject_ms'] / c['render_ms']:.3f} |" for c in costs]
    return "\n".join(md) + "\n\n![temporal reuse](temporal_reuse.png)\n"


def main(argv: Optional[Sequence[str]] = None) -> int:
    a = parse_args(argv)
    args = list(sys.argv[1:] if argv is None else argv)
    command = " ".join(["PYTHONPATH=build/python xvfb-run -a .venv/bin/python",
                        "Testing/Benchmarks/temporal_reuse.py"] + args)
    rows: List[Dict[str, Any]] = []
    costs: List[Dict[str, Any]] = []
    for ds in tqdm(a.datasets_orbit, desc="orbits", unit="dataset"):
        o = Orbit(ds, a.size, a.model)
        run_case(o, "orbit", orbit_path(a.frames, a.step), a, rows, costs, histories=a.histories)
        if ds == a.datasets_orbit[0]:
            half = a.frames // 2
            run_case(o, "TF change mid-orbit", orbit_path(a.frames, a.step), a, rows, costs,
                     tf_change=half, histories=[a.default_history], with_oidn=False)
            run_case(o, f"fast orbit ({a.fast_step}°/frame)",
                     orbit_path(max(a.frames // 3, 2), a.fast_step), a, rows, costs,
                     histories=[a.default_history], with_oidn=False)
            run_case(o, f"roll ({a.roll_step:g}°/frame)",
                     roll_path(max(a.frames // 3, 2), a.roll_step), a, rows, costs,
                     histories=[a.default_history], with_oidn=False)
            run_case(o, "pan (2 % of the width per frame)", pan_path(max(a.frames // 3, 2)), a,
                     rows, costs, histories=[a.default_history], with_oidn=False)
    flick: List[Dict[str, Any]] = []
    for ds in tqdm(a.datasets_static, desc="static flicker", unit="dataset"):
        flick += static_flicker(Orbit(ds, a.size, a.model), a.static_frames)
    a.out.mkdir(parents=True, exist_ok=True)
    chart(a.out / "temporal_reuse.png", rows, a)
    table = [{k: v for k, v in r.items()
              if k not in ("psnr_per_frame", "tpsnr_per_pair", "history_max",
                           "raw_psnr_per_frame", "gains_around_change")}
             for r in rows]
    write_text(a.out / "temporal_reuse.json", json.dumps(
        {"command": command, "args": {k: (str(v) if isinstance(v, Path) else v)
                                      for k, v in vars(a).items()},
         "rows": rows, "static_flicker": flick, "cost": costs},
        indent=1) + "\n")
    keys = list(dict.fromkeys(k for r in table for k in r))
    write_text(a.out / "temporal_reuse.csv", ",".join(keys) + "\n" + "".join(
        ",".join(str(r.get(k, "")) for k in keys) + "\n" for r in table))
    text = markdown(rows, flick, costs, a, command)
    write_text(a.out / "temporal_reuse.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
