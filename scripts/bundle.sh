#!/usr/bin/env bash
# Makes a relocatable bundle of the built binaries for a machine that has a GPU but none
# of our Debian libraries (a GPU cluster node): the command, the test and benchmark
# binaries, the CTest files, and every shared library they need that is not part of the
# C runtime. Run them with LD_LIBRARY_PATH=<bundle>/lib.
#   scripts/bundle.sh [BUILD_DIR] [BUNDLE_DIR]      (defaults: build, bundle)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-bundle}
[ -x "$build/bin/axonguide" ] || { echo "bundle.sh: $build/bin/axonguide not built" >&2; exit 2; }
rm -rf "$out"
mkdir -p "$out/bin" "$out/tests" "$out/lib"
cp "$build/bin/axonguide" "$out/bin/"
for t in "$build"/tests/*_test; do [ -x "$t" ] && cp "$t" "$out/tests/"; done
# Libraries from ldd, except the C runtime and the dynamic loader (the target has newer ones).
for f in "$out"/bin/* "$out"/tests/*; do
  ldd "$f" | awk '/=> \// {print $3}'
done | sort -u | while read -r lib; do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*|libgcc_s.so*) ;;
    *) cp -L "$lib" "$out/lib/" ;;
  esac
done
# Scenes and data the tests read; run-tests.sh points AXG_SOURCE_DIR at this copy.
cp -r scenes "$out/"
[ -d data ] && cp -r data "$out/"
cp -r tests/data "$out/tests/data" 2>/dev/null || true
cat > "$out/run-tests.sh" <<'RUN'
#!/usr/bin/env bash
# Runs every test binary of the bundle (GPU tests included); prints one line per binary.
set -u
here=$(cd "$(dirname "$0")" && pwd)
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export AXG_SOURCE_DIR="$here" AXG_BINARY="$here/bin/axonguide"
status=0
for t in "$here"/tests/*_test; do
  if "$t" "$@" > "$t.log" 2>&1; then echo "PASS $(basename "$t")"; else echo "FAIL $(basename "$t") (see $t.log)"; status=1; fi
done
exit $status
RUN
chmod +x "$out/run-tests.sh"
du -sh "$out" | awk '{print "bundle.sh: " $2 " is " $1}'
