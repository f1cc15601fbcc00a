#!/usr/bin/env bash
# Installs the build and test dependencies from Debian 12's packages, and the
# extra packages named as arguments (scripts/fuzz.sh: clang-14
# libclang-rt-14-dev). Does nothing when they are all present already.
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libopenmesh-dev libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev
  libopenexr-dev libopenimageio-dev openimageio-tools libdraco-dev
  libtbb-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
