"""Section 3: the paper's Tables 2, 3 and 4 (on the first and the second training data set) and
the held-out transfer-function table, read from the committed results of the training studies in
``Training/results/`` when present; not re-measured.

results.json: ``training`` (table stem -> the file read, or None) and ``training_tables`` (per
table: the file's text and whether git tracks it unchanged), so the section re-renders without
the files.
"""
from __future__ import annotations

import argparse
import subprocess
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Tuple

from .common import ROOT, Output, missing_keys
from .scenes import Bench

TABLES = (("Table 2", "unet", "autoencoder (U-Net) baseline vs ours"),
          ("Table 3", "loo", "leave-one-out generalization"),
          ("Table 4", "ablation", "auxiliary-feature ablation"),
          ("Table 3, second data set", "v2-loo",
           "leave-one-volume-out on seven volumes with random transfer functions"),
          ("Table 3, second data set, shipped architecture", "v3-loo",
           "leave-one-volume-out with the network shipped since (hidden 32, 3x3)"),
          ("Table 3, shipped architecture, three seeds", "v3-loo_seeds",
           "v3-loo's unseen-volume gaps with seeds 0, 1 and 2 and their mean (one seed's "
           "training noise is of the size of the gaps)"),
          ("Table 3, the coverage recipe", "v4-loo",
           "leave-one-volume-out with the shipped recipe since 2026-12-05 (the coverage input, "
           "level dropout, the jittered presets as extra data)"),
          ("Table 4, second data set", "v2-features", "auxiliary-feature and loss ablation"),
          ("Held-out transfer functions", "heldout_tf", "ours against OIDN fast on transfer "
           "functions never seen in training"))


def tracked(path: Path) -> str:
    """'' when git tracks ``path`` unchanged, else a note saying it is not committed."""
    ok = subprocess.run(["git", "ls-files", "--error-unmatch", str(path)], cwd=ROOT,
                        capture_output=True).returncode == 0 and subprocess.run(
        ["git", "diff", "--quiet", "HEAD", "--", str(path)], cwd=ROOT).returncode == 0
    return "" if ok else " (working copy, not committed at this commit)"


def measure(bench: Optional[Bench], out: Optional[Output],
            results: Mapping[str, Any]) -> Dict[str, Any]:
    """Reads the files (no rendering: ``bench`` and ``out`` are unused)."""
    found: Dict[str, Optional[str]] = {}
    tables: List[Dict[str, Any]] = []
    for table, stem, title in TABLES:
        entry: Dict[str, Any] = {"table": table, "stem": stem, "title": title, "format": None,
                                 "source": None, "note": "", "text": ""}
        for fmt_, path in (("md", ROOT / "Training/results" / f"{stem}.md"),
                           ("json", ROOT / "Training/results" / f"{stem}.json")):
            if path.exists():
                entry.update(format=fmt_, source=str(path.relative_to(ROOT)),
                             note=tracked(path), text=path.read_text())
                break
        found[stem] = entry["source"]
        tables.append(entry)
    return {"training": found, "training_tables": tables}


def missing(results: Mapping[str, Any]) -> List[str]:
    return missing_keys(results, ("training_tables",))


def render(results: Mapping[str, Any], args: argparse.Namespace,
           out: Output) -> Tuple[List[str], Dict[str, Any]]:
    md = ["## 3. Paper Tables 2, 3, 4: training studies, held-out transfer functions", "",
          "Read from the results of the training studies (issue #5) in "
          "`Training/results/` when present (committed unless marked); not re-measured "
          "by this script.", ""]
    for t in results["training_tables"]:
        stem = t["stem"]
        md += [f"### {t['table']}: {t['title']}", ""]
        if t["format"] == "md":
            text = t["text"].strip().splitlines()
            text = [("#### " + s.lstrip("# ")) if s.startswith("#") else s for s in text]
            md += [f"From `Training/results/{stem}.md`{t['note']}:", ""] + text + [""]
        elif t["format"] == "json":
            md += [f"From `Training/results/{stem}.json`{t['note']} (no Markdown "
                   "version):", "",
                   "```json", t["text"][:4000].strip(), "```", ""]
        else:
            md += [f"Not available: `Training/results/{stem}.md` / `.json` do not exist "
                   "at this commit.", ""]
    return md, {}
