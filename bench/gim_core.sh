#!/usr/bin/env bash
# gim-remesh on its two map cores, one job at a time: the default
# (SurfaceMap) and --core symmetric (InterSurfaceMap, the octahedron as a side
# that never refines). Per model and metric: wall and user seconds, peak
# memory, the image's efficiency (square and octahedron domains), flipped
# triangles and PSNR, the map's symmetric and one-way efficiencies, and the
# seconds of the kept map's refinement (from the symmetric core's takeover
# at 1000 vertices, or from its coarse candidate on the default core: the
# report's seconds_refine of the kept entry of map_variants); the paper's
# Table 1 beside the equilateral rows. Prints a Markdown table.
#   bench/gim_core.sh > table.md
#   MODELS="bunny_small" METRICS=equilateral SIZE=129 bench/gim_core.sh
#   BEFORE=/path/to/older/gim-remesh bench/gim_core.sh   # also its two
#     cores, in the same run (a before/after comparison on one machine)
source "$(dirname "$0")/common.sh"
models="${MODELS-bunny_small gargoyle bunny}"
metrics="${METRICS-right-isosceles equilateral}"
size="${SIZE-257}"

echo "gim-remesh, default core against --core symmetric: $(nproc) cores, commit $commit, size $size, one job at a time."
echo "Image efficiency: square / octahedron domain; map: symmetric and domain -> surface efficiency."
echo "Paper (Table 1, equilateral octahedron): bunny 0.717 / 79.9 dB, gargoyle 0.679 / 79.3 dB (octahedron efficiency / PSNR)."
echo
echo "| model | metric | core | wall s | user s | peak MB | refine s | image eff. square | octahedron | flips | PSNR dB | map symmetric | map → |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for m in $models; do
  for metric in $metrics; do
    for core in ${BEFORE:+surface-map-before} surface-map ${BEFORE:+symmetric-before} symmetric; do
      tag="$m-$metric-$core"
      exe="$bin/gim-remesh"
      [ "${core%-before}" != "$core" ] && exe="$BEFORE"
      /usr/bin/time -f '%e %U %M' -o "$work/$tag.time" "$exe" "$models_dir/$m.obj" \
        -o "$work/$tag.exr" --size "$size" --metric "$metric" --core "${core%-before}" \
        --report "$work/$tag.json" -q >"$work/$tag.out" 2>&1 || true
      python3 - "$work/$tag.json" "$work/$tag.time" "$m" "$metric" "$core" <<'PY'
import json, sys
path, timing, model, metric, core = sys.argv[1:]
# (the last line: a failed command's status comes first)
lines = open(timing).read().strip().splitlines() or [""]
wall, user, kb = (lines[-1].split() + ["-", "-", "0"])[:3]
try:
    r = json.load(open(path))
    i, m = r["image"], r["map"]
    kept = [v for v in r.get("map_variants", []) if v.get("kept")]
    refine = f"{kept[0]['seconds_refine']:.1f}" if kept and "seconds_refine" in kept[0] else "-"
    cells = [refine, f"{i['efficiency_square']:.4f}", f"{i['efficiency_octahedron']:.4f}",
             str(i["flipped_triangles"]), f"{r['distance']['psnr_db']:.2f}",
             f"{m['symmetric_efficiency']:.4f}", f"{m['efficiency_domain_to_surface']:.4f}"]
except (OSError, ValueError, KeyError):
    cells = ["-", "failed"] + ["-"] * 5
mb = f"{int(kb) / 1024:.0f}" if kb.isdigit() and int(kb) > 0 else "-"
print("| " + " | ".join([model, metric, core, wall, user, mb] + cells) + " |")
PY
    done
  done
done
