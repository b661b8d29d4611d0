"""The shown image's per-pixel blend (``ptvConvergence``): data, training and the C++ weights.

After ``k`` accumulated frames the mapper has, per pixel, the raw mean ``M`` (with the frames'
second moment) and the denoised image ``D`` of that mean. It shows a per-pixel mix of four
candidates, from the most smoothed to the least::

    D,  D + box3(M - D),  D + box7(M - D),  M          (linear radiance, per channel)

with softmax weights from a small MLP on nine per-pixel features (:func:`features`): how noisy
``M`` is (its variance from the frames, tone-mapped by the delta method, alone and box-filtered),
how far ``D`` is from ``M`` (alone and over 3x3 and 7x7 pixels), ``log k``, whether ``k`` is 1,
and the tone-mapped luminance of ``M`` and ``D``. The residual boxes add back what the denoiser
smoothed away where the mean has become trustworthy, so the image keeps improving as samples
accumulate instead of stalling at the denoiser's bias. Loss: the tone-mapped MSE of the mix
against a reference (``tonemap(x) = clip(max(0, x)^(1/2.2), 0, 1)``, docs/measuring.md).

Commands (rendering needs ``PYTHONPATH=build/python`` and a display, e.g. ``xvfb-run -a``)::

    # 1. data (resumable; one .npz per view): 3 random views and transfer functions of each
    #    of the seven volumes accumulated to 128 frames (512-spp references), and 6 views of the
    #    jittered presets of head, stent and concrete to 512 frames (2048-spp references)
    .venv/bin/python Training/ptv_training/converge_blend.py capture --out .cache/blend
    .venv/bin/python Training/ptv_training/converge_blend.py capture --out .cache/blend \\
        --tf presets --views 6 --frames 512 --reference-spp 2048
    # 2. train (preset views weighted 3x) and write the C++ weights
    .venv/bin/python Training/ptv_training/converge_blend.py train --data .cache/blend \\
        --header Rendering/Accumulate/ptvConvergenceBlend.h
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Dict, Optional, Sequence, Tuple

import numpy as np

if __package__ in (None, ""):  # run as a file
    sys.path.append(str(Path(__file__).resolve().parents[1]))
    import ptv_training  # noqa: F401
    __package__ = "ptv_training"

GAMMA = 1.0 / 2.2
EPS = 1e-8            #: added inside every log feature
DARKEST = 1e-3        #: the tone map's slope is taken at no less than this (C++ kDarkest)
RESIDUAL_BOXES = (3, 7)  #: box widths of the residual candidates
COUNTS = (1, 2, 4, 8, 16, 32, 64, 128, 256, 512)  #: frame counts a captured view may hold
HAND_OVER_FROM = 256  #: frames after which the image moves to the raw mean (C++ kHandOverFrom)
PRESET_DATASETS = ("head", "stent", "concrete")  #: the volumes with presets (--tf presets)
FEATURES = ("log_var_box", "log_var", "log_diff", "log_diff_box3", "log_diff_box7", "log_k",
            "first_frame", "tone_mean", "tone_denoised")


def tone(x: np.ndarray) -> np.ndarray:
    """``max(0, x)^(1/2.2)`` (NaN -> 0), not clipped: the error estimates' g."""
    return np.power(np.maximum(np.nan_to_num(x), 0.0), GAMMA)


def tonemap(x: np.ndarray) -> np.ndarray:
    """The measuring tone map: ``clip(g(x), 0, 1)``."""
    return np.clip(tone(x), 0.0, 1.0)


def box(image: np.ndarray, size: int) -> np.ndarray:
    """``image`` (H, W) or (H, W, C) box-filtered over size x size pixels, edges clamped (C++
    ``Box``)."""
    from scipy.ndimage import uniform_filter
    if size <= 1:
        return image
    sizes = (size, size) + (1,) * (image.ndim - 2)
    return uniform_filter(image, size=sizes, mode="nearest")


def variance_box(count: int) -> int:
    """Width of the box over the mean's variance after ``count`` frames (C++ VarianceBox)."""
    return 7 if count < 16 else 5 if count < 32 else 3 if count < 128 else 1


