#!/usr/bin/env bash
# Makes a relocatable bundle of the built binaries for a machine that has a GPU but none
# of our Debian libraries (a GPU cluster node): the command and the test binaries, every
# shared library they need that is not part of the C runtime, and the files they read at
# run time (scenes, golden networks, test tables and scripts, plot scripts, the viewer and
# three.js). On the target:
#   bundle/run-tests.sh [--allow-skip] [GTEST_ARGS]   every test binary, golden check on both
#                                      backends, validate gpu; a skip exits 3 (scripts/bundle-run-tests.sh)
#   bundle/axonguide ARGS              the command, with the bundle's paths set
#   scripts/bundle.sh [BUILD_DIR] [BUNDLE_DIR] [TEST...]   (defaults: build, bundle, every test)
# Naming tests (e.g. pipeline_gpu_test device_evidence_test) bundles only those: the full set
# is over 100 MB, more than some GPU machines take (docs/gpu-validation.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-bundle}
shift $(( $# < 2 ? $# : 2 ))
only=("$@")
[ -x "$build/bin/axonguide" ] || { echo "bundle.sh: $build/bin/axonguide not built" >&2; exit 2; }
# The CUDA engine is a plugin that the command loads (accel/src/cuda_plugin.hpp): built here
# if it is not yet, and carried as lib/libaxg_cuda.so, where bin/axonguide looks for it.
cmake --build "$build" --target axg_cuda -j"$(nproc)" >/dev/null ||
  { echo "bundle.sh: the CUDA plugin (target axg_cuda) could not be built in $build: configured without nvcc?" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out/bin" "$out/tests" "$out/lib" "$out/node_modules/three/build" \
         "$out/node_modules/three/examples/jsm/controls" "$out/validate" "$out/tests/app"
cp "$build/bin/axonguide" "$out/bin/"
cp "$build/lib/libaxg_cuda.so" "$out/lib/"
if [ ${#only[@]} -eq 0 ]; then
  for t in "$build"/tests/*_test; do [ -x "$t" ] && cp "$t" "$out/tests/"; done
else
  for t in "${only[@]}"; do
    [ -x "$build/tests/$t" ] || { echo "bundle.sh: $build/tests/$t not built" >&2; exit 2; }
    cp "$build/tests/$t" "$out/tests/"
  done
fi
# Libraries from ldd, except the C runtime and the dynamic loader (the target has its own).
for f in "$out"/bin/* "$out"/tests/*_test "$out"/lib/libaxg_cuda.so; do
  ldd "$f" | awk '/=> \// {print $3}'
done | sort -u | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*|libgcc_s.so*) ;;
    *) cp -L "$lib" "$out/lib/" ;;
  esac
done
cp -r scenes data viewer "$out/"
cp -r validate/plots "$out/validate/"
cp -r tests/data "$out/tests/"
cp tests/app/*.py "$out/tests/app/"
if [ -f node_modules/three/package.json ]; then
  cp node_modules/three/package.json "$out/node_modules/three/"
  cp node_modules/three/build/three.module.js node_modules/three/build/three.core.js "$out/node_modules/three/build/"
  cp node_modules/three/examples/jsm/controls/OrbitControls.js "$out/node_modules/three/examples/jsm/controls/"
fi
cat > "$out/env.sh" <<'ENV'
# Sourced by the bundle's scripts: library and asset paths of this bundle.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export AXG_SOURCE_DIR="$here" AXG_BINARY="$here/bin/axonguide" AXG_PLOTS_DIR="$here/validate/plots"
export AXG_VIEWER_DIR="$here/viewer" AXG_THREE_DIR="$here/node_modules/three"
ENV
cat > "$out/axonguide" <<'RUN'
#!/usr/bin/env bash
source "$(dirname "$0")/env.sh"
exec "$here/bin/axonguide" "$@"
RUN
cp scripts/bundle-run-tests.sh "$out/run-tests.sh"
chmod +x "$out/axonguide" "$out/run-tests.sh"
du -sh "$out" | awk '{print "bundle.sh: " $2 " is " $1}'
