#!/usr/bin/env bash
# ism-partition on the pairs of issue 16: every pair of ../shared/pairs with
# its landmarks, the model pairs without pairs (automatic features), fewer
# pairs than needed (4 of cat/horse, 1 on genus 1 and 2), and the timing row:
# bunny <-> dragon (~64K faces each) with the 6 pairs of
# bench/data/bunny__dragon.pairs.txt (and with the 6 anatomical pairs of
# bench/data/bunny__dragon.landmarks.txt). Each run's wall time, CPU time and peak
# memory come from /usr/bin/time -v. Prints a Markdown table; needs python3.
#   bench/partition_pairs.sh > docs/results-partition.md
#   ONLY="bunny_dragon" bench/partition_pairs.sh     # one row
source "$(dirname "$0")/common.sh"
pairs_dir="$root/../shared/pairs"
rows=()
add() {  # name A B [pairs file]
  if [ -n "${ONLY:-}" ] && [ "$1" != "$ONLY" ]; then return; fi
  rows+=("$1")
  local args=("$2" "$3" --report "$work/$1.json" -q)
  [ -n "${4:-}" ] && args+=(--features "$4")
  if ! /usr/bin/time -v -o "$work/$1.time" "$bin/ism-partition" "${args[@]}" 2>"$work/$1.err"; then
    echo "{}" >"$work/$1.json"
  fi
}
for p in cat__horse rabbit0__rabbit1 hand_plain__hand_vulcan plane61__bird248 vase_A__vase_B \
    bumpy_cube_A__bumpy_cube_B; do
  add "$p" "$pairs_dir/${p%%__*}.obj" "$pairs_dir/${p##*__}.obj" "$pairs_dir/$p.pairs.txt"
done
for p in teapot__cup mug__cup bob__torus double_torus__eight_loop2 eight_loop2__feline \
    spot__bunny_small max_planck__igea face__camelhead venus_loop2__mannequin_devil; do
  add "$p" "$models_dir/${p%%__*}.obj" "$models_dir/${p##*__}.obj"
done
grep -v '^#' "$pairs_dir/cat__horse.pairs.txt" | head -4 >"$work/cat4.txt"
add "cat__horse (4 pairs)" "$pairs_dir/cat.obj" "$pairs_dir/horse.obj" "$work/cat4.txt"
grep -v '^#' "$pairs_dir/vase_A__vase_B.pairs.txt" | head -1 >"$work/vase1.txt"
add "vase_A__vase_B (1 pair)" "$pairs_dir/vase_A.obj" "$pairs_dir/vase_B.obj" "$work/vase1.txt"
echo "0 0" >"$work/one.txt"
add "double_torus__eight_loop2 (1 pair: vertex 0, 0)" "$models_dir/double_torus.obj" \
  "$models_dir/eight_loop2.obj" "$work/one.txt"
add "bunny_dragon" "$models_dir/bunny.obj" "$models_dir/dragon.obj" \
  "$root/bench/data/bunny__dragon.pairs.txt"
add "bunny_dragon (landmarks)" "$models_dir/bunny.obj" "$models_dir/dragon.obj" \
  "$root/bench/data/bunny__dragon.landmarks.txt"
printf '%s\n' "${rows[@]}" >"$work/rows"
python3 - "$work" "$commit" "$root" <<'PY'
import json, os, platform, re, sys
work, commit, root = sys.argv[1], sys.argv[2], sys.argv[3]
rows = open(os.path.join(work, "rows")).read().splitlines()
sys.path.insert(0, os.path.join(root, "bench"))
from gnu_time import time_of as gnu_time
def time_of(name):
    return gnu_time(os.path.join(work, name + ".time"))
print(f"ism-partition: compatible networks and both progressive meshes; {os.cpu_count()} cores "
      f"({platform.machine()}), commit {commit}. Wall and CPU seconds and peak memory of the "
      "whole run (read, check, partition, progressive meshes, validation) from /usr/bin/time -v; "
      "`partition` and `PMs` are the report's stage times. `valid` = both networks valid "
      "against the base, both bases identical to it, both progressive meshes replay exactly.")
print()
print("| pair | genus | loops | faces A / B | given | added | base V / E / F | Steiner A / B | partition s | PMs s | wall s | CPU s | peak MB | valid |")
print("|---|---:|---:|---|---:|---:|---|---|---:|---:|---:|---:|---:|---|")
for name in rows:
    r = json.load(open(os.path.join(work, name + ".json")))
    wall, cpu, mb = time_of(name)
    if "partition" not in r:
        err = open(os.path.join(work, name + ".err")).read().strip().replace("|", "/")
        print(f"| {name} | failed: {err} |||||||||||||")
        continue
    p = r["partition"]
    c = [i["check"] for i in r["inputs"]]
    ok = all(p["checks"].values())
    b = p["base_mesh"]
    print(f"| {name} | {p['genus']} | {p['boundary_loops']} | {c[0]['faces']} / {c[1]['faces']} "
          f"| {p['features_given']} | {p['features_added']} | {b['vertices']} / {b['edges']} / {b['faces']} "
          f"| {p['a']['steiner_vertices']} / {p['b']['steiner_vertices']} "
          f"| {r['seconds']['partition']:.2f} | {r['seconds']['progressive meshes']:.2f} "
          f"| {wall:.2f} | {cpu:.2f} | {mb:.0f} | {'yes' if ok else 'NO'} |")
print()
print("Rows: the six pairs of `../shared/pairs` with all their landmarks; the model pairs of issue 16 "
      "without pairs (automatic features: four on genus 0 counting each boundary loop's centre, "
      "one on genus 1 and 2, each pair = the vertex farthest from the features there are, matched "
      "on the other surface by its geodesic distances to them); fewer pairs than needed (the first "
      "4 of cat/horse, the first of the vase, vertex 0 of both genus-2 models); and `bunny_dragon`, "
      "the timing case (~64K faces each, the 6 pairs of `bench/data/bunny__dragon.pairs.txt`: each "
      "model's extreme vertices along -x, +x, -y, +y, -z, +z, a fixed choice, not anatomical; "
      "`(landmarks)`: the 6 anatomical pairs of `bench/data/bunny__dragon.landmarks.txt`). "
      "`added` counts automatic features and those the tracing adds (on cycles that would close on "
      "one feature or join joined ones, on splitting paths between joined features, at boundary "
      "clip points); the report lists each with its origin. The machine is shared: wall times "
      "follow its load, the CPU column does not.")
PY
