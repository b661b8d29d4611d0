"""The evaluation report (``Testing/Benchmarks/evaluate_report.py``), one module per section.

Every section module has the same three functions:

* ``measure(bench, out, results) -> dict``: the expensive part (VTK rendering, denoising,
  reading committed study results); returns the keys it adds to ``results.json`` (rows of plain
  numbers and strings). Thumbnail galleries are written here: they need the images.
* ``render(results, args, out) -> (lines, derived)``: the cheap part (pure Python +
  matplotlib): the section's Markdown lines, its charts and CSVs, and derived keys (headlines,
  verdicts) that also go into ``results.json``.
* ``missing(results) -> list``: the keys ``render`` needs that ``results`` lacks (an older
  ``results.json``), so ``--render-only`` can refuse with a message instead of a traceback.

Modules: :mod:`.common` (options, constants, CSV/JSON/Markdown helpers, machine info, the output
folder and thumbnails), :mod:`.scenes` (volumes, scenes, the traced-image cache, the shared
measuring context), :mod:`.table1` (sections 1 and 2: Table 1, PSNR against time, the
quality-matched speed-up), :mod:`.samples` (2b: quality against samples, the mapper's own accumulation), :mod:`.training` (3), :mod:`.temporal` (4, with "Camera motion with
temporal reuse"), :mod:`.stress` (5), :mod:`.timing` (6) and :mod:`.report` (the header, the
summary, the measuring run and ``--render-only``).
"""
from __future__ import annotations

import sys
from pathlib import Path

_BENCHMARKS = str(Path(__file__).resolve().parents[1])
if _BENCHMARKS not in sys.path:  # ptvbench lives beside this package
    sys.path.insert(0, _BENCHMARKS)
