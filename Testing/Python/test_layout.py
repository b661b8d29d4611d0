"""The source tree shows the frame (issue #60): Rendering/ has one folder per stage of the frame,
no C++ source of the product is longer than one sitting, and the Rendering module's includes
form no cycle. Reads the source tree only (no build, no display)."""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Dict, List, Set

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
PRODUCT = ("Rendering", "Filters", "Plugin")
SOURCE_SUFFIXES = {".h", ".cxx", ".cu", ".cuh"}
# One sitting: ~400 lines, some headroom for a file that reads as one idea.
MAX_LINES = 500
# Generated tables (weights written by the training pipeline), not code to read.
GENERATED = {"ptvConvergenceBlend.h"}
STAGES = {"Frame", "Trace", "Accumulate", "Denoise", "Display", "Parallel", "Support",
          "Kernels", "Cuda"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def sources(folder: str) -> List[Path]:
    return sorted(p for p in (ROOT / folder).rglob("*")
                  if p.suffix in SOURCE_SUFFIXES and p.is_file())


def test_rendering_has_a_folder_per_stage() -> None:
    folders = {p.name for p in (ROOT / "Rendering").iterdir() if p.is_dir()}
    assert STAGES <= folders, f"missing stage folders: {sorted(STAGES - folders)}"
    loose = [p.name for p in (ROOT / "Rendering").iterdir()
             if p.suffix in SOURCE_SUFFIXES and not p.name.startswith("vtk")]
    assert not loose, f"private sources outside the stage folders: {loose}"


def test_no_source_longer_than_one_sitting() -> None:
    long: Dict[str, int] = {}
    for folder in PRODUCT:
        for path in sources(folder):
            if path.name in GENERATED:
                continue
            count = len(path.read_text(errors="replace").splitlines())
            if count > MAX_LINES:
                long[str(path.relative_to(ROOT))] = count
    assert not long, f"files over {MAX_LINES} lines: {long}"


def test_rendering_includes_form_no_cycle() -> None:
    """Units (a header with its sources: ptvFoo.h, ptvFoo.cxx, ptvFoo.cu) include each other
    without a cycle, so each stage builds on the ones below it. A header without sources that
    only one unit includes (ptvReprojectionRows.h in ptvReprojection.cxx) is part of that unit."""
    files = sources("Rendering")
    stems = {p.name.split(".")[0] for p in files}
    edges: Dict[str, Set[str]] = {u: set() for u in stems}
    for path in files:
        unit = path.name.split(".")[0]
        for name in INCLUDE.findall(path.read_text(errors="replace")):
            target = Path(name).name.split(".")[0]
            if target in stems and target != unit:
                edges[unit].add(target)
    header_only = {p.name.split(".")[0] for p in files if p.suffix in (".h", ".cuh")} - {
        p.name.split(".")[0] for p in files if p.suffix in (".cxx", ".cu")}
    owner = {u: u for u in stems}
    for unit in header_only:
        includers = {u for u, targets in edges.items() if unit in targets}
        if len(includers) == 1:
            owner[unit] = includers.pop()
    units = set(owner.values())
    graph: Dict[str, Set[str]] = {u: set() for u in units}
    for unit, targets in edges.items():
        graph[owner[unit]] |= {owner[t] for t in targets if owner[t] != owner[unit]}
    state: Dict[str, int] = {}
    stack: List[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):] + [nxt]
                raise AssertionError("include cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for unit in sorted(units):
        if unit not in state:
            visit(unit)
