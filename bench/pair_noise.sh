#!/usr/bin/env bash
# How much a two-surface map's figures move when only their rounding does:
# both surfaces of each pair translated by k·1e-9 of their diagonals
# (k = 0..RUNS-1; bench/translate.py), each copy mapped by the symmetric
# core with both sides refining (`inter_surface_map A B --decimate V`), one
# job at a time. Prints each run's figures and their spread, so that a change
# which moves the outputs is judged against the spread rather than one run
# (results-two-surfaces.md, stop 60: a tolerance change moved the genus-2
# pair's efficiency by 0.004 one way and spot ↔ bunny_small's by 0.013 the
# other).
#   bench/pair_noise.sh > table.md
#   PAIRS="torus:cup:150" RUNS=5 bench/pair_noise.sh
# PAIRS: A:B:V, models of ../shared/models and the --decimate target.
source "$(dirname "$0")/common.sh"
pairs="${PAIRS-spot:bunny_small:300 torus:cup:150 double_torus:eight_loop2:300}"
runs="${RUNS-3}"

echo "inter_surface_map A B --decimate V, both surfaces translated by k·1e-9 of their diagonals, k = 0..$((runs - 1)); commit $commit, $(nproc) cores, one job at a time."
echo
echo "| pair | k | symmetric eff. | symmetric Dirichlet | one-way A→B | one-way B→A | user s | wall s |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for p in $pairs; do
  IFS=: read -r a b v <<<"$p"
  for ((k = 0; k < runs; ++k)); do
    python3 "$root/bench/translate.py" "$models_dir/$a.obj" "$work/a$k.obj" "$k"
    python3 "$root/bench/translate.py" "$models_dir/$b.obj" "$work/b$k.obj" "$k"
    /usr/bin/time -f '%U %e' -o "$work/$k.time" "$bin/inter_surface_map" "$work/a$k.obj" \
      "$work/b$k.obj" --decimate "$v" >"$work/$k.out" 2>/dev/null || true
    python3 - "$work/$k.out" "$work/$k.time" "$a ↔ $b ($v)" "$k" "$work/rows.tsv" <<'PY'
import re, sys
out, time, pair, k, rows = sys.argv[1:6]
m = re.search(r"symmetric efficiency ([\d.]+) \(symmetric Dirichlet ([\d.]+)\), "
              r"one-way A->B ([\d.]+), B->A ([\d.]+)", open(out).read())
user, wall = open(time).read().split()[-2:]
print(f"| {pair} | {k} | " + (" | ".join(m.groups()) if m else "failed | | |") + f" | {user} | {wall} |")
if m:
    with open(rows, "a") as f:
        f.write(f"{pair}\t{m.group(1)}\t{m.group(2)}\t{user}\t{wall}\n")
PY
  done
done
echo
python3 - "$work/rows.tsv" <<'PY'
import statistics, sys
by = {}
try:
    for line in open(sys.argv[1]):
        pair, eff, dirichlet, user, wall = line.rstrip("\n").split("\t")
        by.setdefault(pair, []).append((float(eff), float(dirichlet), float(user), float(wall)))
except OSError:
    pass
for pair, rows in by.items():
    parts = []
    for name, j in [("symmetric eff.", 0), ("symmetric Dirichlet", 1), ("user s", 2), ("wall s", 3)]:
        v = [r[j] for r in rows]
        parts.append(f"{name} {min(v):.4g} / {statistics.median(v):.4g} / {max(v):.4g}")
    print(f"- {pair} (min / median / max): " + "; ".join(parts))
PY
