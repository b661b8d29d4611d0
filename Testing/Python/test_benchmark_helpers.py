"""Testing/Benchmarks/ptvbench.py's timing helpers, which every speed figure goes through:
interleaved rounds, the paired ratio (median of per-round ratios) and the hypervisor steal read
from /proc/stat. Plain Python (no VTK, no display)."""
from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import List, Optional, Tuple

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "Testing" / "Benchmarks"))
import ptvbench as pb  # noqa: E402


def test_interleaved_runs_every_call_once_per_round_after_a_warm_up() -> None:
    order: List[str] = []
    runs = pb.interleaved({"a": lambda: order.append("a"), "b": lambda: order.append("b")}, 3,
                          {"a": lambda: {"n": len(order)}})
    assert order == ["a", "b"] * 4  # one warm-up round, then 3 timed ones
    assert len(runs["a"]["times"]) == len(runs["b"]["times"]) == 3
    assert [e["n"] for e in runs["a"]["extra"]] == [3, 5, 7]  # read right after each timed call


def test_paired_ratio_is_the_median_of_per_round_ratios() -> None:
    # Round 2 is slow for both (a busy spell) and keeps its ratio 2; the ratio of the medians
    # (5 / 10) would not see the pairing.
    assert pb.paired_ratio([4.0, 40.0, 5.0], [2.0, 20.0, 10.0]) == 2.0
    assert pb.paired_ratio([3.0, 6.0, 100.0], [1.0, 2.0, 1.0]) == 3.0  # medians: 6 / 1


def test_cpu_steal_reads_proc_stat() -> None:
    if not Path("/proc/stat").exists():
        pytest.fail("/proc/stat is missing: the project's machines are Linux")
    with pb.CpuSteal() as steal:
        # 100 ms of CPU time: /proc/stat counts in 10 ms ticks per CPU, so the total moves
        # by about 10 per busy CPU (a fixed amount of work took under one tick on the CI run).
        end = time.monotonic() + 0.1
        while time.monotonic() < end:
            sum(i * i for i in range(1000))
    assert steal.fraction is not None and 0.0 <= steal.fraction <= 1.0


def test_cpu_steal_is_the_share_of_stolen_ticks(monkeypatch: pytest.MonkeyPatch) -> None:
    ticks: List[Optional[Tuple[int, int]]] = [(10, 1000), (40, 1200)]
    monkeypatch.setattr(pb, "_cpu_ticks", lambda: ticks.pop(0))
    with pb.CpuSteal() as steal:
        pass
    assert steal.fraction == pytest.approx(30 / 200)
    ticks[:] = [None, (0, 5)]  # unreadable at the start: no figure rather than a wrong one
    with pb.CpuSteal() as steal:
        pass
    assert steal.fraction is None
