#!/usr/bin/env bash
# Fuzzes the readers and the mesh checks with libFuzzer (Debian's clang-14)
# under AddressSanitizer + UndefinedBehaviorSanitizer, one target after the
# other, each for SECONDS (default 60):
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: obj off ply stl features
#                                              meta_mesh exr mesh_check (default all)
#
# Each target starts from its committed seed corpus (fuzz/corpus/TARGET) and the
# regression files of tests/data/hostile, mutates with its format's keywords
# (fuzz/dict/TARGET.dict), and grows a working corpus in
# $FUZZ_BUILD_DIR/corpus/TARGET (kept between runs). A crash, a sanitizer
# report, an input that takes more than 10 s (a hang) or more than 1 GB (a
# memory bomb) is a finding: its input is saved under
# $FUZZ_BUILD_DIR/findings/TARGET and the script exits 1 after the last target.
# Prints one line per target: executions, corpus size, findings.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(obj off ply stl features meta_mesh exr mesh_check)
fi

"$root/scripts/install-deps.sh" clang-14 libclang-rt-14-dev
cmake -S "$root/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_BUILD_TYPE=None ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} >/dev/null
if ! cmake --build "$build" -j "${JOBS:-2}" --target $(printf 'fuzz_%s ' "${targets[@]}") \
  >"$build/build.log" 2>&1; then
  tail -n 40 "$build/build.log" >&2
  echo "fuzz: the fuzz targets did not build (log: $build/build.log)" >&2
  exit 1
fi

# Inputs of the hostile regression files for each target.
seeds_of() {
  case "$1" in
    obj | off | ply | stl) find "$root/tests/data/hostile" -iname "*.$1" 2>/dev/null ;;
    features) find "$root/tests/data/hostile" -name "*features*.txt" 2>/dev/null ;;
    meta_mesh) find "$root/tests/data/hostile" -name "*meta_mesh*.txt" 2>/dev/null ;;
    exr) find "$root/tests/data/hostile" -name "*.exr" 2>/dev/null ;;
  esac
}

export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
failed=0
printf '%-11s %12s %10s %8s %9s\n' target executions "exec/s" corpus findings
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target"
  findings="$build/findings/$target"
  mkdir -p "$corpus" "$findings"
  cp -n "$root/fuzz/corpus/$target"/* "$corpus"/ 2>/dev/null || true
  while IFS= read -r seed; do
    [ -n "$seed" ] && cp -n "$seed" "$corpus/regression-$(basename "$seed")"
  done < <(seeds_of "$target")
  dict=()
  if [ -f "$root/fuzz/dict/$target.dict" ]; then dict=(-dict="$root/fuzz/dict/$target.dict"); fi
  log="$build/$target.log"
  before=$(find "$findings" -type f | wc -l)
  status=0
  nice "$build/fuzz_$target" "$corpus" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=1024 -malloc_limit_mb=1024 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$findings/" "${dict[@]}" >"$log" 2>&1 || status=$?
  after=$(find "$findings" -type f | wc -l)
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  printf '%-11s %12s %10s %8s %9s\n' "$target" "${executions:-?}" "${rate:-?}" \
    "$(find "$corpus" -type f | wc -l)" "$((after - before))"
  if [ "$status" -ne 0 ] || [ "$after" -gt "$before" ]; then
    echo "fuzz: $target: finding (exit $status), see $log and $findings" >&2
    grep -m 5 -E "ERROR|runtime error|SUMMARY|timeout|out-of-memory" "$log" >&2 || true
    failed=1
  fi
done
exit "$failed"
