#!/usr/bin/env bash
# Installs the dependencies, builds everything and runs the whole test suite.
# Tests that need ../shared/models skip with a message when it is absent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$@"
build="${BUILD_DIR:-$root/build}"
ctest --test-dir "$build" --output-on-failure -j "${JOBS:-2}"
