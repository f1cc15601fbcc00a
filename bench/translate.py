#!/usr/bin/env python3
"""Writes an OBJ translated by k·1e-9 of its bounding box's diagonal along
every axis: a copy that a map does not see, but whose every computed length
rounds differently (bench/bar_noise.sh, bench/pair_noise.sh).
  translate.py IN.obj OUT.obj K"""
import math
import sys

src, dst, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
lines = open(src).read().splitlines()
points = [list(map(float, l.split()[1:4])) for l in lines if l.startswith("v ")]
lo = [min(p[i] for p in points) for i in range(3)]
hi = [max(p[i] for p in points) for i in range(3)]
shift = k * 1e-9 * math.dist(lo, hi)
with open(dst, "w") as out:
    for l in lines:
        if l.startswith("v "):
            x, y, z = (float(c) + shift for c in l.split()[1:4])
            l = f"v {x!r} {y!r} {z!r}"
        out.write(l + "\n")
