#!/usr/bin/env bash
# Every tool over every hostile regression file (tests/data/hostile) and over
# generated worst cases just under 5 MB (the inputs that turn the fewest bytes
# into the most elements), then the parameter bombs: exit status, wall time
# and peak memory (/usr/bin/time, Debian package `time`), and the tool's
# answer. A run longer than 120 s is cut and shown as TIMEOUT.
#   bench/hostile.sh > docs/results-hostile-runs.md
source "$(dirname "$0")/common.sh"
if [ ! -x /usr/bin/time ]; then
  echo "bench/hostile.sh: needs /usr/bin/time (apt-get install time)" >&2
  exit 1
fi

# Worst cases under 5 MB, written with awk.
gen="$work/generated"
mkdir -p "$gen"
awk 'BEGIN { print "v 0 0 0"; print "v 1 0 0"; print "v 0 1 0";
             for (i = 0; i < 620000; ++i) print "f 1 2 3" }' >"$gen/obj_620k_same_triangle.obj"
awk 'BEGIN { for (i = 0; i < 620000; ++i) print "v 0 0 " i; print "f 1 2 3" }' \
  >"$gen/obj_620k_vertices_1_face.obj"
awk 'BEGIN { print "OFF"; print "3 1200000 0"; print "0 0 0"; print "1 0 0"; print "0 1 0";
             for (i = 0; i < 1200000; ++i) print "3 0 1 2" }' >"$gen/off_1200k_faces.off"
awk 'BEGIN { n = 1000; k = 0; srand(7);
             print "OFF"; print n " 600000 0";
             for (i = 0; i < n; ++i) printf "%.3f %.3f %.3f\n", rand(), rand(), rand();
             for (i = 0; i < 600000; ++i) printf "3 %d %d %d\n", int(rand()*n), int(rand()*n), int(rand()*n) }' \
  >"$gen/off_600k_random_triangles.off"
# 80,000 separate triangles in one plane: 240,000 boundary points with x = 0
# (the boundary weld once compared them pairwise).
awk 'BEGIN { srand(5); for (i = 0; i < 80000; ++i) {
             for (k = 0; k < 3; ++k) printf "v 0 %.4f %.4f\n", rand(), rand();
             printf "f %d %d %d\n", 3 * i + 1, 3 * i + 2, 3 * i + 3 } }' >"$gen/obj_80k_triangles_one_plane.obj"
# Binary PLY, uchar counts and indices: 4 bytes a face over 256 vertices.
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 256\nproperty uchar x\nproperty uchar y\nproperty uchar z\nelement face 1250000\nproperty list uchar uchar vertex_indices\nend_header\n'
  # (no zero bytes: some awks cannot print them)
  awk 'BEGIN { for (i = 0; i < 256; ++i) printf "%c%c%c", 1 + i % 255, 1 + (i * 7) % 255, 1 + (i * 13) % 255 }'
  awk 'BEGIN { srand(3); for (i = 0; i < 1250000; ++i)
               printf "%c%c%c%c", 3, 1 + int(rand()*255), 1 + int(rand()*255), 1 + int(rand()*255) }'
} >"$gen/ply_1250k_uchar_faces.ply"

files=("$root"/tests/data/hostile/*.{obj,off,ply,stl} "$gen"/*)

echo "Hostile input: every tool over the regression files of tests/data/hostile and generated worst cases under 5 MB; $(nproc) cores, commit $commit."
echo "Exit 0: read (and, for a valid surface, processed); 1: refused with the line shown. Seconds are wall time, memory the peak resident set (/usr/bin/time)."
echo
echo "| input | bytes | tool | exit | seconds | peak MB | answer |"
echo "|---|---:|---|---:|---:|---:|---|"
run() {
  local input="$1" tool="$2"
  shift 2
  local status=0
  timeout 120 /usr/bin/time -f "%e %M" -o "$work/time" "$bin/$tool" "$@" -q >/dev/null 2>"$work/err" ||
    status=$?
  local seconds peak answer
  if [ "$status" -eq 124 ]; then
    seconds="TIMEOUT" peak="-"
  else
    read -r seconds peak < <(tail -n 1 "$work/time")  # after "Command exited with ..."
    peak=$((peak / 1024))
  fi
  answer="$(head -c 160 "$work/err" | tr '\n|' ' /' | sed "s|$root/tests/data/hostile/||g; s|$gen/||g; s|$work/||g")"
  echo "| $(basename -- "$input") | $(stat -c %s -- "$input" 2>/dev/null || echo -) | $tool | $status | $seconds | $peak | $answer |"
  rm -f "$work/out.exr" "$work/out.obj"
}
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  run "$f" ism-info "$f"
  run "$f" gim-remesh "$f" -o "$work/out.exr" --size 9
  run "$f" semireg "$f" --base-size 4 --levels 1 -o "$work/out.obj"
  run "$f" torus-remesh "$f" --size 8 -o "$work/out.obj"
done

echo
echo "Parameter bombs (the mesh named does not exist: a refusal that comes before reading it names the parameter):"
echo
echo "| input | bytes | tool | exit | seconds | peak MB | answer |"
echo "|---|---:|---|---:|---:|---:|---|"
missing="$work/never_read.obj"
run "--size 16385" gim-remesh "$missing" -o "$work/out.exr" --size 16385
run "--size 65537" gim-remesh "$missing" -o "$work/out.exr" --size 65537
run "-o out.txt" gim-remesh "$missing" -o "$work/out.txt"
run "--base-size 5000 --levels 8" semireg "$missing" --base-size 5000 --levels 8 -o "$work/out.obj"
run "--size 8192" torus-remesh "$missing" --size 8192 -o "$work/out.obj"
run "--faces 50000000" ism-genmesh sphere --faces 50000000 -o "$work/out.obj"
if [ -d "$models_dir" ]; then
  run "sphere.obj --base-size 100000" semireg "$models_dir/sphere.obj" --base-size 100000 -o "$work/out.obj"
  run "sphere.obj --size 16385" gim-remesh "$models_dir/sphere.obj" --size 16385 -o "$work/out.exr"
fi
