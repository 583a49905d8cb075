#!/usr/bin/env bash
# bundle/run-tests.sh [--allow-skip] [GTEST_ARGS...]   (scripts/bundle.sh copies it there)
# The device evidence, one line each (PASS, FAIL or SKIPPED): every test binary of the
# bundle (the gpu tests compare the CUDA engine with the reference byte for byte), the
# golden networks on the reference and on the cuda backend, and `validate gpu`.
# A skip is not a pass: a test binary whose tests skipped (no GPU, no driver), or a check
# that could not run (exit 3), makes the run exit 3 unless --allow-skip is given. Other
# arguments go to the test binaries (e.g. --gtest_filter=...).
# Exit: 0 everything ran and passed, 1 something failed, 3 nothing failed but something
# was skipped (or nothing ran at all). A binary none of whose tests match a --gtest_filter
# prints NONE and counts as neither.
set -u
source "$(dirname "$0")/env.sh"
allow_skip=0
args=()
for a in "$@"; do
  if [ "$a" = --allow-skip ]; then allow_skip=1; else args+=("$a"); fi
done
passed=0 failed=0 skipped=0
allowed=""
[ $allow_skip = 1 ] && allowed=", allowed by --allow-skip"

# From GoogleTest's summary: "[==========] N tests from M test suites ran." and
# "[  SKIPPED ] K tests, listed below:".
gtest_count() {  # LOG PATTERN
  sed -n "s/^\[$2\] \([0-9][0-9]*\) tests\{0,1\}\(,\| from\).*/\1/p" "$1" | tail -n 1
}

for t in "$here"/tests/*_test; do
  [ -x "$t" ] || continue
  name=$(basename "$t")
  "$t" ${args[@]+"${args[@]}"} > "$t.log" 2>&1
  rc=$?
  ran=$(gtest_count "$t.log" "==========")
  skip=$(gtest_count "$t.log" "  SKIPPED ")
  if [ $rc -ne 0 ]; then
    echo "FAIL $name (exit $rc; see $t.log)"; failed=$((failed + 1))
  elif [ -z "$ran" ]; then
    echo "FAIL $name (no GoogleTest summary; see $t.log)"; failed=$((failed + 1))
  elif [ "$ran" -eq 0 ]; then
    echo "NONE $name (no test matched the arguments)"
  elif [ -n "$skip" ] && [ "$skip" -gt 0 ]; then
    echo "SKIPPED $name ($skip of $ran tests skipped$allowed; see $t.log)"; skipped=$((skipped + 1))
  else
    echo "PASS $name ($ran tests)"; passed=$((passed + 1))
  fi
done

# An axonguide command: exit 0 PASS, 3 (cannot run here) SKIPPED with its first message
# line, anything else FAIL.
check() {  # LABEL LOG ARGS...
  local label=$1 log=$2
  shift 2
  "$here/bin/axonguide" "$@" > "$log" 2>&1
  local rc=$?
  if [ $rc -eq 0 ]; then
    echo "PASS $label"; passed=$((passed + 1))
  elif [ $rc -eq 3 ]; then
    echo "SKIPPED $label ($(grep -m 1 -e 'cannot run' -e 'SKIPPED' "$log" | cut -c 1-300)$allowed; see $log)"
    skipped=$((skipped + 1))
  else
    echo "FAIL $label (exit $rc; see $log)"; failed=$((failed + 1))
  fi
}
check "golden check --backend reference" "$here/golden-reference.log" \
  golden check --backend reference --dir "$here/data/golden"
check "golden check --backend cuda" "$here/golden-cuda.log" golden check --backend cuda --dir "$here/data/golden"
check "validate gpu ($here/validation-gpu/report.md)" "$here/validation-gpu.log" \
  validate gpu --report "$here/validation-gpu"

echo "run-tests: $passed passed, $failed failed, $skipped skipped$allowed"
if [ $failed -gt 0 ]; then exit 1; fi
if [ $skipped -gt 0 ] && [ $allow_skip = 0 ]; then
  echo "run-tests: SKIPPED: a skip is not a pass (nothing ran on a GPU for those); --allow-skip accepts it" >&2
  exit 3
fi
if [ $passed -eq 0 ]; then echo "run-tests: nothing ran" >&2; exit 3; fi
exit 0
