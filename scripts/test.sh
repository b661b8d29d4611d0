#!/usr/bin/env bash
# README command 2: set everything up (CUDA path compiled too) and run every test under Xvfb.
# Usage: scripts/test.sh [ctest args...]   e.g. scripts/test.sh -R OpenVDB
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PTV_BUILD_DIR:-$ROOT/build}"
start=$(date +%s)
bash "$ROOT/scripts/setup.sh" --cuda
cd "$BUILD"
set +e
# -n: start the free-display search at a per-process number, so parallel runs never share :99.
# -noreset: Xvfb otherwise resets when its last client leaves, and a test opening a window during
# that reset aborts in XOpenDisplay ("bad X server connection"; seen under load).
xvfb-run -a -n $((100 + $$ % 800)) -s "-screen 0 1024x768x24 -noreset" \
  ctest --output-on-failure --timeout 1800 "$@"
rc=$?
set -e
echo "scripts/test.sh: wall time $(( $(date +%s) - start )) s, ctest exit code $rc"
exit $rc
