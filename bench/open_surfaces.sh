#!/usr/bin/env bash
# gim-remesh on the open genus-0 models of ../shared/models (holes capped,
# README "Open surfaces in geometry images") at SIZE² (default 257): the
# input's loops, the caps' share of the area and of the pixels, validity,
# the map's one-way efficiency on the input surface, image efficiency and
# folds on the remesh, PSNR of the remesh against the input, the remesh's
# loops; venus_loop2 also with the paper's equilateral metric next to its
# Venus (Table 1). Then the cap shapes compared (CAPS, RINGS:HEIGHT, default:
# the fan, the fan cut by 4 flat rings (gim-remesh's default, DEFAULT_CAP),
# 8 flat rings, 4 rings as a dome of height 0.5) on CAP_MODELS.
# Prints Markdown; needs python3.
#   bench/open_surfaces.sh > docs/results-open-surfaces.md
source "$(dirname "$0")/common.sh"
size="${SIZE:-257}"
models="${MODELS:-venus venus_loop2 face camelhead mannequin_devil head_3holes bunny_open}"
cap_models="${CAP_MODELS:-venus_loop2 head_3holes}"
caps="${CAPS:-0:0 4:0 8:0 4:0.5}"
default_cap="${DEFAULT_CAP:-4:0}"
run() {  # name model extra-options...
  local name="$1" m="$2"
  shift 2
  "$bin/gim-remesh" -q "$models_dir/$m.obj" -o "$work/$name.exr" --size "$size" \
    --mesh "$work/$name.obj" --report "$work/$name.json" "$@" || echo "{}" > "$work/$name.json"
}
for m in $models; do run "$m" "$m"; done
run venus_loop2-eq venus_loop2 --metric equilateral
for m in $cap_models; do
  for c in $caps; do
    if [ "$c" = "$default_cap" ] && [ -f "$work/$m.json" ]; then  # the default: run above
      cp "$work/$m.json" "$work/$m-cap-${c/:/-}.json"
    else
      run "$m-cap-${c/:/-}" "$m" --cap-rings "${c%%:*}" --cap-height "${c##*:}"
    fi
  done
done
python3 - "$work" "$commit" "$size" "$models" "$cap_models" "$caps" <<'PY'
import json, os, platform, sys
work, commit, size, models, cap_models, caps = sys.argv[1:]
def load(name):
    return json.load(open(os.path.join(work, name + ".json")))
print(f"gim-remesh on open genus-0 surfaces, {size}x{size}, {os.cpu_count()} cores ({platform.machine()}). Commit {commit}.")
print()
print("Holes are capped by a fan around each loop's centroid cut by 4 flat rings (the default), the closed surface is mapped and sampled, "
      "alpha marks the input surface. Every figure is on the input surface alone: map efficiency domain->surface "
      "over the input's faces, image efficiency (unit square) and folded triangles over the remesh (grid triangles "
      "with alpha 1 at all corners), PSNR of the remesh against the input. Times in seconds.")
print()
print("| model | faces | loops | cap area | cap pixels | total s | valid | map eff. | image eff. | folds | PSNR dB | remesh V / F | remesh loops |")
print("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|---:|")
for m in models.split():
    r = load(m)
    if not r:
        print(f"| {m} | failed |"); continue
    b = r.get("boundary", {})
    c = r["inputs"][0]["check"]
    print(f"| {m} | {c['faces']} | {c['boundary_loops']} | {b.get('cap_area_fraction', 0):.3f} | {b.get('cap_pixel_fraction', 0):.3f} "
          f"| {r['seconds']['total']:.1f} | {'yes' if r['map']['valid'] else 'NO'} | {r['map']['efficiency_domain_to_surface']:.3f} "
          f"| {r['image']['efficiency_square']:.3f} | {r['image']['flipped_triangles']} | {r['distance']['psnr_db']:.1f} "
          f"| {r['image']['remesh_vertices']} / {r['image']['remesh_faces']} | {b.get('remesh_loops')} |")
e = load("venus_loop2-eq")
if e:
    print()
    print("venus_loop2 with `--metric equilateral` (the paper's Table 1 setting; the paper's Venus is a closed "
          "head of another resolution, ours is open at the neck): map efficiency "
          f"{e['map']['efficiency_domain_to_surface']:.3f}, image efficiency on the regular octahedron "
          f"{e['image']['efficiency_octahedron']:.3f}, PSNR {e['distance']['psnr_db']:.1f} dB; paper: 0.947, 83.2 dB.")
print()
print("Cap shapes (`--cap-rings R --cap-height H`: the fan cut by R rings, lifted into a dome of H times the hole's radius):")
print()
print("| model | rings | height | map eff. | image eff. | folds | PSNR dB | cap pixels |")
print("|---|---:|---:|---:|---:|---:|---:|---:|")
for m in cap_models.split():
    for cap in caps.split():
        rings, height = cap.split(":")
        r = load(f"{m}-cap-{rings}-{height}")
        if not r:
            print(f"| {m} | {rings} | {height} | failed |"); continue
        print(f"| {m} | {rings} | {height} | {r['map']['efficiency_domain_to_surface']:.3f} | {r['image']['efficiency_square']:.3f} "
              f"| {r['image']['flipped_triangles']} | {r['distance']['psnr_db']:.1f} | {r['boundary']['cap_pixel_fraction']:.3f} |")
PY
