#!/usr/bin/env bash
# Builds the project and prints the benchmark tables (never run by the tests).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
"${BUILD_DIR:-$root/build}/bin/bench_measures" --benchmark_counters_tabular=true 2>/dev/null
