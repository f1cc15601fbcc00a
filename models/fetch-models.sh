#!/usr/bin/env bash
# Fetches well-known public test models from the npm registry into
# models/downloaded/ as OBJ (they are not part of the repository):
#   bunny.obj   the Stanford bunny (npm package "bunny"; Stanford 3D Scanning
#               Repository terms: research use, credit the Stanford Computer
#               Graphics Laboratory): 1839 vertices, closed, genus 0.
# Needs node and npm.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$here/downloaded"
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
npm pack --silent bunny@1.0.1 >/dev/null 2>&1
tar xzf bunny-1.0.1.tgz
node -e '
  const b = require("./package/index.js");
  const lines = ["# Stanford bunny from the npm package bunny@1.0.1"];
  for (const p of b.positions) lines.push("v " + p.join(" "));
  for (const c of b.cells) lines.push("f " + c.map(i => i + 1).join(" "));
  require("fs").writeFileSync(process.argv[1], lines.join("\n") + "\n");
' "$out/bunny.obj"
echo "models/downloaded/bunny.obj written" >&2
