"""Shared by the Python tests that run a project script end to end (the benchmarks)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Sequence

ROOT = Path(__file__).resolve().parents[2]


def run_script(script: Path, args: Sequence[str], timeout: float = 600) -> str:
    """Run ``script`` with the test's Python from the source root; assert that it exits 0 and
    prints no VTK error or warning and no traceback. Returns stdout + stderr."""
    done = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT)
    output = done.stdout + done.stderr
    assert done.returncode == 0, output[-4000:]
    for pattern in ("ERROR: In", "Warning: In", "Traceback"):
        assert pattern not in output, output[-4000:]
    return output
