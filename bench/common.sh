# Sourced by the benchmark scripts: builds the project and sets
#   root        the repository
#   bin         the built tools
#   models_dir  ../shared/models
#   work        a scratch directory removed on exit
#   commit      the code measured: COMMIT if given, else the checkout's commit
#               (marked when the tree has uncommitted changes)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh" >/dev/null
bin="${BUILD_DIR:-$root/build}/bin"
models_dir="$root/../shared/models"
commit="${COMMIT:-$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)}"
if [ -z "${COMMIT:-}" ] && [ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ]; then
  commit="$commit with uncommitted changes"
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
