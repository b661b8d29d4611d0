#!/usr/bin/env bash
# The installed plugin folder is self-contained and relocatable. Usage (ctest does this, under
# Xvfb, with PTV_CACHE_DIR and PTV_TEST_TEMP set):
#   install_plugin.sh <build dir> <source dir> <pvbatch> <installed_plugin.py> [<paraview>]
# 1. cmake --install <build> --prefix <temp>/prefix, then the prefix is moved elsewhere (nothing
#    may point into the place it was installed to); no installed file may name the source or the
#    build tree;
# 2. in a private mount namespace the source tree's Data/ and the build tree's copy of it are
#    covered by empty folders, and PTV_DATA_DIR / PYTHONPATH / LD_LIBRARY_PATH are cleared;
# 3. pvbatch loads the plugin file from the moved prefix (LoadPlugin), and the ParaView GUI (when
#    given) loads it by name: --plugin-search-paths=<plugin folder> --plugins=PathTracedVolume;
#    both run installed_plugin.py (the GuideNet model, the presets and the Python package must
#    all come from the moved folder).
set -u
build="$1" source="$2" pvbatch="$3" script="$4" paraview="${5:-}"
temp="${PTV_TEST_TEMP:-/tmp}/install_plugin"
rm -rf "$temp" && mkdir -p "$temp"
cmake --install "$build" --prefix "$temp/prefix" > "$temp/install.log" 2>&1 ||
  { cat "$temp/install.log"; echo "FAIL: cmake --install"; exit 1; }
mv "$temp/prefix" "$temp/moved"
plugin_dir=$(ls -d "$temp"/moved/lib*/paraview-*/plugins/PathTracedVolume)
build_data=$(ls -d "$build"/lib*/paraview-*/plugins/PathTracedVolume/Data)
for f in PathTracedVolume.so libvtkPTVRendering.so libonnxruntime.so.1 Data/Models/guidenet.onnx \
    Data/TransferFunctions/head.json python/pathtracedvolume/__init__.py \
    python/pathtracedvolume/vtkPTVRendering.so; do
  [ -e "$plugin_dir/$f" ] || { echo "FAIL: the plugin folder lacks $f"; exit 1; }
done
if grep -rl -e "$source/Data" -e "$build" "$plugin_dir"; then
  echo "FAIL: installed files (above) name the source or build tree"
  exit 1
fi
# unshare needs root (as CI and scripts/test.sh run); a failure to isolate fails the test.
env -u PTV_DATA_DIR -u PYTHONPATH -u LD_LIBRARY_PATH \
  PTV_PLUGIN_DIR="$plugin_dir" PTV_HIDDEN_DATA="$source/Data:$build_data" \
  SRC_DATA="$source/Data" BUILD_DATA="$build_data" TEMP_DIR="$temp" PVBATCH="$pvbatch" \
  SCRIPT="$script" PTV_SCRIPT="$script" PARAVIEW="$paraview" \
  unshare --mount sh -c '
    mount --make-rprivate / &&
    mount -t tmpfs none "$SRC_DATA" &&
    mount -t tmpfs none "$BUILD_DATA" &&
    cd "$TEMP_DIR" || exit 1
    "$PVBATCH" --force-offscreen-rendering "$SCRIPT" || exit 1
    [ -z "$PARAVIEW" ] && exit 0
    PTV_GUI=1 PTV_RESULT="$TEMP_DIR/gui.txt" timeout 300 "$PARAVIEW" --dr \
      --plugin-search-paths="$PTV_PLUGIN_DIR" --plugins=PathTracedVolume --script="$SCRIPT"
    gui=$?
    echo "GUI:" && cat "$TEMP_DIR/gui.txt" && [ $gui -eq 0 ]'
rc=$?
echo "install_plugin.sh: exit code $rc"
exit $rc
