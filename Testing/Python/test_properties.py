"""docs/properties.md is the property reference (issue #61): its tables must list exactly the
settable properties of vtkPathTracedVolumeMapper (with its parallel plumbing) and of
vtkPTVExpertOptions, each with the default a fresh object has; the mapper stays user-sized
(at most 15 properties besides the plumbing, a header of at most 300 lines).

Needs the built package on PYTHONPATH (no display)."""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Dict, List, Set

import pytest

import pathtracedvolume.vtkPTVRendering as ptv
from vtkmodules.vtkCommonCore import vtkObject
from vtkmodules.vtkRenderingVolume import vtkVolumeMapper

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
REFERENCE = ROOT / "docs" / "properties.md"


def tables() -> Dict[str, Dict[str, str]]:
    """Section title -> {property: default text} of every table in the reference."""
    out: Dict[str, Dict[str, str]] = {}
    section = ""
    for line in REFERENCE.read_text().splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        match = re.match(r"\| `(\w+)` \| ([^|]*) \|", line)
        if match:
            out.setdefault(section, {})[match.group(1)] = match.group(2).strip()
    return out


def settable(cls: Any, base: Any) -> Set[str]:
    """Properties with a Set<name> method on cls but not on base (SetXToY helpers excluded)."""
    names = {m[3:] for m in dir(cls) if m.startswith("Set") and m not in dir(base)}
    return {n for n in names if not any(n.startswith(o + "To") for o in names if o != n)}


def parse(text: str) -> Any:
    """A documented default: on/off, a number, a tuple, or (empty)/(none) for None."""
    if text in ("on", "off"):
        return text == "on"
    if text in ("(empty)", "(none)"):
        return None
    if text.startswith("("):
        return tuple(float(v) for v in text.strip("()").split(","))
    return float(text)


def check_defaults(obj: Any, documented: Dict[str, str]) -> List[str]:
    wrong = []
    for name, text in documented.items():
        value = getattr(obj, "Get" + name)()
        want = parse(text)
        if isinstance(want, bool):
            value = bool(value)
        elif isinstance(want, tuple):
            value = tuple(float(v) for v in value)
        elif want is not None:
            value = float(value)
        if value != want and not (want is None and value in (None, "")):
            wrong.append(f"{name}: {value!r}, documented {text!r}")
    return wrong


def test_mapper_properties_are_the_reference() -> None:
    t = tables()
    documented = {**t["vtkPathTracedVolumeMapper"],
                  **t["Parallel plumbing (set by ParaView's representation)"]}
    assert settable(ptv.vtkPathTracedVolumeMapper, vtkVolumeMapper) == set(documented)
    assert len(t["vtkPathTracedVolumeMapper"]) <= 15
    assert not check_defaults(ptv.vtkPathTracedVolumeMapper(), documented)


def test_expert_options_are_the_reference() -> None:
    documented = tables()["vtkPTVExpertOptions (`GetExpertOptions()`)"]
    assert settable(ptv.vtkPTVExpertOptions, vtkObject) == set(documented)
    options = ptv.vtkPathTracedVolumeMapper().GetExpertOptions()
    assert not check_defaults(options, documented)


def test_the_mapper_header_is_short() -> None:
    lines = (ROOT / "Rendering" / "vtkPathTracedVolumeMapper.h").read_text().splitlines()
    assert len(lines) <= 300, len(lines)


@pytest.mark.parametrize("name", ["StillQuality", "EdgeSamples"])
def test_a_wrong_default_would_be_found(name: str) -> None:
    """The default check can fail: a changed default in the reference is reported."""
    documented = {name: "7"}
    target = ptv.vtkPathTracedVolumeMapper()
    if not hasattr(target, "Set" + name):
        target = target.GetExpertOptions()
    assert check_defaults(target, documented)


def test_telemetry_is_a_few_getters_and_one_statistics_object() -> None:
    """Read-only state on the mapper is what a user acts on (issue #61); what a render cost is in
    vtkPTVRenderStatistics, which every mapper owns."""
    mapper = ptv.vtkPathTracedVolumeMapper()
    inherited = set(dir(vtkVolumeMapper))
    read_only = {m[3:] for m in dir(mapper) if m.startswith("Get") and m not in inherited
                 and not hasattr(mapper, "Set" + m[3:])}
    machine = {"CpuKernelTarget", "CudaAvailable", "CudaStatus", "NumberOfPasses", "PassName",
               "Pass", "Passes", "ExpertOptions", "Statistics", "Controller"}
    assert read_only - machine == {"AccumulatedFrames", "LastRenderTraced", "EstimatedQuality",
                                   "StillConverged", "DenoiserStatus", "ActiveBackend"}
    stats = mapper.GetStatistics()
    assert isinstance(stats, ptv.vtkPTVRenderStatistics) and stats is mapper.GetStatistics()
    assert (stats.GetLastRenderFrames(), stats.GetLastTraceTime(), stats.GetLastEdgeFraction()) \
        == (0, 0.0, 0.0)
