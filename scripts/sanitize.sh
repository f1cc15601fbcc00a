#!/usr/bin/env bash
# Builds ism-info with AddressSanitizer + UBSan and runs it over every model
# of ../shared/models/bad (and a few good ones) and every hostile regression
# file of tests/data/hostile; any sanitizer report fails.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${SANITIZE_BUILD_DIR:-$root/build-sanitize}"
"$root/scripts/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DISM_SANITIZE=ON \
  -DISM_BUILD_TESTS=OFF -DISM_BUILD_BENCH=OFF -DISM_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build" -j "${JOBS:-2}" --target ism_info
shared="$root/../shared/models"
meshes=("$root"/tests/data/hostile/*.{obj,off,ply,stl})
if [ -d "$shared" ]; then
  meshes+=("$shared"/bad/*.obj "$shared"/bunny_small.obj "$shared"/torus.obj)
else
  echo "sanitize: $shared not found, only tests/data/hostile checked" >&2
fi
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:exitcode=99
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=99
checked=0
for mesh in "${meshes[@]}"; do
  status=0
  "$build/bin/ism-info" "$mesh" >/dev/null 2>"$build/sanitize.log" || status=$?
  if [ "$status" -ne 0 ] && [ "$status" -ne 1 ]; then
    cat "$build/sanitize.log" >&2
    echo "sanitize: ism-info $mesh exited $status" >&2
    exit 1
  fi
  if grep -q "Sanitizer\|runtime error" "$build/sanitize.log"; then
    cat "$build/sanitize.log" >&2
    exit 1
  fi
  checked=$((checked + 1))
done
echo "sanitize: $checked passed, 0 failed"
