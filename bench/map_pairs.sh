#!/usr/bin/env bash
# ism-map on pairs of closed surfaces: every pair of ../shared/pairs with its
# landmarks as features (released half way, the default; held; released from
# the start), the closed model pairs of the
# partition benchmark (automatic features; teapot <-> cup also with the 12
# pairs of bench/data/teapot__cup.pairs.txt), and cat <-> horse with 4 of its
# 17 landmarks as features (the other 13 measured). Each run's wall time, CPU
# time and peak memory from /usr/bin/time -v, the measures from the report,
# the landmark errors from the correspondence files, the overlay pair
# checked by overlay_check (bench/overlay_check.cpp). Prints a Markdown table
# next to the published figures; needs python3.
#   bench/map_pairs.sh > table.md
#   ONLY="vase_A__vase_B" bench/map_pairs.sh      # one row
#   TIMEOUT=1800 bench/map_pairs.sh               # seconds per run (default 1200)
source "$(dirname "$0")/common.sh"
pairs_dir="$root/../shared/pairs"
timeout="${TIMEOUT:-1200}"
rows=()
add() {  # name A B pairs-file(or -) landmarks-file(or -) [ism-map options...]
  local name="$1" a="$2" b="$3" pairs="$4" landmarks="$5"
  shift 5
  if [ -n "${ONLY:-}" ] && [ "${name%% (*}" != "$ONLY" ]; then return; fi
  rows+=("$name")
  local key="${#rows[@]}"
  local args=("$a" "$b" -o "$work/$key" --report "$work/$key.json" -q "$@")
  [ "$pairs" != "-" ] && args+=(--features "$pairs")
  printf '%s\n%s\n%s\n%s\n' "$name" "$a" "$b" "$landmarks" >"$work/$key.row"
  if /usr/bin/time -v -o "$work/$key.time" timeout "$timeout" "$bin/ism-map" "${args[@]}" \
      2>"$work/$key.err"; then
    # The overlay pair re-read and checked independently of the map code.
    "$bin/overlay_check" "$a" "$b" "$work/$key" >"$work/$key.check" 2>&1 || true
  else
    echo "{}" >"$work/$key.json"
  fi
  rm -f "$work/$key"_on_?.obj  # large; the correspondences are kept
}
for p in vase_A__vase_B hand_plain__hand_vulcan plane61__bird248 rabbit0__rabbit1 cat__horse \
    bumpy_cube_A__bumpy_cube_B; do
  add "$p" "$pairs_dir/${p%%__*}.obj" "$pairs_dir/${p##*__}.obj" "$pairs_dir/$p.pairs.txt" -
  add "$p (held)" "$pairs_dir/${p%%__*}.obj" "$pairs_dir/${p##*__}.obj" \
    "$pairs_dir/$p.pairs.txt" - --hold-features
  add "$p (released from the start)" "$pairs_dir/${p%%__*}.obj" "$pairs_dir/${p##*__}.obj" \
    "$pairs_dir/$p.pairs.txt" - --release-features-at 0
done
grep -v '^#' "$pairs_dir/cat__horse.pairs.txt" | head -4 >"$work/cat4.txt"
grep -v '^#' "$pairs_dir/cat__horse.pairs.txt" | tail -n +5 >"$work/cat13.txt"
add "cat__horse (4 of 17 landmarks)" "$pairs_dir/cat.obj" "$pairs_dir/horse.obj" "$work/cat4.txt" \
  "$work/cat13.txt"
add "teapot__cup (12 pairs)" "$models_dir/teapot.obj" "$models_dir/cup.obj" \
  "$root/bench/data/teapot__cup.pairs.txt" -
add "teapot__cup (12 pairs, held)" "$models_dir/teapot.obj" "$models_dir/cup.obj" \
  "$root/bench/data/teapot__cup.pairs.txt" - --hold-features
for p in teapot__cup mug__cup bob__torus double_torus__eight_loop2 spot__bunny_small; do
  add "$p" "$models_dir/${p%%__*}.obj" "$models_dir/${p##*__}.obj" - -
