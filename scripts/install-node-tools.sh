#!/usr/bin/env bash
# Installs the npm packages the tests use (the Khronos glTF validator, in
# scripts/gltf-validator/node_modules), with Debian's Node.js and npm when the
# machine has no node. Does nothing when they are present already.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  echo "install-node-tools: installing Debian's nodejs and npm" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
validator="$root/scripts/gltf-validator"
if [ ! -f "$validator/node_modules/gltf-validator/package.json" ]; then
  echo "install-node-tools: installing gltf-validator (npm)" >&2
  npm ci --prefix "$validator" --no-audit --no-fund --loglevel=error >/dev/null
fi
