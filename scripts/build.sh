#!/usr/bin/env bash
# Configures and builds ism (Release) into build/ unless BUILD_DIR says otherwise.
# Extra arguments go to CMake's configure step, e.g. -DISM_SANITIZE=ON.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" "$@" >/dev/null
# Two jobs: CGAL translation units take about 1 GB each to compile.
cmake --build "$build" -j "${JOBS:-2}"
