#!/usr/bin/env bash
# Installs the Debian packages hos needs, only those that are missing.
# Idempotent; run as root (or with sudo available) on Debian 12.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git clang-format
  colmap
  libopencv-dev libeigen3-dev libceres-dev libtinygltf-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libcli11-dev nlohmann-json3-dev libstb-dev
  libnanoflann-dev libmaxflow-dev libmeshoptimizer-dev
  clang-tidy chromium
  slurm-wlm munge
)
# Chromium opens the run report in the browser test (tests/pipeline).
# slurm-wlm and munge run the one-node Slurm of the Slurm executor's test
# (tests/pipeline/slurm_cluster_test.cpp); the test starts its own daemons.
# Node.js and npm run the glTF validator in the texture and pipeline tests
# and fetch the report's model viewer at build time.
# Many machines already carry them from another source, and Debian's npm
# package then conflicts with it, so they are only installed when absent.
if ! command -v node >/dev/null 2>&1; then packages+=(nodejs); fi
if ! command -v npm >/dev/null 2>&1; then packages+=(npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
echo "install-deps: done"
