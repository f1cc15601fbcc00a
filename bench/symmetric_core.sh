#!/usr/bin/env bash
# The symmetric map core (InterSurfaceMap) against SurfaceMap where both
# apply, and on its own for two surfaces: time (user s), peak memory and the
# measures of each run, one job at a time. Prints a Markdown table.
#   bench/symmetric_core.sh > table.md
#   OCTA="sphere cube" SEMIREG="" PAIRS="" bench/symmetric_core.sh   # a subset
# OCTA: models mapped to the octahedron, right isosceles and equilateral
# (`octahedral_map MESH [--equilateral] [--symmetric]`); SEMIREG: models
# mapped to the base semireg chooses at --base-size 100 (written by semireg
# --write-base; `octahedral_map MESH --base B.obj`, every base vertex a
# cone); PAIRS: A:B:V for `inter_surface_map A B --decimate V` (symmetric
# core only). On the octahedron and the bases, SurfaceMap moves cones
# between surface vertices, the symmetric core releases them continuously.
source "$(dirname "$0")/common.sh"
octa="${OCTA-sphere cube bunny_small spot gargoyle fandisk}"
semireg="${SEMIREG-double_torus torus spot}"
pairs="${PAIRS-spot:bunny_small:300 torus:cup:150 double_torus:eight_loop2:300}"

# run TAG CMD...: the command's output and `user-seconds peak-KB` in $work/TAG.*
run() {
  local tag=$1
  shift
  /usr/bin/time -f '%U %M' -o "$work/$tag.time" "$@" >"$work/$tag.out" 2>"$work/$tag.err" || true
}
rows=()
for m in $octa; do
  for metric in right_isosceles equilateral; do
    flag=""
    [ "$metric" = equilateral ] && flag="--equilateral"
    for core in SurfaceMap symmetric; do
      tag="octa-$m-$metric-$core"
      extra=""
      [ "$core" = symmetric ] && extra="--symmetric"
      run "$tag" "$bin/octahedral_map" "$models_dir/$m.obj" $flag $extra
      rows+=("$tag|$m, octahedron $metric|$core")
    done
  done
done
for m in $semireg; do
  "$bin/semireg" -q "$models_dir/$m.obj" --base-size 100 -o "$work/$m-remesh.ply" \
    --write-base "$work/$m-base.obj" 2>/dev/null || continue
  for core in SurfaceMap symmetric; do
    tag="base-$m-$core"
    extra=""
    [ "$core" = symmetric ] && extra="--symmetric"
    run "$tag" "$bin/octahedral_map" "$models_dir/$m.obj" --base "$work/$m-base.obj" $extra
    rows+=("$tag|$m, semireg base 100|$core")
  done
done
for p in $pairs; do
  IFS=: read -r a b v <<<"$p"
  tag="pair-$a-$b-$v"
  run "$tag" "$bin/inter_surface_map" "$models_dir/$a.obj" "$models_dir/$b.obj" --decimate "$v"
  rows+=("$tag|$a ↔ $b, --decimate $v|symmetric (both sides refine)")
done

echo "Symmetric map core against SurfaceMap, $(nproc) cores, commit $commit, one job at a time."
echo "Efficiency: symmetric; one-way domain (or A) -> surface (or B) and back. User seconds, peak MB."
echo
echo "| case | core | user s | peak MB | valid | symmetric eff. | one-way → | one-way ← |"
echo "|---|---|---:|---:|---|---:|---:|---:|"
for row in "${rows[@]}"; do
  IFS='|' read -r tag what core <<<"$row"
  read -r user kb <"$work/$tag.time" || { user="-"; kb=0; }
  python3 - "$work/$tag.out" "$what" "$core" "$user" "$kb" <<'PY'
import re, sys
path, what, core, user, kb = sys.argv[1:]
text = open(path).read()
valid = "yes" if re.search(r"valid( from both sides:)? yes", text) else "no"
m = (re.search(r"efficiency: symmetric ([\d.]+), domain->surface ([\d.]+), surface->domain ([\d.]+)", text)
     or re.search(r"symmetric efficiency ([\d.]+) .*A->B ([\d.]+), B->A ([\d.]+)", text))
sym, fwd, bwd = (m.group(1), m.group(2), m.group(3)) if m else ("-", "-", "-")
mb = f"{int(kb) / 1024:.0f}" if kb.isdigit() and int(kb) > 0 else "-"
print(f"| {what} | {core} | {user} | {mb} | {valid} | {sym} | {fwd} | {bwd} |")
PY
done
