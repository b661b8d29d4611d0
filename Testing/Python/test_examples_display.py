"""Without a display the examples stop with exit status 2 and say how to get one.

Debian's VTK and ParaView render offscreen on an X server too: without ``$DISPLAY``,
``Examples/vtkpython_head.py`` aborted in X ("bad X server connection") and
``pvpython --force-offscreen-rendering Examples/pvpython_head.py`` crashed (SIGSEGV in ``XSync``
during the first render). Both now check first (``pathtracedvolume.headless``).
"""
from __future__ import annotations

import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Dict, List

from pathtracedvolume import headless

ROOT = Path(__file__).resolve().parents[2]
PVPYTHON = shutil.which("pvpython") or "/usr/bin/pvpython"


def _run_without_display(command: List[str]) -> subprocess.CompletedProcess:
    env: Dict[str, str] = {k: v for k, v in os.environ.items()
                           if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    return subprocess.run(command, capture_output=True, text=True, timeout=120, cwd=ROOT,
                          env=env)


def _assert_refused(done: subprocess.CompletedProcess, interpreter: str, arguments: str) -> None:
    """Exit status 2 and one line on stderr: why, and the command under ``xvfb-run -a``."""
    output = done.stdout + done.stderr
    assert done.returncode == headless.NO_DISPLAY_EXIT, output[-4000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, output[-4000:]
    assert "no X display (DISPLAY is not set)" in lines[0], lines[0]
    assert lines[0].endswith(f"run it under Xvfb: xvfb-run -a {interpreter} {arguments}"), lines[0]
    assert "Traceback" not in output, output[-4000:]


def test_vtkpython_example_without_display_says_how_to_get_one() -> None:
    script = "Examples/vtkpython_head.py"
    done = _run_without_display([sys.executable, script, "--size", "32", "--frames", "1"])
    interpreter = Path(sys.executable)
    if ROOT in interpreter.parents:  # shown relative to the working directory, the root
        interpreter = interpreter.relative_to(ROOT)
    _assert_refused(done, shlex.quote(str(interpreter)), f"{script} --size 32 --frames 1")
    assert done.stdout == "", done.stdout  # stopped before reading or rendering anything


def test_vtkpython_example_help_needs_no_display() -> None:
    done = _run_without_display([sys.executable, "Examples/vtkpython_head.py", "--help"])
    assert done.returncode == 0, done.stdout + done.stderr
    assert "--frames" in done.stdout


def test_pvpython_example_without_display_says_how_to_get_one() -> None:
    script = "Examples/pvpython_head.py"
    done = _run_without_display([PVPYTHON, "--force-offscreen-rendering", script,
                                 "--size", "32", "--frames", "1"])
    _assert_refused(done, "pvpython --force-offscreen-rendering",
                    f"{script} --size 32 --frames 1")


def test_display_missing_rules() -> None:
    assert headless.display_missing(environ={}, platform="linux")
    assert headless.display_missing(environ={"DISPLAY": ""}, platform="linux")
    assert not headless.display_missing(environ={"DISPLAY": ":99"}, platform="linux")
    assert not headless.display_missing(headless=True, environ={}, platform="linux")
    assert not headless.display_missing(environ={}, platform="win32")
    assert headless.headless_window("vtkEGLRenderWindow")
    assert headless.headless_window("vtkOSOpenGLRenderWindow")
    assert not headless.headless_window("vtkXOpenGLRenderWindow")


def test_message_is_one_line_with_the_command() -> None:
    message = headless.no_display_message(["pvbatch", "/nonexistent/my script.py", "--size", "8"])
    assert "\n" not in message
    assert message.startswith("my script.py: no X display")
    assert message.endswith("xvfb-run -a pvbatch '/nonexistent/my script.py' --size 8")
