"""Whether a render window can open here, and the one-line way out when it cannot.

Debian's VTK and ParaView 5.11 open every render window, offscreen ones too, on an X server
(``vtkXOpenGLRenderWindow``; they have no EGL or OSMesa context). Without ``$DISPLAY`` plain VTK
aborts in ``XOpenDisplay`` ("bad X server connection") and ParaView crashes in its first render
(SIGSEGV in ``XSync``, ``docs/reliability.md``). Scripts that open a window call
:func:`require_display` first and, on such a machine, stop with exit status
:data:`NO_DISPLAY_EXIT` and the command to run instead.
"""
from __future__ import annotations

import os
import shlex
import sys
from pathlib import Path
from typing import Mapping, Optional, Sequence

NO_DISPLAY_EXIT = 2
# VTK's render windows that need no X server (VTK_OPENGL_HAS_EGL / VTK_OPENGL_HAS_OSMESA builds).
HEADLESS_WINDOW_CLASSES = frozenset({"vtkEGLRenderWindow", "vtkOSOpenGLRenderWindow"})


def headless_window(window_class: str) -> bool:
    """True for a VTK render window class that renders without a display (EGL, OSMesa)."""
    return window_class in HEADLESS_WINDOW_CLASSES


def display_missing(headless: bool = False, environ: Optional[Mapping[str, str]] = None,
                    platform: Optional[str] = None) -> bool:
    """True on Linux without ``$DISPLAY``, unless ``headless`` (the window needs no X server)."""
    environ = os.environ if environ is None else environ
    platform = sys.platform if platform is None else platform
    return platform.startswith("linux") and not headless and not environ.get("DISPLAY")


def _shown(word: str) -> str:
    """A path under the working directory relative to it, anything else as it is."""
    if os.sep not in word:
        return word
    try:
        relative = os.path.relpath(word)
    except ValueError:
        return word
    return relative if not relative.startswith(os.pardir) and len(relative) < len(word) else word


def no_display_message(command: Sequence[str]) -> str:
    """The one line that says why ``command`` cannot render here and how to run it instead."""
    scripts = [word for word in command if word.endswith(".py")]
    name = Path(scripts[0] if scripts else command[0]).name
    shown = shlex.join(_shown(word) for word in command)
    return (f"{name}: no X display (DISPLAY is not set), and this VTK opens every render window, "
            f"offscreen ones too, on an X server; run it under Xvfb: xvfb-run -a {shown}")


def require_display(command: Sequence[str], headless: bool = False) -> None:
    """Exit with status 2 and a one-line hint on stderr where no render window can open.

    ``command`` is the command line to suggest under ``xvfb-run -a`` (interpreter, its options,
    the script and its arguments); ``headless``: the render window needs no X server.
    """
    if display_missing(headless):
        print(no_display_message(command), file=sys.stderr)
        sys.exit(NO_DISPLAY_EXIT)
