#!/usr/bin/env bash
# The octahedral map on every closed genus-0 model of ../shared/models:
# partition + progressive mesh (issue 3) and the map core (issue 4).
#   bench/map.sh [equilateral|right_isosceles]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
bin="${BUILD_DIR:-$root/build}/bin"
models="$root/../shared/models"
metric="${1:-right_isosceles}"
echo "Octahedral map, $metric metric, $(nproc) cores. Times in seconds, memory in MB."
echo "Efficiency: one-way domain->surface (fwd), surface->domain (bwd), symmetric (sym)."
echo "Fast path: optimisations whose one-ring lay inside one face of M¹."
echo
echo "Partition: all candidate networks; pm + choice: their progressive meshes and coarse maps (1000 vertices)."
echo
echo "| model | faces | Steiner | networks | partition | pm + choice | refine | validate | total | peak MB | valid | fwd | bwd | sym | fast path |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|"
for m in bunny spot gargoyle dragon max_planck igea nefertiti fandisk sphere cube bunny_small; do
  "$bin/map_bench" "$models/$m.obj" "$metric" || true
done
