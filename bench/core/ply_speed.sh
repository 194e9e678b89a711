#!/bin/sh
# Times loading a binary little-endian PLY point cloud (x y z, normals, colours).
# Usage: bench/core/ply_speed.sh <build folder> [points]
# The file is written once, read back timed; the first read may include the
# page cache being warm (the file was just written), i.e. this measures parsing.
set -e
build=${1:-build}
points=${2:-10000000}
file="${TMPDIR:-/tmp}/hos-ply-bench.ply"
"$build/bin/hos-ply-bench" "$points" "$file"
rm -f "$file"
