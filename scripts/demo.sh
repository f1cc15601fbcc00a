#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the main job on a bundled model:
# an octahedral geometry image of models/blob.obj, with its remesh, preview
# and report, in out/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build="${BUILD_DIR:-$root/build}"
mkdir -p "$root/out"
"$build/bin/gim-remesh" "$root/models/blob.obj" -o "$root/out/blob.exr" \
  --normals "$root/out/blob_normals.exr" --mesh "$root/out/blob_remesh.obj" \
  --preview "$root/out/blob.png" --report "$root/out/blob.json"
echo "outputs in out/: blob.exr (geometry image), blob_normals.exr, blob_remesh.obj, blob.png (preview), blob.json (report)" >&2
