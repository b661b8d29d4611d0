"""The ParaView panel is user-sized (issue #61): Plugin/PathTracedVolumeRepresentation.xml shows at
most 10 properties without the gear, documents each in one sentence, never shows the expert
options (vtkPTVExpertOptions: scripts still set them) but three ParaView's own features use, shows the MPI-only settings only in a
parallel session (ParaView's SessionTypeDecorator) and exposes every property it declares.
test_representation.py checks in pvbatch that ParaView reads the decorator.

Needs the built package on PYTHONPATH (no display)."""
from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Dict, Set

import pathtracedvolume.vtkPTVRendering as ptv
from vtkmodules.vtkCommonCore import vtkObject

ROOT = Path(os.environ.get("PTV_SOURCE_DIR") or Path(__file__).resolve().parents[2])
XML = ROOT / "Plugin" / "PathTracedVolumeRepresentation.xml"
REPRESENTATION = "Path Traced Volume"
MPI_ONLY = {"ReplicateVolumeLimit", "GhostLayers"}
# Expert options of the mapper that ParaView's own features make panel settings (behind the
# gear): the idle refinement's and still renders' frame caps, and the view's light kit.
PANEL_EXPERTS = {"MaximumAccumulatedFrames", "MaximumStillFrames", "UseRendererLight"}
SENTENCE_END = re.compile(r"[.!?](\s|$)")


def declared() -> Dict[str, ET.Element]:
    proxy = ET.parse(XML).getroot().find(".//RepresentationProxy")
    assert proxy is not None
    return {p.get("name"): p for p in proxy if p.get("name")}


def exposed() -> Dict[str, ET.Element]:
    group = ET.parse(XML).getroot().find(".//ExposedProperties/PropertyGroup")
    assert group is not None
    return {p.get("name"): p for p in group.findall("Property")}


def expert_options() -> Set[str]:
    names = {m[3:] for m in dir(ptv.vtkPTVExpertOptions)
             if m.startswith("Set") and m not in dir(vtkObject)}
    return {n for n in names if not any(n.startswith(o + "To") for o in names if o != n)}


def test_every_declared_property_is_exposed() -> None:
    assert set(declared()) == set(exposed())


def test_at_most_ten_visible_without_the_gear() -> None:
    visible = [name for name, p in exposed().items()
               if p.get("panel_visibility", "default") == "default"
               or p.get("panel_visibility_default_for_representation") == REPRESENTATION]
    assert 1 <= len(visible) <= 10, visible


def test_expert_options_are_never_shown() -> None:
    experts = (expert_options() - PANEL_EXPERTS) & set(exposed())
    assert experts, "the panel's scripting names no longer match vtkPTVExpertOptions"
    shown = {n for n in experts if exposed()[n].get("panel_visibility") != "never"}
    assert not shown, f"expert options in the panel: {sorted(shown)}"


def test_docs_are_one_sentence() -> None:
    long = {}
    for name, prop in declared().items():
        doc = prop.find("Documentation")
        assert doc is not None and doc.text and doc.text.strip(), f"{name} has no documentation"
        text = " ".join(doc.text.split())
        if len(SENTENCE_END.findall(text)) != 1:
            long[name] = text
    assert not long, long


def test_mpi_settings_show_only_in_parallel_sessions() -> None:
    for name, prop in declared().items():
        decorators = [d for d in prop.findall("Hints/PropertyWidgetDecorator")
                      if d.get("type") == "SessionTypeDecorator"]
        if name in MPI_ONLY:
            assert len(decorators) == 1, name
            assert decorators[0].get("requires") == "parallel", name
            assert decorators[0].get("mode") == "visibility", name
        else:
            assert not decorators, name
