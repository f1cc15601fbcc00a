#!/usr/bin/env bash
# gim-remesh on every closed genus-0 model of ../shared/models at 257²:
# stage times, peak memory, map and image efficiencies, flips, PSNR, next to
# the published figures (paper Table 1; Praun & Hoppe's spherical pipeline as
# the issue measured it). Prints a Markdown table; needs python3 for JSON.
#   bench/gim.sh > docs/results-gim.md
source "$(dirname "$0")/common.sh"
for m in bunny spot gargoyle dragon max_planck igea nefertiti fandisk sphere cube bunny_small; do
  "$bin/gim-remesh" -q "$models_dir/$m.obj" -o "$work/$m.exr" --report "$work/$m.json" || echo "{}" > "$work/$m.json"
  "$bin/gim-remesh" -q "$models_dir/$m.obj" -o "$work/$m-eq.exr" --metric equilateral --report "$work/$m-eq.json" || echo "{}" > "$work/$m-eq.json"
done
python3 - "$work" "$commit" <<'PY'
import json, os, platform, sys
work, commit = sys.argv[1], sys.argv[2]
# Published figures: paper Table 1 (regular octahedron, one-way efficiency and
# PSNR) and the spherical pipeline of Praun & Hoppe measured on the same files
# (square-domain efficiency, flips, PSNR) as issue 5 quotes them.
paper = {"bunny": (0.717, 79.9), "gargoyle": (0.679, 79.3)}
spherical = {"bunny": "0.604 (0.660 best) / 127 / 79.7", "gargoyle": "0.551 / 168 / -",
             "igea": "0.851 / - / -", "spot": "0.615 / - / -"}
models = ["bunny", "spot", "gargoyle", "dragon", "max_planck", "igea", "nefertiti", "fandisk", "sphere", "cube", "bunny_small"]
print(f"gim-remesh, 257x257, {os.cpu_count()} cores ({platform.machine()}). Times in seconds, memory in MB.")
print("Default run (right-isosceles metric): map efficiency domain->surface, image efficiency on the unit square, flipped grid triangles, PSNR of the remesh.")
print("Equilateral run (`--metric equilateral`): image efficiency on the regular octahedron |x|+|y|+|z|=1, as in the paper's Table 1.")
print()
print("`map`: the progressive meshes and coarse maps of every candidate network, then the refinement, for both map variants side by side (inverse-stretch weight 0.1 and 1; the better one-way map is kept, README \"Measures\"). Both runs weight the stretch by curvature (`--curvature-weight 0.5`, the default; the paper's map is plain symmetric stretch).")
print(f"Commit {commit}.")
print()
print("| model | faces | partition | map | sample | total | peak MB | valid | map eff. | square eff. | flips | PSNR dB | spherical (sq. eff. / flips / PSNR) | equilateral: octa eff. / PSNR | paper (octa eff. / PSNR) |")
print("|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|---:|---|")
for m in models:
    r = json.load(open(os.path.join(work, m + ".json")))
    e = json.load(open(os.path.join(work, m + "-eq.json")))
    if not r:
        print(f"| {m} | failed |"); continue
    s = r["seconds"]
    faces = r["inputs"][0]["check"]["faces"]
    p = paper.get(m)
    print(f"| {m} | {faces} | {s['partition']:.2f} | {s['map']:.2f} | {s['sample']:.2f} | {s['total']:.2f} | {r['peak_memory_mb']:.0f} | {'yes' if r['map']['valid'] else 'NO'} "
          f"| {r['map']['efficiency_domain_to_surface']:.3f} | {r['image']['efficiency_square']:.3f} | {r['image']['flipped_triangles']} | {r['distance']['psnr_db']:.1f} "
          f"| {spherical.get(m, '')} | {e['image']['efficiency_octahedron']:.3f} / {e['distance']['psnr_db']:.1f} | {'%.3f / %.1f' % p if p else ''} |" if e else "")
PY
