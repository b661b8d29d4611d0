"""Shared by the Python tests: collect a VTK object's error and warning messages."""
from __future__ import annotations

from typing import List


def observe(obj) -> List[str]:
    """A list that receives "ErrorEvent: <text>" / "WarningEvent: <text>" for each message of
    ``obj`` from now on (which also keeps them off the output window)."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING

    messages: List[str] = []

    @calldata_type(VTK_STRING)
    def on_message(caller, event, calldata):
        messages.append(f"{event}: {calldata}")

    obj.AddObserver("ErrorEvent", on_message)
    obj.AddObserver("WarningEvent", on_message)
    return messages
