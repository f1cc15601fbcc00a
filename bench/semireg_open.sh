#!/usr/bin/env bash
# semireg on the open models of ../shared/models (README "Open surfaces in
# semi-regular remeshes") with --base-size for each of SIZES (default 50
# 100), level 4: base, boundary points added to it, the caps' share of the
# area, map efficiency on the input surface (one-way and symmetric), folds
# and faces of the remesh (and before folds were re-sampled) and the input's folds by the same measure, PSNR
# against the input, time and peak memory, the remesh's loops; a failure prints the tool's line. TIMEOUT (default 600 s)
# bounds each run. Prints Markdown rows for docs/results-open-surfaces.md.
source "$(dirname "$0")/common.sh"
models="${MODELS:-venus head_3holes camelhead mannequin_devil face bunny_open venus_loop2}"
sizes="${SIZES:-50 100}"
echo "semireg on open surfaces, level 4, $(nproc) cores ($(uname -m)). Commit $commit."
echo
echo "| model | --base-size | base V / F | points | cap area | map eff. (sym.) | flips / faces (at grid points, re-sampled vertices) | input flips | PSNR dB | s | MB | loops in / out |"
echo "|---|---:|---|---:|---:|---|---|---:|---:|---:|---:|---|"
for n in $sizes; do
  for m in $models; do
    name="$m-$n"
    if ! timeout "${TIMEOUT:-600}" "$bin/semireg" -q "$models_dir/$m.obj" --base-size "$n" \
      -o "$work/$name.obj" --report "$work/$name.json" 2> "$work/$name.err"; then
      echo "| $m | $n | failed: $(head -c 200 "$work/$name.err" | tr '\n|' '  ') |"
      continue
    fi
    python3 - "$work/$name.json" "$m" "$n" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); m = r["map"]; b = r["boundary"]
print(f"| {sys.argv[2]} | {sys.argv[3]} | {r['base']['vertices']} / {r['base']['faces']} | {b['base_boundary_points']} "
      f"| {b['cap_area_fraction']:.3f} | {m['efficiency_domain_to_surface']:.3f} ({m['symmetric_efficiency']:.3f}) "
      f"| {r['remesh']['flipped_triangles']} / {r['remesh']['faces']} ({r['remesh'].get('flipped_triangles_at_grid_points', '-')}, {r['remesh'].get('resampled_vertices', '-')}) | {r['remesh']['input_flipped_triangles']} "
      f"| {r['distance']['psnr_db']:.1f} "
      f"| {r['seconds']['total']:.1f} | {r['peak_memory_mb']:.0f} | {b['loops']} / {b['remesh_loops']} |")
PY
  done
done