def features(mean: np.ndarray, second: np.ndarray, denoised: np.ndarray,
             count: int) -> np.ndarray:
    """(H, W, 9) float32 features of :data:`FEATURES` from the mean, the mean of the squared
    frames and the denoised image (H, W, 3 each, linear) after ``count`` frames."""
    m = mean.astype(np.float64)
    d = denoised.astype(np.float64)
    clamped = np.maximum(m, DARKEST)
    slope = GAMMA * tone(clamped) / clamped
    if count >= 2:
        spread = np.maximum(second.astype(np.float64) - m * m, 0.0) / (count - 1)
        var = (spread * slope * slope).mean(-1)
        var_box = box(var, variance_box(count))
    else:
        var = var_box = np.zeros(m.shape[:2])
    diff = ((tone(d) - tone(m)) ** 2).mean(-1)
    shape = m.shape[:2]
    phi = [np.log(var_box + EPS), np.log(var + EPS), np.log(diff + EPS),
           np.log(box(diff, 3) + EPS), np.log(box(diff, 7) + EPS),
           np.full(shape, np.log(count)), np.full(shape, 1.0 if count == 1 else 0.0),
           tonemap(m).mean(-1), tonemap(d).mean(-1)]
    return np.stack(phi, -1).astype(np.float32)


def candidates(mean: np.ndarray, denoised: np.ndarray) -> np.ndarray:
    """(4, H, W, C) linear candidates: D, D + box3(M - D), D + box7(M - D), M."""
    m = mean.astype(np.float64)
    d = denoised.astype(np.float64)
    out = [d] + [d + box(m - d, s) for s in RESIDUAL_BOXES] + [m]
    return np.stack(out).astype(np.float32)


def blend_weights(weights: Dict[str, np.ndarray], phi: np.ndarray) -> np.ndarray:
    """(H, W, 4) softmax weights of the exported MLP (:func:`export`) on features ``phi``."""
    hidden = np.maximum(phi @ weights["w1"].T + weights["b1"], 0.0)
    logits = hidden @ weights["w2"].T + weights["b2"]
    logits -= logits.max(-1, keepdims=True)
    e = np.exp(logits)
    return e / e.sum(-1, keepdims=True)


def shown(weights: Dict[str, np.ndarray], mean: np.ndarray, second: np.ndarray,
          denoised: np.ndarray, count: int) -> np.ndarray:
    """The image the mapper shows (pass Converged) in numpy: the reference for the C++ one."""
    w = blend_weights(weights, features(mean, second, denoised, count))
    mix = np.einsum("hwk,khwc->hwc", w, candidates(mean, denoised))
    t = hand_over(count)
    return np.maximum(mix + t * (mean.astype(np.float64) - mix), 0.0)


def hand_over(count: int) -> float:
    """How far the shown image has moved to the raw mean after ``count`` frames: 0 up to
    :data:`HAND_OVER_FROM`, then linearly in log2(count) to 1 at twice that twice (the blend is
    trained up to 512 frames; the raw mean is the converged image's unbiased estimate)."""
    if count <= HAND_OVER_FROM:
        return 0.0
    return float(min(1.0, np.log2(count / HAND_OVER_FROM) / 2.0))


# --- data ---------------------------------------------------------------------------------
class SecondMoment:
    """The frames' second moment rebuilt from the Radiance pass read after each frame (the
    running mean M_k): frame k is k M_k - (k - 1) M_k-1."""

    def __init__(self) -> None:
        self.count = 0
        self.previous: Optional[np.ndarray] = None
        self.value: Optional[np.ndarray] = None

    def add(self, mean: np.ndarray) -> np.ndarray:
        """Take the mean after the next frame (float64 (H, W, 3)); returns the second moment."""
        self.count += 1
        k = self.count
        frame = mean if k == 1 else k * mean - (k - 1) * self.previous
        self.value = frame * frame if k == 1 else self.value + (frame * frame - self.value) / k
        self.previous = mean
        return self.value


