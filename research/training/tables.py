"""Markdown tables and result files of the study scripts (feature_noise.py, noise_aware.py)."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Sequence

from pathtracedvolume.atomic import write_text

REPO_ROOT = Path(__file__).resolve().parents[2]


def row(*cells: object) -> str:
    """One Markdown table row (an empty cell as "| |")."""
    return "|" + "|".join(f" {c} " if c != "" else " " for c in cells) + "|"


def shown(path: Path) -> str:
    """``path`` relative to the repository when inside it (the command line as typed)."""
    try:
        return str(path.resolve().relative_to(REPO_ROOT))
    except ValueError:
        return str(path)


def write_results(results: Path, stem: str, lines: Sequence[str], rows: Any) -> None:
    """``<results>/<stem>.md`` (``lines``) and ``.json`` (``rows``), atomically; prints the
    table."""
    results.mkdir(parents=True, exist_ok=True)
    write_text(results / f"{stem}.md", "\n".join(lines) + "\n")
    write_text(results / f"{stem}.json", json.dumps(rows, indent=1) + "\n")
    print("\n".join(lines))
