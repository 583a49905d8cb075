#!/usr/bin/env bash
# `cmake --install BUILD --prefix P`, then the installed command run from elsewhere:
# it reads its data from P/share/axonguide (not the source tree), runs, draws and plots;
# and a bare copy of the binary, with no data folder at all, still draws (the viewer is
# compiled in). Usage: check_install.sh BUILD_DIR
set -euo pipefail
build=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/p" > "$tmp/install.log"
cd "$tmp"
unset AXG_SOURCE_DIR AXG_VIEWER_DIR AXG_THREE_DIR AXG_PLOTS_DIR
exe="$tmp/p/bin/axonguide"
data=$("$exe" --version | sed -n 's/^data: //p')
[ "$data" = "$tmp/p/share/axonguide" ] || { echo "installed command reads data from '$data', not $tmp/p/share/axonguide"; exit 1; }
for f in scenes/default.json data/golden viewer/template.html viewer/plot_run.py three/build/three.module.js validate/plots/common.py; do
  [ -e "$data/$f" ] || { echo "not installed: share/axonguide/$f"; exit 1; }
done
"$exe" run "$data/scenes/paper-direct-100.json" --out run -q
"$exe" verify run > /dev/null
"$exe" view run > /dev/null
grep -q 'data:text/javascript;base64,' run/view.html || { echo "view.html has no inlined three.js"; exit 1; }
"$exe" plot run > /dev/null
[ -s run/growth.png ] || { echo "plot wrote no growth.png"; exit 1; }
"$exe" golden check > /dev/null
# The Python package, when the build made it: imported from the prefix, away from the
# build tree, and run.
if [ -d "$build/python/axonguide" ]; then
  PYTHONPATH="$tmp/p/lib/python3/dist-packages" /usr/bin/python3 - "$tmp/p" "$data" <<'PY'
import sys, axonguide
prefix, data = sys.argv[1], sys.argv[2]
assert axonguide.__file__.startswith(prefix), axonguide.__file__
r = axonguide.run(data + "/scenes/paper-direct-100.json", threads=1)
assert len(r.neurons) == 100, len(r.neurons)
PY
fi
# A copy of the binary alone: no share/ beside it, and no source tree to fall back to.
mkdir bare && cp "$exe" bare/
AXG_SOURCE_DIR=/nonexistent bare/axonguide view run > /dev/null
AXG_SOURCE_DIR=/nonexistent bare/axonguide plot run > /dev/null
echo "installed and relocated command: data from share/axonguide, run, verify, view, plot, golden check, Python package: ok"