def capture_view(scene, view: Dict, frames: int, reference_spp: int) -> Dict[str, np.ndarray]:
    """One view's reference and, at each power of two up to ``frames``, its mean, second moment
    and denoised image (the mapper's defaults, Denoise on)."""
    mapper = scene.set_view(view, seed=view["reference_seed"], denoise=False,
                            max_frames=max(reference_spp // 16, 1), coverage=False)
    mapper.SetSamplesPerFrame(16)
    scene.render(max(reference_spp // 16, 1))
    data = {"reference": scene.get_pass("Radiance")}
    scene.set_view(view, seed=view["input_seed"], denoise=True, max_frames=frames)
    moments = SecondMoment()
    for k in range(1, frames + 1):
        scene.render(1)
        mean = scene.get_pass("Radiance").astype(np.float64)
        second = moments.add(mean)
        if k & (k - 1) == 0:
            data[f"mean{k}"] = mean.astype(np.float32)
            data[f"second{k}"] = second.astype(np.float32)
            data[f"denoised{k}"] = scene.get_pass("Denoised")
    return data


def capture(args: argparse.Namespace) -> int:
    from tqdm import tqdm
    from pathtracedvolume.atomic import atomic_path
    from .generate import (all_datasets, dataset_histogram, random_view_parameters,
                           view_parameters)
    from .scene import Scene

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    presets = args.tf == "presets"
    datasets = args.datasets or (PRESET_DATASETS if presets else all_datasets())
    jobs = [(ds, i) for ds in datasets for i in range(args.views)]
    start = time.perf_counter()

    def target(ds: str, i: int) -> Path:
        return out / (f"{ds}_preset_{i}.npz" if presets else f"{ds}_{i}.npz")

    for ds in tqdm(datasets, desc="volumes", disable=None):
        todo = [i for i in range(args.views) if not target(ds, i).exists()]
        if not todo:
            continue
        scene = Scene(ds, (args.size, args.size))
        histogram = None if presets else dataset_histogram(ds)
        for i in todo:
            view = (view_parameters(ds, i, args.seed, args.size, args.reference_spp) if presets
                    else random_view_parameters(ds, i, args.seed, args.size,
                                                args.reference_spp, histogram))
            data = capture_view(scene, view, args.frames, args.reference_spp)
            with atomic_path(target(ds, i), suffix=".tmp.npz") as tmp:
                np.savez(tmp, **data)
    print(f"{len(jobs)} views in {out} ({time.perf_counter() - start:.0f} s this run)")
    return 0


# --- training -----------------------------------------------------------------------------
def samples(files: Sequence[Path], preset_weight: float = 1.0
            ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(features (N, 9), linear candidates (N, 4, 3), reference (N, 3), loss weight (N,)) of
    every pixel of every count of ``files``. A pixel's loss weight is 1 / the tone-mapped MSE
    of the better of M and D on its image: each (view, count) then counts by its error relative
    to what the inputs already reach (PSNR is logarithmic), not by its absolute error, which
    falls 100-fold from 1 to 128 frames and would leave the high counts untrained. Views of
    the presets (``--tf presets`` captures) count ``preset_weight`` times."""
    xs, cs, rs, ws = [], [], [], []
    for path in files:
        data = np.load(path)
        ref = data["reference"].reshape(-1, 3)
        for k in COUNTS:
            if f"mean{k}" not in data:
                continue
            m, s, d = data[f"mean{k}"], data[f"second{k}"], data[f"denoised{k}"]
            xs.append(features(m, s, d, k).reshape(-1, len(FEATURES)))
            cs.append(candidates(m, d).reshape(4, -1, 3).transpose(1, 0, 2))
            rs.append(ref)
            target = tonemap(data["reference"]).astype(np.float64)
            best = min(np.mean((tonemap(m) - target) ** 2), np.mean((tonemap(d) - target) ** 2))
            weight = preset_weight if "_preset_" in path.name else 1.0
            ws.append(np.full(len(ref), weight / max(best, 1e-10), np.float32))
    return np.concatenate(xs), np.concatenate(cs), np.concatenate(rs), np.concatenate(ws)


def torch_tonemap(x):  # type: ignore[no-untyped-def]
    """:func:`tonemap` in torch (differentiable; 1e-12 keeps the gradient at 0 finite)."""
    import torch
    return torch.clamp((torch.clamp(x, min=0.0) + 1e-12) ** GAMMA, max=1.0)


def fit(x: np.ndarray, c: np.ndarray, r: np.ndarray, weight: np.ndarray, hidden: int,
        steps: int, seed: int) -> Dict[str, np.ndarray]:
    """Train the MLP (Adam, cosine schedule, batches of 32768 pixels); returns its exported
    weights with the feature normalisation folded into the first layer."""
    import torch
    from tqdm import tqdm

    torch.manual_seed(seed)
    X, C, R, W = (torch.from_numpy(np.ascontiguousarray(v)) for v in (x, c, r, weight))
    W = W / W.mean()
    mu, sd = X.mean(0), X.std(0) + 1e-6
    net = torch.nn.Sequential(torch.nn.Linear(X.shape[1], hidden), torch.nn.ReLU(),
                              torch.nn.Linear(hidden, C.shape[1]))
    opt = torch.optim.Adam(net.parameters(), lr=1e-2)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(opt, steps)
    gen = torch.Generator().manual_seed(seed)
    for _ in tqdm(range(steps), desc="train", leave=False, disable=None):
        idx = torch.randint(0, X.shape[0], (32768,), generator=gen)
        w = torch.softmax(net((X[idx] - mu) / sd), -1)
        out = (w[..., None] * C[idx]).sum(1)
        loss = (W[idx, None] * (torch_tonemap(out) - torch_tonemap(R[idx])) ** 2).mean()
        opt.zero_grad()
        loss.backward()
        opt.step()
        schedule.step()
    w1 = net[0].weight.detach().double() / sd.double()[None, :]
    b1 = net[0].bias.detach().double() - (w1 * mu.double()[None, :]).sum(1)
    return {"w1": w1.numpy(), "b1": b1.numpy(), "w2": net[2].weight.detach().double().numpy(),
            "b2": net[2].bias.detach().double().numpy()}


def write_header(path: Path, weights: Dict[str, np.ndarray], command: str) -> None:
    """The weights as the C++ header ptvConvergence.cxx includes (written atomically)."""
    def array(name: str, values: np.ndarray) -> str:
        body = ", ".join(f"{v:.9g}f" for v in values.ravel())
        return f"constexpr float {name}[{values.size}] = {{ {body} }};"

    hidden, inputs = weights["w1"].shape
    lines = [
        "// Generated by Training/ptv_training/converge_blend.py; do not edit. Command:",
        f"// {command}",
        "#ifndef ptvConvergenceBlend_h", "#define ptvConvergenceBlend_h", "",
        "namespace ptv", "{", "namespace blend", "{",
        f"constexpr int kInputs = {inputs};", f"constexpr int kHidden = {hidden};",
        f"constexpr int kCandidates = {weights['w2'].shape[0]};",
        "/// First layer (kHidden x kInputs, row-major; feature normalisation folded in).",
        array("kW1", weights["w1"]), array("kB1", weights["b1"]),
        "/// Second layer (kCandidates x kHidden): logits of D, D + box3, D + box7, M.",
        array("kW2", weights["w2"]), array("kB2", weights["b2"]),
        "}", "}", "", "#endif", ""]
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text("\n".join(lines))
    tmp.replace(path)


def read_header(path: Path) -> Dict[str, np.ndarray]:
    """The weights of a header written by :func:`write_header`."""
    import re
    text = path.read_text()
    out = {}
    for name, key in (("kW1", "w1"), ("kB1", "b1"), ("kW2", "w2"), ("kB2", "b2")):
        body = re.search(rf"{name}\[\d+\] = {{ (.*?) }};", text).group(1)
        out[key] = np.array([float(v.rstrip("f")) for v in body.split(", ")])
    hidden = int(re.search(r"kHidden = (\d+);", text).group(1))
    out["w1"] = out["w1"].reshape(hidden, -1)
    out["w2"] = out["w2"].reshape(-1, hidden)
    return out


def train(args: argparse.Namespace) -> int:
    files = sorted(Path(args.data).glob("*.npz"))
    if args.exclude:
        files = [f for f in files if f.name.split("_")[0] not in args.exclude]
    if not files:
        print(f"no captured views in {args.data}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    x, c, r, w = samples(files, args.preset_weight)
    weights = fit(x, c, r, w, args.hidden, args.steps, args.seed)
    print(f"trained on {len(files)} views, {len(x)} pixel samples, "
          f"{time.perf_counter() - start:.0f} s")
    if args.header:
        write_header(Path(args.header), weights, " ".join(["converge_blend.py"] + sys.argv[1:]))
    if args.npz:
        np.savez(args.npz, **weights)
    return 0


def parse_args(argv: Optional[Sequence[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", required=True)
    cap = sub.add_parser("capture", help="render the training accumulations")
    cap.add_argument("--out", required=True, help="folder of <dataset>_<view>.npz")
    cap.add_argument("--datasets", nargs="*", help="default: all seven")
    cap.add_argument("--views", type=int, default=3, help="views per dataset (default 3)")
    cap.add_argument("--size", type=int, default=256, help="image size (default 256)")
    cap.add_argument("--frames", type=int, default=128, help="frames per view (default 128)")
    cap.add_argument("--reference-spp", type=int, default=512, help="default 512")
    cap.add_argument("--seed", type=int, default=777, help="view seed (default 777)")
    cap.add_argument("--tf", choices=("random", "presets"), default="random",
                     help="random transfer functions of all seven volumes (default) or the "
                          "presets of head, stent and concrete, jittered")
    tr = sub.add_parser("train", help="fit the blend and write its weights")
    tr.add_argument("--data", required=True, help="folder written by capture")
    tr.add_argument("--exclude", nargs="*", default=[], help="datasets left out")
    tr.add_argument("--hidden", type=int, default=8, help="hidden units (default 8)")
    tr.add_argument("--steps", type=int, default=2000, help="Adam steps (default 2000)")
    tr.add_argument("--preset-weight", type=float, default=3.0,
                    help="weight of the preset views against the random ones (default 3)")
    tr.add_argument("--seed", type=int, default=0)
    tr.add_argument("--header", help="write the C++ weights header here")
    tr.add_argument("--npz", help="write the weights as .npz here")
    return p.parse_args(argv)


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = parse_args(argv)
    return capture(args) if args.command == "capture" else train(args)


if __name__ == "__main__":
    sys.exit(main())
