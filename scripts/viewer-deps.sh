#!/usr/bin/env bash
# The web viewer's npm packages (viewer/package-lock.json): three.js, copied
# into viewer/vendor/ (not committed), and playwright-core for its headless
# test. Installs only when viewer/node_modules is missing or older than the
# lock file. Without Node.js or the registry it warns and leaves the viewer
# unvendored; the viewer's test then skips with that reason.
set -euo pipefail
viewer="$(cd "$(dirname "$0")/../viewer" && pwd)"
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  echo "viewer-deps: node/npm not found; the viewer is not vendored" >&2
  exit 0
fi
cd "$viewer"
if [ ! -f node_modules/.package-lock.json ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  echo "viewer-deps: npm ci in $viewer" >&2
  if ! npm ci --no-audit --no-fund --loglevel=error >/dev/null; then
    echo "viewer-deps: npm ci failed; the viewer is not vendored" >&2
    exit 0
  fi
fi
node scripts/vendor.mjs
