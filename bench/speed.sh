#!/usr/bin/env bash
# Issue 18's speed table: each tool end to end on the models the issue
# names, one job at a time, wall and user seconds, peak memory and the
# report's stages, next to the issue's targets and the spherical pipeline
# (PM + SphereParam + SphereSample, measured on this machine when the issue
# was filed). With BEFORE=dir (an older build's bin/), each run is made with
# both builds, alternating, and the outputs are compared byte for byte:
# a before/after comparison in one run on one machine.
#   bench/speed.sh > table.md
#   BEFORE=/path/to/old/build/bin RUNS="gim:bunny semireg:bunny" bench/speed.sh
source "$(dirname "$0")/common.sh"
runs="${RUNS-gim:sphere gim:blob20k gim:cube gim:bunny gim:dragon semireg:bunny torus:teapot}"
"$bin/ism-genmesh" blob --faces 20000 --seed 1 -o "$work/blob20k.obj" >/dev/null

echo "Speed end to end ($(nproc) cores, commit $commit${BEFORE:+, against $BEFORE}), one job at a time."
echo "gim-remesh at 257², semireg --base-size 100, torus-remesh with the model's 3x3 features."
echo
echo "| run | build | wall s | user s | peak MB | stages s (report) | same output | target | spherical pipeline |"
echo "|---|---|---:|---:|---:|---|---|---|---|"
for run in $runs; do
  tool="${run%%:*}" model="${run#*:}"
  input="$models_dir/$model.obj"
  [ "$model" = blob20k ] && input="$work/blob20k.obj"
  case "$tool" in
    gim) exe=gim-remesh ext=exr args=() ;;
    semireg) exe=semireg ext=obj args=(--base-size 100) ;;
    torus) exe=torus-remesh ext=obj args=(--features "$models_dir/${model}_features_3x3.txt") ;;
  esac
  case "$tool:$model" in
    gim:bunny) target="≤ 15 s" sph="17.1 s / 119 MB" ;;
    gim:dragon) target="≤ 16 s" sph="18.0 s / 116 MB" ;;
    gim:sphere) target="≤ 1.2 s" sph="1.3 s / 82 MB" ;;
    gim:blob20k) target="≤ 5 s" sph="4.4 s / 88 MB" ;;
    gim:cube) target="≤ 3 s" sph="" ;;
    semireg:bunny) target="≤ 8 s" sph="" ;;
    torus:teapot) target="≤ 10 s" sph="" ;;
    *) target="" sph="" ;;
  esac
  for build in ${BEFORE:+before} now; do
    dir="$bin"
    [ "$build" = before ] && dir="$BEFORE"
    tag="$tool-$model-$build"
    /usr/bin/time -f '%e %U %M' -o "$work/$tag.time" "$dir/$exe" "$input" "${args[@]}" \
      -o "$work/$tag.$ext" --report "$work/$tag.json" -q >/dev/null 2>&1 || true
    same=""
    if [ "$build" = now ] && [ -n "${BEFORE:-}" ]; then
      if cmp -s "$work/$tool-$model-before.$ext" "$work/$tag.$ext"; then same=yes; else same=**no**; fi
    fi
    python3 - "$work/$tag.json" "$work/$tag.time" "$tool $model" "$build" "$same" "$target" "$sph" <<'PY'
import json, sys
path, timing, name, build, same, target, sph = sys.argv[1:]
lines = open(timing).read().strip().splitlines() or [""]
wall, user, kb = (lines[-1].split() + ["-", "-", "0"])[:3]
try:
    seconds = json.load(open(path))["seconds"]
    stages = ", ".join(f"{k} {v:.1f}" for k, v in seconds.items() if k != "total" and v >= 0.3)
except (OSError, ValueError, KeyError):
    stages = "failed"
print(f"| {name} | {build} | {wall} | {user} | {int(kb) / 1024:.0f} | {stages} | {same} | {target} | {sph} |")
PY
  done
done
