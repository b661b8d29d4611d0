#!/usr/bin/env bash
# Makes docs/paraview-gui.png: the ParaView GUI under Xvfb, running docs/paraview_gui_startup.py
# (plugin, head CT as "Path Traced Volume", 8 frames), then a grab of the whole screen.
# One-off tools, not installed by scripts/setup.sh:  apt-get install x11-apps imagemagick
# Usage (from the repository root, after scripts/setup.sh):  docs/paraview_gui_screenshot.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export PTV_SOURCE_DIR="$PWD"
export PTV_CACHE_DIR="${PTV_CACHE_DIR:-$PWD/.cache}"
export PTV_PLUGIN="$PWD/build/lib/paraview-5.11/plugins/PathTracedVolume/PathTracedVolume.so"
export PYTHONPATH="$PWD/build/python"
export PROTOCOL_BUFFERS_PYTHON_IMPLEMENTATION=python
WAIT="${WAIT:-120}"   # seconds for the GUI to start, run the script and render
xvfb-run -a -s "-screen 0 1280x800x24 -noreset" bash -c '
  HOME=$(mktemp -d) paraview --script=docs/paraview_gui_startup.py > /tmp/ptv-paraview-gui.log 2>&1 & pid=$!
  sleep '"$WAIT"'
  xwd -root -silent | convert xwd:- -resize 1024x -colors 256 png:docs/paraview-gui.png
  kill $pid'
ls -l docs/paraview-gui.png
