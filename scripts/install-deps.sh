#!/usr/bin/env bash
# Installs the build and test dependencies from Debian 12's packages, then
# the npm packages the tests use (scripts/install-node-tools.sh) and the
# viewer's (scripts/viewer-deps.sh), and the extra packages named as
# arguments (scripts/fuzz.sh: clang-14 libclang-rt-14-dev). Does nothing when
# all are present.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libopenmesh-dev libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev
  libopenexr-dev libopenimageio-dev openimageio-tools libdraco-dev
  libtbb-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev
  pybind11-dev python3-dev python3-numpy python3-pytest
  # ism-batch's test runs shards through GNU parallel; the viewer's test
  # renders in headless Chromium (about 120 MB, 20 s to install).
  parallel chromium
  "$@"
)
# The viewer's vendoring and test scripts run on Node.js (any Debian 12 one).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then packages+=(nodejs npm); fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The glTF validator only checks outputs: without it (no network) the tests
# that use it skip with a message, the rest still run.
"$(dirname "$0")/install-node-tools.sh" ||
  echo "install-deps: warning: the npm packages could not be installed; the glTF validation tests will skip" >&2
# The viewer's three.js (vendored into viewer/vendor/) and its test's
# playwright-core, from the npm registry at the versions of package-lock.json.
"$(dirname "$0")/viewer-deps.sh"
