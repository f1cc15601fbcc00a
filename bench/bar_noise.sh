#!/usr/bin/env bash
# How much a remesher's figures move when only their rounding does: the
# model translated by k·1e-9 of its bounding box's diagonal (k = 0..RUNS-1;
# a translation the map does not see, but every length it computes rounds
# differently), each copy run through the same command, one job at a time.
# Prints each run's figures and their spread, so that a change which moves
# the outputs can be judged against the spread rather than against one run
# (results-two-surfaces.md, stop 58: bunny square 29-33 flipped triangles).
#   bench/bar_noise.sh > table.md
#   MODEL=gargoyle TOOL=gim-remesh ARGS="--metric equilateral --core symmetric" RUNS=5 \
#     bench/bar_noise.sh
# TOOL is gim-remesh (figures: image efficiency square and octahedron,
# flipped triangles, PSNR) or semireg (the map's efficiency domain ->
# surface, PSNR).
source "$(dirname "$0")/common.sh"
model="${MODEL-bunny}"
tool="${TOOL-gim-remesh}"
args="${ARGS---core symmetric}"
runs="${RUNS-3}"
case "$tool" in
  gim-remesh) ext=exr ;;
  semireg) ext=ply ;;
  *)
    echo "TOOL must be gim-remesh or semireg" >&2
    exit 1
    ;;
esac

echo "$tool $model $args: the model translated by k·1e-9 of its diagonal, k = 0..$((runs - 1)); commit $commit, $(nproc) cores, one job at a time."
echo
echo "| k | efficiency | octahedron | flips | PSNR dB | map s |"
echo "|---:|---:|---:|---:|---:|---:|"
for ((k = 0; k < runs; ++k)); do
  python3 "$root/bench/translate.py" "$models_dir/$model.obj" "$work/$k.obj" "$k"
  # shellcheck disable=SC2086
  "$bin/$tool" "$work/$k.obj" -o "$work/$k.$ext" --report "$work/$k.json" $args -q >/dev/null 2>&1 || true
done
python3 - "$work" "$runs" "$tool" <<'PY'
import json, statistics, sys
work, runs, tool = sys.argv[1], int(sys.argv[2]), sys.argv[3]
rows = []
for k in range(runs):
    try:
        r = json.load(open(f"{work}/{k}.json"))
    except (OSError, ValueError):
        print(f"| {k} | failed | | | | |")
        continue
    if tool == "gim-remesh":
        i = r["image"]
        row = [i["efficiency_square"], i["efficiency_octahedron"], i["flipped_triangles"]]
    else:
        row = [r["map"]["efficiency_domain_to_surface"], None, None]
    row += [r["distance"]["psnr_db"], r["seconds"]["map"]]
    rows.append(row)
    cells = [f"{v:.5f}" if isinstance(v, float) else ("-" if v is None else str(v)) for v in row[:3]]
    print(f"| {k} | " + " | ".join(cells) + f" | {row[3]:.3f} | {row[4]:.1f} |")
if rows:
    print()
    for name, j in [("efficiency", 0), ("octahedron", 1), ("flips", 2), ("PSNR dB", 3)]:
        values = [r[j] for r in rows if r[j] is not None]
        if values:
            print(f"- {name}: min {min(values):.5g}, median {statistics.median(values):.5g}, "
                  f"max {max(values):.5g}")
PY