done
printf '%s\n' "${#rows[@]}" >"$work/count"
python3 - "$work" "$commit" "$timeout" "$root" <<'PY'
import json, math, os, platform, re, sys
work, commit, timeout, root = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
count = int(open(os.path.join(work, "count")).read())
published = {
    "vase_A__vase_B (held)": "Dirichlet 4.60 (Takayama 2022, 9.1 h), 5.00 (Schmidt 2020)",
    "teapot__cup": "efficiency 0.598 released, 0.471 held (paper, 22 features)",
    "teapot__cup (12 pairs)": "efficiency 0.598 released (paper, 22 features)",
    "teapot__cup (12 pairs, held)": "efficiency 0.471 held (paper, 22 features)",
}
sys.path.insert(0, os.path.join(root, "bench"))
from gnu_time import time_of as gnu_time
def time_of(key):
    return gnu_time(os.path.join(work, key + ".time"))
def read_obj(path):
    v = []
    for line in open(path):
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:4]])
    return v
def landmark_error(key, a, b, landmarks):
    # Mean distance (relative to B's bounding-box diagonal) from the image of
    # A's landmark to B's, over the landmarks not given as features.
    pairs = [tuple(int(x) for x in l.split()[:2]) for l in open(landmarks) if l.strip() and not l.startswith("#")]
    vb = read_obj(b)
    lo = [min(p[k] for p in vb) for k in range(3)]
    hi = [max(p[k] for p in vb) for k in range(3)]
    diagonal = math.dist(lo, hi)
    rows = {}
    for line in open(os.path.join(work, key + "_A_to_B.txt")):
        i, j, w = line.split()
        rows.setdefault(int(i), []).append((int(j), float(w)))
    errors = []
    for ia, ib in pairs:
        image = [sum(w * vb[j][k] for j, w in rows[ia]) for k in range(3)]
        errors.append(math.dist(image, vb[ib]) / diagonal)
    return sum(errors) / len(errors), len(errors)
print(f"ism-map: maps between two closed surfaces, both refined on the symmetric core; "
      f"{os.cpu_count()} cores ({platform.machine()}), commit {commit}, at most {timeout} s per run. "
      "Wall and CPU seconds and peak memory from /usr/bin/time -v. Efficiencies: symmetric "
      "(2 / (L2n²(A→B) + L2n²(B→A)), ≤ 1) and one-way; Dirichlet = the symmetric Dirichlet energy "
      "with both areas scaled to 1 = 4 / symmetric efficiency (4 for an isometry). Residual: the "
      "largest distance from a feature's image to its partner, relative to the bounding-box "
      "diagonal (0 when held).")
print()
print("| pair | faces A / B | given / added | refined A / B | overlay triangles | bijection (overlay_check) | wall s | CPU s | peak MB | symmetric | A→B | B→A | Dirichlet | residual | landmarks | published |")
print("|---|---|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|")
for key in map(str, range(1, count + 1)):
    name, a, b, landmarks = open(os.path.join(work, key + ".row")).read().splitlines()
    r = json.load(open(os.path.join(work, key + ".json")))
    wall, cpu, mb = time_of(key)
    pub = published.get(name, "")
    if "map" not in r:
        err = open(os.path.join(work, key + ".err")).read().strip().splitlines()
        err = (err[-1] if err else "timed out").replace("|", "/")
        print(f"| {name} | failed after {wall:.0f} s: {err} ||||||||||||||| {pub} |")
        continue
    m, p = r["map"], r["partition"]
    c = [i["check"] for i in r["inputs"]]
    residual = max([max(f["error_on_b"], f["error_on_a"]) for f in m["feature_residuals"]], default=0)
    lm = ""
    if landmarks != "-":
        mean, n = landmark_error(key, a, b, landmarks)
        lm = f"mean {mean:.4f} over {n}"
    check = open(os.path.join(work, key + ".check")).read().strip()
    try:
        k = json.loads(check)
        worst = max(abs(k[s][f]) for s in ("on_a", "on_b")
                    for f in ("signed_area_error", "unsigned_area_error"))
        flips = k["on_a"]["flipped"] + k["on_b"]["flipped"]
        bij = ("yes" if k["bijective"] else "**NO**") + f" (flipped {flips}, area error {worst:.1e})"
    except ValueError:
        bij = "check failed: " + check.replace("|", "/")
    print(f"| {name} | {c[0]['faces']} / {c[1]['faces']} | {p['features_given']} / {p['features_added']} "
          f"| {m['faces'][0]} / {m['faces'][1]} | {m['overlay']['triangles']} | {bij} | {wall:.1f} | {cpu:.1f} | {mb:.0f} "
          f"| {m['symmetric_efficiency']:.4f} | {m['efficiency_a_to_b']:.4f} | {m['efficiency_b_to_a']:.4f} "
          f"| {m['symmetric_dirichlet']:.3f} | {residual:.4f} | {lm} | {pub} |")
PY
