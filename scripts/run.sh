#!/usr/bin/env bash
# README command 1: set everything up and render the bundled default (head CT, its "Head Smooth" preset)
# to out/head.png. Extra arguments go to scripts/render.py (see --help there).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PTV_BUILD_DIR:-$ROOT/build}"
bash "$ROOT/scripts/setup.sh"
export PYTHONPATH="$BUILD/python${PYTHONPATH:+:$PYTHONPATH}"
xvfb-run -a -n $((100 + $$ % 800)) -s "-screen 0 1024x768x24 -noreset" \
  "$ROOT/.venv/bin/python" "$ROOT/scripts/render.py" \
  --dataset head --output "$ROOT/out/head.png" "$@"
