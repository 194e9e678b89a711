#!/usr/bin/env bash
# Installs the Debian packages hos needs, only those that are missing.
# Idempotent; run as root (or with sudo available) on Debian 12.
#   scripts/install-deps.sh                 # what building and running hos needs
#   scripts/install-deps.sh --test          # and what the test suite needs
#   scripts/install-deps.sh --print [--test]  # list the packages, one a line; install nothing
set -euo pipefail

with_tests=0
print_only=0
for arg in "$@"; do
  case "$arg" in
    --test) with_tests=1 ;;
    --print) print_only=1 ;;
    *)
      echo "install-deps: unknown argument '$arg' (known: --test, --print)" >&2
      exit 2
      ;;
  esac
done

# Building and running hos: the compiler, COLMAP (the sfm stage runs it) and
# the libraries the stages link.
packages=(
  build-essential cmake ninja-build pkg-config git
  colmap
  libopencv-dev libeigen3-dev libceres-dev libtinygltf-dev libyaml-cpp-dev
  libcli11-dev nlohmann-json3-dev libstb-dev libjpeg-dev
  libnanoflann-dev libmaxflow-dev libmeshoptimizer-dev
  libexiv2-dev libheif-dev libsqlite3-dev
)
# The test suite: GoogleTest; clang-format and clang-tidy (scripts/test.sh
# checks formatting and tidies the recent changes); Chromium opens the run
# report in the browser test (tests/pipeline); slurm-wlm and munge run the
# one-node Slurm of the Slurm executor's test
# (tests/pipeline/slurm_cluster_test.cpp), which starts its own daemons.
test_packages=(
  libgtest-dev libgmock-dev clang-format clang-tidy chromium slurm-wlm munge
)
if [ "$with_tests" -eq 1 ]; then packages+=("${test_packages[@]}"); fi
# Node.js and npm fetch the report's model viewer at build time and run the
# glTF validator in the tests. Many machines already carry them from another
# source, and Debian's npm package then conflicts with it, so they are only
# installed when absent.
if ! command -v node >/dev/null 2>&1; then packages+=(nodejs); fi
if ! command -v npm >/dev/null 2>&1; then packages+=(npm); fi

if [ "$print_only" -eq 1 ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

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
