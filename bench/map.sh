#!/usr/bin/env bash
# The octahedral map on every closed genus-0 model of ../shared/models:
# partition + progressive mesh (issue 3) and the map core (issue 4).
#   bench/map.sh [equilateral|right_isosceles]
source "$(dirname "$0")/common.sh"
metric="${1:-right_isosceles}"
echo "Octahedral map, $metric metric, $(nproc) cores, commit $commit. Times in seconds, memory in MB."
echo "One map per model with the library's defaults (MapOptions: symmetric energy, relaxed cone moves; RefineOptions: level sweeps, local relaxation, final sweeps); the tools add variants and weights on top."
echo "Efficiency: one-way domain->surface (fwd), surface->domain (bwd), symmetric (sym)."
echo "Fast path: optimisations whose one-ring lay inside one face of M¹."
echo "Discs: disc re-embeddings kept / tried (RefineOptions: outlier discs and discs in local relaxation)."
echo "Meta-mesh (map/meta_mesh.hpp): the map in symmetric form; its pieces (cells of the overlay); the time to build it, validate it from both sides and measure it from its pieces; valid: from both sides, with the pieces' symmetric efficiency equal to the map's (1e-9)."
echo "Queries (MetaMeshSampler, indexed from the pieces validation cut): sample 1025²: the 1025x1025 octahedral geometry image, domain -> surface (threads as gim-remesh); back 1025²: as many points surface -> domain, one thread. Peak memory includes the image (25 MB)."
echo
echo "Partition: all candidate networks; pm + choice: their progressive meshes and coarse maps (1000 vertices)."
echo
echo "| model | faces | Steiner | networks | partition | pm + choice | refine | validate | total | peak MB | valid | fwd | bwd | sym | fast path | discs | sample 1025² s | back 1025² s | meta-mesh pieces | meta-mesh s | meta-mesh valid |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
for m in bunny spot gargoyle dragon max_planck igea nefertiti fandisk sphere cube bunny_small; do
  "$bin/map_bench" "$models_dir/$m.obj" "$metric" || true
done
