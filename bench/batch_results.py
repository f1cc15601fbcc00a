#!/usr/bin/env python3
"""Lists, checks, tabulates and compares ism-batch results (bench/batch.sh).

  batch_results.py list MODELS_DIR        closed genus-0 models of models.json, then torus.obj (refused: genus 1)
  batch_results.py check LIST DIR         every listed mesh's line once, outputs only for ok lines,
                                          an error line for the others, nothing partial in DIR
  batch_results.py table DIR              a Markdown table of DIR/results.jsonl
  batch_results.py compare DIR_A DIR_B    same names, statuses, errors and figures
Exit status 1 when a check or a comparison fails.
"""
import json
import os
import sys


def read_results(folder):
    lines = [json.loads(l) for l in open(os.path.join(folder, "results.jsonl")) if l.strip()]
    return lines, {l["name"]: l for l in lines}


def list_models(models_dir):
    models = json.load(open(os.path.join(models_dir, "models.json")))
    closed = [m["file"] for m in models if m["genus"] == 0 and m["boundary_loops"] == 0]
    for f in closed + ["torus.obj"]:
        print(os.path.join(os.path.abspath(models_dir), f))


def list_names(list_file):
    names = []
    for line in open(list_file):
        line = line.rstrip("\r\n")
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        path, _, name = line.partition("\t")
        names.append(name or os.path.splitext(os.path.basename(path.strip()))[0])
    return names


def check(list_file, folder):
    problems = []
    lines, by_name = read_results(folder)
    names = list_names(list_file)
    if len(lines) != len(by_name):
        problems.append(f"{len(lines)} lines for {len(by_name)} names")
    for name in names:
        r = by_name.get(name)
        if r is None:
            problems.append(f"{name}: no line")
            continue
        out = os.path.join(folder, name)
        if r["status"] == "ok":
            if r["error"] is not None or not os.path.isfile(os.path.join(out, "report.json")):
                problems.append(f"{name}: ok without its outputs")
        elif not r["error"] or os.path.exists(out):
            problems.append(f"{name}: {r['status']} without an error line, or with outputs")
    extra = set(by_name) - set(names)
    if extra:
        problems.append(f"lines for meshes not in the list: {sorted(extra)}")
    partial = [f for f in os.listdir(folder) if f.startswith(".") and f != ".results.lock"]
    if partial:
        problems.append(f"left on disk: {partial}")
    for p in problems:
        print("check:", p, file=sys.stderr)
    ok = sum(1 for r in lines if r["status"] == "ok")
    print(f"check: {folder}: {len(names)} meshes, {len(lines)} lines, {ok} ok, "
          f"{len(lines) - ok} failed; {len(problems)} problems", file=sys.stderr)
    return 1 if problems else 0


def table(folder):
    lines, _ = read_results(folder)
    print("| model | shard | status | seconds | faces | map eff. | square eff. | flips | PSNR dB | error |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---|")
    for r in lines:
        f = r.get("figures") or {}
        get = lambda section, key, fmt: (fmt % f[section][key]) if key in f.get(section, {}) else ""
        print(f"| {r['name']} | {r['shard']} | {r['status']} | {r['seconds']:.1f} "
              f"| {get('input', 'faces', '%d')} | {get('map', 'efficiency_domain_to_surface', '%.3f')} "
              f"| {get('image', 'efficiency_square', '%.3f')} | {get('image', 'flipped_triangles', '%d')} "
              f"| {get('distance', 'psnr_db', '%.1f')} | {r['error'] or ''} |")
    return 0


def compare(a, b):
    _, ra = read_results(a)
    _, rb = read_results(b)
    differences = []
    if set(ra) != set(rb):
        differences.append(f"names differ: {sorted(set(ra) ^ set(rb))}")
    for name in sorted(set(ra) & set(rb)):
        for key in ("input", "tool", "status", "error", "exit_code", "figures"):
            if ra[name].get(key) != rb[name].get(key):
                differences.append(f"{name}: {key}: {ra[name].get(key)} vs {rb[name].get(key)}")
    for d in differences:
        print("compare:", d, file=sys.stderr)
    print(f"compare: {a} and {b}: {len(set(ra) & set(rb))} meshes in both; statuses, errors and "
          f"figures {'identical' if not differences else 'DIFFER (%d)' % len(differences)}",
          file=sys.stderr)
    return 1 if differences else 0


if __name__ == "__main__":
    commands = {"list": (list_models, 1), "check": (check, 2), "table": (table, 1), "compare": (compare, 2)}
    if len(sys.argv) < 2 or sys.argv[1] not in commands or len(sys.argv) != 2 + commands[sys.argv[1]][1]:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(commands[sys.argv[1]][0](*sys.argv[2:]) or 0)
