#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the main job on a bundled model.
# (Until gim-remesh can map a surface, the main job is the input check.)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${BUILD_DIR:-$root/build}"
mkdir -p "$root/out"
"$build/bin/ism-info" "$root/models/blob.obj" --report "$root/out/blob-info.json"
echo "report written to out/blob-info.json" >&2
