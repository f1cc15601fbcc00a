#!/usr/bin/env bash
# semireg on shared models of every genus, with decimated bases of 50, 100
# and 200 vertices, at levels 4 and 5: faces, base size, time, peak memory,
# one-way map efficiency (base -> surface), PSNR of the remesh; the paper's
# anchors next to bunny (§6.2: one-way efficiency 0.915 for the semi-regular
# bunny, 0.800 for Guskov et al.'s GSP). Prints a Markdown table; needs python3.
#   bench/semireg.sh > docs/results-semireg.md
#   MODELS="bunny_small" SIZES="100" bench/semireg.sh    # a quick subset
# Each level is a separate run (the map is computed twice); times and memory
# are those of the level-4 run.
source "$(dirname "$0")/common.sh"
models="${MODELS:-bunny spot torus rocker_arm double_torus eight_loop2}"
sizes="${SIZES:-50 100 200}"
for m in $models; do
  for s in $sizes; do
    for k in 4 5; do
      tag="$m-$s-$k"
      if ! "$bin/semireg" -q "$models_dir/$m.obj" -o "$work/$tag.ply" --base-size "$s" --levels "$k" \
          --report "$work/$tag.json" 2>"$work/$tag.err"; then
        echo "{}" >"$work/$tag.json"
      fi
      rm -f "$work/$tag.ply"
    done
  done
done
python3 - "$work" "$models" "$sizes" "$commit" <<'PY'
import json, os, platform, sys
work, models, sizes, commit = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4]
paper = {"bunny": "0.915 (GSP 0.800)"}
def load(tag):
    with open(os.path.join(work, tag + ".json")) as f:
        return json.load(f)
print(f"semireg, decimated bases (`--base-size`), equilateral base faces, features released; "
      f"{os.cpu_count()} cores ({platform.machine()}), commit {commit}. Times in seconds, memory in MB (level-4 run).")
print()
print("Bases: four decimations (isotropic; isotropic with valences towards 6; isotropic with valences from curvature; quadric) "
      "and, where valid, the same vertices connected by their Voronoi regions' dual; each partitioned and mapped to 5000 "
      "vertices (two at a time), the lowest energy kept (`base` column). "
      "`map` includes the progressive meshes and the choice.")
print()
print("| model | genus | faces | base V / F | base | decimate | partition | map | total | peak MB | valid | one-way eff. | symmetric eff. | PSNR dB L4 | PSNR dB L5 | paper one-way eff. |")
print("|---|---:|---:|---|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|")
for m in models:
    for s in sizes:
        r, r5 = load(f"{m}-{s}-4"), load(f"{m}-{s}-5")
        if not r or "map" not in r:
            err = open(os.path.join(work, f"{m}-{s}-4.err")).read().strip().replace("|", "/")
            print(f"| {m} | | | {s} | failed: {err} ||||||||||||")
            continue
        c = r["inputs"][0]["check"]
        t = r["seconds"]
        psnr5 = f"{r5['distance']['psnr_db']:.1f}" if r5 and "distance" in r5 else "failed"
        print(f"| {m} | {c['genus']} | {c['faces']} | {r['base']['vertices']} / {r['base']['faces']} "
              f"| {r['base'].get('chosen', '')} | {t.get('base', 0):.2f} | {t['partition']:.2f} | {t['map']:.2f} | {t['total']:.2f} "
              f"| {r['peak_memory_mb']:.0f} | {'yes' if r['map']['valid'] else 'NO'} "
              f"| {r['map']['efficiency_domain_to_surface']:.3f} | {r['map']['symmetric_efficiency']:.3f} "
              f"| {r['distance']['psnr_db']:.1f} | {psnr5} | {paper.get(m, '')} |")
PY
