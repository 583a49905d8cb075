#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, and runs the test suite
# (unit tests, the accelerator's CPU-emulated pipeline, GPU tests that skip without a
# GPU, and the quick validation). The full validation runs with `ctest -L validation`.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh --tests
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2 -LE validation
