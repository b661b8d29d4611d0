#!/usr/bin/env bash
# README command 2: set everything up (CUDA path compiled too) and run every test under Xvfb,
# then (whole suite only) the C++ tests under the sanitizers (scripts/sanitize.sh).
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
echo "scripts/test.sh: ctest exit code $rc after $(( $(date +%s) - start )) s"
# The whole suite (no ctest arguments) also runs the C++ tests under the sanitizers (issue #9):
# AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer on every `cxx` test, then
# ThreadSanitizer on the concurrency tests (two renders at once; the worker pool). Their builds (build-asan/, build-tsan/) are cached like
# build/. PTV_SANITIZE=0 skips them.
if (($# == 0)) && [[ "${PTV_SANITIZE:-1}" != 0 ]]; then
  set +e
  bash "$ROOT/scripts/sanitize.sh"
  asan=$?
  bash "$ROOT/scripts/sanitize.sh" --thread
  tsan=$?
  set -e
  echo "scripts/test.sh: sanitizers: address/undefined/leak exit code $asan, thread exit code $tsan"
  ((rc == 0 && asan != 0)) && rc=$asan
  ((rc == 0 && tsan != 0)) && rc=$tsan
fi
echo "scripts/test.sh: wall time $(( $(date +%s) - start )) s, exit code $rc"
exit $rc
